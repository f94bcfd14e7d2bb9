"""The maneuver trim's climb angle offline, against the truth, at a soak's pull-ups, pull-outs and
level-offs: the air data's gamma (two low-passes T and 5 T of the pressure altitude,
``maneuver_trim.h``) and the same plus ``ClimbAngleComplement``'s correction from AZ, AOA, ROL and YAW
(``--maneuver-trim-gamma-load-factor on``), both recomputed here open loop on the recorded air
data and z (no freeze rule: what the sensors give, not what a suspected failure would hold).

Flies each selected run of a soak's ``runs.jsonl`` again as recorded (its flight only) and prints
per path transition (the true gamma's 2-s mean through 0.5 deg: ``climb+`` a pull-up or push-over
into a climb or descent, ``climb-`` the level-off) the delay (s) that best aligns each estimate
with the true gamma over the 15 s from 2 s before the transition, the RMS error left at that
delay and the largest error (deg) without it; then the same over the whole flight.

Truth is read from the flight's log after the flight, for this diagnosis only.

Run: .venv/bin/python tools/maneuver/gamma_lag.py DIR/runs.jsonl [--runs 0,1] [--time-constant 0.5]
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import soak_runs  # noqa: E402
from transition_lag import truth_rates  # noqa: E402

from f16mmae.loop.flight import fly, scenario_from_dict  # noqa: E402
from f16mmae.names import FRAME_RATE_HZ, SENSORS  # noqa: E402

F = FRAME_RATE_HZ
DT = 1.0 / F
G = 32.174


def air_gamma(alt: np.ndarray, mach: np.ndarray, sound: float, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """maneuver_trim.h's observe(): (gamma, V = c lp_T(M), a = c M_dot) per frame."""
    gf, gs = 1 - math.exp(-1 / (F * t)), 1 - math.exp(-1 / (F * 5 * t))
    hf = hs = alt[0]
    mf = ms = mach[0]
    g, v, a = np.zeros(len(alt)), np.zeros(len(alt)), np.zeros(len(alt))
    for i in range(len(alt)):
        if i:
            hf += gf * (alt[i] - hf)
            hs += gs * (alt[i] - hs)
            mf += gf * (mach[i] - mf)
            ms += gs * (mach[i] - ms)
        v[i] = sound * mf
        g[i] = math.asin(max(-math.sin(0.5), min(math.sin(0.5), (hf - hs) / (4 * t) / v[i])))
        a[i] = sound * (mf - ms) / (4 * t)
    return g, v, a


def complement(z: np.ndarray, g_air: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, t_phi: float = 10.0) -> np.ndarray:
    """ClimbAngleComplement's recursion (maneuver_trim.h) without the freeze rule."""
    n_i, al_i, p_i, r_i = (SENSORS.index(s) for s in ("AZ", "AOA", "ROL", "YAW"))
    c1, c5 = 1 - math.exp(-1 / (F * t)), 1 - math.exp(-1 / (F * 5 * t))
    c_roll = 1 - math.exp(-1 / (F * t_phi))
    phi_ref = lambda vel, r: math.asin(max(-0.9, min(0.9, vel * r / G)))  # noqa: E731
    out = np.zeros(len(g_air))
    phi, f1, f5, gamma = phi_ref(v[0], z[0, r_i]), 0.0, 0.0, g_air[0]
    for i in range(len(g_air)):
        if i:
            phi += DT * z[i, p_i] + c_roll * (phi_ref(v[i], z[i, r_i]) - phi)
        al = z[i, al_i]
        n_w = z[i, n_i] * math.cos(al) + (math.sin(gamma + al) + a[i] / G) * math.sin(al)
        w = G / v[i] * (n_w * math.cos(phi) - math.cos(gamma))
        f1 += c1 * (w - f1)
        f5 += c5 * (w - f5)
        gamma = max(-0.5, min(0.5, g_air[i] + t * (25 * f5 - f1) / 4))
        out[i] = gamma
    return out


def best_lag(est: np.ndarray, ref: np.ndarray, lo: int, hi: int) -> tuple[float, float]:
    best = (math.inf, 0.0)
    lo = max(lo, 6 * int(F))
    for d in range(0, 6 * int(F) + 1, 4):
        best = min(best, (float(np.mean((est[lo:hi] - ref[lo - d:hi - d]) ** 2)), d / F))
    return best[1], math.sqrt(best[0])


def transitions(g_true: np.ndarray) -> list[tuple[int, str]]:
    k = np.ones(2 * int(F)) / (2 * F)
    on = np.abs(np.convolve(np.degrees(g_true), k, mode="same")) > 0.5
    ch = np.nonzero(on[1:] != on[:-1])[0]
    return [(int(i) + 1, "climb+" if on[i + 1] else "climb-") for i in ch]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    soak_runs.add_arguments(ap)
    ap.add_argument("--time-constant", type=float, default=0.5, help="T of the air data's low-passes (default 0.5)")
    args = ap.parse_args(argv)
    records, bank = soak_runs.selected(ap, args)
    sound = float(np.asarray(bank.z_trim)[SENSORS.index("VEL")]) / float(bank.mach)
    t = args.time_constant
    for r in records:
        s = fly(scenario_from_dict(r["scenario"]), bank, estimator_options=r["estimator"], record_series=True).series
        g_true, _ = truth_rates(s["truth_log"])
        air, z = np.asarray(s["air_data"]), np.asarray(s["z"])
        g_air, v, a = air_gamma(air[:, 1], air[:, 0], sound, t)
        ests = {"air data": g_air, "air data + AZ correction": complement(z, g_air, v, a, t)}
        print(f"run {r['run_index']}: transition at s, then per estimate: lag s / rms deg at it, max |err| deg")
        n = len(g_true)
        for i, tag in transitions(g_true):
            lo, hi = i - 2 * int(F), min(n, i + 13 * int(F))
            cells = []
            for name, e in ests.items():
                lag, rms = best_lag(e, g_true, lo, hi)
                cells.append(f"{name}: {lag:4.2f} / {math.degrees(rms):4.2f}, "
                             f"{math.degrees(np.max(np.abs(e[lo:hi] - g_true[lo:hi]))):4.2f}")
            print(f"  {tag:7s} {i / F:6.1f}  " + " | ".join(cells))
        for name, e in ests.items():
            lag, rms = best_lag(e, g_true, 0, n)
            print(f"  whole flight, {name}: lag {lag:4.2f} s, rms at it {math.degrees(rms):4.2f} deg, "
                  f"rms at 0 {math.degrees(np.sqrt(np.mean((e - g_true) ** 2))):4.2f} deg")


if __name__ == "__main__":
    main()
