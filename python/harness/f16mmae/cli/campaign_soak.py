"""``f16mmae campaign soak``: long failure-free flights, false declarations per flight hour."""
from __future__ import annotations

import argparse

from ..campaign.soak import GOALS_PER_H, SoakCampaign, run_soak
from ..campaign.soak.campaign import FLIGHTS_MAX, PROFILES, SOAK_FLIGHT_S
from ..campaign.soak.report import points_text
from ..truth.aircraft import ALT_FT_RANGE, MACH_RANGE
from ..truth.maneuvers import ManeuverError, parse_maneuver
from ..names import FLIGHT_S_MAX
from ..report.evidence import describe_counts, describe_per_hour
from .campaign_common import add_flight_settings, add_run_arguments, flight_settings, run_and_report, validated
from .campaign_envelope import points_from_args
from .options import CliError, number

DESCRIPTION = f"""\
The soak campaign: failure-free flights at the bank's design point (or at --mach, --alt-ft,
or at each flight point of --points / --mach-alt), trimmed, with the dither
on, the MMAE in the loop, counting false declarations per flight hour at each turbulence
level listed (pooled over the points, and per point).  The aircraft holds trim, or flies the
maneuvers of --maneuver (the grammar of 'f16mmae run --help') or of --profile (from each
point's own flight condition) in every flight.  --hours is per point and level; the hours are
cut into flights of --flight-s seconds (default {SOAK_FLIGHT_S:g}), each one run of the
campaign engine, so a soak resumes flight by flight and distributes like any campaign.
Flight n has the same seed at every level and every point (common random numbers).

Goals (issue 14): {', '.join(f'{k} <= {v:g}/h' for k, v in GOALS_PER_H.items())}, judged on the
95 % Poisson interval (demonstrated / consistent / not met).
"""

EXAMPLES = """\
points: --points and --mach-alt as in 'campaign envelope' (all | local | extrema | qline |
1-24,NOM | random:N[:seed=S]; MACH:ALT_FT,... labelled C1, C2, ...); default: the bank's
design point alone (labelled NOM), or --mach/--alt-ft (labelled C1), not with --points.

examples:
  f16mmae campaign soak --hours 1 --turbulence light
  f16mmae campaign soak --hours 10 --turbulence none,light,moderate,severe --check
  f16mmae campaign soak --hours 0.1 --flight-s 60 --workers 1 --out /tmp/soak
  f16mmae campaign soak --hours 2 --profile tour      # maneuvering flight, 540-s tours
  f16mmae campaign soak --hours 10 --turbulence severe --profile hold   # a pilot holds the trim
  f16mmae campaign soak --hours 10 --tuning scheduled --adapt-turbulence --mach 0.6 --alt-ft 10000   # off nominal
  f16mmae campaign soak --hours 10 --points random:40 --turbulence moderate --tuning scheduled --adapt-turbulence
  f16mmae campaign soak --hours 2 --mach-alt 0.35:15000,0.7:30000 --turbulence light,moderate
  f16mmae campaign soak --hours 1 --flight-s 120 --maneuver turn@10:bank=30 --maneuver climb@20:to=23000ft

profile tour (flights >= 540 s, from the flight condition): climb 4,000 ft at 2,000 fpm
at 10 s with a 60-s 30 deg right turn from 60 s, +0.1 Mach from 150 s, a 60-s left turn from
200 s, back down from 300 s and back to the start speed from 350 s, a 90-s right turn from 450 s.
profile hold (any length): the pilot holds the altitude, Mach and wings level of 0 s.

Output (DIR, default results/campaign-soak): runs.jsonl (one record per flight: seed,
scenario, declarations, each false declaration with how long it lasted; with --points or
--mach-alt its point), summary.json (per level pooled over the points, and per point),
soak_timeline.png, soak_durations.png, soak_rate_by_level.png, with two or more points
soak_map.png (the points coloured by false declarations per flight hour, per level), report.html.
Every flight with a false declaration is listed with the 'f16mmae run' command that flies it.
Resume: run the same command again; a longer --hours keeps the flights already flown.
"""


def register(kinds) -> None:
    """Add the ``soak`` parser to the ``campaign`` kinds."""
    s = kinds.add_parser("soak", help="hours of failure-free flight: false declarations per hour (issue 14)",
                         description=DESCRIPTION, epilog=EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    s.add_argument("--hours", default="1", metavar="H",
                   help="flight hours per turbulence level and point (default 1)")
    s.add_argument("--flight-s", default=str(SOAK_FLIGHT_S), metavar="S",
                   help=f"length of each flight in s, at most {FLIGHT_S_MAX:g} (default {SOAK_FLIGHT_S:g})")
    s.add_argument("--maneuver", action="append", default=[], metavar="KIND@T:KEY=VALUE",
                   help="a maneuver every flight flies (repeatable; grammar of 'f16mmae run --help')")
    s.add_argument("--profile", default=None, metavar="NAME", help=f"a maneuver profile: {', '.join(PROFILES)}")
    s.add_argument("--mach", default=None, metavar="M",
                   help=f"the flight condition every flight starts trimmed at, with --alt-ft: Mach "
                        f"{MACH_RANGE[0]}-{MACH_RANGE[1]} (default: the bank's design point)")
    s.add_argument("--alt-ft", default=None, metavar="H",
                   help=f"with --mach: pressure altitude, {ALT_FT_RANGE[0]:,.0f}-{ALT_FT_RANGE[1]:,.0f} ft")
    s.add_argument("--points", default=None, metavar="SEL",
                   help="flight points as in campaign envelope: all | local | extrema | qline | comma list of "
                        "1-24 and NOM | random:N[:seed=S] (default: the design point alone)")
    s.add_argument("--mach-alt", default=None, metavar="M:H,...", help="custom points MACH:ALT_FT")
    add_flight_settings(s, None, failures=False)
    add_run_arguments(s, "results/campaign-soak")
    s.set_defaults(func=_soak)


def config_from_args(args) -> SoakCampaign:
    flight_s = number("--flight-s", args.flight_s, minimum=0.0, exclusive=True, maximum=FLIGHT_S_MAX)
    hours = number("--hours", args.hours, minimum=0.0, exclusive=True,
                   maximum=FLIGHTS_MAX * flight_s / 3600.0)
    maneuvers = []
    for text in args.maneuver:
        try:
            maneuvers.append(str(parse_maneuver(text)))
        except ManeuverError as exc:
            raise CliError(f"--maneuver: {exc}") from None
    if args.profile is not None and args.profile not in PROFILES:
        raise CliError(f"--profile {args.profile!r} is unknown; valid: {', '.join(PROFILES)}")
    if (args.mach is not None or args.alt_ft is not None) and (args.points is not None or args.mach_alt is not None):
        raise CliError("give --mach/--alt-ft (one flight condition) or --points/--mach-alt (flight points), "
                       "not both")
    mach = None if args.mach is None else number("--mach", args.mach, minimum=MACH_RANGE[0], maximum=MACH_RANGE[1])
    alt_ft = None if args.alt_ft is None else number("--alt-ft", args.alt_ft, minimum=ALT_FT_RANGE[0],
                                                     maximum=ALT_FT_RANGE[1])
    points = () if args.points is None and args.mach_alt is None else points_from_args(args)
    return validated(SoakCampaign(**flight_settings(args), hours=hours, duration_s=flight_s,
                                  maneuvers=tuple(maneuvers), profile=args.profile, mach=mach, alt_ft=alt_ft,
                                  points=points))


def _soak(args) -> int:
    return run_and_report(args, config_from_args(args), run_soak, print_summary)


#: The points with a false declaration ``print_summary`` lists by name.
LISTED_POINTS = 12


def print_summary(summary: dict, stream) -> None:
    t = summary.get("timing", {})
    points = summary.get("points") or []
    if summary.get("maneuvers"):
        flown = "maneuvering: " + ", ".join(summary["maneuvers"])
    elif summary.get("profile"):
        flown = f"maneuvering (profile {summary['profile']} from each point)"
    else:
        flown = "at trim"
    where = (f"{len(points)} points ({points_text(summary)})" if len(points) > 1
             else f"Mach {summary['mach']}, {summary['alt_ft']:.0f} ft")
    print(f"soak: {summary['flights_per_level']} flights of {summary['flight_s']:g} s per level"
          f"{' and point' if len(points) > 1 else ''} {flown}, {where}, seed {summary['seed']}, "
          f"{summary['tuning']} bank; wall {t.get('wall_s', 0):.1f} s", file=stream)
    print("false declarations per flight hour (95% Poisson interval), goal and verdict"
          + (", pooled over the points:" if len(points) > 1 else ":"), file=stream)
    for lv in summary["levels"]:
        hyps = describe_counts(lv["hypotheses"])
        d = lv["duration_s"]
        first = lv["first_declaration_s"]
        lasted = "" if d["median"] is None else (f"; lasted median {d['median']:.2f} s, max {d['max']:.2f} s; "
                                                 f"first in its flight at median {first['median']:.0f} s, "
                                                 f"earliest {first['min']:.1f} s")
        print(f"  {lv['level']:>8}: {describe_per_hour(lv['per_hour'])}; "
              f"{lv['flights_with_false_declaration']}/{lv['flights']} flights with one; hypotheses: {hyps}{lasted}",
              file=stream)
    if len(points) > 1:
        _print_points(points, stream)
    print(f"goals: {'met' if summary['goals_met'] else 'NOT met'} (no level 'not met')", file=stream)


def _print_points(points: list[dict], stream) -> None:
    """One line per point with a false declaration (its count and hypotheses per level), the
    first :data:`LISTED_POINTS`; the points without one counted."""
    declared = [p for p in points if any(q["per_hour"]["events"] for q in p["levels"])]
    print(f"by point: {len(points) - len(declared)} of {len(points)} without a false declaration"
          + (", the others:" if declared else ""), file=stream)
    for p in declared[:LISTED_POINTS]:
        levels = "; ".join(f"{q['level']} {q['per_hour']['events']} ({describe_counts(q['hypotheses'], top=3)})"
                           for q in p["levels"] if q["per_hour"]["events"])
        print(f"  {p['label']:>5} (Mach {p['mach']:.3f}, {p['alt_ft']:.0f} ft): {levels}", file=stream)
    if len(declared) > LISTED_POINTS:
        print(f"  ... and {len(declared) - LISTED_POINTS} more (summary.json: points)", file=stream)
