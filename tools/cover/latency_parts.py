"""What a single campaign's detection latencies are made of, per case, from its run records.

Each failure run's record holds the injected hypothesis' probability p(t) (sampled every
``p_injected_dt_s``) and its declarations.  For the runs that declare the injected hypothesis
(latency ``L`` after the onset ``t_f``), the latency splits into

  lift    from the onset to the first sample with p > ``--leave`` (default 1e-3): the time the
          hypothesis sits on its floor, i.e. before its evidence starts to outweigh the floor's
          ln(1/p_min) (a little more for a cover sensor hypothesis, whose floor is lowered by
          its Occam factor, filter_bank.h);
  climb   from there to the first sample with p > the threshold (0.9);
  hold    from there to the declaration: the dwell, plus every restart of it (p falling back
          below the threshold).

Printed per case: runs declared / runs, the medians of L, lift, climb and hold, and the runs
whose dwell restarted (hold more than one sample over the dwell).  ``--dwell-s`` and
``--threshold`` default to the records' estimator settings.

Run: .venv/bin/python tools/cover/latency_parts.py results/e1_cover/runs.jsonl [--mode complete]
"""
from __future__ import annotations

import argparse
import collections
import json

import numpy as np


def parts(record: dict, leave: float, threshold: float) -> tuple[float, float, float] | None:
    """(lift, climb, hold) in seconds, or None when the run has no latency."""
    lat = record.get("latency_s")
    if lat is None:
        return None
    t_f = float(record["failure_time_s"])
    p = np.asarray(record["p_injected"], dtype=float)
    dt = float(record["p_injected_dt_s"])
    t = np.arange(len(p)) * dt
    after = t >= t_f
    first_off = np.flatnonzero(after & (p > leave))
    first_top = np.flatnonzero(after & (p > threshold))
    if not len(first_off) or not len(first_top):
        return None
    t_off, t_top = t[first_off[0]], t[first_top[0]]
    return t_off - t_f, t_top - t_off, t_f + lat - t_top


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs")
    ap.add_argument("--mode", default="complete")
    ap.add_argument("--leave", type=float, default=1e-3)
    args = ap.parse_args(argv)
    by_case = collections.defaultdict(list)
    n_case = collections.Counter()
    settings = None
    with open(args.runs) as fh:
        for line in fh:
            r = json.loads(line)
            if r["case"] == "NONE":
                continue
            mode = r["failures"][0]["mode"]
            if mode != args.mode:
                continue
            settings = r["estimator_settings"]
            n_case[r["case"]] += 1
            got = parts(r, args.leave, float(settings["threshold"]))
            if got is not None:
                by_case[r["case"]].append((r["latency_s"],) + got)
    dwell = float(settings["dwell_s"])
    print(f"mode {args.mode}: dwell {dwell:g} s, threshold {settings['threshold']:g}; medians (s)")
    print("case  declared  latency  lift  climb  hold  dwell-restarted")
    everyone = []
    for case in sorted(n_case, key=lambda c: list(n_case).index(c)):
        rows = np.array(by_case[case]) if by_case[case] else np.zeros((0, 4))
        everyone.extend(by_case[case])
        if not len(rows):
            print(f"{case:5s} 0/{n_case[case]}")
            continue
        med = np.median(rows, axis=0)
        restarted = int(np.sum(rows[:, 3] > dwell + 0.04))
        print(f"{case:5s} {len(rows)}/{n_case[case]}  {med[0]:7.2f}  {med[1]:4.2f}  {med[2]:5.2f}  {med[3]:4.2f}  {restarted}")
    rows = np.array(everyone)
    med = np.median(rows, axis=0)
    print(f"all   {len(rows)}/{sum(n_case.values())}  {med[0]:7.2f}  {med[1]:4.2f}  {med[2]:5.2f}  {med[3]:4.2f}  "
          f"{int(np.sum(rows[:, 3] > dwell + 0.04))}")


if __name__ == "__main__":
    main()
