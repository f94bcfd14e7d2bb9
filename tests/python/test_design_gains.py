"""Steady-state gains (design/gains.py) and exact discretization (design/discretize.py)
against independent answers: SciPy's Schur-method DARE, a covariance-propagating Kalman
filter run to convergence, scipy.signal's ZOH and a quadrature of the Q_d integral."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg
import scipy.signal

from f16mmae.design.discretize import discretize, van_loan_qd, zoh
from f16mmae import names
from f16mmae.design import bank
from f16mmae.design.gains import (DesignError, designed_filter_count, forget_designed_filters, solve_filter_dare,
                                  steady_state_gains)


def random_system(seed, n=13, m=7, p=3, rho=0.995):
    rng = np.random.default_rng(seed)
    phi = rng.standard_normal((n, n))
    phi *= rho / np.max(np.abs(np.linalg.eigvals(phi)))
    h = rng.standard_normal((m, n))
    g = rng.standard_normal((n, p))
    qd = g @ g.T  # rank p < n: singular, as the untuned design's Q_d
    r = np.diag(rng.uniform(0.01, 1.0, m))
    return phi, h, qd, r


@pytest.mark.parametrize("seed", range(6))
def test_dare_matches_scipy(seed):
    phi, h, qd, r = random_system(seed)
    p = solve_filter_dare(phi, h, qd, r)
    p_ref = scipy.linalg.solve_discrete_are(phi.T, h.T, qd, r)
    assert np.allclose(p, p_ref, rtol=1e-9, atol=1e-10 * np.abs(p_ref).max())
    assert np.allclose(p, p.T, atol=0)


def test_gains_match_a_converged_covariance_propagating_filter():
    phi, h, qd, r = random_system(42, rho=0.97)
    ss = steady_state_gains(phi, h, qd, r)
    p = np.eye(len(phi))  # P-(t_0): any start converges
    for _ in range(3000):
        a = h @ p @ h.T + r
        k = p @ h.T @ np.linalg.inv(a)
        p_plus = (np.eye(len(phi)) - k @ h) @ p
        p = phi @ p_plus @ phi.T + qd
    a = h @ p @ h.T + r
    k = p @ h.T @ np.linalg.inv(a)
    assert np.allclose(ss.p_minus, p, rtol=1e-8, atol=1e-12)
    assert np.allclose(ss.a, a, rtol=1e-8)
    assert np.allclose(ss.k, k, rtol=1e-7, atol=1e-12)
    assert ss.spectral_radius < 1.0


def test_unstable_undetectable_design_is_refused():
    phi = np.diag([1.05, 0.5])  # the unstable mode is not measured
    h = np.array([[0.0, 1.0]])
    with pytest.raises(DesignError, match="no stabilizing solution"):
        steady_state_gains(phi, h, np.eye(2), np.eye(1), name="hypothesis X")


GAIN_FIELDS = ("p_minus", "p_plus", "k", "a")


def _same_bits(g1, g2) -> bool:
    return (all(getattr(g1, f).tobytes() == getattr(g2, f).tobytes() for f in GAIN_FIELDS)
            and g1.spectral_radius == g2.spectral_radius)


def test_a_problem_posed_again_is_not_solved_again_and_gets_its_own_arrays():
    phi, h, qd, r = random_system(3)
    forget_designed_filters()
    first = steady_state_gains(phi, h, qd, r)
    assert designed_filter_count() == 1
    again = steady_state_gains(phi.copy(), np.asfortranarray(h), qd.copy(), r.copy())  # same values
    assert designed_filter_count() == 1 and _same_bits(first, again)
    assert all(getattr(first, f) is not getattr(again, f) for f in GAIN_FIELDS)
    again.k[:] = 0.0  # a caller's arrays are its own
    assert _same_bits(first, steady_state_gains(phi, h, qd, r))
    r2 = r.copy()
    r2[0, 0] = np.nextafter(r2[0, 0], 1.0)  # one bit apart: another problem
    steady_state_gains(phi, h, qd, r2)
    assert designed_filter_count() == 2
    with pytest.raises(DesignError):
        steady_state_gains(np.diag([1.05, 0.5]), np.array([[0.0, 1.0]]), np.eye(2), np.eye(1))
    assert designed_filter_count() == 2  # a refused design is not kept


def test_a_bank_poses_29_problems_and_each_filter_equals_its_own_solution_bit_for_bit():
    # a failed actuator changes B_d only: NONE and the 15 actuator hypotheses share one filter,
    # each sensor failure (and sensor pair) shares its filter with its 5 actuator companions
    forget_designed_filters()
    design = bank.design_bank(bank.NOMINAL_MACH, bank.NOMINAL_ALT_FT, "untuned")
    assert len(design.filters) == len(names.ALL_HYPOTHESES) and designed_filter_count() == 1 + 7 + 21
    for f in design.filters:
        forget_designed_filters()  # each hypothesis solved alone, nothing shared
        alone = steady_state_gains(f.model.phi, f.model.h, f.model.qd, design.r)
        assert _same_bits(f.gains, alone), f.name


def test_non_positive_r_is_refused():
    with pytest.raises(DesignError, match="R is not positive definite"):
        solve_filter_dare(np.eye(2) * 0.5, np.eye(2), np.eye(2), np.diag([1.0, 0.0]))


def test_zoh_matches_scipy_signal():
    phi, _, _, _ = random_system(3, n=5, m=2)
    f = scipy.linalg.logm(phi).real * 64.0
    b = np.random.default_rng(3).standard_normal((5, 2))
    ad, bd = zoh(f, b, 1 / 64)
    ref = scipy.signal.cont2discrete((f, b, np.eye(5), np.zeros((5, 2))), 1 / 64, method="zoh")
    assert np.allclose(ad, ref[0], rtol=1e-10, atol=1e-12)
    assert np.allclose(bd, ref[1], rtol=1e-10, atol=1e-12)


def test_van_loan_qd_matches_quadrature():
    rng = np.random.default_rng(5)
    f = rng.standard_normal((4, 4)) - 2 * np.eye(4)
    g = rng.standard_normal((4, 2))
    gqg = g @ np.diag([2.0, 0.5]) @ g.T
    dt = 0.05

    def integrand(s):
        e = scipy.linalg.expm(f * s)
        return (e @ gqg @ e.T).ravel()

    ref = scipy.integrate.quad_vec(integrand, 0.0, dt, epsabs=1e-14, epsrel=1e-12)[0].reshape(4, 4)
    assert np.allclose(van_loan_qd(f, gqg, dt), ref, rtol=1e-9, atol=1e-15)
    dm = discretize(f, np.zeros((4, 1)), g, np.diag([2.0, 0.5]), dt)
    assert np.allclose(dm.qd, ref, rtol=1e-9, atol=1e-15)
    assert np.allclose(dm.phi, scipy.linalg.expm(f * dt))
