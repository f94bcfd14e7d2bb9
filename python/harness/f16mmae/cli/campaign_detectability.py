"""``f16mmae campaign detectability``: detection probability against the size of a failure."""
from __future__ import annotations

import argparse

from ..campaign.detectability import DetectabilityCampaign, run_campaign
from ..campaign.detectability.campaign import COMPONENTS, DEFAULT_LOSSES, DEFAULT_RATES, DEFAULT_SIZES, SIZE_MAX
from ..campaign.detectability.report import print_table
from .campaign_common import (add_failure_instant, add_flight_settings, add_run_arguments, failure_instant,
                              flight_settings, run_and_report, validated)
from .options import CliError, number, parse_choices

DESCRIPTION = """\
Detectability curves: how small a failure the MMAE sees.  For each sensor (VEL AOA PIT AZ
ROL YAW AY) the detection probability against a bias (--sizes, in multiples of that
sensor's white-noise sigma in the truth model: 0.5 ft/s, 0.1 deg, 0.1 deg/s, 0.01 g,
0.1 deg/s, 0.1 deg/s, 0.005 g) and against a drift (--rates, sigma per second from the
onset); for each actuator (LS RS LF RF RUD) against the fraction of its effectiveness lost
(--losses, 1 = nothing left).  N seeded runs per size, the failure at --failure-time (3.0 s)
of a flight that lasts 5 s beyond it, at the bank's design point.  Run n of a component flies
the same seed (and, with --failure-jitter, the same failure offset) at every size, so a
curve's points differ by the failure's size alone.

"Detected": the failed component's hypothesis declared at or after the onset within the
flight.  "Any declared": some failure declared after the onset (the gap is mis-isolation).
Each probability with its 95 % Clopper-Pearson interval.
"""

EXAMPLES = f"""\
examples:
  f16mmae campaign detectability                      # every component, default sizes, 10 runs
  f16mmae campaign detectability --components AOA,VEL,LS --sizes 1,3,10 --runs 5
  f16mmae campaign detectability --components RUD --losses 0.2,0.5,0.9 --turbulence none
  f16mmae campaign detectability --components LS,RS --failure-jitter 1   # dither phases sampled

defaults: --sizes {','.join(f'{x:g}' for x in DEFAULT_SIZES)} (sigma), --rates {','.join(f'{x:g}' for x in DEFAULT_RATES)} (sigma/s),
          --losses {','.join(f'{x:g}' for x in DEFAULT_LOSSES)} (fraction lost)
Output (DIR, default results/campaign-detectability): runs.jsonl (one record per run,
resumable), summary.json (per family, component and size: rates with intervals),
bias.png, drift.png, loss.png (one panel per component), report.html.
Results page: f16mmae report DIR --markdown docs/results/detectability.md
"""


def register(kinds) -> None:
    """Add the ``detectability`` parser to the ``campaign`` kinds."""
    s = kinds.add_parser("detectability", help="detection probability against bias, drift and loss size",
                         description=DESCRIPTION, epilog=EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    add_flight_settings(s, "10", "seeded runs per component and size (default 10)")
    s.add_argument("--components", default=None, metavar="LIST",
                   help=f"comma-separated components (default all: {','.join(COMPONENTS)})")
    s.add_argument("--sizes", default=None, metavar="LIST",
                   help=f"sensor bias sizes in sigma, each in (0, {SIZE_MAX:g}]")
    s.add_argument("--rates", default=None, metavar="LIST",
                   help=f"sensor drift rates in sigma per second, each in (0, {SIZE_MAX:g}]")
    s.add_argument("--losses", default=None, metavar="LIST",
                   help="actuator fractions of effectiveness lost, each in (0, 1]")
    add_failure_instant(s)
    add_run_arguments(s, "results/campaign-detectability")
    s.set_defaults(func=_detectability)


def parse_sizes(option: str, text: str | None, default: tuple[float, ...], top: float) -> tuple[float, ...]:
    """A comma list of numbers in (0, top] (CliError naming the option and the bad value)."""
    if text is None:
        return default
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise CliError(f"{option} {text!r} gives no value")
    values = tuple(number(option, t, minimum=0.0, exclusive=True, maximum=top) for t in items)
    if len(set(values)) != len(values):
        raise CliError(f"{option} {text!r} lists a value twice")
    return values


def config_from_args(args) -> DetectabilityCampaign:
    """A validated ``DetectabilityCampaign`` from the parsed arguments (CliError otherwise)."""
    if args.mode.lower() != "complete":
        raise CliError(f"--mode {args.mode!r}: campaign detectability sets the mode per family "
                       "(bias, drift, loss); choose sizes with --sizes, --rates, --losses")
    settings = {k: v for k, v in flight_settings(args).items() if k != "mode"}
    cfg = DetectabilityCampaign(
        **settings, **failure_instant(args),
        components=parse_choices("--components", args.components, COMPONENTS, "component"),
        sizes=parse_sizes("--sizes", args.sizes, DEFAULT_SIZES, SIZE_MAX),
        rates=parse_sizes("--rates", args.rates, DEFAULT_RATES, SIZE_MAX),
        losses=parse_sizes("--losses", args.losses, DEFAULT_LOSSES, 1.0))
    return validated(cfg)


def _detectability(args) -> int:
    return run_and_report(args, config_from_args(args), run_campaign, print_summary)


def print_summary(summary: dict, stream) -> None:
    t = summary.get("timing", {})
    print(f"detectability campaign: {summary['runs_per_size']} runs/size, seed {summary['seed']}, "
          f"{summary['turbulence']} turbulence, Mach {summary['mach']}, {summary['alt_ft']:.0f} ft; "
          f"wall {t.get('wall_s', 0):.1f} s\n", file=stream)
    print_table(summary, stream)
