"""What the ``campaign`` kinds' command lines share: the flight settings every campaign
config has (``engine.config.CampaignConfig``), where a campaign runs and writes, and running
it with its report."""
from __future__ import annotations

import json
import shlex
import sys

from ..banks import BankError, bank_path
from ..campaign.engine.config import DITHER_SCALE_MAX, RUNS_MAX
from ..campaign.engine.executor import WORKERS_MAX, default_workers, make_executor
from ..campaign.engine.failure_runs import CASES
from ..names import FEEDBACK_MODES, TURBULENCE_LEVELS
from ..outputs import writable_dir
from ..report.page import render_report
from . import evidence
from .options import (CliError, add_estimator_arguments, choice, estimator_options_from_args,
                      number, parse_choices, seed)


def add_flight_settings(p, runs: str, runs_help: str) -> None:
    """The options of the shared config fields (``--runs`` with its kind's default and help),
    the estimator settings included."""
    p.add_argument("--runs", default=runs, metavar="N", help=runs_help)
    p.add_argument("--seed", default="1", metavar="S", help="campaign seed >= 1 (default 1)")
    p.add_argument("--tuning", default="tuned", metavar="tuned|untuned|FILE",
                   help="the bank under test: a shipped tuning or a bank file (default tuned)")
    p.add_argument("--turbulence", default="light", metavar="LEVEL",
                   help="none | light | moderate | severe (default light)")
    p.add_argument("--mode", default="complete", metavar="MODE",
                   help="failure mode injected (default complete, the paper's model: a failed "
                        "sensor reads the truth's trim value, a failed surface is frozen at trim)")
    p.add_argument("--feedback", default="mmae", metavar="mmae|raw",
                   help="FCS feedback: the MMAE's z_hat (paper) or raw sensors (default mmae)")
    p.add_argument("--no-dither", action="store_true", help="fly without dither (the paper always dithers)")
    p.add_argument("--dither-scale", default="1.0", metavar="X",
                   help="multiply the truth model's default dither amplitudes by X (default 1)")
    add_estimator_arguments(p)


def flight_settings(args) -> dict:
    """The shared config fields from the options of :func:`add_flight_settings` and the
    estimator options, each checked (CliError naming the bad value)."""
    settings = dict(
        runs=number("--runs", args.runs, integer=True, minimum=1, maximum=RUNS_MAX),
        seed=seed("--seed", args.seed),
        tuning=args.tuning, mode=args.mode.lower(),
        turbulence=choice("--turbulence", args.turbulence, TURBULENCE_LEVELS),
        feedback=choice("--feedback", args.feedback, FEEDBACK_MODES),
        dither=not args.no_dither, dither_scale=number("--dither-scale", args.dither_scale, minimum=0.0,
                                                           maximum=DITHER_SCALE_MAX),
        **estimator_options_from_args(args),
    )
    check_tuning("--tuning", args.tuning)
    return settings


def add_run_arguments(p, default_out: str) -> None:
    """--workers / --scheduler / --out / --quiet: where a campaign runs and writes."""
    p.add_argument("--workers", default=None, metavar="W", help="local worker processes (default: all cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler tcp://HOST:PORT (needs the 'dask' extra)")
    p.add_argument("--out", default=default_out, metavar="DIR", help=f"output directory (default {default_out})")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--allow-mixed", action="store_true",
                   help="resume over runs stored by other code (a git commit, JSBSim or LCM version); "
                        "refused by default")
    p.add_argument("--check", action="store_true",
                   help="exit 1 when a goal is not met (a verdict 'not met'), for CI")


def check_tuning(option: str, value: str) -> None:
    """CliError unless ``value`` is a shipped tuning or a readable bank file."""
    try:
        bank_path(value)
    except BankError:
        raise CliError(f"{option} {value!r} is neither tuned, untuned nor a readable bank file") from None


def validated(cfg):
    """``cfg.validate()`` (its CampaignError reaches the command line as any F16mmaeError)."""
    return cfg.validate()


def run_and_report(args, run, print_summary) -> int:
    """Run a campaign where the arguments say (``--workers`` local processes or a Dask
    ``--scheduler``): ``run(executor, executor_label, show_progress)`` returns its outcome
    (``summary``, ``summary_path``, ``executed``, ``resumed``). Then write its report.html,
    print its summary (``print_summary(summary, stream)``), the campaign's evidence and where
    everything is. With ``--check``: 1 when the summary's ``goals_met`` is false, else 0."""
    if args.workers is not None and args.scheduler is not None:
        raise CliError("give --workers or --scheduler, not both")
    workers = (number("--workers", args.workers, integer=True, minimum=1, maximum=WORKERS_MAX)
               if args.workers is not None else None)
    writable_dir(args.out)  # before any flight; the campaign then locks it
    label = f"Dask at {args.scheduler}" if args.scheduler else f"{workers or default_workers()} local process(es)"
    with make_executor(workers=workers, scheduler=args.scheduler) as ex:
        outcome = run(ex, label, not args.quiet)
    out = outcome.summary_path.parent
    outcome.summary["command"] = "f16mmae " + shlex.join(args.argv)  # what made it, for results pages
    outcome.summary_path.write_text(json.dumps(outcome.summary, indent=1) + "\n")
    report = render_report(out)
    print_summary(outcome.summary, sys.stdout)
    evidence.print_campaign(outcome.summary, sys.stdout)
    print(f"\nrecords: {out / 'runs.jsonl'}  ({outcome.executed} run, {outcome.resumed} resumed)")
    print(f"summary: {outcome.summary_path}")
    for name in outcome.summary.get("figures", {}).values():
        print(f"figure:  {out / name}")
    print(f"report:  {report}")
    if args.check and not outcome.summary["goals_met"]:
        print("check: a goal is not met (see the verdicts above): exit 1", file=sys.stderr)
        return 1
    return 0


def parse_cases(text: str | None) -> tuple[str, ...]:
    """``--cases``: a comma list of NONE and the single failures (default: all)."""
    return parse_choices("--cases", text, CASES, "case")


