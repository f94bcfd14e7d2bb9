"""Options every command shares: range-checked numbers and choices (a :class:`CliError` names
the option, the bad value and the valid range or choices), comma lists, and the estimator
settings of ``run``, ``hil`` and the campaigns."""
from __future__ import annotations

import math

from ..errors import F16mmaeError


class CliError(F16mmaeError):
    """A bad argument: the message names the bad value and the valid choices."""


def number(option: str, value, *, integer: bool = False, minimum=None, exclusive: bool = False,
           below=None):
    """``value`` of ``option`` as an int (``integer``) or a finite float, at least ``minimum``
    (above it if ``exclusive``) and below ``below``; CliError naming the option, the value
    and the valid range otherwise."""
    try:
        x = int(value) if integer else float(value)
    except (TypeError, ValueError):
        kind = "an integer" if integer else "a number"
        raise CliError(f"{option} {value!r} is not {kind}") from None
    if not integer and not math.isfinite(x):
        raise CliError(f"{option} {value!r} must be finite")
    if minimum is not None and (x <= minimum if exclusive else x < minimum):
        raise CliError(f"{option} {value!r} must be {'>' if exclusive else '>='} {minimum}")
    if below is not None and not x < below:
        raise CliError(f"{option} {value!r} must be < {below}")
    return x


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


def estimator_options_from_args(args) -> dict:
    out = {}
    for opt, key in (("--threshold", "threshold"), ("--dwell-s", "dwell_s"), ("--p-min", "p_min")):
        value = getattr(args, key)
        if value is None:
            continue
        out[key] = number(opt, value)
    return out
