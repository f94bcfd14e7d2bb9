"""What the ``campaign`` kinds' command lines share: the flight settings every campaign
config has (``engine.config.CampaignConfig``), where a campaign runs and writes, and running
it with its report."""
from __future__ import annotations

import contextlib
import json
import shlex
import sys

from ..banks import BankError, bank_path, load_bank
from ..campaign.engine.config import DITHER_SCALE_MAX, RUNS_MAX
from ..campaign.engine.executor import WORKERS_MAX, default_workers, make_executor
from ..campaign.engine.failure_runs import CASES, FAILURE_JITTER_S_MAX
from ..campaign.engine.store import write_summary
from ..campaign.engine.variants import VARIANTS_KIND
from ..loop.estimator_options import bank_defaults
from ..names import FAILURE_TIME_S, FEEDBACK_MODES, FLIGHT_S, FLIGHT_S_MAX, TURBULENCE_LEVELS
from ..outputs import writable_dir
from ..report.page import render_report
from . import evidence
from .options import (NO_DITHER_HELP, CliError, add_estimator_arguments, choice, estimator_options_from_args,
                      flight_seconds, number, parse_choices, seed)


def add_flight_settings(p, runs: str | None, runs_help: str = "", failures: bool = True) -> None:
    """The options of the shared config fields (``--runs`` with its kind's default and help,
    unless ``runs`` is None; ``--mode`` unless the kind flies no failure), the estimator
    settings included."""
    if runs is not None:
        p.add_argument("--runs", default=runs, metavar="N", help=runs_help)
    p.add_argument("--seed", default="1", metavar="S", help="campaign seed >= 1 (default 1)")
    p.add_argument("--tuning", default="tuned", metavar="tuned|untuned|scheduled|FILE",
                   help="the bank under test: a shipped tuning, the scheduled bank (designed on first use) "
                        "or a bank file (default tuned)")
    p.add_argument("--turbulence", default="light", metavar="LEVEL[,LEVEL...]",
                   help="none | light | moderate | severe, or a comma list of them flown with common "
                        "seeds and reported side by side (default light)")
    if failures:
        p.add_argument("--mode", "--modes", dest="mode", default="complete", metavar="MODE[,MODE...]",
                       help="failure mode injected, NAME[=VALUE] (default complete, the paper's model: a "
                            "failed sensor reads the truth's trim value, a failed surface is frozen at trim; "
                            "actuators: complete stuck hardover loss=F; sensors: complete null stuck hardover "
                            "bias=B drift=R). campaign single takes a comma list: the same cases in every "
                            "mode, a mode flying only the cases whose component it applies to, reported "
                            "side by side")
    p.add_argument("--feedback", default="mmae", metavar="mmae|raw|reconfigure",
                   help="FCS feedback: the MMAE's z_hat (paper), raw sensors, or raw sensors with the "
                        "MMAE's estimate only on the sensors a declaration has failed (default mmae)")
    p.add_argument("--no-dither", action="store_true", help=NO_DITHER_HELP)
    p.add_argument("--dither-scale", default="1.0", metavar="X",
                   help="multiply the truth model's default dither amplitudes by X (default 1)")
    add_estimator_arguments(p)


def add_failure_jitter(p, what: str = "each run's failure") -> None:
    """``--failure-jitter J`` (engine.failure_runs: a seeded offset in [0, J) per run); ``what``
    names what it shifts."""
    p.add_argument("--failure-jitter", default="0", metavar="J",
                   help=f"{what} up to J s later, drawn from the run's seed (default 0: every run fails at the "
                        "same instant, so meets the same phase of the deterministic surface dither; a frozen "
                        "surface steps from wherever the dither had it). The flight lasts as long after its "
                        "failure as without. J of a second or more samples the surface lines' phases")


def failure_jitter(args, duration_s: float) -> float:
    """``--failure-jitter``'s value, checked, and with it the longest flight, ``duration_s`` + J,
    within FLIGHT_S_MAX (CliError naming the bad value)."""
    jitter = number("--failure-jitter", args.failure_jitter, minimum=0.0, maximum=FAILURE_JITTER_S_MAX)
    if duration_s + jitter > FLIGHT_S_MAX:
        raise CliError(f"--failure-jitter {jitter:g} takes a {duration_s:g}-s flight past the longest "
                       f"({FLIGHT_S_MAX:g} s)")
    return jitter


def add_failure_instant(p) -> None:
    """``--failure-time`` and ``--failure-jitter``: when each run's failure comes
    (:func:`failure_instant`)."""
    p.add_argument("--failure-time", default=f"{FAILURE_TIME_S:g}", metavar="S",
                   help=f"when the failure is injected (s, default {FAILURE_TIME_S:g}); the flight lasts "
                        f"{FLIGHT_S - FAILURE_TIME_S:g} s beyond it. Later: the estimator has flown longer "
                        "before the failure (its turbulence adaptation settles over 5 s)")
    add_failure_jitter(p, "each run's failure, after --failure-time,")


def failure_instant(args) -> dict:
    """The config fields of :func:`add_failure_instant`'s options: ``failure_time_s``,
    ``failure_jitter_s`` and ``duration_s`` (the failure time and the time after it), each
    checked (CliError naming the bad value)."""
    failure_time = flight_seconds("--failure-time", args.failure_time)
    duration = failure_time + FLIGHT_S - FAILURE_TIME_S
    if duration > FLIGHT_S_MAX:
        raise CliError(f"--failure-time {failure_time:g} leaves no room for the {FLIGHT_S - FAILURE_TIME_S:g} s "
                       f"after it (flights up to {FLIGHT_S_MAX:g} s)")
    return dict(failure_time_s=failure_time, failure_jitter_s=failure_jitter(args, duration), duration_s=duration)


def flight_settings(args) -> dict:
    """The shared config fields from the options of :func:`add_flight_settings` and the
    estimator options, each checked (CliError naming the bad value)."""
    settings = dict(
        seed=seed("--seed", args.seed), tuning=args.tuning,
        turbulence=turbulence_levels("--turbulence", args.turbulence),
        feedback=choice("--feedback", args.feedback, FEEDBACK_MODES),
        dither=not args.no_dither, dither_scale=number("--dither-scale", args.dither_scale, minimum=0.0,
                                                           maximum=DITHER_SCALE_MAX),
        estimator=estimator_options_from_args(args),
    )
    if getattr(args, "runs", None) is not None:
        settings["runs"] = number("--runs", args.runs, integer=True, minimum=1, maximum=RUNS_MAX)
    if getattr(args, "mode", None) is not None:
        settings["mode"] = args.mode.lower()
    check_tuning("--tuning", args.tuning)
    check_estimator_for_bank("--tuning", args.tuning, settings["estimator"])
    return settings


def turbulence_levels(option: str, text: str) -> str:
    """One turbulence level or a comma list of distinct levels, lower-cased and joined by commas;
    CliError naming a bad or repeated level and the valid ones."""
    levels = [x.strip() for x in text.split(",") if x.strip()] or [text]
    for x in levels:
        choice(option, x, TURBULENCE_LEVELS)
    levels = [x.lower() for x in levels]
    if len(set(levels)) != len(levels):
        raise CliError(f"{option} {text!r} lists a level twice")
    return ",".join(levels)


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
        raise CliError(f"{option} {value!r} is neither tuned, untuned, scheduled nor a readable bank file") from None


def check_estimator_for_bank(option: str, value: str, estimator: dict) -> None:
    """CliError when the estimator settings, with bank ``value``'s defaults applied
    (``loop.estimator_options.bank_defaults``), leave an option without the one it applies with;
    before anything flies (the bank is read once a process)."""
    if not estimator:
        return
    try:
        bank_defaults(estimator, load_bank(value)[2])
    except ValueError as exc:
        raise CliError(f"{exc} ({option} {value})") from None


def validated(cfg):
    """``cfg.validate()`` (its CampaignError reaches the command line as any F16mmaeError)."""
    return cfg.validate()


def run_and_report(args, cfg, run, print_summary) -> int:
    """Run campaign ``cfg`` where the arguments say (``--workers`` local processes or a Dask
    ``--scheduler``): the kind's ``run(cfg, out, executor, executor_label=, show_progress=,
    allow_mixed=)`` returns its outcome (``summary``, ``summary_path``, ``executed``,
    ``resumed``). Then write its report.html,
    print its summary (``print_summary(summary, stream)``), the campaign's evidence and where
    everything is. With ``--check``: 1 when the summary's ``goals_met`` is false, else 0.
    ``args.executor`` (set by ``campaign paper``, not an option): an executor to fly on, with its
    ``args.executor_label``, instead of one made here."""
    if args.workers is not None and args.scheduler is not None:
        raise CliError("give --workers or --scheduler, not both")
    workers = (number("--workers", args.workers, integer=True, minimum=1, maximum=WORKERS_MAX)
               if args.workers is not None else None)
    writable_dir(args.out)  # before any flight; the campaign then locks it
    label = f"Dask at {args.scheduler}" if args.scheduler else f"{workers or default_workers()} local process(es)"
    shared = getattr(args, "executor", None)
    with (contextlib.nullcontext(shared) if shared is not None
          else make_executor(workers=workers, scheduler=args.scheduler)) as ex:
        outcome = run(cfg, args.out, ex, executor_label=getattr(args, "executor_label", label),
                      show_progress=not args.quiet, allow_mixed=args.allow_mixed)
    out = outcome.summary_path.parent
    outcome.summary["command"] = "f16mmae " + shlex.join(args.argv)  # what made it, for results pages
    write_summary(outcome.summary_path, outcome.summary)
    report = render_report(out)
    if outcome.summary["kind"] == VARIANTS_KIND:  # flown at several turbulence levels or modes
        for row in outcome.summary["variants"]:
            variant_dir = out / row["directory"]
            print(f"\n=== {row['label']} ({variant_dir}) ===")
            print_summary(json.loads((variant_dir / "summary.json").read_text()), sys.stdout)
            render_report(variant_dir)
        print()
        evidence.print_variants(outcome.summary, sys.stdout)
    else:
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


