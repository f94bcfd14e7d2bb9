"""Whether the no-failure filter's AOA and AZ predictions are biased between schedule nodes:
NONE's own residuals binned by how far the schedule in force is from a node.

Re-flies every run of a soak's ``runs.jsonl`` (``transition_lag.py``'s flight, bit for bit)
and replays the estimator with the record's settings, recording per frame the NONE filter's
residuals z - H x of AOA and AZ in units of their RMS over the flight, and the largest
interpolation weight in force (``schedule_state["weights"]``: 1 at a node, 1/2 half-way
between two nodes, 1/4 at a cell's centre). Frames are binned by that weight, and split into
wings level (true |phi| < 5 deg) with the air data's climb rate under 300 ft/min ("steady") and
the rest ("maneuvering"); per bin: frames, mean AOA and AZ residual (RMS units) and the mean
of their product's sign pattern, the fraction of frames with AOA below and AZ above
prediction by 0.5 RMS or more ("AOA-/AZ+", the pattern of the soak's VEL and AOA
declarations).

Truth (the bank angle) is read from the flight's log after the flight, for this diagnosis only.

    .venv/bin/python tools/maneuver/node_bias.py DIR/runs.jsonl [--runs 1,4] [--extra '{"k": v}']
"""
from __future__ import annotations

import argparse
import json
import math

import numpy as np

from f16mmae.names import FRAME_RATE_HZ, SENSORS

import soak_runs  # tools/maneuver: the soak's runs flown again

BINS = ((0.95, 1.01, "at a node (w >= 0.95)"), (0.75, 0.95, "0.75 <= w < 0.95"),
        (0.5, 0.75, "0.5 <= w < 0.75"), (0.0, 0.5, "w < 0.5 (cell interior)"))


def replay(record: dict, bank, extra: dict | None) -> dict:
    """Per frame: NONE's AOA and AZ residuals (RMS units), the largest weight, steady or not."""
    ia, iz = SENSORS.index("AOA"), SENSORS.index("AZ")
    res, wmax, alt = [], [], []

    def observe(i, est, z_hat, series):
        r = soak_runs.none_residuals(est)
        res.append((r[ia], r[iz]) if r is not None else (np.nan, np.nan))
        st = est.core_bank.schedule_state
        wmax.append(max(st["weights"]) if len(st["weights"]) else 1.0)

    s = soak_runs.fly_and_replay(record, bank, extra, after_update=observe).series
    n = len(s["z"])
    res, wmax = np.array(res, float).reshape(-1, 2), np.array(wmax)
    alt = np.array([a[1] for a in s["air_data"][:n]], float)
    res /= np.sqrt(np.nanmean(res ** 2, axis=0))
    log = s["truth_log"]
    phi = np.degrees(log["state"][:n, list(log["state_names"]).index("phi_rad")])
    k = int(FRAME_RATE_HZ)
    climb = np.zeros(n)
    climb[k:] = (alt[k:] - alt[:-k]) * 60.0          # ft/min over the last second
    steady = (np.abs(phi) < 5.0) & (np.abs(climb) < 300.0)
    return {"res": res, "w": wmax, "steady": steady}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    soak_runs.add_arguments(ap)
    ap.add_argument("--extra", type=json.loads, default=None, help="estimator settings to override (JSON)")
    args = ap.parse_args(argv)
    records, bank = soak_runs.selected(ap, args)
    parts = [replay(r, bank, args.extra) for r in records]
    res = np.concatenate([p["res"] for p in parts])
    w = np.concatenate([p["w"] for p in parts])
    steady = np.concatenate([p["steady"] for p in parts])
    ok = np.all(np.isfinite(res), axis=1)
    print(f"{len(records)} flights, {len(w)} frames; NONE's residuals in units of their flight RMS")
    print(f"{'bin':<26} {'part':<12} {'frames':>7} {'AOA mean':>9} {'AZ mean':>8} {'AOA-/AZ+':>9}")
    for lo, hi, label in BINS:
        for part, mask in (("steady", steady), ("maneuvering", ~steady)):
            m = ok & mask & (w >= lo) & (w < hi)
            if not m.any():
                print(f"{label:<26} {part:<12} {0:7d}")
                continue
            a, z = res[m, 0], res[m, 1]
            pattern = float(np.mean((a <= -0.5) & (z >= 0.5)))
            print(f"{label:<26} {part:<12} {int(m.sum()):7d} {a.mean():+9.3f} {z.mean():+8.3f} {pattern:9.3f}")


if __name__ == "__main__":
    main()
