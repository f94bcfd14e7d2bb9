"""Lab driver (not in the wheel): how close the failure-free runs of an envelope campaign come to
a false alarm, bank by bank: the highest probability any failure hypothesis reaches after the
start-up in each NONE run, the runs flown again on each bank given with the records' estimator
settings and the threshold raised to 0.999 (no declaration: level 0 throughout, so every bank
is read on the same frames).

    python tools/schedule/none_peaks.py DIR/runs.jsonl BANK[,BANK...] [--start-s S]

BANK: a tuning name (scheduled, tuned) or a bank file. Per bank: the NONE runs whose peak
exceeds 0.9, 0.5, 0.3 and 0.1, the median peak, and the runs above 0.3 by hypothesis and point
with the times of their peaks.
The start-up (default 1 s, the records' start_up_s when they carry one) is left out: its frames
weigh no hypothesis."""
from __future__ import annotations

import argparse
import collections
import json
import sys

import numpy as np

from f16mmae.banks import BankError, load_bank
from f16mmae.loop.flight import fly, scenario_from_dict


def peaks(records: list[dict], bank, start_s: float | None) -> list[tuple[float, str, str, float]]:
    """(peak probability, its hypothesis, the run's point, its time in s) per NONE record, flown on ``bank``."""
    out = []
    for r in records:
        opts = dict(r.get("estimator") or {})
        opts["threshold"] = 0.999
        run = fly(scenario_from_dict(r["scenario"]), bank, estimator_options=opts)
        p = np.nan_to_num(np.asarray(run.probabilities, dtype=float))
        t0 = start_s if start_s is not None else float(opts.get("start_up_s", 1.0))
        after = np.asarray(run.time_s) > t0
        q, t = p[after].copy(), np.asarray(run.time_s)[after]
        q[:, run.hypotheses.index("NONE")] = 0.0
        i, k = np.unravel_index(int(np.argmax(q)), q.shape)
        out.append((float(q[i, k]), run.hypotheses[k], str(r.get("point")), float(t[i])))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", help="an envelope campaign's runs.jsonl")
    ap.add_argument("banks", help="comma-separated tuning names or bank files")
    ap.add_argument("--start-s", type=float, default=None, help="leave out frames up to this time, s")
    a = ap.parse_args(argv)
    try:
        records = [json.loads(line) for line in open(a.runs) if line.strip()]
    except (OSError, ValueError) as exc:
        ap.error(f"cannot read {a.runs}: {exc}")
    records = [r for r in records if r.get("case") == "NONE"]
    if not records:
        ap.error(f"{a.runs} holds no NONE run")
    for name in a.banks.split(","):
        try:
            _, _, bank = load_bank(name)
        except BankError as exc:
            ap.error(str(exc))
        got = peaks(records, bank, a.start_s)
        m = np.array([g[0] for g in got])
        above = collections.Counter((h, pt) for v, h, pt, _ in got if v > 0.3)
        times = sorted(round(ts, 2) for v, _, _, ts in got if v > 0.3)
        print(f"{name}: {len(m)} NONE runs; peak > 0.9: {(m > 0.9).sum()}, > 0.5: {(m > 0.5).sum()}, "
              f"> 0.3: {(m > 0.3).sum()}, > 0.1: {(m > 0.1).sum()}; median {np.median(m):.2e}")
        print("   above 0.3 (hypothesis, point): " + ", ".join(f"{h}@{pt} {n}" for (h, pt), n in sorted(above.items()))
              + (f"; at {times[0]:.2f}-{times[-1]:.2f} s, median {np.median(times):.2f} s" if times else ""))
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
