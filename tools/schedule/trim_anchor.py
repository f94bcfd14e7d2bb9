"""Lab driver (not in the wheel): how far the scheduled trim a failed sensor's `complete`
hypothesis expects lies from what the failed sensor reads (the trim's uncertainty that
design/hypotheses.py's `constant` model takes as TRIM_SIGMA).

    python tools/schedule/trim_anchor.py --runs DIR [--sensor VEL|AOA|...] [--bank FILE]

Flies again the runs of an envelope campaign's records (DIR/runs.jsonl; their scenarios, bank
and estimator settings) whose case is the sensor's failure, and prints per run: the failed
reading's mean and sd after the failure (+0.2 s), the scheduled trim of that sensor when the
air data's running mean settles (frame 128) and at the end, the healthy reading's mean over
0.5 s to the failure, and the run's outcome; then the RMS of the settled trim's offset from the
failed reading (a `complete` failure reads the truth's trim plus noise: truth/sensors.py).
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from f16mmae import names
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.truth.sensors import NOISE_SIGMA

SETTLED_FRAME = 128   # 2 s at 64 Hz: the air data's running mean has settled


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", required=True, help="an envelope campaign's output folder")
    ap.add_argument("--sensor", default="VEL", choices=names.SENSORS)
    ap.add_argument("--bank", default=None, help="bank file (default: the records')")
    args = ap.parse_args()
    j = names.SENSORS.index(args.sensor)
    runs = [json.loads(line) for line in open(Path(args.runs) / "runs.jsonl")]
    offsets, points = [], {}
    for r in runs:
        if r["case"] != args.sensor:
            continue
        _, _, bank = load_bank(args.bank or r["bank"])
        est = Estimator(bank, **r["estimator"])
        rec = []
        fly(scenario_from_dict(r["scenario"]), bank, estimator=est,
            on_frame=lambda t, u, z, air: rec.append((t, z[j], est.core_bank.z_trim[j])))
        a = np.array(rec)
        t = a[:, 0]
        failed = a[t > r["failure_time_s"] + 0.2, 1]
        healthy = a[(t > 0.5) & (t < r["failure_time_s"]), 1]
        off = a[SETTLED_FRAME, 2] - failed.mean()
        offsets.append(off)
        points.setdefault(r.get("point", ""), []).append(off)
        print(f"{r.get('point', '')} seed {r['seed']}: failed reading {failed.mean():.5g} (sd {failed.std():.3g}), "
              f"scheduled trim {a[SETTLED_FRAME, 2]:.5g} at 2 s, {a[-1, 2]:.5g} at the end; healthy reading "
              f"0.5-{r['failure_time_s']:g} s {healthy.mean():.5g}; offset {off:+.3g}; {r['outcome']}")
    if not offsets:
        raise SystemExit(f"no {args.sensor} run in {args.runs}/runs.jsonl")
    for p, o in points.items():
        print(f"  {p}: RMS {np.sqrt(np.mean(np.square(o))):.3g} over {len(o)} runs")
    print(f"settled trim - failed reading ({args.sensor}): RMS {np.sqrt(np.mean(np.square(offsets))):.3g} over "
          f"{len(offsets)} runs, range {min(offsets):+.3g} to {max(offsets):+.3g}; sensor noise sigma {NOISE_SIGMA[j]:.3g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
