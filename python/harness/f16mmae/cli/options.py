"""Options every command shares: range-checked numbers and choices (a :class:`CliError` names
the option, the bad value and the valid range or choices), comma lists, and the estimator
settings of ``run``, ``hil`` and the campaigns."""
from __future__ import annotations

import math

from .. import core
from ..errors import F16mmaeError
from ..names import DWELL_S_MAX, FLIGHT_S_MAX, K_BANK, SCHEDULE_MODES


class CliError(F16mmaeError):
    """A bad argument: the message names the bad value and the valid choices."""


#: Seeds are 32-bit signed integers for JSBSim; 0 means 1 to it, so seeds start at 1.
SEED_MAX = 2**31 - 1


def number(option: str, value, *, integer: bool = False, minimum=None, exclusive: bool = False,
           below=None, maximum=None):
    """``value`` of ``option`` as an int (``integer``) or a finite float, at least ``minimum``
    (above it if ``exclusive``), below ``below`` and at most ``maximum``; CliError naming the
    option, the value and the valid range otherwise."""
    try:
        x = int(value) if integer else float(value)
    except (TypeError, ValueError, OverflowError):
        kind = "an integer" if integer else "a number"
        raise CliError(f"{option} {value!r} is not {kind}") from None
    if not integer and not math.isfinite(x):
        raise CliError(f"{option} {value!r} must be finite")
    upper = below if below is not None else maximum
    valid = ""
    if minimum is not None and upper is not None:
        valid = f" (valid: {'(' if exclusive else '['}{minimum}, {upper}{')' if below is not None else ']'})"
    if minimum is not None and (x <= minimum if exclusive else x < minimum):
        raise CliError(f"{option} {value!r} must be {'>' if exclusive else '>='} {minimum}{valid}")
    if below is not None and not x < below:
        raise CliError(f"{option} {value!r} must be < {below}{valid}")
    if maximum is not None and not x <= maximum:
        raise CliError(f"{option} {value!r} must be <= {maximum}{valid}")
    return x


def seed(option: str, value) -> int:
    """A seed: an integer in [1, SEED_MAX]."""
    return number(option, value, integer=True, minimum=1, maximum=SEED_MAX)


def flight_seconds(option: str, value) -> float:
    """A flight duration or a time in one: a number of seconds in (0, FLIGHT_S_MAX]."""
    return number(option, value, minimum=0.0, exclusive=True, maximum=FLIGHT_S_MAX)


def choice(option: str, value: str, valid) -> str:
    """``value`` of ``option`` lower-cased if it is one of ``valid``; CliError listing them."""
    v = value.lower()
    if v not in valid:
        raise CliError(f"{option} {value!r} is unknown; valid: {', '.join(valid)}")
    return v


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


def add_estimator_arguments(p) -> None:
    """--threshold / --dwell-s / --p-min: the declarer and floor of core.HierarchicalBank.
    Unset, each is the bank's recommended setting (its typed field, from the tuning's
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
    p.add_argument("--adapt-turbulence", action="store_true",
                   help="adapt the likelihoods on line to the turbulence intensity (one residual "
                        "covariance scale common to all hypotheses; cpp/f16mmae/turbulence_adaptation.h). "
                        "Default off: the bank as designed")
    p.add_argument("--maneuver-kinematics", action="store_true",
                   help="add to the filters' propagation the kinematic and gravity terms their wings-level "
                        "linearization drops (steady turns and pull-ups; cpp/f16mmae/maneuver_kinematics.h). "
                        "Default off: the bank as designed")
    p.add_argument("--actuator-limits", action="store_true",
                   help="the filters see the commands through the actuators' rate and position limits "
                        "(a roll-in's or pull-up's saturated commands; cpp/f16mmae/actuator_limits.h). "
                        "Default off: the bank as designed")
    p.add_argument("--maneuver-tempering", default=None, metavar="G",
                   help="temper every likelihood by 1 + (dn/G)^2 while the estimated load factor is dn g off "
                        "the trim (a pull-up's model error; cpp/f16mmae/maneuver_kinematics.h). Default off")
    p.add_argument("--trim-tracking", default=None, metavar="TAU_S",
                   help="track the trim on line with time constant TAU_S seconds (e.g. 30): the "
                        "bank's trim plus a slow low-pass offset of u and z, frozen while a failure "
                        "hypothesis rises or is declared (default: off)")
    p.add_argument("--trim-freeze-probability", default=None, metavar="P",
                   help="with --trim-tracking: a failure hypothesis above P freezes the trim "
                        "estimate (0 < P <= 1; default 0.05; 1 freezes only at a declaration)")
    p.add_argument("--schedule-mode", default=None, metavar="|".join(SCHEDULE_MODES),
                   help="a scheduled bank (--bank scheduled): interpolate between grid points on the "
                        "measured air data, or switch to the nearest with hysteresis (default "
                        f"{SCHEDULE_MODES[0]}; a bank designed at one point ignores it)")


def estimator_options_from_args(args) -> dict:
    """The estimator settings given, each range-checked: threshold in (0.5, 1), dwell in
    [0, DWELL_S_MAX] s, p_min in [0, 1/K) with K the hypotheses on line (13)."""
    out = {}
    if args.threshold is not None:
        out["threshold"] = number("--threshold", args.threshold, minimum=0.5, exclusive=True, below=1.0)
    if args.dwell_s is not None:
        out["dwell_s"] = number("--dwell-s", args.dwell_s, minimum=0.0, maximum=DWELL_S_MAX)
    if args.p_min is not None:
        out["p_min"] = number("--p-min", args.p_min, minimum=0.0, below=round(1.0 / K_BANK, 6))
    if args.trim_tracking is not None:
        out["trim_time_constant_s"] = number("--trim-tracking", args.trim_tracking, minimum=0.0, exclusive=True,
                                             maximum=1e6)
    if args.trim_freeze_probability is not None:
        if args.trim_tracking is None:
            raise CliError("--trim-freeze-probability applies with --trim-tracking only")
        out["trim_freeze_probability"] = number("--trim-freeze-probability", args.trim_freeze_probability,
                                                minimum=0.0, exclusive=True, maximum=1.0)
    if getattr(args, "adapt_turbulence", False):
        out["adapt_turbulence"] = True
    if getattr(args, "maneuver_kinematics", False):
        out["maneuver_kinematics"] = True
    if getattr(args, "actuator_limits", False):
        out["actuator_limits"] = True
    if getattr(args, "maneuver_tempering", None) is not None:
        out["maneuver_tempering_g"] = number("--maneuver-tempering", args.maneuver_tempering, minimum=0.0,
                                             exclusive=True, maximum=100.0)
    if args.schedule_mode is not None:
        out["schedule_mode"] = choice("--schedule-mode", args.schedule_mode, SCHEDULE_MODES)
    return out


def auth_from_option(path: str | None):
    """``--auth-key FILE`` as a ``core.FrameAuth`` (None without the option); CliError naming
    the file and what is wrong with it."""
    if path is None:
        return None
    try:
        return core.FrameAuth.from_key_file(path)
    except ValueError as exc:
        raise CliError(f"--auth-key: {exc}") from None
