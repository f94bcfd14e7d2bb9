"""Lab driver (not in the wheel): how far the scheduled trim a failed VEL sensor's `complete`
hypothesis expects lies from what the failed sensor reads.

    python tools/schedule/vel_anchor.py --runs DIR [--hold-readings settled] [--bank FILE]

Flies again the VEL runs of an envelope campaign's records (DIR/runs.jsonl; their scenarios and
bank), the estimator built with the records' settings and ``hold_readings``, and prints per run:
the failed reading's mean and sd after the failure (+0.2 s), the scheduled VEL trim when the air
data's running mean settles (frame 128) and at the end, the healthy reading's mean over 0.5-3 s,
the bank's own VEL trim (the primary node's), and the run's outcome; then the RMS of the
settled trim's offset from the failed reading.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", required=True, help="an envelope campaign's output folder")
    ap.add_argument("--hold-readings", default="settled", choices=("off", "start", "settled"))
    ap.add_argument("--bank", default=None, help="bank file (default: the records')")
    args = ap.parse_args()
    runs = [json.loads(line) for line in open(Path(args.runs) / "runs.jsonl")]
    offsets = []
    for r in runs:
        if r["case"] != "VEL":
            continue
        _, _, bank = load_bank(args.bank or r["bank"])
        settings = {k: v for k, v in r["estimator"].items() if k != "hold_readings"}
        est = Estimator(bank, **settings, hold_readings=args.hold_readings)
        rec = []
        fly(scenario_from_dict(r["scenario"]), bank, estimator=est,
            on_frame=lambda t, u, z, air: rec.append((t, z[0], est.core_bank.z_trim[0])))
        a = np.array(rec)
        t = a[:, 0]
        failed = a[t > r["failure_time_s"] + 0.2, 1]
        healthy = a[(t > 0.5) & (t < r["failure_time_s"]), 1]
        offsets.append(a[128, 2] - failed.mean())
        print(f"seed {r['seed']}: failed reading {failed.mean():.2f} (sd {failed.std():.2f}), scheduled VEL trim "
              f"{a[128, 2]:.2f} at 2 s, {a[-1, 2]:.2f} at the end; healthy reading 0.5-{r['failure_time_s']:g} s "
              f"{healthy.mean():.2f}; bank VEL trim {bank.z_trim[0]:.2f}; {r['outcome']}")
    print(f"settled trim - failed reading: RMS {np.sqrt(np.mean(np.square(offsets))):.2f} ft/s over {len(offsets)} runs, "
          f"range {min(offsets):+.2f} to {max(offsets):+.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
