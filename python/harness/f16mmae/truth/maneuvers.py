"""Scenario maneuvers: what the pilot commands, when, and the ``--maneuver`` grammar.

A maneuver is ``KIND@TIME:KEY=VALUE[:KEY=VALUE]`` (kinds and keys lower case, units optional
but, when written, exactly the ones below)::

    climb@T:to=ALTft[:rate=Rfpm]       climb to ALT ft at R ft/min (default 2000 fpm)
    descend@T:to=ALTft[:rate=Rfpm]     descend to ALT ft at R ft/min (default 2000 fpm)
    accel@T:to=Mmach[:rate=Rmach/s]    accelerate to Mach M at R Mach/s (default 0.005)
    decel@T:to=Mmach[:rate=Rmach/s]    decelerate to Mach M at R Mach/s (default 0.005)
    turn@T:bank=Bdeg[:for=Ss]          level turn at bank B deg (right +, |B| <= 60; 0 rolls
                                       out), held S s then rolled out (default: until the next turn)

T is the start time (s).  E.g. ``climb@5:to=25000ft:rate=3000fpm``, ``turn@20:bank=30``,
``accel@40:to=0.6mach``.  Altitude targets lie in 5,000-35,000 ft, Mach targets in 0.3-0.8
(the trimmable envelope), rates are positive (climb/descent at most 10,000 fpm, speed changes at
most 0.05 Mach/s).  Three independent channels: vertical (climb, descend), speed (accel, decel)
and lateral (turn); a channel's maneuvers may not overlap in time, maneuvers of different
channels may (a climbing turn).  :func:`check_schedule` checks a list against the flight's
start condition: each climb goes up from the altitude the previous vertical maneuver left,
each descent down, and likewise for accel / decel.

This is the PILOT's schedule: it goes to the truth model's outer loop
(:mod:`.outer_loop`), never to the estimator.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import F16mmaeError
from .aircraft import ALT_FT_RANGE, MACH_RANGE

#: The maneuver kinds, by channel.
VERTICAL = ("climb", "descend")
SPEED = ("accel", "decel")
LATERAL = ("turn",)
KINDS: tuple[str, ...] = VERTICAL + SPEED + LATERAL

DEFAULT_CLIMB_RATE_FPM = 2000.0
MAX_CLIMB_RATE_FPM = 10_000.0
DEFAULT_MACH_RATE_PER_S = 0.005
MAX_MACH_RATE_PER_S = 0.05
MAX_BANK_DEG = 60.0

FORMS = ("climb@T:to=ALTft[:rate=Rfpm] | descend@T:to=ALTft[:rate=Rfpm] | "
         "accel@T:to=Mmach[:rate=Rmach/s] | decel@T:to=Mmach[:rate=Rmach/s] | "
         "turn@T:bank=Bdeg[:for=Ss]")

# key -> unit suffix, per kind; the first key is required.
_KEYS = {
    "climb": (("to", "ft"), ("rate", "fpm")),
    "descend": (("to", "ft"), ("rate", "fpm")),
    "accel": (("to", "mach"), ("rate", "mach/s")),
    "decel": (("to", "mach"), ("rate", "mach/s")),
    "turn": (("bank", "deg"), ("for", "s")),
}


class ManeuverError(F16mmaeError, ValueError):
    """A maneuver spec or schedule is invalid; the message names the token and the valid forms."""


@dataclass(frozen=True)
class ManeuverSpec:
    """One maneuver: ``kind`` (:data:`KINDS`), start ``time_s``, ``target`` (ft, Mach or bank
    deg) and ``rate`` (ft/min, Mach/s, or for a turn its hold time in s; None = default or,
    for a turn, until the next turn)."""

    kind: str
    time_s: float
    target: float
    rate: float | None = None

    @property
    def channel(self) -> str:
        return "vertical" if self.kind in VERTICAL else ("speed" if self.kind in SPEED else "lateral")

    @property
    def rate_value(self) -> float | None:
        """The rate in force (the default if none was given; a turn's hold time or None)."""
        if self.rate is not None or self.kind in LATERAL:
            return self.rate
        return DEFAULT_CLIMB_RATE_FPM if self.kind in VERTICAL else DEFAULT_MACH_RATE_PER_S

    @property
    def end_s(self) -> float:
        """When the maneuver's command stops changing (a turn: when it rolls out, inf if held)."""
        if self.kind in LATERAL:
            return math.inf if self.rate is None else self.time_s + self.rate
        return math.inf  # a ramp's end depends on where it starts: see check_schedule

    def __str__(self) -> str:
        (k0, u0), (k1, u1) = _KEYS[self.kind]
        text = f"{self.kind}@{self.time_s:g}:{k0}={self.target:g}{u0}"
        return text + ("" if self.rate is None else f":{k1}={self.rate:g}{u1}")


def _number(token: str, text: str, what: str, unit: str) -> float:
    body = text[: -len(unit)] if text.lower().endswith(unit) else text
    try:
        x = float(body)
    except ValueError:
        raise ManeuverError(f"maneuver {token!r}: {what} {text!r} is not a number (in {unit}); "
                            f"valid forms: {FORMS}") from None
    if not math.isfinite(x):
        raise ManeuverError(f"maneuver {token!r}: {what} {text!r} must be finite")
    return x


def parse_maneuver(token: str) -> ManeuverSpec:
    """One ``--maneuver`` / TOML string (module docstring) -> ManeuverSpec; ManeuverError
    naming the token and the valid forms."""
    if not isinstance(token, str):
        raise ManeuverError(f"a maneuver must be a string like 'climb@5:to=25000ft', got {token!r}; "
                            f"valid forms: {FORMS}")
    head, *fields = token.strip().split(":")
    kind, at, when = head.partition("@")
    kind = kind.strip().lower()
    if kind not in KINDS:
        raise ManeuverError(f"maneuver {token!r}: unknown kind {kind!r}; valid forms: {FORMS}")
    if not at:
        raise ManeuverError(f"maneuver {token!r} has no start time ('{kind}@T:...'); valid forms: {FORMS}")
    time_s = _number(token, when.strip(), "start time", "s")
    if time_s < 0:
        raise ManeuverError(f"maneuver {token!r}: start time {time_s:g} s must be >= 0")
    keys = dict(_KEYS[kind])
    values: dict[str, float] = {}
    for f in fields:
        key, eq, val = f.partition("=")
        key = key.strip().lower()
        if not eq or key not in keys:
            raise ManeuverError(f"maneuver {token!r}: bad field {f!r}; a {kind} takes "
                                f"{', '.join(f'{k}=...{u}' for k, u in _KEYS[kind])}; valid forms: {FORMS}")
        if key in values:
            raise ManeuverError(f"maneuver {token!r} gives {key} twice")
        values[key] = _number(token, val.strip(), key, keys[key])
    k0, k1 = (k for k, _ in _KEYS[kind])
    if k0 not in values:
        raise ManeuverError(f"maneuver {token!r} needs {k0}=...; valid forms: {FORMS}")
    return make_maneuver(kind, time_s, values[k0], values.get(k1), token)


def make_maneuver(kind: str, time_s: float, target: float, rate: float | None = None,
                  token: str | None = None) -> ManeuverSpec:
    """A checked ManeuverSpec (ranges of the module docstring)."""
    token = token or f"{kind}@{time_s}"
    if kind in VERTICAL:
        if not ALT_FT_RANGE[0] <= target <= ALT_FT_RANGE[1]:
            raise ManeuverError(f"maneuver {token!r}: altitude {target:g} ft outside "
                                f"{ALT_FT_RANGE[0]:.0f}-{ALT_FT_RANGE[1]:.0f} ft")
        if rate is not None and not 0 < rate <= MAX_CLIMB_RATE_FPM:
            raise ManeuverError(f"maneuver {token!r}: rate {rate:g} fpm must lie in (0, {MAX_CLIMB_RATE_FPM:g}]")
    elif kind in SPEED:
        if not MACH_RANGE[0] <= target <= MACH_RANGE[1]:
            raise ManeuverError(f"maneuver {token!r}: Mach {target:g} outside {MACH_RANGE[0]}-{MACH_RANGE[1]}")
        if rate is not None and not 0 < rate <= MAX_MACH_RATE_PER_S:
            raise ManeuverError(f"maneuver {token!r}: rate {rate:g} Mach/s must lie in (0, {MAX_MACH_RATE_PER_S:g}]")
    else:
        if not abs(target) <= MAX_BANK_DEG:
            raise ManeuverError(f"maneuver {token!r}: bank {target:g} deg must lie in "
                                f"[-{MAX_BANK_DEG:g}, {MAX_BANK_DEG:g}]")
        if rate is not None and not rate > 0:
            raise ManeuverError(f"maneuver {token!r}: for={rate:g} s must be > 0")
    return ManeuverSpec(kind, float(time_s), float(target), None if rate is None else float(rate))


def ramp_end_s(start_value: float, m: ManeuverSpec) -> float:
    """When a climb/descent/speed change that starts from ``start_value`` reaches its target."""
    if m.kind in LATERAL:
        return m.end_s
    per_s = m.rate_value / 60.0 if m.kind in VERTICAL else m.rate_value
    return m.time_s + abs(m.target - start_value) / per_s


def check_schedule(maneuvers, mach: float, alt_ft: float) -> tuple[ManeuverSpec, ...]:
    """Sorted by start time and checked against the start condition (module docstring)."""
    ms = tuple(sorted((parse_maneuver(m) if isinstance(m, str) else m for m in maneuvers),
                      key=lambda m: m.time_s))
    for m in ms:
        if not isinstance(m, ManeuverSpec):
            raise ManeuverError(f"maneuvers must be strings or ManeuverSpec objects, got {m!r}")
    state = {"vertical": float(alt_ft), "speed": float(mach), "lateral": 0.0}
    busy = {"vertical": (-math.inf, None), "speed": (-math.inf, None), "lateral": (-math.inf, None)}
    for m in ms:
        end, prev = busy[m.channel]
        if m.time_s < end:
            raise ManeuverError(f"maneuver {m} starts before {prev} has finished (at {end:g} s); "
                                "maneuvers of one channel may not overlap")
        if m.kind in ("climb", "accel") and not m.target > state[m.channel]:
            raise ManeuverError(f"maneuver {m}: the target is not above {state[m.channel]:g}, "
                                f"where the flight is then (use {'descend' if m.kind == 'climb' else 'decel'})")
        if m.kind in ("descend", "decel") and not m.target < state[m.channel]:
            raise ManeuverError(f"maneuver {m}: the target is not below {state[m.channel]:g}, "
                                f"where the flight is then (use {'climb' if m.kind == 'descend' else 'accel'})")
        busy[m.channel] = (ramp_end_s(state[m.channel], m) if m.kind not in LATERAL
                           else (m.time_s if m.rate is None else m.end_s), m)
        state[m.channel] = m.target
    return ms


__all__ = ["KINDS", "FORMS", "ManeuverError", "ManeuverSpec", "check_schedule", "make_maneuver",
           "parse_maneuver", "ramp_end_s"]
