"""The absolute ratings of stored dual campaigns with their false alarms scored again by the
current rule (campaign/dual/scoring.py ``false_alarm_before_second``), from each run's stored
declarations: how many pairs a change of that rule moves, without flying again.  The other
fields of each pair (correct, transient-wrong, latency) are the stored ones.

    .venv/bin/python tools/dual/rescore_false_alarms.py DIR [DIR ...]
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from f16mmae.campaign.dual.scoring import false_alarm_before_second
from f16mmae.campaign.engine import outcomes


def rescored(d: Path) -> tuple[dict, int, list[str]]:
    """(summary, absolutely Good pairs under the current rule, the pairs whose rating moved)."""
    summary = json.loads((d / "summary.json").read_text())
    records = [json.loads(line) for line in (d / "runs.jsonl").read_text().splitlines() if line.strip()]
    good, moved = 0, []
    for p in summary["pairs"]:
        runs = [r for r in records if r["kind"] == "dual" and r["first"] == p["first"] and r["second"] == p["second"]]
        alarms = sum(false_alarm_before_second(r["declarations"], r["first"], r["second_time_s"]) for r in runs)
        rating, _ = outcomes.rate_absolute(p["runs"], p["correct"], alarms,
                                           p["evidence"]["rates"]["transient_wrong"]["count"], p["latency_s"]["median"])
        good += rating == "Good"
        if rating != p.get("absolute_rating"):
            moved.append(f"{p['first']}>{p['second']}: {p.get('absolute_rating')} -> {rating}")
    return summary, good, moved


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+", type=Path, help="dual campaign directories (summary.json, runs.jsonl)")
    for d in ap.parse_args().dirs:
        summary, good, moved = rescored(d)
        print(f"{d}: seed {summary['seed']}, {summary['runs_per_pair']} runs a pair, absolutely Good "
              f"{summary['absolute_ratings']['Good']} stored -> {good} now" + "".join(f"\n  {m}" for m in moved))


if __name__ == "__main__":
    main()
