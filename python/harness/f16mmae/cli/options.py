"""Options every command shares: range-checked numbers and choices (a :class:`CliError` names
the option, the bad value and the valid range or choices), comma lists, and the estimator
settings of ``run``, ``hil`` and the campaigns."""
from __future__ import annotations

import argparse
import math
import os

from .. import core
from ..errors import F16mmaeError
from ..loop.estimator_options import COMMAND_LINE, check
from ..names import FLIGHT_S_MAX


class CliError(F16mmaeError):
    """A bad argument: the message names the bad value and the valid choices."""


#: Seeds are 32-bit signed integers for JSBSim; 0 means 1 to it, so seeds start at 1.
SEED_MAX = 2**31 - 1
#: ``--no-dither``'s help on ``run`` and the campaigns (docs/results/excitation.md, round 36).
NO_DITHER_HELP = ("fly without dither (the paper always dithers): the banks are designed with it, and without it "
                  "every shipped estimator declares falsely (docs/results/excitation.md)")


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
    """The estimator's settings (``loop.estimator_options``): the declarer and floor of
    core.HierarchicalBank and its on-line options.  Unset, --threshold / --dwell-s / --p-min are
    the bank's recommended settings (its typed fields, from the tuning's [estimator] table; the
    shipped tuned bank: p_min 1e-9, threshold 0.9, dwell 0.25 s), else the core's default (the
    paper's: 0.001, 0.9, 0.25 s); every on-line option is off unless given."""
    for o in COMMAND_LINE:
        if o.negatable:   # on in a default setting: --no-FLAG turns it off
            p.add_argument(o.flag, action=argparse.BooleanOptionalAction, default=None, help=o.help)
        elif o.kind == "switch":
            p.add_argument(o.flag, action="store_true", help=o.help)
        else:
            p.add_argument(o.flag, default=None, metavar=o.metavar, help=o.help)


def estimator_options_from_args(args) -> dict:
    """The estimator settings given, each checked against its table row
    (``loop.estimator_options.check``: range, choices, the option it applies with)."""
    out = {}
    for o in COMMAND_LINE:
        value = getattr(args, o.dest, None)
        if value is None or (value is False and not o.negatable):
            continue
        if o.kind == "switch":
            out[o.key] = bool(value)
        elif o.kind == "choice":
            out[o.key] = choice(o.flag, value, o.choices)
        elif o.kind == "file":   # a path, made absolute; a table inline as given
            out[o.key] = value if o.is_inline(value) else os.path.abspath(value)
        elif o.kind == "table":
            out[o.key] = value
        else:
            out[o.key] = number(o.flag, value)
    try:
        check(out)
    except ValueError as exc:
        raise CliError(str(exc)) from None
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
