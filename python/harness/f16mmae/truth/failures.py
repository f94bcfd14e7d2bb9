"""Failure specifications: which component fails, when, how; and the ``--fail`` parser.

A failure is ``FailureSpec(name, time_s, mode, value)``: ``name`` one of the five actuators
(LS RS LF RF RUD) or seven sensors (VEL AOA PIT AZ ROL YAW AY) of ``names``; ``time_s >= 0``
the onset (s from the start of the run); ``mode`` (default ``complete``, the paper's model):

    actuators  complete | stuck | hardover | loss       (see truth.actuators)
    sensors    complete | null | stuck | hardover | bias | drift   (see truth.sensors)

``value`` parameterises a mode (hardover side +1/-1; loss: remaining effectiveness fraction
0 <= f < 1; bias: offset in the sensor's unit; drift: rate in unit/s); None takes the default.
CLI syntax (repeatable): ``--fail NAME@TIME[:MODE[=VALUE]]``, names and modes case-insensitive,
e.g. ``LS@3.0``, ``PIT@5:stuck``, ``AZ@2:bias=0.2``, ``RUD@1:hardover=-1``.
This is failure TRUTH: it goes to the truth model and the record, never to the estimator.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..names import ACTUATORS, SENSORS
from .actuators import ACTUATOR_MODES
from .sensors import SENSOR_MODES

#: Every failable component, actuators then sensors.
COMPONENTS: tuple[str, ...] = ACTUATORS + SENSORS
DEFAULT_MODE = "complete"


@dataclass(frozen=True)
class FailureSpec:
    """One injected failure: component ``name``, onset ``time_s`` (s), ``mode``, ``value``."""

    name: str
    time_s: float
    mode: str = DEFAULT_MODE
    value: float | None = None

    @property
    def is_actuator(self) -> bool:
        return self.name in ACTUATORS

    @property
    def index(self) -> int:
        """Index in ``u`` (actuator) or ``z`` (sensor)."""
        return ACTUATORS.index(self.name) if self.is_actuator else SENSORS.index(self.name)

    def to_dict(self) -> dict:
        d = {"name": self.name, "time_s": self.time_s, "mode": self.mode}
        if self.value is not None:
            d["value"] = self.value
        return d

    def __str__(self) -> str:
        tail = "" if self.value is None else f"={self.value:g}"
        return f"{self.name}@{self.time_s:g}:{self.mode}{tail}"


def modes_for(name: str) -> tuple[str, ...]:
    """The failure modes valid for component ``name``."""
    return ACTUATOR_MODES if name in ACTUATORS else SENSOR_MODES


def make_failure(name: str, time_s: float, mode: str | None = None,
                 value: float | None = None) -> FailureSpec:
    """A validated FailureSpec (name/mode case-insensitive); ValueError names the valid choices."""
    nm = str(name).strip().upper()
    if nm not in COMPONENTS:
        raise ValueError(f"unknown failure name {name!r}; valid: {', '.join(COMPONENTS)}")
    try:
        t = float(time_s)
    except (TypeError, ValueError):
        raise ValueError(f"failure time {time_s!r} of {nm} is not a number") from None
    if not math.isfinite(t) or t < 0.0:
        raise ValueError(f"failure time of {nm} must be a finite number >= 0 s, got {time_s}")
    md = DEFAULT_MODE if mode is None or str(mode).strip() == "" else str(mode).strip().lower()
    valid = modes_for(nm)
    if md not in valid:
        kind = "actuator" if nm in ACTUATORS else "sensor"
        raise ValueError(f"unknown failure mode {mode!r} for {kind} {nm}; valid: {', '.join(valid)}")
    v = None
    if value is not None:
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"failure value {value!r} of {nm}:{md} is not a number") from None
        if not math.isfinite(v):
            raise ValueError(f"failure value of {nm}:{md} must be finite, got {value}")
        if md in ("complete", "stuck", "null"):
            raise ValueError(f"failure mode {md} of {nm} takes no value, got {value}")
        if md == "loss" and not (0.0 <= v < 1.0):
            raise ValueError(f"loss of {nm}: remaining effectiveness must be in [0, 1), got {v}")
        if md == "hardover" and v == 0.0:
            raise ValueError(f"hardover of {nm}: value selects the side, +1 or -1, got 0")
    return FailureSpec(nm, t, md, v)


def parse_fail(text: str) -> FailureSpec:
    """Parse ``NAME@TIME[:MODE[=VALUE]]`` (the CLI's ``--fail``); ValueError on bad input."""
    s = str(text).strip()
    syntax = "expected NAME@TIME[:MODE[=VALUE]], e.g. LS@3.0 or PIT@5.0:stuck"
    if "@" not in s:
        raise ValueError(f"bad failure {text!r}: {syntax}; names: {', '.join(COMPONENTS)}")
    name, rest = s.split("@", 1)
    time_txt, _, mode_txt = rest.partition(":")
    mode, _, value = mode_txt.partition("=")
    if not time_txt.strip():
        raise ValueError(f"bad failure {text!r}: missing time; {syntax}")
    return make_failure(name, time_txt.strip(), mode or None, value.strip() or None)


#: Alias of :func:`parse_fail`.
parse_failure = parse_fail


def parse_fail_args(texts) -> tuple[FailureSpec, ...]:
    """Parse several ``--fail`` texts, sorted by onset; a component may fail only once."""
    specs = tuple(sorted((parse_fail(t) for t in texts or ()), key=lambda f: f.time_s))
    check_unique(specs)
    return specs


def check_unique(specs) -> None:
    """Raise ValueError if a component is failed twice."""
    seen: set[str] = set()
    for f in specs:
        if f.name in seen:
            raise ValueError(f"component {f.name} is failed more than once; give one failure per component")
        seen.add(f.name)
