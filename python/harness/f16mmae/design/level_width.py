"""The range W_j of a failed sensor's unknown level under the ``cover`` failure model, derived
from the design model (the tuning's ``failed_sensor_level_width``, ``f16mmae design
--failed-sensor-level-width PIT=reading``).

A ``cover`` sensor hypothesis reads failed sensor j as an unknown level, uniform over W_j,
plus its noise (hypotheses.py): its first frame, and each re-entry from the probability floor
(cpp/f16mmae/filter_bank.h), carries the Occam constant

    c_j = ln(sqrt(2 pi A_jj) / W_j)   nats,

A_jj = R_jj the reading's noise variance in that hypothesis (its row of H is removed).
``"range"`` takes W_j as the sensor's full range (``truth.sensors.FULL_SCALE``), the default of
every sensor but the pitch gyro (``DEFAULT_WIDTHS``).  ``"reading"``, the pitch gyro's default,
derives it instead from where a failed reading is: a sensor failed complete, null or stuck reads its
trim, zero or the value it had at the onset, i.e. (in wings-level flight, for the rate gyros)
a value from the healthy reading's own distribution.  The design model gives that
distribution: the no-failure model (``Phi, B_d, Q_d, R``: the design's air and pseudonoise)
driven by its process and sensor noise and by the truth's default dither, open loop
(as ``design/distinguish.py``), has the stationary reading variance

    sigma_j^2 = (H P H')_jj + R_jj + mean_t y_j(t)^2,    P = Phi P Phi' + Q_d,

y(t) the dither's noise-free periodic response.  W_j is the width of the uniform density whose
entropy equals that of N(0, sigma_j^2),

    W_j = sqrt(2 pi e) sigma_j,   so   c_j = ln(sqrt(A_jj) / sigma_j) - 1/2,

i.e. the uniform level charges a reading at the first frame, on average, what a level drawn
from the healthy reading's Gaussian would (E[-ln N(z; 0, sigma^2)] = ln(sqrt(2 pi e) sigma)).
A hardover reading lies outside W_j; the core's uniform factor is a constant, so it pays c_j
as any other.  The open-loop model spreads a slow state (VEL's phugoid) far wider than the
closed loop does: the rule is meant for the sensors the short-period and roll modes drive.
Where the open-loop model has modes on or outside the unit circle (|lambda| >= 1: at high
dynamic pressure a divergence of about a second, Mach 0.8 at 5,000 ft, which the FCS holds in
closed loop), the stationary spread is taken over the stable modes alone: with Phi = V Lambda
V^-1 and W the rows of V^-1 of the stable modes S, V_S their columns,

    P_S[i, k] = (W Q_d W^H)[i, k] / (1 - lambda_i conj(lambda_k)),   P = Re(V_S P_S V_S^H),

and the dither's response is simulated in the same modes; a model with every mode stable
takes the Lyapunov solution above unchanged.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import solve_discrete_lyapunov

from .. import names
from ..truth import dither as dither_mod

#: The value of a ``failed_sensor_level_width`` entry that asks for the derived width.
READING = "reading"
#: The value that asks for the sensor's full range (truth.sensors.FULL_SCALE).
RANGE = "range"
#: The widths of a cover sensor the tuning does not name: the pitch gyro's derived (c_PIT of the
#: shipped tuning about -2.43 nats; its false stabilator duals are the least separated), the
#: others' full ranges (the rule declares AOA in failure-free flight and costs PIT runs when
#: given to the other sensors).
DEFAULT_WIDTHS = {"PIT": READING}


def effective_spec(spec: dict, covered: tuple[str, ...]) -> dict:
    """``spec`` (the tuning's table) with ``DEFAULT_WIDTHS`` for the ``covered`` sensors it does
    not name; ``RANGE`` entries dropped (the full range is the hypotheses' own width)."""
    out = {s: v for s, v in DEFAULT_WIDTHS.items() if s in covered and s not in spec}
    out.update(spec)
    return {s: out[s] for s in names.SENSORS if s in out and out[s] != RANGE}

#: Seconds of the dither's noise-free response simulated; the mean square is taken over the
#: second half (the first settles the transient).
DITHER_SECONDS = 20.0


def dither_response(phi: np.ndarray, bd: np.ndarray, h: np.ndarray, frame_rate_hz: float,
                    seconds: float = DITHER_SECONDS) -> np.ndarray:
    """(nz,) mean square of each reading's noise-free response to the truth's default dither
    over the second half of ``seconds`` (the open-loop model from rest; complex modal
    coordinates allowed, the reading is the real part)."""
    d = dither_mod.Dither()
    frames = int(round(seconds * frame_rate_hz))
    x = np.zeros(phi.shape[0], dtype=np.result_type(phi, bd))
    acc = np.zeros(h.shape[0])
    kept = 0
    for i in range(frames):
        if i >= frames // 2:
            y = (h @ x).real
            acc += y * y
            kept += 1
        x = phi @ x + bd[:, :names.NU] @ np.asarray(d.value(i / frame_rate_hz))
    return acc / kept


def reading_sigma(phi: np.ndarray, bd: np.ndarray, qd: np.ndarray, r: np.ndarray, h: np.ndarray,
                  frame_rate_hz: float) -> np.ndarray:
    """(nz,) sigma_j of the module docstring: the healthy readings' stationary standard deviation
    under the no-failure model, noise plus the dither, over its stable modes where some are
    not (the module docstring). ValueError when the model is not finite."""
    if not (np.all(np.isfinite(phi)) and np.all(np.isfinite(qd)) and np.all(np.isfinite(bd))):
        raise ValueError("the no-failure model is not finite: no stationary spread to derive a level width from")
    lam, v = np.linalg.eig(phi)
    if np.all(np.abs(lam) < 1.0):
        p = solve_discrete_lyapunov(phi, qd)
        var = np.diag(h @ p @ h.T) + np.diag(r) + dither_response(phi, bd, h, frame_rate_hz)
        return np.sqrt(var)
    stable = np.abs(lam) < 1.0
    w = np.linalg.inv(v)[stable]
    vs, ls = v[:, stable], lam[stable]
    ps = (w @ qd @ w.conj().T) / (1.0 - np.outer(ls, ls.conj()))
    p = (vs @ ps @ vs.conj().T).real
    var = np.diag(h @ p @ h.T) + np.diag(r) + dither_response(np.diag(ls), w @ bd, h @ vs, frame_rate_hz)
    return np.sqrt(var)


def width_from_sigma(sigma: float) -> float:
    """W = sqrt(2 pi e) sigma: the uniform of the Gaussian's entropy."""
    return math.sqrt(2.0 * math.pi * math.e) * float(sigma)


def occam_nats(width: float, a_jj: float) -> float:
    """c = ln(sqrt(2 pi A_jj) / W), the constant a level uniform over W carries."""
    return math.log(math.sqrt(2.0 * math.pi * a_jj) / width)


def level_widths(spec: dict, phi: np.ndarray, bd: np.ndarray, qd: np.ndarray, r: np.ndarray,
                 h: np.ndarray, frame_rate_hz: float) -> dict[str, dict[str, float]]:
    """Per sensor of ``spec`` (sensor -> W in its units, or ``READING``): ``{"width": W,
    "occam_nats": c_j}`` with A_jj = R_jj, and ``"sigma"`` for a derived one (the no-failure
    model's ``phi, bd, qd, r, h``). Empty for an empty spec."""
    if not spec:
        return {}
    sigma = (reading_sigma(phi, bd, qd, r, h, frame_rate_hz)
             if any(v == READING for v in spec.values()) else None)
    out = {}
    for sensor in names.SENSORS:
        if sensor not in spec:
            continue
        j = names.SENSORS.index(sensor)
        entry = {}
        if spec[sensor] == READING:
            entry["sigma"] = float(sigma[j])
            entry["width"] = width_from_sigma(sigma[j])
        else:
            entry["width"] = float(spec[sensor])
        entry["occam_nats"] = occam_nats(entry["width"], float(r[j, j]))
        out[sensor] = entry
    return out
