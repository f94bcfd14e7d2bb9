"""Summarise single-failure campaigns (``f16mmae campaign single --out DIR``) run by run, per
directory and mode: correct runs (the directory's NONE runs included) with 95 % Clopper-Pearson intervals, runs with a false
alarm, runs with a transient-wrong declaration, the complete-mode latency median / p95 over
the failure runs that declared the injected surface, and how many runs' final declaration was a
partial hypothesis (``declared_hypotheses``, the names before scoring).

Run: .venv/bin/python tools/cover/partial_summary.py DIR [DIR ...]
"""
from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np
from scipy.stats import beta


def interval(k: int, n: int) -> tuple[float, float]:
    lo = 0.0 if k == 0 else beta.ppf(0.025, k, n - k + 1)
    hi = 1.0 if k == n else beta.ppf(0.975, k + 1, n - k)
    return 100 * lo, 100 * hi


def main(dirs) -> None:
    for d in dirs:
        with open(f"{d}/runs.jsonl") as fh:
            summarise(d, [json.loads(line) for line in fh if line.strip()])


def summarise(d: str, runs: list[dict]) -> None:
    """One campaign directory: each mode's runs with the directory's NONE runs."""
    print(d)
    by_mode = defaultdict(list)
    for r in runs:
        fails = r["scenario"].get("failures") or []
        mode = fails[0].get("mode", "complete") if fails else None
        if fails and fails[0].get("value") is not None and mode == "loss":
            mode = f"loss={fails[0]['value']:g}"
        by_mode[mode].append(r)
    none_runs = by_mode.pop(None, [])
    for mode, rs in by_mode.items():
        rs = rs + none_runs
        n, k = len(rs), sum(r["outcome"] == "correct" for r in rs)
        fa = sum(bool(r["false_alarm"]) for r in rs)
        tw = sum(bool(r.get("transient_wrong")) for r in rs)
        lat = [r["latency_s"] for r in rs if r.get("latency_s") is not None]
        partial = sum(1 for r in rs if r.get("declared_hypotheses") and ":" in r["declared_hypotheses"][-1])
        lo, hi = interval(k, n)
        med = np.median(lat) if lat else float("nan")
        p95 = np.percentile(lat, 95) if lat else float("nan")
        wrong = [(r["case"], r["final_hypothesis"]) for r in rs if r["outcome"] != "correct"]
        print(f"{mode}: {k}/{n} [{lo:.1f}-{hi:.1f} %]; FA runs {fa}; TW runs {tw}; latency median {med:.2f} s, "
              f"p95 {p95:.2f} s ({len(lat)} runs); final declaration partial {partial}; not correct {wrong}")
    print(f"NONE runs: {sum(r['outcome'] == 'correct' for r in none_runs)}/{len(none_runs)}")


if __name__ == "__main__":
    main(sys.argv[1:])
