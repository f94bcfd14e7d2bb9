"""Steady-state Kalman filter gains from the discrete algebraic Riccati equation (DARE).

For ``x_{i+1} = Phi x_i + B_d u_i + w_d`` (cov ``Q_d``), ``z_i = H x_i + v_i`` (cov ``R``),
the steady-state a-priori covariance ``P^-`` solves the filter DARE::

    P^- = Phi P^- Phi^T - Phi P^- H^T (H P^- H^T + R)^{-1} H P^- Phi^T + Q_d

and the filter's residual covariance, gain and a-posteriori covariance are::

    A = H P^- H^T + R                         (paper eq. 5)
    K = P^- H^T A^{-1}
    P^+ = (I - K H) P^-

The filter recursion ``x+ = x- + K (z - H x-)``, ``x-_{i+1} = Phi x+ + B_d u`` has error
dynamics ``Phi (I - K H)``; a design whose spectral radius is not below one is refused.

The DARE is solved with the structure-preserving doubling algorithm (Chu, Fan, Lin & Wang,
2004), which converges quadratically and keeps the iterates symmetric; SciPy's
``solve_discrete_are`` (a Schur method) is the independent check in the tests.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import F16mmaeError


class DesignError(F16mmaeError, ValueError):
    """A filter design that cannot be used: no stabilizing DARE solution, unstable filter."""


@dataclass(frozen=True)
class SteadyStateGains:
    """Steady-state filter quantities of one hypothesis (sizes n states, m measurements)."""

    p_minus: np.ndarray  # (n, n) a-priori covariance
    p_plus: np.ndarray   # (n, n) a-posteriori covariance
    k: np.ndarray        # (n, m) Kalman gain
    a: np.ndarray        # (m, m) residual covariance, eq. 5
    spectral_radius: float  # of the error dynamics Phi (I - K H)


def solve_filter_dare(phi: np.ndarray, h: np.ndarray, qd: np.ndarray, r: np.ndarray,
                      *, tol: float = 1e-13, max_iter: int = 100) -> np.ndarray:
    """Stabilizing solution ``P^-`` of the filter DARE above (structure-preserving doubling).

    Raises DesignError when the iteration does not converge (no stabilizing solution:
    an undetectable unstable mode, or an unstable mode without process noise)."""
    phi, h, qd, r = (np.asarray(x, dtype=float) for x in (phi, h, qd, r))
    n, m = phi.shape[0], h.shape[0]
    if phi.shape != (n, n) or h.shape != (m, n) or qd.shape != (n, n) or r.shape != (m, m):
        raise ValueError(
            f"shapes Phi {phi.shape}, H {h.shape}, Q_d {qd.shape}, R {r.shape} do not fit "
            f"n={n} states and m={m} measurements")
    try:
        np.linalg.cholesky(r)
    except np.linalg.LinAlgError:
        raise DesignError("R is not positive definite: every sensor needs a positive noise "
                          "variance") from None
    # Doubling on the dual (control) form X = A^T X A - ... + Q with A = Phi^T, B = H^T.
    ak = phi.T.copy()
    gk = h.T @ np.linalg.solve(r, h)
    hk = 0.5 * (qd + qd.T)
    eye = np.eye(n)
    with np.errstate(over="ignore", invalid="ignore"):  # divergence is detected below
        for _ in range(max_iter):
            try:
                w = np.linalg.solve(eye + gk @ hk, np.hstack([ak, gk]))  # (I + G H)^{-1} [A, G]
            except np.linalg.LinAlgError:
                break
            w_a, w_g = w[:, :n], w[:, n:]
            h_next = hk + ak.T @ hk @ w_a
            gk = gk + ak @ w_g @ ak.T
            gk = 0.5 * (gk + gk.T)
            ak = ak @ w_a
            h_next = 0.5 * (h_next + h_next.T)
            step = np.max(np.abs(h_next - hk))
            hk = h_next
            if not np.all(np.isfinite(hk)):
                break
            if step <= tol * max(1.0, np.max(np.abs(hk))):
                return hk
    raise DesignError(
        "the filter Riccati equation has no stabilizing solution (doubling did not converge): "
        "an unstable mode is unobservable from the remaining sensors or receives no noise")


def steady_state_gains(phi: np.ndarray, h: np.ndarray, qd: np.ndarray, r: np.ndarray,
                       *, name: str = "filter") -> SteadyStateGains:
    """``P^-`` from the DARE, then ``A = H P^- H^T + R`` (eq. 5), ``K = P^- H^T A^{-1}``.

    Raises DesignError naming ``name`` when the resulting filter is unstable."""
    try:
        p = solve_filter_dare(phi, h, qd, r)
    except DesignError as exc:
        raise DesignError(f"{name}: {exc}") from None
    a = h @ p @ h.T + r
    a = 0.5 * (a + a.T)
    k = np.linalg.solve(a, h @ p).T  # P H^T A^{-1}, A symmetric
    n = phi.shape[0]
    p_plus = (np.eye(n) - k @ h) @ p
    p_plus = 0.5 * (p_plus + p_plus.T)
    rho = float(np.max(np.abs(np.linalg.eigvals(phi @ (np.eye(n) - k @ h)))))
    if not rho < 1.0:
        raise DesignError(f"{name}: the steady-state filter is unstable: spectral radius of "
                          f"Phi (I - K H) is {rho:.6f} >= 1")
    return SteadyStateGains(p_minus=p, p_plus=p_plus, k=k, a=a, spectral_radius=rho)
