"""``f16mmae campaign dual``: the dual-failure Monte Carlo campaign (paper Sec. VI, Fig. 7)."""
from __future__ import annotations

import argparse

from ..campaign.dual import DualCampaign, run_campaign
from ..names import COMPONENTS, FAILURE_TIME_S
from . import evidence
from .campaign_common import (add_failure_jitter, add_flight_settings, add_run_arguments, failure_jitter, flight_settings,
                              run_and_report, validated)
from .options import CliError, flight_seconds, parse_choices

DESCRIPTION = """\
The dual-failure campaign (paper Sec. VI, Fig. 7): every ordered pair (first, second) of
the twelve single failures (LS RS LF RF RUD VEL AOA PIT AZ ROL YAW AY), 132 pairs, N
seeded runs each.  The first failure occurs at 3.0 s, the second at --second-time-s
(default 5.0 s, "two or more seconds later"), in a 10-s flight at the bank's design point
with the hierarchical MMAE in the loop: level 0 should declare the first failure, then the
level-1 bank of that failure (NONE, it, and its 11 duals) the dual.  As the baseline the
campaign also flies each second failure alone at the same time with the same seeds, and
rates each pair against it:

  Good  correct >= baseline's - 10 points, median latency after the second failure
        <= baseline's + 0.5 s, and the dual held (stays declared) >= baseline's - 10 points
  Fair  not Good, but some run correct and (correct >= 50 % or >= baseline's - 10 points)
  Poor  no better, but the dual was declared in some run or its probability reached 0.5
  ND    the dual never declared and its probability never reached 0.5

(correct: the run ends declaring the dual; latency: its first declaration after the
second failure; hold: the fraction of the flight after that during which it stays
declared.  Thresholds: f16mmae.campaign.dual.scoring.RATING_RULES.)
"""

EXAMPLES = """\
examples:
  f16mmae campaign dual                                # 132 pairs x 3 runs + 12 baselines
  f16mmae campaign dual --runs 10 --workers 2
  f16mmae campaign dual --pairs LS+PIT,AOA+RUD --runs 5    # FIRST+SECOND, ordered
  f16mmae campaign dual --first LS,RS --second LF,RF       # the stabilator/flaperon block
  f16mmae campaign dual --tuning untuned --turbulence moderate --out results/dual-untuned

Output (DIR, default results/campaign-dual):
  runs.jsonl              one record per run (seed, scenario, bank hash, version,
                          declarations, outcome, latency, hold, probability histories of
                          the dual and of the first failure), appended as runs finish
  summary.json            per pair: runs, correct, missed, wrong, false alarms, latency
                          median/p95, hold, rating (+ reason); per second failure: its
                          baseline; the rating matrix and its agreement with the paper's
  dual_matrix.png         the Fig. 7 matrix (correct k/N and median latency per cell)
                          beside the paper's Fig. 7
  dual_probabilities.png  12 x 12 small multiples of the mean probability of each dual
  report.html             one page: parameters, figures, definitions, tables
Resume: run the same command again -- runs already in DIR/runs.jsonl are skipped.
Seeds: run n of every pair with second failure B, and of B's baseline, is seeded from
(--seed, B, n) -- common random numbers between a pair and its baseline.
"""


def register(kinds) -> None:
    """Add the ``dual`` parser to the ``campaign`` kinds."""
    p = kinds.add_parser("dual", help="every ordered pair of failures, N runs each (paper Fig. 7)",
                         description=DESCRIPTION, epilog=EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    add_flight_settings(p, "3", "seeded runs per pair and per baseline (default 3)")
    p.add_argument("--pairs", default=None, metavar="LIST",
                   help="comma-separated ordered pairs FIRST+SECOND, e.g. LS+PIT,AOA+RUD "
                        "(default: all 132)")
    p.add_argument("--first", default=None, metavar="LIST",
                   help="first failures (default all twelve); with --second: their cross product")
    p.add_argument("--second", default=None, metavar="LIST", help="second failures (default all twelve)")
    p.add_argument("--first-time-s", default=str(FAILURE_TIME_S), metavar="T",
                   help=f"first failure time (default {FAILURE_TIME_S} s)")
    p.add_argument("--second-time-s", default="5.0", metavar="T", help="second failure time (default 5.0 s)")
    p.add_argument("--duration-s", default="10", metavar="T", help="flight duration (default 10 s)")
    add_failure_jitter(p, "each run's two failures, the same shift for both and for the pair's baseline,")
    add_run_arguments(p, "results/campaign-dual")
    p.set_defaults(func=_dual)


def _names(option: str, text: str | None) -> tuple[str, ...]:
    return parse_choices(option, text, COMPONENTS, "failure")


def parse_pairs(pairs: str | None, first: str | None, second: str | None) -> tuple[tuple[str, str], ...]:
    """The ordered pairs from --pairs, or the cross product of --first x --second (a != b)."""
    if pairs is not None:
        if first is not None or second is not None:
            raise CliError("give --pairs or --first/--second, not both")
        out = []
        for item in (x.strip() for x in pairs.split(",") if x.strip()):
            parts = [x.strip().upper() for x in item.split("+")]
            if len(parts) != 2 or any(x not in COMPONENTS for x in parts):
                raise CliError(f"--pairs: {item!r} is not FIRST+SECOND with both of {','.join(COMPONENTS)} "
                               f"(e.g. LS+PIT)")
            if parts[0] == parts[1]:
                raise CliError(f"--pairs: {item!r} fails {parts[0]} twice; a dual needs two different failures")
            out.append((parts[0], parts[1]))
        if not out:
            raise CliError(f"--pairs {pairs!r} names no pair; e.g. --pairs LS+PIT,AOA+RUD")
        if len(set(out)) != len(out):
            raise CliError(f"--pairs {pairs!r} lists a pair twice")
        return tuple(out)
    firsts, seconds = _names("--first", first), _names("--second", second)
    out = tuple((a, b) for a in firsts for b in seconds if a != b)
    if not out:
        raise CliError(f"--first {first} x --second {second} leaves no pair of two different failures")
    return out


def config_from_args(args) -> DualCampaign:
    """A validated ``DualCampaign`` from the parsed arguments (CliError otherwise)."""
    duration = flight_seconds("--duration-s", args.duration_s)
    cfg = DualCampaign(
        **flight_settings(args), pairs=parse_pairs(args.pairs, args.first, args.second),
        first_time_s=flight_seconds("--first-time-s", args.first_time_s),
        second_time_s=flight_seconds("--second-time-s", args.second_time_s),
        duration_s=duration,
        failure_jitter_s=failure_jitter(args, duration),
    )
    return validated(cfg)


def _dual(args) -> int:
    return run_and_report(args, config_from_args(args), run_campaign, print_summary)


_SHORT = {"Good": "G", "Fair": "F", "Poor": "P", "ND": "ND"}


def print_summary(summary: dict, stream) -> None:
    """The rating matrix as text (rows: first failure, columns: second) and the counts."""
    t = summary.get("timing", {})
    print(f"dual-failure campaign: {summary['runs_per_pair']} runs/pair, seed {summary['seed']}, "
          f"{summary['tuning']} bank, {summary['turbulence']} turbulence, failures at "
          f"{summary['first_time_s']:g} s and {summary['second_time_s']:g} s of {summary['duration_s']:g} s; "
          f"wall {t.get('wall_s', 0):.1f} s", file=stream)
    print("\nrating against the baseline (rows: first failure, columns: second; G Good, F Fair, P Poor, "
          "ND no detection, . not flown); * absolutely Good (>= 90% correct, no false alarm, no "
          "transient-wrong, median latency <= 1.5 s):", file=stream)
    m = summary["matrix"]
    absolute = {(p["first"], p["second"]) for p in summary["pairs"] if p.get("absolute_rating") == "Good"}
    print("first\\2nd " + "".join(f"{b:>4}" for b in COMPONENTS), file=stream)
    for a in COMPONENTS:
        cells = []
        for b in COMPONENTS:
            mark = _SHORT.get(m.get(a, {}).get(b), ".") + ("*" if (a, b) in absolute else "")
            cells.append("  --" if a == b else f"{mark:>4}")
        print(f"{a:<9} " + "".join(cells), file=stream)
    counts = summary["ratings"]
    print("\n" + ", ".join(f"{k}: {v}" for k, v in counts.items()) + f" (of {sum(counts.values())} pairs)",
          file=stream)
    print("absolute: " + ", ".join(f"{k}: {v}" for k, v in summary["absolute_ratings"].items()), file=stream)
    print("\nbaselines, each second failure alone (95% Clopper-Pearson intervals; TW transient-wrong, "
          "FA false-alarm runs; detection fractions count misses):", file=stream)
    evidence.print_cases(summary["baselines"], stream, label="failure")
    worse = [p for p in summary["pairs"] if p["rating"] != "Good" or p.get("absolute_rating") != "Good"]
    if worse:
        print(f"\npairs not Good on either rating ({len(worse)}):", file=stream)
        evidence.print_cases(worse, stream, label="pair")
    c = summary.get("paper_comparison", {})
    if c.get("cells"):
        print(f"paper Fig. 7: same rating in {c['equal']} of {c['cells']} comparable cells, "
              f"same Good/not-Good in {c['good_vs_not_good_equal']}", file=stream)
