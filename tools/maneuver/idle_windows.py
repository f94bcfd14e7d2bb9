"""Where a soak's false declarations fall against the throttle at idle.

Re-flies every run of a soak's ``runs.jsonl`` (its scenario, bank and estimator settings; the
same flight) and finds the frames whose commanded throttle (the sixth input u_THR the estimator
sees, the outer loop's lever plus the dither, clipped to [0, 1]) is below ``--idle`` (default
0.025: the lever at 0, the dither's positive half only). Prints per flight the idle span (first
to last idle frame) and counts the false declarations before it, inside it, in the ``--after``
seconds after it (default 60: the spool-up and the return to trim) and later.

Run: .venv/bin/python tools/maneuver/idle_windows.py results/DIR/runs.jsonl
"""
from __future__ import annotations

import argparse
import json

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import NONE


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs")
    ap.add_argument("--idle", type=float, default=0.025)
    ap.add_argument("--after", type=float, default=60.0)
    args = ap.parse_args(argv)
    total = np.zeros(4, int)
    for line in open(args.runs):
        r = json.loads(line)
        bank = load_bank(r["bank"])[2]
        fl = fly(scenario_from_dict(r["scenario"]), bank, estimator_options=r["estimator"], record_series=True)
        idle = np.flatnonzero(fl.series["u"][:, -1] < args.idle)
        t = fl.time_s
        lo, hi = (t[idle[0]], t[idle[-1]]) if len(idle) else (np.inf, np.inf)
        times = [d["time_s"] for d in r["declarations"] if d["hypothesis"] != NONE]
        n = np.array([sum(x < lo for x in times), sum(lo <= x <= hi for x in times),
                      sum(hi < x <= hi + args.after for x in times), sum(x > hi + args.after for x in times)])
        total += n
        print(f"seed {r['seed']}: idle {lo:.1f}-{hi:.1f} s; false declarations before {n[0]}, at idle {n[1]}, "
              f"within {args.after:g} s after {n[2]}, later {n[3]}")
    print(f"all: before {total[0]}, at idle {total[1]}, within {args.after:g} s after {total[2]}, later {total[3]}")


if __name__ == "__main__":
    main()
