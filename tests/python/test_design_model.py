"""The design model (design/linearize.py, model.py, hypotheses.py): the finite-difference
linearization against JSBSim's own FGLinearization and against the nonlinear truth's step
responses; the augmented model's structure and the truth parameters it uses; the filter's
consistency on data simulated from the linear model itself; the hypotheses' removed column
or row."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae import names
from f16mmae.design import bank, hypotheses, linearize, model
from f16mmae.design.flights import fly_open_loop
from f16mmae.design.report import linear_step
from f16mmae.truth import actuators, aircraft, sensors


@pytest.fixture(scope="module")
def design():
    return bank.design_bank(0.4, 20_000.0, "tuned")


def test_finite_differences_agree_with_fglinearization(design):
    lin = design.linearized.lin
    fdm, _ = aircraft.trimmed_fdm(0.4, 20_000.0)
    a_j, b_j, u_names = linearize.jsbsim_linearization(fdm)
    scale = np.abs(lin.a).max(axis=1, keepdims=True)
    assert np.max(np.abs(a_j - lin.a) / scale) < 1e-3
    # FGLinearization's inputs are the pilot commands, passed by the mixer with the trim
    # command scales: elevator = both stabilators, aileron = LF - RF differential, rudder.
    e_max, a_max, r_max = actuators.TRIM_COMMAND_SCALE_RAD
    col = dict(zip(u_names, b_j.T))
    pairs = [(col["DeCmd"] / e_max, lin.b[:, 0] + lin.b[:, 1]),
             (col["DaCmd"] / a_max, lin.b[:, 2] - lin.b[:, 3]),
             (col["DrCmd"] / r_max, lin.b[:, 4])]
    for ours_j, ours in pairs:
        assert np.allclose(ours_j, ours, rtol=1e-3, atol=1e-3 * np.abs(ours).max())
    assert lin.evaluations == 27


def test_bare_airframe_modes(design):
    ev = np.linalg.eigvals(design.linearized.lin.a)
    assert np.all(ev.real < 0)
    # short period, Dutch roll, roll subsidence of the bare airframe: -0.51+-0.78j,
    # -0.26+-2.24j, -0.96
    for target in (-0.51 + 0.78j, -0.26 + 2.24j, -0.96):
        assert np.min(np.abs(ev - target)) < 0.03


def test_augmented_model_uses_the_truth_parameters(design):
    c = design.continuous
    lag = np.asarray(actuators.LAG_RAD_S)
    assert np.allclose(np.diag(c.f)[8:], -lag) and np.allclose(c.b[8:], np.diag(lag))
    assert not c.b[:8].any() and not c.f[8:, :8].any()
    assert np.allclose(c.r_diag, np.asarray(sensors.NOISE_SIGMA) ** 2)
    assert np.allclose(c.h, np.hstack([design.linearized.lin.c, design.linearized.lin.dd]))
    # gust rate enters only the air-relative velocity states u, alpha, beta
    assert set(np.flatnonzero(np.abs(c.g).sum(axis=1))) == {0, 1, 4}
    assert np.allclose(design.u_trim, design.linearized.trim.u_rad)
    assert np.allclose(design.h_output, design.filter("NONE").model.h)


def test_linear_step_responses_match_the_nonlinear_truth(design):
    n = int(2.0 * names.FRAME_RATE_HZ)
    step = math.radians(0.2)
    for surface in ("LS", "RF", "RUD"):
        nl = fly_open_loop(turbulence_level="none", duration_s=2.0, dither=False, noise=False,
                           step=(surface, step)).z_ideal
        li = linear_step(design, surface, step, n)
        floor = 3 * np.asarray(sensors.NOISE_SIGMA)
        rel = np.abs(nl - li).max(axis=0) / np.maximum(np.abs(nl).max(axis=0), floor)
        assert rel.max() < 0.05, (surface, rel)


def test_nis_is_m_on_data_from_the_linear_model_itself(design):
    f = design.filter("NONE")
    phi, bd, h, k, a = f.model.phi, f.model.bd, f.model.h, f.gains.k, f.gains.a
    rng = np.random.default_rng(7)
    lam, vec = np.linalg.eigh(design.discrete.qd)  # Q_d is only semi-definite
    lq = vec * np.sqrt(np.clip(lam, 0.0, None))
    lr = np.linalg.cholesky(design.r)
    n = 20_000
    x, xh = np.zeros(names.NX), np.zeros(names.NX)
    nis = np.empty(n)
    r_all = np.empty((n, names.NZ))
    for i in range(n):
        u = 0.01 * np.sin(2 * np.pi * np.array([1.3, 1.7, 1.1, 1.5, 0.9]) * i / 64)
        z = h @ x + lr @ rng.standard_normal(names.NZ)
        r = z - h @ xh
        r_all[i] = r
        nis[i] = r @ np.linalg.solve(a, r)
        xh = phi @ (xh + k @ r) + bd @ u
        x = phi @ x + bd @ u + lq @ rng.standard_normal(names.NX)
    # NIS ~ chi2(7): mean 7, sd of the mean sqrt(14/n) (residuals are white: no inflation)
    assert abs(nis[500:].mean() - names.NZ) < 4 * math.sqrt(2 * names.NZ / n)
    assert np.allclose(r_all[500:].var(axis=0) / np.diag(a), 1.0, atol=0.05)


def test_hypotheses_differ_from_none_exactly_in_the_removed_column_or_row(design):
    none = design.filter("NONE").model
    assert [f.name for f in design.filters] == list(names.ALL_HYPOTHESES)
    for f in design.filters:
        m = f.model
        assert np.array_equal(m.phi, none.phi)
        failed = names.failed_components(f.name)
        cols = [names.ACTUATORS.index(c) for c in failed if c in names.ACTUATORS]
        rows = [names.SENSORS.index(c) for c in failed if c in names.SENSORS]
        keep_c = [j for j in range(names.NU) if j not in cols]
        keep_r = [i for i in range(names.NZ) if i not in rows]
        assert np.array_equal(m.bd[:, keep_c], none.bd[:, keep_c]) and not m.bd[:, cols].any()
        assert np.array_equal(m.h[keep_r], none.h[keep_r]) and not m.h[rows].any()
        # a failed sensor's channel carries only noise: A_ii = R_ii, no gain on it
        for i in rows:
            assert f.gains.a[i, i] == pytest.approx(design.r[i, i], rel=1e-12)
            assert np.allclose(f.gains.k[:, i], 0.0, atol=1e-15)
        assert f.gains.spectral_radius < 1.0


def test_failed_actuator_lag_state_decays_to_trim(design):
    m = design.filter("LS").model
    x = np.zeros(names.NX)
    x[names.STATES.index("d_ls_rad")] = 0.01
    for _ in range(64):  # one second with full command on every surface
        x = m.phi @ x + m.bd @ np.full(names.NU, 0.01)
    assert abs(x[names.STATES.index("d_ls_rad")]) < 0.01 * math.exp(-20.2) * 1.01 + 1e-12
    assert x[names.STATES.index("d_rs_rad")] == pytest.approx(0.01, rel=1e-6)


def test_unknown_hypothesis_component_is_refused(design):
    none = design.filter("NONE").model
    with pytest.raises(ValueError, match="unknown component 'XX'"):
        hypotheses.hypothesis_model("LS+XX", none.phi, none.bd, none.h)


def test_flight_condition_out_of_range_is_refused():
    with pytest.raises(ValueError, match="mach 0.9 outside the supported range 0.3-0.8"):
        model.linearize_truth(0.9, 20_000.0)
    with pytest.raises(ValueError, match="alt_ft 40000.0 outside the supported range"):
        bank.design_bank(0.4, 40_000.0, "untuned")


def test_gust_models(design):
    lt, c = design.linearized, design.continuous
    w = model.build_model(lt.lin, lt.trim.vt_fps, "light", 20_000.0, gust_model="white_gust")
    assert np.array_equal(w.g[:8], -lt.lin.a_uvw) and not w.g[8:].any()
    s, v, length = c.gust_sigma_fps, lt.trim.vt_fps, model.GUST_SCALE_LENGTH_FT
    assert np.allclose(np.diag(w.qc), [2 * s[0] ** 2 * length / v, s[1] ** 2 * length / v,
                                       s[2] ** 2 * length / v])
    assert np.allclose(np.diag(c.qc), [2 * s[0] ** 2 * v / length, 3 * s[1] ** 2 * v / length,
                                       3 * s[2] ** 2 * v / length])
    none = model.build_model(lt.lin, lt.trim.vt_fps, "none", 20_000.0)
    assert not none.qc.any()
    with pytest.raises(ValueError, match="unknown gust model 'x'; valid: gust_rate, white_gust"):
        model.build_model(lt.lin, lt.trim.vt_fps, "light", 20_000.0, gust_model="x")


def test_uvw_jacobian_matches_numerical_differentiation():
    x = np.array([410.0, 0.14, 0.0, 0.14, 0.03, 0.0, 0.0, 0.0])
    u, v, w = linearize._uvw(x)

    def angles(uvw):
        uu, vv, ww = uvw
        return np.array([uu, np.arctan2(ww, uu), np.arcsin(vv / np.linalg.norm(uvw))])

    h = 1e-4
    num = np.column_stack([(angles(np.array([u, v, w]) + h * e) - angles(np.array([u, v, w]) - h * e))
                           / (2 * h) for e in np.eye(3)])
    assert np.allclose(linearize.uvw_jacobian(x), num, rtol=1e-7, atol=1e-12)
