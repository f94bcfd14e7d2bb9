"""``f16mmae campaign single``: the single-failure Monte Carlo campaign (paper Sec. V)."""
from __future__ import annotations

import argparse
import sys

from ..cli import CliError, choice, number

DESCRIPTION = """\
Monte Carlo campaigns of closed-loop flights of the nonlinear JSBSim F-16 with the MMAE
estimator in the loop.

  single   every single failure (LS RS LF RF RUD VEL AOA PIT AZ ROL YAW AY) and the
           no-failure case NONE, N seeded runs each, the failure at 3.0 s of an 8-s
           flight, scored for isolation, missed/false alarms and detection latency
           (the paper's Figs. 3-6).
  dual     every ordered pair of failures (first at 3.0 s, second at 5.0 s), N runs
           each, rated Good / Fair / Poor / ND against the lone second failure
           (the paper's Fig. 7).
  envelope the nominal design flown at flight conditions around its design point: the
           single-failure campaign at each point (the paper's Fig. 9).
"""

SINGLE_DESCRIPTION = """\
The single-failure campaign (paper Sec. V): every single failure (LS RS LF RF RUD VEL
AOA PIT AZ ROL YAW AY) and the no-failure case NONE, N seeded runs each, the failure at
3.0 s of an 8-s flight at the bank's design point, the MMAE in the loop.  Scored per case
for correct isolation, missed and wrong isolation, false alarms and detection latency;
figures like the paper's Figs. 3-6 (tuned bank beside the untuned baseline).
"""

SINGLE_EXAMPLES = """\
examples:
  f16mmae campaign single                          # 13 cases x 10 runs, tuned + untuned banks
  f16mmae campaign single --runs 3 --cases LS,PIT,NONE --baseline none
  f16mmae campaign single --tuning untuned --baseline none --turbulence moderate
  f16mmae campaign single --workers 1              # in this process (profiling)
  f16mmae campaign single --scheduler tcp://10.0.0.5:8786   # on a Dask cluster

Output (DIR, default results/campaign-single):
  runs.jsonl      one record per run (seed, scenario, bank hash, version, declarations,
                  outcome, latency), appended as runs finish
  summary.json    per case: runs, correct, missed, wrong, false_alarms, latency_s median/p95
  probability_strips.png, latency.png, report.html
Resume: run the same command again -- runs already in DIR/runs.jsonl are skipped.

Per-run seeds are derived from (--seed, case, run index), so the same arguments give the
same results on any executor.  Scoring definitions: see report.html or the README.
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "campaign",
        help="Monte Carlo campaigns (single, dual, envelope)",
        description=DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    kinds = p.add_subparsers(dest="kind", metavar="KIND")
    s = kinds.add_parser(
        "single",
        help="every single failure and NONE, N runs each (paper Figs. 3-6)",
        description=SINGLE_DESCRIPTION,
        epilog=SINGLE_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    s.add_argument("--runs", default="10", metavar="N", help="seeded runs per case (default 10, as the paper)")
    s.add_argument("--seed", default="1", metavar="S", help="campaign seed >= 1 (default 1)")
    s.add_argument("--cases", default=None, metavar="LIST",
                   help="comma-separated cases (default: NONE and all twelve failures)")
    s.add_argument("--tuning", default="tuned", metavar="tuned|untuned|FILE",
                   help="the bank under test: a shipped tuning or a bank file (default tuned)")
    s.add_argument("--baseline", default="untuned", metavar="untuned|tuned|FILE|none",
                   help="a second bank flown on the same seeds for the side-by-side "
                        "figure (default untuned; 'none' to skip)")
    s.add_argument("--turbulence", default="light", metavar="LEVEL",
                   help="none | light | moderate | severe (default light)")
    s.add_argument("--mode", default="complete", metavar="MODE",
                   help="failure mode injected (default complete, the paper's model)")
    s.add_argument("--feedback", default="mmae", metavar="mmae|raw",
                   help="FCS feedback: the MMAE's z_hat (paper) or raw sensors (default mmae)")
    s.add_argument("--no-dither", action="store_true", help="fly without dither (the paper always dithers)")
    s.add_argument("--dither-scale", default="1.0", metavar="X",
                   help="multiply the truth model's default dither amplitudes by X (default 1)")
    add_estimator_arguments(s)
    add_run_arguments(s, "results/campaign-single")
    s.set_defaults(func=_single)
    from . import campaign_dual, campaign_envelope  # the other kinds, each in its own module

    campaign_dual.register(kinds)
    campaign_envelope.register(kinds)
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])


def add_run_arguments(p, default_out: str) -> None:
    """--workers / --scheduler / --out / --quiet: where a campaign runs and writes."""
    p.add_argument("--workers", default=None, metavar="W", help="local worker processes (default: all cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler tcp://HOST:PORT (needs the 'dask' extra)")
    p.add_argument("--out", default=default_out, metavar="DIR", help=f"output directory (default {default_out})")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def check_tuning(option: str, value: str) -> None:
    """CliError unless ``value`` is a shipped tuning or a readable bank file."""
    from ..campaign.single import CampaignError, bank_path

    try:
        bank_path(value)
    except CampaignError:
        raise CliError(f"{option} {value!r} is neither tuned, untuned nor a readable bank file") from None


def validated(cfg):
    """``cfg.validate()``, its CampaignError as a CliError."""
    from ..campaign.runner import CampaignError

    try:
        return cfg.validate()
    except CampaignError as exc:
        raise CliError(str(exc)) from None


def run_and_report(args, run, print_summary) -> int:
    """Run a campaign where the arguments say (``--workers`` local processes or a Dask
    ``--scheduler``): ``run(executor, executor_label, show_progress)`` returns its outcome
    (``summary``, ``summary_path``, ``executed``, ``resumed``). Then write its report.html,
    print its summary (``print_summary(summary, stream)``) and where everything is. Errors of
    the executor, the campaign or the results store become CliErrors naming the problem."""
    from ..campaign.executor import ExecutorError, default_workers, make_executor
    from ..campaign.report import render_report
    from ..campaign.runner import CampaignError
    from ..campaign.store import StoreError

    if args.workers is not None and args.scheduler is not None:
        raise CliError("give --workers or --scheduler, not both")
    workers = number("--workers", args.workers, integer=True, minimum=1) if args.workers is not None else None
    label = f"Dask at {args.scheduler}" if args.scheduler else f"{workers or default_workers()} local process(es)"
    try:
        with make_executor(workers=workers, scheduler=args.scheduler) as ex:
            outcome = run(ex, label, not args.quiet)
    except (ExecutorError, CampaignError, StoreError) as exc:
        raise CliError(str(exc)) from None
    out = outcome.summary_path.parent
    report = render_report(out)
    print_summary(outcome.summary, sys.stdout)
    print(f"\nrecords: {out / 'runs.jsonl'}  ({outcome.executed} run, {outcome.resumed} resumed)")
    print(f"summary: {outcome.summary_path}")
    for name in outcome.summary.get("figures", {}).values():
        print(f"figure:  {out / name}")
    print(f"report:  {report}")
    return 0


def add_estimator_arguments(p) -> None:
    """--threshold / --dwell-s / --p-min: the declarer and floor of core.HierarchicalBank.
    Unset, each is the bank's recommended setting (its metadata "estimator", from the tuning's
    [estimator] table; the shipped tuned bank: p_min 1e-9, threshold 0.9, dwell 0.25 s), else
    the core's default (the paper's: 0.001, 0.9, 0.25 s)."""
    p.add_argument("--threshold", default=None, metavar="P",
                   help="declare a hypothesis when its probability exceeds P (0.5 < P < 1; "
                        "default: the bank's recommended, else 0.9)")
    p.add_argument("--dwell-s", default=None, metavar="S",
                   help="... for S seconds in a row (default: the bank's recommended, else 0.25)")
    p.add_argument("--p-min", default=None, metavar="P",
                   help="probability floor (default: the bank's recommended -- tuned: 1e-9 -- "
                        "else the core's 0.001, the paper's)")


def estimator_options_from_args(args) -> dict:
    out = {}
    for opt, key in (("--threshold", "threshold"), ("--dwell-s", "dwell_s"), ("--p-min", "p_min")):
        value = getattr(args, key)
        if value is None:
            continue
        out[key] = number(opt, value)
    return out


def parse_choices(option: str, text: str | None, valid: tuple[str, ...], noun: str) -> tuple[str, ...]:
    """A comma list of names from ``valid`` (case-insensitive, each at most once); all of
    ``valid`` when ``text`` is None. CliError naming the option, the bad names and the valid ones."""
    if text is None:
        return valid
    items = [c.strip().upper() for c in text.split(",") if c.strip()]
    bad = [c for c in items if c not in valid]
    if bad or not items:
        raise CliError(f"{option}: unknown {noun}(s) {', '.join(bad) or repr(text)}; valid: {','.join(valid)}")
    if len(set(items)) != len(items):
        raise CliError(f"{option} {text!r} lists a {noun} twice")
    return tuple(items)


def parse_cases(text: str | None) -> tuple[str, ...]:
    from ..campaign.single import CASES

    return parse_choices("--cases", text, CASES, "case")


def config_from_args(args):
    """A validated ``SingleCampaign`` from the parsed arguments (CliError otherwise)."""
    from ..campaign.single import FEEDBACK_MODES, TURBULENCE_LEVELS, SingleCampaign

    turbulence = choice("--turbulence", args.turbulence, TURBULENCE_LEVELS)
    feedback = choice("--feedback", args.feedback, FEEDBACK_MODES)
    baseline = None if args.baseline.lower() == "none" else args.baseline
    cfg = SingleCampaign(
        runs=number("--runs", args.runs, integer=True, minimum=1), seed=number("--seed", args.seed, integer=True, minimum=1),
        cases=parse_cases(args.cases), tuning=args.tuning, baseline=baseline,
        turbulence=turbulence, mode=args.mode.lower(), feedback=feedback,
        dither=not args.no_dither, dither_scale=number("--dither-scale", args.dither_scale),
        **estimator_options_from_args(args),
    )
    return validated(cfg)


def _single(args) -> int:
    from ..campaign.single import run_campaign

    cfg = config_from_args(args)
    check_tuning("--tuning", cfg.tuning)
    if cfg.baseline is not None:
        check_tuning("--baseline", cfg.baseline)
    return run_and_report(args, lambda ex, label, progress: run_campaign(
        cfg, args.out, ex, executor_label=label, show_progress=progress), print_summary)


def print_summary(summary: dict, stream) -> None:
    t = summary.get("timing", {})
    print(f"single-failure campaign: {summary['runs_per_case']} runs/case, seed {summary['seed']}, "
          f"{summary['turbulence']} turbulence, Mach {summary['mach']}, {summary['alt_ft']:.0f} ft, "
          f"feedback {summary['feedback']}; wall {t.get('wall_s', 0):.1f} s", file=stream)
    blocks = [(summary["tuning"], summary["cases"])]
    if summary.get("baseline"):
        blocks.append((summary["baseline"]["tuning"], summary["baseline"]["cases"]))
    for tuning, cases in blocks:
        print(f"\n{tuning} bank:", file=stream)
        print(f"  {'case':<5} {'runs':>4} {'correct':>7} {'missed':>6} {'wrong':>5} {'FA':>3} "
              f"{'lat med':>8} {'lat p95':>8}", file=stream)
        for c in cases:
            lat = c["latency_s"]
            med = "-" if lat["median"] is None else f"{lat['median']:.2f}"
            p95 = "-" if lat["p95"] is None else f"{lat['p95']:.2f}"
            print(f"  {c['case']:<5} {c['runs']:>4} {c['correct']:>7} {c['missed']:>6} {c['wrong']:>5} "
                  f"{c['false_alarms']:>3} {med:>8} {p95:>8}", file=stream)
    met = summary.get("goals", {}).get("met")
    if met is not None:
        print(f"\ngoals (>= 99% correct, 0 false alarms, latency median <= 1 s, p95 <= 2 s): "
              f"{'all met' if met else 'NOT all met'} for the {summary['tuning']} bank", file=stream)
