"""core.FilterModel / core.FilterBank against independent answers: a numpy Bayes update
(eqs. 1-2), the floor's water-filling semantics, and covariance-propagating Kalman filters
started at SciPy's DARE solution (they must give the same residuals and probabilities as
the steady-state bank), in both the dynamic-size and the fixed-size F-16 bank."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are

from f16mmae import core


def random_plant(rng, n, p, m, q_var=1e-2, r_var=1e-2):
    phi = rng.standard_normal((n, n))
    phi *= 0.95 / max(abs(np.linalg.eigvals(phi)))
    return phi, rng.standard_normal((n, p)), rng.standard_normal((m, n)), q_var * np.eye(n), r_var * np.eye(m)


def hypotheses(phi, bd, h, q, r):
    """NONE, then each actuator (B column removed), then each sensor (H row removed), each
    with its DARE gain: P- from scipy, A = H P- H^T + R (eq. 5), K = P- H^T A^-1."""
    out = []
    for kind, j in [("none", -1)] + [("act", j) for j in range(bd.shape[1])] + [("sen", j) for j in range(h.shape[0])]:
        bd_k, h_k = bd.copy(), h.copy()
        if kind == "act":
            bd_k[:, j] = 0.0
        if kind == "sen":
            h_k[j, :] = 0.0
        p_prior = solve_discrete_are(phi.T, h_k.T, q, r)
        a = h_k @ p_prior @ h_k.T + r
        a = 0.5 * (a + a.T)
        out.append(dict(phi=phi, bd=bd_k, h=h_k, k=p_prior @ h_k.T @ np.linalg.inv(a), a=a, p_prior=p_prior))
    return out


class CovarianceKalmanBank:
    """The reference: full Kalman filters (covariance propagated every frame) and the
    textbook Bayes update of eq. 1 with the Gaussian density of eq. 2, floored by
    p = max(p_min, s * bayes) with s solving sum p = 1."""

    def __init__(self, hyps, q, r, p_min, strip):
        self.h = hyps
        self.q, self.r, self.p_min, self.strip = q, r, p_min, strip
        n = hyps[0]["phi"].shape[0]
        self.x = [np.zeros(n) for _ in hyps]
        self.P = [hk["p_prior"].copy() for hk in hyps]
        k = len(hyps)
        self.p = np.full(k, p_min)
        self.p[0] = 1.0 - (k - 1) * p_min

    def step(self, z, u):
        m = len(z)
        dens, res = [], []
        for i, hk in enumerate(self.h):
            A = hk["h"] @ self.P[i] @ hk["h"].T + self.r
            K = self.P[i] @ hk["h"].T @ np.linalg.inv(A)
            r = z - hk["h"] @ self.x[i]
            q = r @ np.linalg.solve(A, r)
            lead = 1.0 if self.strip else 1.0 / ((2 * np.pi) ** (m / 2) * np.sqrt(np.linalg.det(A)))
            dens.append(lead * np.exp(-0.5 * q))
            res.append(r)
            x_post = self.x[i] + K @ r
            P_post = (np.eye(len(x_post)) - K @ hk["h"]) @ self.P[i]
            self.x[i] = hk["phi"] @ x_post + hk["bd"] @ u
            self.P[i] = hk["phi"] @ P_post @ hk["phi"].T + self.q
        bayes = np.array(dens) * self.p
        bayes /= bayes.sum()
        self.p = water_fill(bayes, self.p_min)
        return self.p, np.array(res)


def water_fill(bayes, p_min):
    """p_k = max(p_min, s b_k), sum p = 1, by trying n = 0, 1, ... of the smallest b_k at the
    floor (independent of the C++ iteration)."""
    order = np.argsort(bayes)
    for n in range(len(bayes)):
        free = order[n:]
        s = (1.0 - n * p_min) / bayes[free].sum()
        if s * bayes[free].min() >= p_min and (n == 0 or s * bayes[order[n - 1]] <= p_min):
            p = np.full(len(bayes), p_min)
            p[free] = s * bayes[free]
            return p
    raise AssertionError("no water-filling solution")


def models_of(hyps):
    return [core.FilterModel(phi=hk["phi"], bd=hk["bd"], h=hk["h"], k=hk["k"], a=hk["a"]) for hk in hyps]


def fly(rng, phi, bd, h, q, r, frames, fail_actuator_at=None):
    """Linear truth with unit dither; actuator 0 stops answering at frame fail_actuator_at."""
    x = np.zeros(phi.shape[0])
    zs, us = [], []
    for i in range(frames):
        zs.append(h @ x + rng.multivariate_normal(np.zeros(h.shape[0]), r))
        u = np.sin(2 * np.pi * (0.7 + 0.37 * np.arange(bd.shape[1])) * i / 64.0 + np.arange(bd.shape[1]))
        us.append(u)
        b = bd.copy()
        if fail_actuator_at is not None and i >= fail_actuator_at:
            b[:, 0] = 0.0
        x = phi @ x + b @ u + rng.multivariate_normal(np.zeros(len(x)), q)
    return np.array(zs), np.array(us)


@pytest.mark.parametrize("strip", [True, False])
def test_steady_state_bank_equals_covariance_kalman_filters_at_the_dare_solution(strip):
    rng = np.random.default_rng(1)
    phi, bd, h, q, r = random_plant(rng, 3, 2, 2)
    hyps = hypotheses(phi, bd, h, q, r)  # NONE, 2 actuators, 2 sensors
    bank = core.FilterBank(models_of(hyps), strip_leading_term=strip)
    assert not bank.fixed_size and bank.size == 5
    ref = CovarianceKalmanBank(hyps, q, r, p_min=0.001, strip=strip)
    zs, us = fly(rng, phi, bd, h, q, r, 300, fail_actuator_at=100)
    for z, u in zip(zs, us):
        p = bank.step(z, u)
        p_ref, r_ref = ref.step(z, u)
        np.testing.assert_allclose(bank.residuals, r_ref, rtol=0, atol=1e-9)
        np.testing.assert_allclose(p, p_ref, rtol=0, atol=1e-9)
        assert abs(p.sum() - 1.0) < 1e-12 and p.min() >= 0.001
    assert np.argmax(bank.probabilities) == 1  # the failed actuator's hypothesis wins


def test_f16_sized_bank_runs_fixed_size_and_matches_the_reference():
    rng = np.random.default_rng(2)
    phi, bd, h, q, r = random_plant(rng, 13, 5, 7, 1e-3, 1e-3)
    hyps = hypotheses(phi, bd, h, q, r)
    assert len(hyps) == 13
    bank = core.FilterBank(models_of(hyps))
    assert bank.fixed_size
    ref = CovarianceKalmanBank(hyps, q, r, p_min=0.001, strip=True)
    zs, us = fly(rng, phi, bd, h, q, r, 120)
    for z, u in zip(zs, us):
        p = bank.step(z, u)
        p_ref, r_ref = ref.step(z, u)
        np.testing.assert_allclose(bank.residuals, r_ref, rtol=0, atol=1e-8)
        np.testing.assert_allclose(p, p_ref, rtol=0, atol=1e-8)
    blend = bank.probabilities @ bank.state_estimates
    np.testing.assert_allclose(bank.blended_state, blend, atol=1e-12)
    np.testing.assert_allclose(bank.z_hat, h @ blend, atol=1e-12)
    np.testing.assert_allclose(bank.step_frames(zs[:5], us[:5])[-1], bank.probabilities, atol=0)


def scalar_models(a_values):
    # x stays 0 (K = 0, Bd = 0): r = z, q = z^2 / A
    return [core.FilterModel(phi=[[0.5]], bd=[[0.0]], h=[[1.0]], k=[[0.0]], a=[[a]]) for a in a_values]


def test_hand_computed_bayes_update_and_leading_term():
    a = np.array([1.0, 4.0, 0.25])
    prior = np.array([0.5, 0.3, 0.2])
    z = 1.3
    for strip in (True, False):
        bank = core.FilterBank(scalar_models(a), p_min=0.0, strip_leading_term=strip, initial_probabilities=prior)
        lead = 1.0 if strip else 1.0 / np.sqrt(2 * np.pi * a)
        f = lead * np.exp(-0.5 * z * z / a) * prior
        np.testing.assert_allclose(bank.update([z]), f / f.sum(), rtol=1e-13)
        np.testing.assert_allclose(bank.log_likelihoods, np.log(lead) - 0.5 * z * z / a, rtol=1e-13)


def test_floor_water_fills_and_a_floored_hypothesis_recovers():
    bank = core.FilterBank(scalar_models([1.0, 0.1, 10.0]), strip_leading_term=False)
    rng = np.random.default_rng(3)
    for sigma, winner in ((np.sqrt(0.1), 1), (np.sqrt(10.0), 2)):
        for _ in range(150):
            prior = bank.probabilities
            p = bank.update([sigma * rng.standard_normal()])
            bayes = prior * np.exp(bank.log_likelihoods)
            np.testing.assert_allclose(p, water_fill(bayes / bayes.sum(), 0.001), atol=1e-12)
            assert p.min() >= 0.001 and abs(p.sum() - 1) < 1e-12
        assert np.argmax(p) == winner and p[winner] > 0.99


def test_huge_residuals_never_give_nan():
    bank = core.FilterBank(scalar_models([1.0, 100.0, 2.0]))
    p = bank.update([1e100])  # q = 1e200 / A
    assert np.all(np.isfinite(p)) and np.argmax(p) == 1
    p2 = bank.update([1e300])  # q overflows for all: no information
    np.testing.assert_array_equal(p2, p)
    assert np.all(np.isfinite(bank.z_hat)) and np.all(np.isfinite(bank.blended_state))


def test_non_finite_frames_are_rejected_and_counted():
    rng = np.random.default_rng(4)
    phi, bd, h, q, r = random_plant(rng, 3, 2, 2)
    bank = core.FilterBank(models_of(hypotheses(phi, bd, h, q, r)))
    bank.step([0.1, 0.2], [0.3, 0.4])
    before = (bank.probabilities, bank.state_estimates, bank.prior_states, bank.residuals)
    bank.update([np.nan, 0.0])
    bank.propagate([0.0, np.inf])
    assert bank.rejected_frames == 2
    for a, b in zip(before, (bank.probabilities, bank.state_estimates, bank.prior_states, bank.residuals)):
        np.testing.assert_array_equal(a, b)
    bank.reset()
    assert bank.rejected_frames == 0 and bank.probabilities[0] == pytest.approx(1 - 4 * 0.001)


def test_boundary_errors_name_the_expected_shape():
    rng = np.random.default_rng(5)
    phi, bd, h, q, r = random_plant(rng, 13, 5, 7)
    hyps = hypotheses(phi, bd, h, q, r)
    bank = core.FilterBank(models_of(hyps))
    with pytest.raises(ValueError, match=r"z must have shape \(7,\), got \(6,\)"):
        bank.update(np.zeros(6))
    with pytest.raises(ValueError, match=r"u must have shape \(5,\), got \(5, 1\)"):
        bank.step(np.zeros(7), np.zeros((5, 1)))
    with pytest.raises(ValueError, match=r"k must have shape \(13, 7\), got \(7, 13\)"):
        core.FilterModel(phi=phi, bd=bd, h=h, k=hyps[0]["k"].T, a=hyps[0]["a"])
    with pytest.raises(ValueError, match="not positive definite"):
        core.FilterModel(phi=phi, bd=bd, h=h, k=hyps[0]["k"], a=-hyps[0]["a"])
    with pytest.raises(ValueError, match="unstable"):
        core.FilterModel(phi=2 * phi, bd=bd, h=h, k=0 * hyps[0]["k"], a=hyps[0]["a"])
    with pytest.raises(ValueError, match="p_min"):
        core.FilterBank(models_of(hyps), p_min=0.2)
    with pytest.raises(ValueError, match="sum to 1"):
        core.FilterBank(models_of(hyps), initial_probabilities=np.full(13, 0.5))
    with pytest.raises(ValueError, match=r"h_output must have shape \(7, 13\)"):
        core.FilterBank(models_of(hyps), h_output=np.zeros((13, 7)))
    with pytest.raises(ValueError, match=r"models\[1\] must be a core.FilterModel"):
        core.FilterBank([models_of(hyps)[0], "x"])
    m = core.FilterModel(phi=phi, bd=bd, h=h, k=hyps[0]["k"], a=hyps[0]["a"])
    np.testing.assert_array_equal(m.phi, phi)
    assert (m.nx, m.nu, m.nz) == (13, 5, 7)
