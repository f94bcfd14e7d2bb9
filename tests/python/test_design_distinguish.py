"""design/distinguish.py: the expected evidence per frame between two hypotheses, computed
from the models (Lyapunov + the dither's periodic response + Gauss-Hermite), against the
mean of the real core's per-frame log-likelihood differences on data simulated from the same
linear model, and its sign on the F-16 bank's known cases."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae import core
from f16mmae.design import distinguish
from f16mmae.design.gains import steady_state_gains


@pytest.mark.parametrize("amplitude", [0.8, 8.0])
def test_evidence_rate_matches_the_core_on_simulated_data(amplitude):
    rng = np.random.default_rng(3)
    phi = np.array([[0.95, 0.10, 0.0], [-0.08, 0.90, 0.05], [0.0, 0.1, 0.85]])
    bd = np.array([[0.0], [0.1], [0.05]])
    h = np.array([[1.0, 0.0, 0.2], [0.0, 1.0, 0.0], [0.3, 0.0, 1.0]])
    q, r = np.diag([0.01, 0.02, 0.01]), np.diag([0.04, 0.02, 0.05])
    width, level_q = np.array([0.0, 6.0, 0.0]), np.array([0.0, 0.05 * 0.02, 0.0])
    h_fail = h.copy()
    h_fail[1] = 0.0  # truth: sensor 1 failed, reading its trim value (0) plus noise
    g_none, g_fail = steady_state_gains(phi, h, q, r), steady_state_gains(phi, h_fail, q, r)
    models = [core.FilterModel(phi=phi, bd=bd, h=h_fail, k=g_fail.k, a=g_fail.a, uninformative_width=width,
                               uninformative_level_q=level_q),
              core.FilterModel(phi=phi, bd=bd, h=h, k=g_none.k, a=g_none.a)]
    own = distinguish.ScoredFilter(phi=phi, bd=bd, h=h_fail, k=g_fail.k,
                                   a_inv=np.linalg.inv(g_fail.a) * np.outer([1, 0, 1], [1, 0, 1]),
                                   levels=((1, *distinguish.level_filter(0.05 * 0.02, float(g_fail.a[1, 1])),
                                            float(g_fail.a[1, 1])),))
    none = distinguish.ScoredFilter(phi=phi, bd=bd, h=h, k=g_none.k, a_inv=np.linalg.inv(g_none.a))
    frames = 120_000
    u = amplitude * np.sin(2 * np.pi * 0.05 * np.arange(frames))[:, None]
    expect = distinguish.rates(phi, q, r, bd, h_fail, own, [none], u[:2000])[0]
    fb = core.FilterBank(models, p_min=1e-6)
    x = np.zeros(3)
    w = rng.multivariate_normal(np.zeros(3), q, frames)
    v = rng.multivariate_normal(np.zeros(3), r, frames)
    diffs = np.empty(frames)
    for i in range(frames):
        fb.step(h_fail @ x + v[i], u[i])
        ll = fb.log_likelihoods
        diffs[i] = ll[0] - ll[1]
        x = phi @ x + bd @ u[i] + w[i]
    kept = diffs[1000:]
    se = kept.std() / np.sqrt(len(kept)) * 3.0  # frames are correlated: a generous error
    assert abs(kept.mean() - expect) < max(4 * se, 0.02 * abs(expect)), (kept.mean(), expect, se)


@pytest.fixture(scope="module")
def design():
    from f16mmae.design import bank
    from f16mmae import names

    hyps = ("NONE", "AZ", "AOA", "PIT", "AOA+AZ", "PIT+AZ")
    assert all(n in names.ALL_HYPOTHESES for n in hyps)
    return bank.design_bank(0.4, 20_000.0, "tuned", hypotheses=hyps)


def test_paper_models_cannot_tell_aoa_after_az_but_can_tell_pit(design):
    # the dual campaign's one ND pair (AZ>AOA) against a pair it rates Good (AZ>PIT)
    d_aoa = distinguish.evidence_rates(design, "AOA+AZ", ["AZ"])["AZ"]
    d_pit = distinguish.evidence_rates(design, "PIT+AZ", ["AZ"])["AZ"]
    assert d_aoa < 0.0 < d_pit
    assert distinguish.frames_to_lift(d_aoa, 1e-9) == float("inf")
    assert distinguish.frames_to_lift(2.0, np.exp(-20.0)) == pytest.approx(10.0)


def test_the_throttle_dither_makes_calm_air_aoa_distinguishable():
    """Calm air, a bank designed for calm air: without the throttle a failed AOA reading its
    trim is as likely as a working one (D <= 0: the campaign's 0/20), with the throttle dither
    modelled (six inputs, throttle dither scheduled at the design point) it is not."""
    import dataclasses

    from f16mmae.design import bank
    from f16mmae.design.tuning import load_tuning
    from f16mmae.truth import dither

    calm = load_tuning("tuned")
    calm = dataclasses.replace(calm, name="tuned-none", turbulence="none")
    d = {}
    for throttle in (False, True):
        design = bank.design_bank(0.4, 20_000.0, calm, hypotheses=("NONE", "AOA"), throttle_input=throttle)
        d[throttle] = distinguish.evidence_rates(design, "AOA", ["NONE"], calm=True)["NONE"]
    assert d[False] <= 0.0 < 0.1 < d[True]
    u = distinguish.dither_inputs(640, 64.0, throttle_at=(0.4, 20_000.0))
    assert u.shape == (640, 6)
    np.testing.assert_allclose(u[:, :5], distinguish.dither_inputs(640, 64.0))
    assert np.max(np.abs(u[:, 5])) == pytest.approx(dither.scheduled_throttle_amplitude(0.4, 20_000.0), rel=1e-3)
