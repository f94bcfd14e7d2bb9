"""The maneuver trim's acceleration estimators offline, against the truth, on a soak's flights:
the air data's Mach rate (two low-passes T and 5 T, ``maneuver_trim.h``), and the airspeed of z
(VEL / cos(AOA)) through the same pair or through ``AirspeedAccel``'s second-order
differentiator (natural frequency w0, damping zeta).

Flies each selected run of a soak's ``runs.jsonl`` again as recorded (its flight only; the
estimators here run on its recorded air data and z, open loop) and prints per estimator:
``spread``: the standard deviation of the estimate minus the truth's acceleration (1-s central
difference of the true airspeed, 2-s mean) over 265-295 s of the tour (level, unaccelerated);
``lag``: the delay (s) that best aligns the estimate with that truth over the deceleration
(345-380 s) and the acceleration (145-180 s), with the RMS error left at that delay; and the
error at 1, 3 and 5 s after the start of each speed change.

Truth is read from the flight's log after the flight, for this diagnosis only.

Run: .venv/bin/python tools/maneuver/accel_estimates.py DIR/runs.jsonl --runs 16,17
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import soak_runs  # noqa: E402

from f16mmae.loop.flight import fly, scenario_from_dict  # noqa: E402
from f16mmae.names import FRAME_RATE_HZ, SENSORS  # noqa: E402

F = FRAME_RATE_HZ
DT = 1.0 / F


def two_lowpass(x: np.ndarray, t: float) -> np.ndarray:
    """(lp_T(x) - lp_5T(x)) / (4 T), both starting at x[0]."""
    gf, gs = 1 - math.exp(-1 / (F * t)), 1 - math.exp(-1 / (F * 5 * t))
    out, lf, ls = np.zeros(len(x)), x[0], x[0]
    for i, v in enumerate(x):
        lf += gf * (v - lf)
        ls += gs * (v - ls)
        out[i] = (lf - ls) / (4 * t)
    return out


def differentiator(x: np.ndarray, w0: float, zeta: float = 1 / math.sqrt(2)) -> np.ndarray:
    """AirspeedAccel's recursion (maneuver_trim.h) without the freeze rule, a^ starting at 0."""
    v_hat, a_hat, out = x[0], 0.0, np.zeros(len(x))
    for i, v in enumerate(x):
        if i:
            e = v - v_hat
            v_hat += DT * (a_hat + 2 * zeta * w0 * e)
            a_hat += DT * w0 * w0 * e
        out[i] = a_hat
    return out


def best_lag(est: np.ndarray, ref: np.ndarray, lo: int, hi: int) -> tuple[float, float]:
    best = (math.inf, 0.0)
    for d in range(0, 6 * int(F) + 1, 4):
        best = min(best, (float(np.mean((est[lo:hi] - ref[lo - d:hi - d]) ** 2)), d / F))
    return best[1], math.sqrt(best[0])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    soak_runs.add_arguments(ap)
    args = ap.parse_args(argv)
    records, bank = soak_runs.selected(ap, args)
    sound = float(np.asarray(bank.z_trim)[SENSORS.index("VEL")]) / float(bank.mach)
    for r in records:
        s = fly(scenario_from_dict(r["scenario"]), bank, estimator_options=r["estimator"], record_series=True).series
        log = s["truth_log"]
        vt = log["state"][:, list(log["state_names"]).index("vt_fps")]
        n, w = len(vt), int(F) // 2
        idx = np.arange(n)
        lo, hi = np.clip(idx - w, 0, n - 1), np.clip(idx + w, 0, n - 1)
        truth = np.convolve((vt[hi] - vt[lo]) / ((hi - lo) / F), np.ones(2 * int(F)) / (2 * F), mode="same")
        air, z = np.asarray(s["air_data"]), np.asarray(s["z"])
        v_air = sound * air[:, 0]
        v_z = z[:, SENSORS.index("VEL")] / np.cos(z[:, SENSORS.index("AOA")])
        cands = {"air data, T 0.5 s (as flown)": two_lowpass(v_air, 0.5), "air data, T 0.3 s": two_lowpass(v_air, 0.3),
                 "VEL, T 0.25 s": two_lowpass(v_z, 0.25), "VEL, w0 1.0": differentiator(v_z, 1.0),
                 "VEL, w0 1.5": differentiator(v_z, 1.5), "VEL, w0 2.5": differentiator(v_z, 2.5)}
        t = np.arange(n) / F
        level = (t > 265) & (t < 295)
        print(f"run {r['run_index']}: estimator, spread (ft/s^2), decel lag s / rms, accel lag s / rms, "
              "error 1/3/5 s into the acceleration | the deceleration")
        for name, a in cands.items():
            dl, dr = best_lag(a, truth, int(345 * F), int(380 * F))
            al, ar = best_lag(a, truth, int(145 * F), int(180 * F))
            errs = " ".join(f"{a[int(x * F)] - truth[int(x * F)]:+.2f}" for x in (151, 153, 155))
            errs2 = " ".join(f"{a[int(x * F)] - truth[int(x * F)]:+.2f}" for x in (351, 353, 355))
            print(f"  {name:28s} {np.std(a[level] - truth[level]):5.2f}  {dl:4.2f} / {dr:4.2f}  {al:4.2f} / {ar:4.2f}"
                  f"  {errs} | {errs2}")


if __name__ == "__main__":
    main()
