"""Lab driver (not in the wheel): how the failure runs of envelope campaigns go wrong -- nothing
declared (missed) or another hypothesis declared (wrong) -- from the injected hypothesis'
probability the records keep (``p_injected``, every ``p_injected_dt_s``, stored to 5 decimals:
below 1e-5 it reads 0).

    python tools/schedule/miss_kind.py DIR [DIR ...] [--cases LS,RS,LF,RF,RUD] [--qbar-min 0] [--qbar-max inf]

Per campaign directory and case, over the failure runs at points with q̄ in [--qbar-min, --qbar-max):

  correct / missed / wrong   the campaign's outcomes, and the correct runs' median latency (s)
  missed: unseen             p_injected never reached 1e-5 after the failure: the floor was not
                             left (the evidence per frame, tempered, too small or negative)
  missed: rising             it rose to 1e-5 or more but not to a declaration within the window
                             (late: median time after the failure it first reached 1e-5, and
                             its median largest value)
"""
from __future__ import annotations

import argparse
import collections
import json
import math
from pathlib import Path

import numpy as np

from f16mmae.campaign.envelope.points import dynamic_pressure_psf

VISIBLE = 1e-5


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--cases", default="LS,RS,LF,RF,RUD")
    ap.add_argument("--qbar-min", type=float, default=0.0)
    ap.add_argument("--qbar-max", type=float, default=math.inf)
    args = ap.parse_args()
    cases = args.cases.split(",")
    for d in args.dirs:
        rows = collections.defaultdict(list)
        for line in Path(d, "runs.jsonl").read_text().splitlines():
            r = json.loads(line)
            sc = r["scenario"]
            if r["case"] in cases and args.qbar_min <= dynamic_pressure_psf(sc["mach"], sc["alt_ft"]) < args.qbar_max:
                rows[r["case"]].append(r)
        print(f"== {d} (q̄ {args.qbar_min:g} to {args.qbar_max:g})")
        for case in cases:
            rs = rows.get(case, [])
            if not rs:
                continue
            out = collections.Counter(r["outcome"] for r in rs)
            lat = [r["latency_s"] for r in rs if r["outcome"] == "correct" and r["latency_s"] is not None]
            unseen, seen_at, peak = 0, [], []
            for r in rs:
                if r["outcome"] != "missed":
                    continue
                dt = r["p_injected_dt_s"]
                after = r["p_injected"][int(round(r["failure_time_s"] / dt)):]
                hit = next((i for i, p in enumerate(after) if p >= VISIBLE), None)
                if hit is None:
                    unseen += 1
                else:
                    seen_at.append(hit * dt)
                    peak.append(max(after))
            med = (lambda v, f: format(float(np.median(v)), f) if v else "-")
            print(f"  {case:4s} correct {out['correct']:3d} (latency {med(lat, '.2f')} s)  wrong {out['wrong']:3d}  "
                  f"missed {out['missed']:3d}: unseen {unseen:3d}, rising {len(seen_at):3d} "
                  f"(1e-5 at {med(seen_at, '.1f')} s, peak {med(peak, '.2g')})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
