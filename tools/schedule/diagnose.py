"""Lab driver (not in the wheel): why each unacceptable point of a ``spacing.py`` run fails.

    python tools/schedule/diagnose.py results/t.json [more.json ...]

Per unacceptable point (q̄ from the standard atmosphere): the false-alarm runs (the hypothesis
declared first and when, seconds into the flight) and the failure cases missed or wrongly
isolated (case: missed / wrong runs); then, per dynamic-pressure band, the share of failure
runs correct per case, and the false-alarm runs by the hypothesis declared.
"""
from __future__ import annotations

import argparse
import collections
import json

from f16mmae.campaign.envelope.points import dynamic_pressure_psf
from f16mmae.names import COMPONENTS, NONE

BANDS = ((0, 100), (100, 200), (200, 300), (300, 1000))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    args = ap.parse_args()
    for path in args.runs:
        d = json.loads(open(path).read())
        print(f"== {path}: acceptable {sum(r['acceptable'] for r in d['rows'])}/{len(d['rows'])}")
        by_point = collections.defaultdict(list)
        for r in d["records"]:
            by_point[(r["mach"], r["alt_ft"])].append(r)
        for row in d["rows"]:
            if row["acceptable"]:
                continue
            rs = by_point[(row["mach"], row["alt_ft"])]
            fa = [f"{r['declared'][0]}@{r['declared_at_s'][0]:.1f}" if r.get("declared_at_s") else r["declared"][0]
                  for r in rs if r["false_alarm"]]
            bad = collections.Counter((r["case"], r["outcome"]) for r in rs if r["case"] != NONE and r["outcome"] != "correct")
            print(f"  Mach {row['mach']:.3f} {row['alt_ft']:6.0f} ft q {dynamic_pressure_psf(row['mach'], row['alt_ft']):4.0f}: "
                  f"correct {row['correct']:.0%}, FA runs {row['false_alarm_runs']} [{' '.join(fa)}]; "
                  + " ".join(f"{c}:{o[:4]}x{n}" for (c, o), n in sorted(bad.items())))
        for lo, hi in BANDS:
            rs = [r for r in d["records"] if lo <= dynamic_pressure_psf(r["mach"], r["alt_ft"]) < hi]
            if not rs:
                continue
            pts = {(r["mach"], r["alt_ft"]) for r in rs}
            ok = {(row["mach"], row["alt_ft"]) for row in d["rows"] if row["acceptable"]}
            per_case = " ".join(f"{c} {sum(r['outcome'] == 'correct' for r in rs if r['case'] == c)}/"
                                f"{sum(r['case'] == c for r in rs)}" for c in COMPONENTS)
            fa = collections.Counter(r["declared"][0] for r in rs if r["false_alarm"] and r["declared"])
            print(f"  q {lo}-{hi}: {len(pts & ok)}/{len(pts)} acceptable; {per_case}; FA runs "
                  f"{sum(r['false_alarm'] for r in rs)} {dict(fa)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
