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

The hypotheses of a bank share their filters: a failed actuator's hypothesis differs from the
no-failure one only in ``B_d``, which none of the quantities above involves, so a complete-failure
bank's 79 hypotheses pose 29 distinct problems (NONE, the 7 sensor failures and the 21 sensor
pairs).  ``steady_state_gains`` keeps the filters it designed, keyed by the exact bytes of
``(Phi, H, Q_d, R)``, and hands out copies for a problem it has solved: the same numbers, bit
for bit, as solving it again.
"""
from __future__ import annotations

from collections import OrderedDict
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
    rhs = np.empty((n, 2 * n))  # [A, G], refilled every step
    with np.errstate(over="ignore", invalid="ignore"):  # divergence is detected below
        for _ in range(max_iter):
            rhs[:, :n] = ak
            rhs[:, n:] = gk
            try:
                w = np.linalg.solve(eye + gk @ hk, rhs)  # (I + G H)^{-1} [A, G]
            except np.linalg.LinAlgError:
                break
            w_a, w_g = w[:, :n], w[:, n:]
            h_next = hk + ak.T @ hk @ w_a
            gk = gk + ak @ w_g @ ak.T
            gk = 0.5 * (gk + gk.T)
            ak = ak @ w_a
            h_next = 0.5 * (h_next + h_next.T)
            step = np.abs(h_next - hk).max()
            hk = h_next
            if not np.isfinite(hk).all():
                break
            if step <= tol * max(1.0, np.abs(hk).max()):
                return hk
    raise DesignError(
        "the filter Riccati equation has no stabilizing solution (doubling did not converge): "
        "an unstable mode is unobservable from the remaining sensors or receives no noise")


#: Filters designed in this process, by problem (``_problem_key``), oldest first; at most
#: ``_DESIGNED_MAX`` (a scheduled design's node poses 29 problems, none shared with another node).
_DESIGNED: OrderedDict[tuple, SteadyStateGains] = OrderedDict()
_DESIGNED_MAX = 256


def _problem_key(*arrays: np.ndarray) -> tuple:
    """The exact identity of a design problem: each array's shape and float64 bytes."""
    out = []
    for x in arrays:
        x = np.ascontiguousarray(x, dtype=float)
        out += [x.shape, x.tobytes()]
    return tuple(out)


def forget_designed_filters() -> None:
    """Empty the store of designed filters (the next call of each problem solves it anew)."""
    _DESIGNED.clear()


def designed_filter_count() -> int:
    """How many distinct problems the store holds."""
    return len(_DESIGNED)


def _copy(g: SteadyStateGains) -> SteadyStateGains:
    return SteadyStateGains(p_minus=g.p_minus.copy(), p_plus=g.p_plus.copy(), k=g.k.copy(), a=g.a.copy(),
                            spectral_radius=g.spectral_radius)


def steady_state_gains(phi: np.ndarray, h: np.ndarray, qd: np.ndarray, r: np.ndarray,
                       *, name: str = "filter") -> SteadyStateGains:
    """``P^-`` from the DARE, then ``A = H P^- H^T + R`` (eq. 5), ``K = P^- H^T A^{-1}``; a
    problem solved before in this process is not solved again (module docstring).

    Raises DesignError naming ``name`` when the resulting filter is unstable."""
    key = _problem_key(phi, h, qd, r)
    known = _DESIGNED.get(key)
    if known is None:
        known = _design(phi, h, qd, r, name)  # a refused design raises: never stored
        _DESIGNED[key] = known
        while len(_DESIGNED) > _DESIGNED_MAX:
            _DESIGNED.popitem(last=False)
    return _copy(known)


def _design(phi: np.ndarray, h: np.ndarray, qd: np.ndarray, r: np.ndarray, name: str) -> SteadyStateGains:
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
