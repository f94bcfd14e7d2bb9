"""``f16mmae run``: one closed-loop flight with failures injected, the MMAE in the loop."""
from __future__ import annotations

import argparse

from ..banks import BankError, load_bank
from ..campaign.engine import outcomes
from ..campaign.engine.config import scaled_dither
from ..campaign.engine.scoring import expected_hypothesis, score_run
from ..loop.flight import fly
from ..names import FAILURE_TIME_S, FEEDBACK_MODES, FLIGHT_S, TURBULENCE_LEVELS
from ..report.flight import write_flight
from ..outputs import writable_dir
from ..truth import Scenario, TrimError, parse_fail
from ..truth.aircraft import ALT_FT_RANGE, MACH_RANGE
from ..truth.turbulence import GustBurst
from ..truth.maneuvers import ManeuverError, parse_maneuver
from .options import (NO_DITHER_HELP, CliError, add_estimator_arguments, choice, estimator_options_from_args,
                      flight_seconds, number, seed)

DESCRIPTION = """\
Fly the nonlinear JSBSim F-16 (our FCS, dither on) with the MMAE estimator in the loop
and report what it declared.  The estimator sees only the surface commands u and the
sensor outputs z (minus its bank's trim), never the injected failures.
"""

EXAMPLES = """\
examples:
  f16mmae run                                  # no failure: nothing should be declared
  f16mmae run --fail LS@3.0                    # left stabilator fails at 3.0 s (mode complete)
  f16mmae run --fail PIT@3.0:stuck --seed 7 --out results/pit
  f16mmae run --fail LS@3 --fail PIT@5         # a dual: level-1 bank after the first declaration
  f16mmae run --fail RUD --turbulence moderate --feedback raw
  f16mmae run --mach 0.42 --alt-ft 21000 --fail AOA   # off the bank's design point
  f16mmae run --duration 60 --maneuver climb@5:to=25000ft:rate=3000fpm --maneuver turn@20:bank=30

--fail NAME@TIME[:MODE[=VALUE]]: NAME one of LS RS LF RF RUD VEL AOA PIT AZ ROL YAW AY (any case);
TIME in s (default 3.0 when '@TIME' is left out); MODE for actuators complete | stuck |
hardover | loss, for sensors complete | null | stuck | hardover | bias | drift (default
complete, the paper's model).

--maneuver KIND@T:KEY=VALUE[:KEY=VALUE] (repeatable), the pilot's schedule, flown by the
truth FCS's outer loop (altitude, Mach and bank hold; never seen by the estimator):
  climb@T:to=ALTft[:rate=Rfpm]      descend@T:to=ALTft[:rate=Rfpm]     (default 2000 fpm)
  accel@T:to=Mmach[:rate=Rmach/s]   decel@T:to=Mmach[:rate=Rmach/s]    (default 0.005 Mach/s)
  turn@T:bank=Bdeg[:for=Ss]         level turn, right bank +, |B| <= 60, 0 rolls out
T in s; targets within Mach 0.3-0.8, 5,000-35,000 ft; units optional but exact when written;
climbs, speed changes and turns may overlap each other, not themselves.

With --out DIR: DIR/run.json (seed, scenario, bank hash, version, failures,
declarations -- a back-out is a declaration of NONE --, final hypothesis),
DIR/probabilities.csv (time_s, then one column per hypothesis that was on line: the
union over the flight, empty while off line), DIR/probabilities.png, and DIR/flight.parquet
(pyarrow installed) or DIR/flight.csv: one row per frame with u, z, z_hat, the
probabilities and, prefixed truth_, the truth model's state, surface positions and failures
active -- recorded for you, never seen by the estimator.
"""



def register(subparsers) -> None:
    p = subparsers.add_parser(
        "run", help="one closed-loop flight with failures injected",
        description=DESCRIPTION, epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_flight_arguments(p)
    add_estimator_arguments(p)
    p.add_argument("--out", default=None, metavar="DIR", help="write run.json, probabilities.csv/.png here")
    p.set_defaults(func=_run)


def add_flight_arguments(p, bank_help: str = "model bank: a shipped tuning, the scheduled bank or a bank "
                                              "file (default tuned)") -> None:
    """The options of one flight, shared by ``run`` and ``hil``."""
    p.add_argument("--fail", action="append", default=[], metavar="NAME@TIME[:MODE[=VALUE]]",
                   help=f"inject a failure (repeatable); TIME defaults to {FAILURE_TIME_S} s, MODE to complete")
    p.add_argument("--maneuver", action="append", default=[], metavar="KIND@T:KEY=VALUE",
                   help="a maneuver (repeatable): climb|descend@T:to=ALTft[:rate=Rfpm], "
                        "accel|decel@T:to=Mmach[:rate=Rmach/s], turn@T:bank=Bdeg[:for=Ss]")
    p.add_argument("--seed", default="1", metavar="N", help="seed >= 1 for noise and turbulence (default 1, one of the seeds the shipped "
                        "bank was tuned on: campaigns fly evaluation seeds, see f16mmae/seeds.py)")
    p.add_argument("--duration", default=str(FLIGHT_S), metavar="S", help=f"flight length in s (default {FLIGHT_S:g})")
    p.add_argument("--turbulence", default="light", metavar="LEVEL",
                   help="none | light | moderate | severe (default light)")
    p.add_argument("--gust-burst", default=None, metavar="LEVEL@START+DURATION",
                   help="switch the turbulence to LEVEL from START s for DURATION s, then back "
                        "(e.g. severe@3.0+2.0; default none)")
    p.add_argument("--mach", default=None, metavar="M", help="flight Mach (default: the bank's design point)")
    p.add_argument("--alt-ft", default=None, metavar="H", help="flight altitude in ft (default: the bank's)")
    p.add_argument("--bank", default="tuned", metavar="tuned|untuned|scheduled|FILE", help=bank_help)
    p.add_argument("--feedback", default="mmae", metavar="mmae|raw|reconfigure",
                   help="FCS feedback: the MMAE's z_hat (paper), raw sensors, or raw sensors with the "
                        "MMAE's estimate only on the sensors a declaration has failed (default mmae)")
    p.add_argument("--no-dither", action="store_true", help=NO_DITHER_HELP)
    p.add_argument("--dither-scale", default="1.0", metavar="X",
                   help="multiply the truth model's default dither amplitudes by X, 0-5 (default 1)")


def parse_failures(specs: list[str]):
    """``--fail`` values -> truth FailureSpecs (TIME defaults to 3.0 s when omitted)."""
    out = []
    for text in specs:
        name, sep, rest = text.partition("@")
        if not sep:  # NAME or NAME:MODE
            name, colon, mode = text.partition(":")
            text = f"{name}@{FAILURE_TIME_S}" + (f":{mode}" if colon else "")
        try:
            out.append(parse_fail(text))
        except ValueError as exc:
            raise CliError(f"--fail {text!r}: {exc}") from None
    return out


def scenario_fields(args) -> dict:
    """The scenario fields the arguments give, checked (CliError on a bad value);
    ``mach``/``alt_ft`` are None when left to the bank's design point."""
    turbulence = choice("--turbulence", args.turbulence, TURBULENCE_LEVELS)
    feedback = choice("--feedback", args.feedback, FEEDBACK_MODES)
    seed_ = seed("--seed", args.seed)
    duration = flight_seconds("--duration", args.duration)
    mach = None if args.mach is None else number("--mach", args.mach, minimum=MACH_RANGE[0], maximum=MACH_RANGE[1])
    alt_ft = (None if args.alt_ft is None
              else number("--alt-ft", args.alt_ft, minimum=ALT_FT_RANGE[0], maximum=ALT_FT_RANGE[1]))
    dither_scale = number("--dither-scale", args.dither_scale, minimum=0.0, maximum=5.0)
    failures = parse_failures(args.fail)
    burst = None
    if getattr(args, "gust_burst", None) is not None:
        try:
            burst = GustBurst.parse(args.gust_burst)
        except ValueError as exc:
            raise CliError(f"--gust-burst: {exc}") from None
        if burst.start_s >= duration:
            raise CliError(f"--gust-burst {args.gust_burst}: the burst starts after the {duration}-s flight")
    late = [f for f in failures if f.time_s >= duration]
    if late:
        raise CliError(f"--fail {late[0].name}@{late[0].time_s}: the failure time is not inside the "
                       f"{duration}-s flight (use --duration)")
    maneuvers = []
    for text in args.maneuver:
        try:
            maneuvers.append(parse_maneuver(text))
        except ManeuverError as exc:
            raise CliError(f"--maneuver: {exc}") from None
    late = [m for m in maneuvers if m.time_s >= duration]
    if late:
        raise CliError(f"--maneuver {late[0]}: the start time is not inside the {duration}-s flight (use --duration)")
    return {
        "maneuvers": tuple(maneuvers),
        "mach": mach, "alt_ft": alt_ft, "turbulence": turbulence,
        "dither": not args.no_dither, "duration_s": duration, "seed": seed_, "feedback": feedback,
        "failures": tuple(failures), "gust_burst": burst,
        "dither_scale": dither_scale,
    }


def build_scenario(fields: dict, bank):
    """The truth Scenario: the checked fields, the bank's design point where not given."""
    fields = dict(fields)
    fields["mach"] = float(bank.mach if fields["mach"] is None else fields["mach"])
    fields["alt_ft"] = float(bank.alt_ft if fields["alt_ft"] is None else fields["alt_ft"])
    fields["dither"] = scaled_dither(fields["dither"], fields.pop("dither_scale"))
    try:
        return Scenario(**fields)
    except ValueError as exc:
        raise CliError(str(exc)) from None


def flight_from_args(args):
    """(bank label, bank path, ModelBank, Scenario) of the flight options of ``run`` and ``hil``,
    each checked, and ``--out`` checked writable, all before anything flies."""
    fields = scenario_fields(args)
    if args.out:
        writable_dir(args.out)
    try:
        label, path, bank = load_bank(args.bank)
    except BankError as exc:
        raise CliError(f"--bank: {exc}") from None
    return label, path, bank, build_scenario(fields, bank)


def _run(args) -> int:
    options = estimator_options_from_args(args)
    label, path, bank, scenario = flight_from_args(args)
    try:
        result = fly(scenario, bank, estimator_options=options, record_series=bool(args.out))
    except (ValueError, TrimError) as exc:  # bad estimator option, untrimmable flight condition
        raise CliError(str(exc)) from None
    injected = expected_hypothesis([f["name"] for f in result.failures])
    t_f = min((f["time_s"] for f in result.failures), default=None)
    scored = score_run(injected, t_f, result.declarations)
    first = [f["name"] for f in sorted(result.failures, key=lambda f: f["time_s"])][:1] if len(result.failures) > 1 else []
    scored.update(outcomes.run_fields(result.declarations, t_f, {injected, *first}, scenario.duration_s))

    s = result.scenario
    d = s["dither"] if isinstance(s["dither"], dict) else {"enabled": bool(s["dither"])}
    dither = ("off" if not d.get("enabled") else
              "on, throttle dither scheduled" if d.get("throttle_schedule") else
              f"on, throttle dither {d['throttle_amplitude']:g}" if d.get("throttle_amplitude") else "on")
    print(f"flight: {s['duration_s']:g} s at Mach {s['mach']:g}, {s['alt_ft']:.0f} ft, "
          f"{s['turbulence']} turbulence, seed {s['seed']}, dither {dither}, "
          f"feedback {result.feedback}; bank {label} ({result.bank_hash[:12]})")
    if s.get("maneuvers"):
        print(f"maneuvers: {', '.join(s['maneuvers'])}")
    inj = ", ".join(f"{f['name']} at {f['time_s']:g} s ({f['mode']})" for f in result.failures)
    print(f"injected: {inj or 'nothing'}")
    if result.declarations:
        for d in result.declarations:
            what = "back-out to NONE" if d["hypothesis"] == "NONE" else f"declared {d['hypothesis']}"
            print(f"  {d['time_s']:7.3f} s  {what}")
    else:
        print("  no declaration")
    verdict = {"correct": "right", "missed": "MISSED", "wrong": "WRONG"}[scored["outcome"]]
    extra = f", latency {scored['latency_s']:.3f} s" if scored["latency_s"] is not None else ""
    fa = ((", FALSE ALARM before the failure" if injected != "NONE" else ", but FALSE ALARM(S) on the way")
          if scored["false_alarm"] else "")
    fa += ", TRANSIENT-WRONG declaration(s) after the failure" if scored["transient_wrong"] else ""
    print(f"final hypothesis: {result.final_hypothesis} (expected {injected}: {verdict}{extra}{fa})")
    tm = result.timing
    print(f"cost: {tm['wall_s']:.3f} s wall ({s['duration_s'] / tm['wall_s']:.0f}x real time); "
          f"truth model {tm['truth_s']:.3f} s, estimator {tm['estimator_s']:.3f} s")
    if args.out:
        paths = write_flight(result, args.out, **scored, bank_file=str(path))
        print(f"wrote {paths['run']}, {paths['csv'].name}, {paths['png'].name}, {paths['table'].name}")
    return 0
