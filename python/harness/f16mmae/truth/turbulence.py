"""Dryden turbulence (MIL-F-8785C) through JSBSim's own turbulence model.

Levels map to JSBSim's ``atmosphere/turb-type = 3`` (MIL-F-8785C Dryden, "milspec") and
``atmosphere/turbulence/milspec/severity``, an index into the specification's
probability-of-exceedance (POE) curves of high-altitude gust intensity::

    level      severity   POE of the gust intensity   (MIL-F-8785C definition)
    none       0          turbulence off (turb-type 0)
    light      3          1e-2
    moderate   4          1e-3
    severe     6          1e-5

Below 1,000 ft the intensity follows the 20-ft wind (set to 15 / 30 / 45 kt for light /
moderate / severe, the specification's low-altitude definitions); above, the POE curve.
Seeds: JSBSim draws the gusts from ``simulation/randomseed`` set at load time (aircraft.load_fdm).

A gust burst (``GustBurst``, the CLI's ``--gust-burst LEVEL@START+DURATION``) switches the
turbulence to another level for a while: from the first frame whose time is >= start_s the
level is ``level``, from the first frame >= start_s + duration_s the scenario's own level
again (``schedule`` gives those frames; the truth model applies each before that frame's
JSBSim steps, on both engines).

GUST_SIGMA_FPS lists the gust intensity (standard deviation of the NED gust velocity
components, ft/s, average of north and down) MEASURED from JSBSim over 60 s at Mach 0.4
(0.6 at 35,000 ft), seed 1, per level and altitude; the lateral component is about 20 %
lower.  Roll-rate gusts p_g: about 1.9 / 3.7 / 9.4 deg/s at 20,000 ft.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..names import TURBULENCE_LEVELS

#: JSBSim ``atmosphere/turbulence/milspec/severity`` per level.
MILSPEC_SEVERITY: dict[str, int] = {"none": 0, "light": 3, "moderate": 4, "severe": 6}
#: Probability of exceedance of the gust intensity per level (MIL-F-8785C).
PROBABILITY_OF_EXCEEDANCE: dict[str, float | None] = {
    "none": None, "light": 1e-2, "moderate": 1e-3, "severe": 1e-5,
}
#: 20-ft wind (ft/s) per level, effective only below 1,000 ft AGL: 0, 15, 30, 45 kt.
WIND_20FT_FPS: dict[str, float] = {"none": 0.0, "light": 25.3, "moderate": 50.6, "severe": 76.0}
#: Measured gust intensity sigma (ft/s) per level at altitude_ft -> sigma.
GUST_SIGMA_FPS: dict[str, dict[int, float]] = {
    "none": {5_000: 0.0, 20_000: 0.0, 35_000: 0.0},
    "light": {5_000: 7.2, 20_000: 3.7, 35_000: 0.4},
    "moderate": {5_000: 10.5, 20_000: 7.4, 35_000: 5.0},
    "severe": {5_000: 18.3, 20_000: 21.3, 35_000: 16.0},
}
#: JSBSim turbulence-type code of MIL-F-8785C Dryden.
TURB_TYPE_MILSPEC_DRYDEN = 3


def check_level(level: str) -> str:
    """Return ``level`` lower-cased, or raise ValueError naming the valid levels."""
    lv = str(level).lower()
    if lv not in MILSPEC_SEVERITY:
        raise ValueError(f"unknown turbulence level {level!r}; valid: {', '.join(TURBULENCE_LEVELS)}")
    return lv


@dataclass(frozen=True)
class GustBurst:
    """The turbulence at ``level`` from ``start_s`` for ``duration_s`` seconds (module docstring)."""

    level: str
    start_s: float
    duration_s: float

    def __post_init__(self):
        object.__setattr__(self, "level", check_level(self.level))
        for name in ("start_s", "duration_s"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0.0:
                raise ValueError(f"gust burst {name} must be a finite number of seconds >= 0, got {v!r}")
            object.__setattr__(self, name, float(v))
        if self.duration_s <= 0.0:
            raise ValueError(f"gust burst duration_s must be > 0 s, got {self.duration_s!r}")

    @classmethod
    def parse(cls, text: str) -> "GustBurst":
        """``LEVEL@START+DURATION`` (e.g. ``severe@3.0+2.0``); ValueError naming the format."""
        form = (f"expected LEVEL@START+DURATION with LEVEL one of {', '.join(TURBULENCE_LEVELS)} "
                f"and times in s, e.g. severe@3.0+2.0")
        level, at, rest = str(text).partition("@")
        start, plus, duration = rest.partition("+")
        if not at or not plus:
            raise ValueError(f"gust burst {text!r}: {form}")
        try:
            return cls(level.strip(), float(start), float(duration))
        except ValueError as exc:
            raise ValueError(f"gust burst {text!r}: {form} ({exc})") from None

    def to_dict(self) -> dict:
        return {"level": self.level, "start_s": self.start_s, "duration_s": self.duration_s}

    def text(self) -> str:
        return f"{self.level}@{self.start_s!r}+{self.duration_s!r}"

    def schedule(self, base_level: str, frame_rate_hz: float) -> list[tuple[int, str]]:
        """[(frame, level)]: the burst's level from its first frame, ``base_level`` from its end."""
        eps = 1e-6
        first = math.ceil(self.start_s * frame_rate_hz - eps)
        end = math.ceil((self.start_s + self.duration_s) * frame_rate_hz - eps)
        return [(first, self.level), (max(end, first + 1), check_level(base_level))]


def apply(fdm, level: str) -> None:
    """Switch ``fdm``'s turbulence to ``level`` (none, light, moderate, severe)."""
    lv = check_level(level)
    if lv == "none":
        fdm["atmosphere/turb-type"] = 0
        fdm["atmosphere/turbulence/milspec/severity"] = 0
        return
    fdm["atmosphere/turb-type"] = TURB_TYPE_MILSPEC_DRYDEN
    fdm["atmosphere/turbulence/milspec/windspeed_at_20ft_AGL-fps"] = WIND_20FT_FPS[lv]
    fdm["atmosphere/turbulence/milspec/severity"] = MILSPEC_SEVERITY[lv]
