"""Exact zero-order-hold discretization of a linear time-invariant model.

Continuous model (paper Sec. IV, eq. 6 without the failure bookkeeping)::

    x'(t) = F x(t) + B u(t) + G w(t),      E[w(t) w(s)^T] = Q_c delta(t - s)

sampled every ``dt_s`` with ``u`` held constant over a frame gives (eq. 3)::

    x(t_{i+1}) = Phi x(t_i) + B_d u(t_i) + w_d(t_i),      E[w_d w_d^T] = Q_d

    Phi = e^{F dt},   B_d = int_0^dt e^{F s} ds B,   Q_d = int_0^dt e^{F s} G Q_c G^T e^{F^T s} ds

``Phi`` and ``B_d`` come from one matrix exponential of the block matrix
``[[F, B], [0, 0]] dt``; ``Q_d`` from Van Loan's method (1978): with
``M = [[-F, G Q_c G^T], [0, F^T]] dt`` and ``e^M = [[., E12], [0, E22]]``,
``Phi = E22^T`` and ``Q_d = E22^T E12``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm


@dataclass(frozen=True)
class DiscreteModel:
    """``x_{i+1} = phi x_i + bd u_i + w_d``, ``cov(w_d) = qd``; sampled every ``dt_s`` seconds."""

    phi: np.ndarray
    bd: np.ndarray
    qd: np.ndarray
    dt_s: float


def zoh(f: np.ndarray, b: np.ndarray, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
    """``(Phi, B_d)`` of ``x' = F x + B u`` under a zero-order hold of period ``dt_s``."""
    f = np.asarray(f, dtype=float)
    b = np.asarray(b, dtype=float)
    n, m = b.shape
    if f.shape != (n, n):
        raise ValueError(f"F must be {n}x{n} to match B ({n}x{m}), got {f.shape}")
    if not dt_s > 0.0:
        raise ValueError(f"the sample period must be positive, got dt_s={dt_s}")
    block = np.zeros((n + m, n + m))
    block[:n, :n] = f
    block[:n, n:] = b
    e = expm(block * dt_s)
    return e[:n, :n], e[:n, n:]


def van_loan_qd(f: np.ndarray, gqg: np.ndarray, dt_s: float) -> np.ndarray:
    """Discrete process-noise covariance ``Q_d`` of continuous white noise of spectral
    density ``G Q_c G^T`` (``gqg``, n x n) through ``x' = F x`` over ``dt_s`` (Van Loan)."""
    f = np.asarray(f, dtype=float)
    n = f.shape[0]
    m = np.zeros((2 * n, 2 * n))
    m[:n, :n] = -f
    m[:n, n:] = gqg
    m[n:, n:] = f.T
    e = expm(m * dt_s)
    phi = e[n:, n:].T
    qd = phi @ e[:n, n:]
    return 0.5 * (qd + qd.T)


def discretize(f: np.ndarray, b: np.ndarray, g: np.ndarray, qc: np.ndarray,
               dt_s: float) -> DiscreteModel:
    """Exact discretization of ``x' = F x + B u + G w`` (``cov w = Q_c delta``) at ``dt_s``."""
    g = np.asarray(g, dtype=float)
    qc = np.atleast_2d(np.asarray(qc, dtype=float))
    if g.shape[1] != qc.shape[0] or qc.shape[0] != qc.shape[1]:
        raise ValueError(f"G is {g.shape} but Q_c is {qc.shape}; need G n x p and Q_c p x p")
    phi, bd = zoh(f, b, dt_s)
    qd = van_loan_qd(f, g @ qc @ g.T, dt_s)
    return DiscreteModel(phi=phi, bd=bd, qd=qd, dt_s=float(dt_s))
