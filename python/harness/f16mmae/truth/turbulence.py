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

The turbulence axes: JSBSim draws the Dryden gusts in axes turned by the mean wind's heading
``atmosphere/psiw-rad`` (x along it), and turns the roll and pitch gusts with the horizontal
ones but not the yaw gust, so the yaw gust's sign against the side gust, and the pitch gust's
against the vertical one, flip with the axes.  With no mean wind the heading is whatever the
sign of a round-off wind left by the trimmed initial condition makes it (about 1e-12 ft/s, from
``run_ic``): 0 at some flight conditions and pi at others, about half the envelope each, the
nominal point at pi.  The truth therefore fixes the axes at ``TURBULENCE_AXES_PSI_RAD`` with the
mean wind exactly zero at every flight's start (:func:`hold_axes`, called by ``aircraft.trim`` and
``aircraft.restart``), so every flight condition flies one turbulence model: the nominal point's,
whose yaw gust the filters' Dryden gust states were fitted to (design/gust_states.py).  Neither
heading makes both rotational gusts physical: the aerodynamics see p - p_g, q - q_g, r - r_g
(FGAuxiliary), so a gust field frozen in the air gives q_g = -dw_g/dx and r_g = +dv_g/dx along the
fuselage, of opposite signs against the time derivatives of w_g and v_g, while JSBSim's form
(MIL-STD-1797A's first-order filters) gives both the same sign: at pi the pitch gust has the
physical sign and the yaw gust the other, at 0 the reverse.  Before, a filter with gust states
read the other half's yaw gusts with the wrong sign, and the rudder was declared falsely there in
moderate air (docs/results/envelope_scheduled.md, round 47).

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
#: The heading (rad) of JSBSim's turbulence axes in every flight (module docstring): x pointing
#: south, against the trimmed flight path (the aircraft is trimmed flying north).
TURBULENCE_AXES_PSI_RAD = math.pi


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


def hold_axes(fdm) -> None:
    """Fix ``fdm``'s turbulence axes at TURBULENCE_AXES_PSI_RAD with no mean wind (module
    docstring).  JSBSim sets the axes' heading through a wind (at zero wind it resets it to 0)
    and recomputes it from the mean wind whenever the wind's north component is not zero, so the
    heading is set with a wind that is then zeroed exactly."""
    fdm["atmosphere/wind-north-fps"] = 1.0
    fdm["atmosphere/psiw-rad"] = TURBULENCE_AXES_PSI_RAD
    for axis in ("north", "east", "down"):
        fdm[f"atmosphere/wind-{axis}-fps"] = 0.0


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
