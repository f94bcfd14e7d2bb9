"""``f16mmae campaign maneuver``: failures injected during climbs, descents, speed changes and turns."""
from __future__ import annotations

import argparse

from ..campaign.maneuver import MANEUVERS, ManeuverCampaign, run_maneuver
from ..campaign.maneuver.campaign import CLIMB_FT, CLIMB_RATE_FPM, MACH_RATE_PER_S, MACH_STEP, TURN_BANK_DEG
from ..report.evidence import describe_per_hour, describe_rate
from .campaign_common import (add_failure_jitter, add_flight_settings, add_run_arguments, failure_jitter, flight_settings,
                              parse_cases, run_and_report, validated)
from .campaign_envelope import points_from_args
from .options import CliError, flight_seconds, number, parse_choices

DESCRIPTION = f"""\
The maneuver campaign: at each flight point the truth F-16 starts trimmed and flies one
maneuver (its FCS outer loop, on the pilot side: the estimator is never told), with the
no-failure case NONE and each single failure injected mid-maneuver, N seeded runs each:
  climb    +{CLIMB_FT:g} ft at {CLIMB_RATE_FPM:g} fpm        descend  -{CLIMB_FT:g} ft at {CLIMB_RATE_FPM:g} fpm
  accel    +{MACH_STEP:g} Mach at {MACH_RATE_PER_S:g} Mach/s (-{MACH_STEP:g} where +{MACH_STEP:g} leaves the envelope)
  turn     a level {TURN_BANK_DEG:g} deg turn
Scored per maneuver: correct fraction of the failure runs (goal >= 95 %), runs with a false
alarm, false declarations per hour of maneuvering flight (95 % intervals), latency median
(VEL apart).  The bank under test is --tuning: today the nominal (unscheduled) bank, or a
scheduled bank file.  Run n of (maneuver, case) flies the same seed at every point.
"""

EXAMPLES = """\
points: --points and --mach-alt as in 'campaign envelope' (all | local | extrema | qline |
1-24,NOM | random:N[:seed=S]; MACH:ALT_FT,...); default: NOM alone.

examples:
  f16mmae campaign maneuver --runs 3
  f16mmae campaign maneuver --points random:6 --maneuvers climb,turn --runs 2
  f16mmae campaign maneuver --mach-alt 0.6:25000 --cases NONE,LS,PIT --tuning FILE

Output (DIR, default results/campaign-maneuver): runs.jsonl, summary.json,
maneuver_map.png (points coloured by correct fraction, per maneuver), maneuver_strips.png
(mean probability of the injected failure per maneuver and case), report.html.
"""


def register(kinds) -> None:
    """Add the ``maneuver`` parser to the ``campaign`` kinds."""
    m = kinds.add_parser("maneuver", help="failures injected during climbs, descents, speed changes and turns",
                         description=DESCRIPTION, epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_flight_settings(m, "3", "seeded runs per point, maneuver and case (default 3)")
    m.add_argument("--points", default=None, metavar="SEL", help="flight points as in campaign envelope (default NOM)")
    m.add_argument("--mach-alt", default=None, metavar="M:H,...", help="custom points MACH:ALT_FT")
    m.add_argument("--maneuvers", default=None, metavar="LIST",
                   help=f"comma list of {','.join(MANEUVERS)} (default all)")
    m.add_argument("--cases", default=None, metavar="LIST",
                   help="comma-separated cases (default: NONE and all twelve failures)")
    m.add_argument("--maneuver-time", default="2", metavar="S", help="when the maneuver begins (s, default 2)")
    m.add_argument("--failure-time", default="6", metavar="S", help="when the failure is injected (s, default 6)")
    m.add_argument("--duration", default="14", metavar="S", help="flight length (s, default 14)")
    add_failure_jitter(m, "each run's failure, after --failure-time,")
    add_run_arguments(m, "results/campaign-maneuver")
    m.set_defaults(func=_maneuver)


def config_from_args(args) -> ManeuverCampaign:
    if args.points is None and args.mach_alt is None:
        args.points = "NOM"
    points = points_from_args(args)
    maneuvers = tuple(x.lower() for x in parse_choices("--maneuvers", args.maneuvers and args.maneuvers.upper(),
                                                       tuple(x.upper() for x in MANEUVERS), "maneuver"))
    duration = flight_seconds("--duration", args.duration)
    cfg = ManeuverCampaign(**flight_settings(args), points=points, maneuvers=maneuvers, cases=parse_cases(args.cases),
                           maneuver_time_s=number("--maneuver-time", args.maneuver_time, minimum=0.0),
                           failure_time_s=number("--failure-time", args.failure_time, minimum=0.0, exclusive=True),
                           failure_jitter_s=failure_jitter(args, duration), duration_s=duration)
    if cfg.failure_time_s <= cfg.maneuver_time_s:
        raise CliError(f"--failure-time {cfg.failure_time_s:g} must come after --maneuver-time "
                       f"{cfg.maneuver_time_s:g} (the failure is injected mid-maneuver)")
    return validated(cfg)


def _maneuver(args) -> int:
    return run_and_report(args, config_from_args(args), run_maneuver, print_summary)


def print_summary(summary: dict, stream) -> None:
    t = summary.get("timing", {})
    print(f"maneuver campaign: {summary['tuning']} bank, {len(summary['points'])} point(s), "
          f"{summary['runs_per_case']} run(s) per case, seed {summary['seed']}, {summary['turbulence']} turbulence; "
          f"wall {t.get('wall_s', 0):.1f} s", file=stream)
    print(f"\n  {'maneuver':>8} {'correct [95% CI]':>18} {'FA runs':>8} {'lat med':>7} {'VEL lat':>7}  "
          "false declarations per maneuvering hour", file=stream)
    for r in summary["by_maneuver"] + [{"maneuver": "all", **summary["overall"]}]:
        lat = "-" if r["latency_median_s"] is None else f"{r['latency_median_s']:.2f}"
        vel = "-" if r["vel_latency_median_s"] is None else f"{r['vel_latency_median_s']:.2f}"
        print(f"  {r['maneuver']:>8} {describe_rate(r['rates'].get('correct')):>18} "
              f"{r['false_alarm_runs']:>4}/{r['runs']:<3} {lat:>7} {vel:>7}  {describe_per_hour(r['per_hour'])}",
              file=stream)
