"""Dryden gust states inside the filters (design/gust_states.py, ``f16mmae design
--gust-states``): the gust subsystem has the Dryden variances (SciPy's Lyapunov solver against
the hand formulas), the kinematic part of the rate columns is what the finite-difference
linearization has in its kinematic rows, the bank is 19 states and runs in the fixed-size
core (the same probabilities as the dynamic-size bank), and the design command reproduces it."""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
from scipy.linalg import solve_continuous_lyapunov

from f16mmae import core, names
from f16mmae.cli import main as cli
from f16mmae.design import bank, gust_states
from f16mmae.design.model import GUST_SCALE_LENGTH_FT, build_model, linearize_truth
from f16mmae.design.tuning import load_tuning


@pytest.fixture(scope="module")
def linearized():
    return linearize_truth(bank.NOMINAL_MACH, bank.NOMINAL_ALT_FT)


@pytest.fixture(scope="module")
def severe_model(linearized):
    return build_model(linearized.lin, linearized.trim.vt_fps, "severe", bank.NOMINAL_ALT_FT, "dryden_states")


def test_gust_states_have_the_dryden_variances(severe_model):
    m = severe_model
    assert m.nx == 19 and m.state_names == names.STATES + gust_states.GUST_STATES
    g = slice(names.NX, m.nx)
    # the gust subsystem is autonomous (nothing of the aircraft drives it)
    assert np.all(m.f[g, :names.NX] == 0.0)
    p = solve_continuous_lyapunov(m.f[g, g], -m.g[g] @ m.qc @ m.g[g].T)
    su, sv, sw = m.gust_sigma_fps
    length, span = GUST_SCALE_LENGTH_FT, gust_states.WINGSPAN_FT
    # roll and pitch gusts: the heading-free average of MIL-F-8785C's sigma_p^2 and sigma_q^2
    pq = 0.5 * ((1.9 * sw) ** 2 / (length * span) + math.pi * sw**2 / (2.0 * span * length))
    # r_g = -(s/V) v_g / (1 + tau_r s), v_g of corner a_v = 2V/L: the integral of
    # w^2 / ((w^2 + a^2)(w^2 + c^2)) over the real line is pi / (a + c), so
    # var r_g = a_v sigma_v^2 / (V^2 tau_r (1 + a_v tau_r))
    v, a_v, tau_r = m.vt_fps, 2.0 * m.vt_fps / length, 3.0 * span / (math.pi * m.vt_fps)
    expected = [su**2, sv**2, sw**2, pq, pq, a_v * sv**2 / (v * v * tau_r * (1.0 + a_v * tau_r))]
    assert np.diag(p) == pytest.approx(expected, rel=1e-9)
    # w_g' = -(2V/L) w_g: its correlation time is L / 2V
    assert m.f[names.NX + 2, names.NX + 2] == pytest.approx(-2.0 * m.vt_fps / length)


def test_kinematic_rate_columns_are_the_linearization_kinematic_rows(linearized):
    lin = linearized.lin
    kin = gust_states.kinematic_rate_columns(lin.x_trim)
    rates = lin.a[:, [5, 2, 6]]
    # theta' = q and phi' = p + tan(theta) r are kinematics only: the finite differences agree
    for row in (3, 7):
        assert rates[row] == pytest.approx(kin[row], abs=1e-6)
    # the moment rows have no kinematic part (rates are zero at the trim)
    assert np.all(kin[[2, 5, 6]] == 0.0)


def test_zero_order_models_are_unchanged_by_the_option(linearized):
    m = build_model(linearized.lin, linearized.trim.vt_fps, "light", bank.NOMINAL_ALT_FT)
    assert m.nx == names.NX and m.g.shape == (names.NX, 3)
    g = build_model(linearized.lin, linearized.trim.vt_fps, "light", bank.NOMINAL_ALT_FT, "dryden_states")
    assert np.array_equal(g.f[:names.NX, :names.NX], m.f) and np.array_equal(g.h[:, :names.NX], m.h)


def test_design_gust_states_writes_a_19_state_bank_the_fixed_core_runs(tmp_path, capsys):
    out = tmp_path / "gust.f16bank"
    assert cli.main(["design", "--tuning", "tuned_gust", "--gust-level", "moderate", "--out", str(out)]) == 0
    mb = core.load_bank(str(out))
    assert mb.nx == 19 and list(mb.state_names)[-6:] == list(gust_states.GUST_STATES)
    meta = json.loads(mb.metadata)
    assert meta["model"]["gust_model"] == "dryden_states" and meta["model"]["gust_level"] == "moderate"
    assert meta["command"].endswith("--tuning tuned_gust --gust-level moderate")
    # the recorded command reproduces the file byte for byte
    again = tmp_path / "again.f16bank"
    assert cli.main(meta["command"].split()[1:] + ["--out", str(again)]) == 0
    assert again.read_bytes() == out.read_bytes()
    # nx selects the fixed-size 19-state core (tests/cpp: it equals the dynamic-size one)
    fixed = core.HierarchicalBank(mb)
    assert fixed.fixed_size
    for _ in range(64):  # at the trim nothing is declared
        fixed.step(mb.z_trim, mb.u_trim)
    assert fixed.declarations == [] and fixed.probabilities[0] > 0.9


def test_gust_options_are_refused_with_the_valid_choices(tmp_path, capsys):
    assert cli.main(["design", "--gust-level", "stormy", "--out", str(tmp_path / "x.f16bank")]) != 0
    err = capsys.readouterr().err
    assert "stormy" in err and "severe" in err
    assert cli.main(["design", "--schedule", "--gust-states", "--out", str(tmp_path / "s.f16sched")]) != 0
    assert "--gust-states" in capsys.readouterr().err


def test_tuning_arguments_name_the_options_that_made_the_tuning():
    t = load_tuning("tuned")
    assert bank.tuning_arguments(t) == "tuned"
    g = dataclasses.replace(t, name="tuned-severe-gust", turbulence="severe", gust_model="dryden_states")
    assert bank.tuning_arguments(g) == "tuned --gust-level severe --gust-states"
    c = dataclasses.replace(g, name="tuned-severe-gust-cover", failure_model="cover")
    assert bank.tuning_arguments(c) == "tuned --gust-level severe --gust-states --failure-model cover"


def test_padded_gust_states_are_inert(linearized):
    """A 13-state bank padded with inert gust states (``pad_bank``, for a schedule whose low
    nodes carry gust states): 19 states, the gust estimates stay exactly 0 in every filter, and
    the residuals and probabilities are the 13-state bank's frame for frame (the independent
    answer: the unpadded bank, run through the 13-state core)."""
    plain = bank.to_model_bank(bank.design_bank(bank.NOMINAL_MACH, bank.NOMINAL_ALT_FT, load_tuning("tuned"),
                                                linearized=linearized))
    padded = gust_states.pad_bank(plain)
    assert padded.nx == 19 and tuple(padded.state_names) == names.STATES + gust_states.GUST_STATES
    assert gust_states.pad_bank(padded) is padded
    assert padded.estimator_settings == plain.estimator_settings and padded.tuning == plain.tuning
    assert json.loads(padded.metadata)["inert_gust_states"] == list(gust_states.GUST_STATES)
    rng = np.random.default_rng(5)
    n = 300
    sd = np.sqrt(np.diag(plain.hypotheses[0].a))
    z = plain.z_trim + rng.normal(size=(n, names.NZ)) * sd + np.outer(np.sin(np.arange(n) / 9.0), 2.0 * sd)
    u = plain.u_trim + 0.01 * np.sign(np.sin(np.arange(n) / 13.0))[:, None] * np.ones(names.NU)
    hp, hq = core.HierarchicalBank(plain), core.HierarchicalBank(padded)
    singles = [i for i, h in enumerate(padded.hypotheses) if h.name in names.SINGLE_HYPOTHESES]
    fb = core.FilterBank([core.FilterModel(phi=padded.hypotheses[i].phi, bd=padded.hypotheses[i].bd,
                                           h=padded.hypotheses[i].h, k=padded.hypotheses[i].k,
                                           a=padded.hypotheses[i].a) for i in singles])
    for t in range(n):
        hp.step(z[t], u[t])
        hq.step(z[t], u[t])
        fb.step(z[t] - plain.z_trim, u[t] - plain.u_trim)
        np.testing.assert_allclose(hq.residuals, hp.residuals, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(np.log(hq.probabilities), np.log(hp.probabilities), rtol=1e-9, atol=1e-9)
        assert not fb.state_estimates[:, names.NX:].any() and not fb.prior_states[:, names.NX:].any()
    assert np.abs(fb.state_estimates[:, :names.NX]).max() > 0   # the plain states did move
    assert hq.declarations == hp.declarations


def test_pad_state_appends_zero_gust_states_and_refuses_other_sizes():
    x = np.arange(names.NX, dtype=float)
    padded = gust_states.pad_state(x)
    assert len(padded) == 19 and (padded[:names.NX] == x).all() and not padded[names.NX:].any()
    assert gust_states.pad_state(padded) is not None and (gust_states.pad_state(padded) == padded).all()
    with pytest.raises(ValueError, match="pad_state: 5 states, neither 13 nor 19"):
        gust_states.pad_state(np.zeros(5))
