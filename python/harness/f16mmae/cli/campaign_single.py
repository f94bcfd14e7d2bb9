"""``f16mmae campaign single``: the single-failure Monte Carlo campaign (paper Sec. V)."""
from __future__ import annotations

import argparse

from ..campaign.single import SingleCampaign, run_campaign
from . import evidence
from .campaign_common import (add_failure_instant, add_flight_settings, add_run_arguments, check_tuning,
                              failure_instant, flight_settings, parse_cases, run_and_report, validated)

DESCRIPTION = """\
The single-failure campaign (paper Sec. V): every single failure (LS RS LF RF RUD VEL
AOA PIT AZ ROL YAW AY) and the no-failure case NONE, N seeded runs each, the failure at
3.0 s of an 8-s flight at the bank's design point (--failure-time S: at S s, the flight
5 s longer), the MMAE in the loop.  Scored per case
for correct isolation, missed and wrong isolation, false alarms and detection latency;
figures like the paper's Figs. 3-6 (tuned bank beside the untuned baseline).
"""

EXAMPLES = """\
examples:
  f16mmae campaign single                          # 13 cases x 10 runs, tuned + untuned banks
  f16mmae campaign single --runs 3 --cases LS,PIT,NONE --baseline none
  f16mmae campaign single --tuning untuned --baseline none --turbulence moderate
  f16mmae campaign single --runs 5 --baseline none --turbulence none,light,moderate,severe
  f16mmae campaign single --runs 5 --baseline none --mode complete,stuck,hardover,null,loss=0.5
  f16mmae campaign single --baseline none --turbulence severe --failure-time 20
                                                   # the estimator 20 s in the air first
  f16mmae campaign single --baseline none --failure-jitter 1
                                                   # failures spread over 3-4 s: every dither phase
  f16mmae campaign single --workers 1              # in this process (profiling)
  f16mmae campaign single --scheduler tcp://10.0.0.5:8786   # on a Dask cluster

Output (DIR, default results/campaign-single):
  runs.jsonl      one record per run (seed, scenario, bank hash, version, declarations,
                  outcome, latency), appended as runs finish
  summary.json    per case: runs, correct, missed, wrong, false_alarms, latency_s median/p95
  probability_strips.png, latency.png, report.html
With a list of turbulence levels or modes: each variant's summary, figures and report in
DIR/<variant>/ (e.g. DIR/moderate, DIR/loss=0.5), DIR/summary.json and DIR/report.html put
them side by side, variants.png draws them. A mode flies only the cases whose component it
applies to (actuators: complete stuck hardover loss; sensors: complete null stuck hardover
bias drift); the others are listed as skipped. Run n of a case flies the same seed in every
variant.
Resume: run the same command again -- runs already in DIR/runs.jsonl are skipped.

Per-run seeds are derived from (--seed, case, run index), so the same arguments give the
same results on any executor.  Scoring definitions: see report.html or the README.
"""


def register(kinds) -> None:
    """Add the ``single`` parser to the ``campaign`` kinds."""
    s = kinds.add_parser(
        "single",
        help="every single failure and NONE, N runs each (paper Figs. 3-6)",
        description=DESCRIPTION,
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_flight_settings(s, "10", "seeded runs per case (default 10, as the paper)")
    s.add_argument("--cases", default=None, metavar="LIST",
                   help="comma-separated cases (default: NONE and all twelve failures)")
    s.add_argument("--baseline", default="untuned", metavar="untuned|tuned|FILE|none",
                   help="a second bank flown on the same seeds for the side-by-side "
                        "figure (default untuned; 'none' to skip)")
    add_failure_instant(s)
    add_run_arguments(s, "results/campaign-single")
    s.set_defaults(func=_single)


def config_from_args(args) -> SingleCampaign:
    """A validated ``SingleCampaign`` from the parsed arguments (CliError otherwise)."""
    baseline = None if args.baseline.lower() == "none" else args.baseline
    cfg = SingleCampaign(**flight_settings(args), **failure_instant(args), cases=parse_cases(args.cases),
                         baseline=baseline)
    if cfg.baseline is not None:
        check_tuning("--baseline", cfg.baseline)
    return validated(cfg)


def _single(args) -> int:
    return run_and_report(args, config_from_args(args), run_campaign, print_summary)


def print_summary(summary: dict, stream) -> None:
    t = summary.get("timing", {})
    print(f"single-failure campaign: {summary['runs_per_case']} runs/case, seed {summary['seed']}, "
          f"{summary['turbulence']} turbulence, Mach {summary['mach']}, {summary['alt_ft']:.0f} ft, "
          f"feedback {summary['feedback']}; wall {t.get('wall_s', 0):.1f} s", file=stream)
    blocks = [(summary["tuning"], summary["cases"])]
    if summary.get("baseline"):
        blocks.append((summary["baseline"]["tuning"], summary["baseline"]["cases"]))
    for tuning, cases in blocks:
        print(f"\n{tuning} bank (95% Clopper-Pearson intervals; v: verdict on >= 99% correct; TW: "
              f"transient-wrong runs; FA: runs with a false alarm; detection fractions count misses):",
              file=stream)
        evidence.print_cases(cases, stream)
    met = summary.get("goals", {}).get("met")
    if met is not None:
        print(f"\ngoals on the point estimates (>= 99% correct, 0 false alarms, latency median <= 1 s, "
              f"p95 <= 2 s): {'all met' if met else 'NOT all met'} for the {summary['tuning']} bank", file=stream)
