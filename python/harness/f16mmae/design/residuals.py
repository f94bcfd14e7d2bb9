"""Residuals of a steady-state filter on recorded (u, z) and their statistics (paper
Sec. III and VII: a matched filter's residuals are zero-mean, white, of covariance A_k).

Filter (perturbations from trim, x-_0 = 0)::

    r_i = z_i - H x-_i,   x+_i = x-_i + K r_i,   x-_{i+1} = Phi x+_i + B_d u_i

Statistics per scalar channel c: mean / sqrt(A_cc), var / A_cc, lag-1 autocorrelation
(whiteness; ~0 for white residuals, |rho| < 2/sqrt(N) at 95 %), and the normalized
innovation squared ``NIS_i = r_i^T A^{-1} r_i`` (chi-square with m = 7 degrees of freedom
when the filter is matched: mean 7).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def filter_residuals(phi: np.ndarray, bd: np.ndarray, h: np.ndarray, k: np.ndarray,
                     u: np.ndarray, z: np.ndarray) -> np.ndarray:
    """(n, m) residuals of the steady-state filter over a record (u (n, nu), z (n, m))."""
    x = np.zeros(phi.shape[0])
    out = np.empty((len(z), h.shape[0]))
    for i in range(len(z)):
        r = z[i] - h @ x
        out[i] = r
        x = phi @ (x + k @ r) + bd @ u[i]
    return out


@dataclass(frozen=True)
class ResidualStats:
    """Statistics of residuals pooled over flights (per channel arrays have length m)."""

    mean_over_sigma: np.ndarray
    var_over_a: np.ndarray
    lag1_autocorr: np.ndarray
    nis_mean: float
    nis_median: float
    frames: int

    def table(self, channel_names) -> str:
        lines = [f"{'':>8}" + "".join(f"{c:>9}" for c in channel_names)]
        for label, vals in (("mean/sA", self.mean_over_sigma), ("var/A", self.var_over_a),
                            ("rho(1)", self.lag1_autocorr)):
            lines.append(f"{label:>8}" + "".join(f"{v:9.3f}" for v in vals))
        lines.append(f"NIS mean {self.nis_mean:.2f} (matched: {len(channel_names)}), "
                     f"median {self.nis_median:.2f}, {self.frames} frames")
        return "\n".join(lines)


def residual_stats(residuals: list[np.ndarray], a: np.ndarray) -> ResidualStats:
    """Pool the residual records of several flights against one residual covariance A."""
    r = np.vstack(residuals)
    sd = np.sqrt(np.diag(a))
    nis = np.einsum("ij,ij->i", r, np.linalg.solve(a, r.T).T)
    rho = []
    for c in range(r.shape[1]):
        num = sum(float(np.dot(x[1:, c] - x[:, c].mean(), x[:-1, c] - x[:, c].mean())) for x in residuals)
        den = sum(float(np.dot(x[:, c] - x[:, c].mean(), x[:, c] - x[:, c].mean())) for x in residuals)
        rho.append(num / den if den > 0 else 0.0)
    return ResidualStats(mean_over_sigma=r.mean(axis=0) / sd, var_over_a=r.var(axis=0) / np.diag(a),
                         lag1_autocorr=np.array(rho), nis_mean=float(nis.mean()),
                         nis_median=float(np.median(nis)), frames=len(r))
