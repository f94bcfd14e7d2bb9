"""The five F-16 surface actuators (LS RS LF RF RUD) and the mixing into JSBSim's controls.

Each actuator is a first-order lag with a rate limit and position limits (Stevens & Lewis,
*Aircraft Control and Simulation*, F-16 model: all actuators a lag of 20.2 rad/s, i.e.
tau = 0.0495 s; stabilators +-25 deg at 60 deg/s, ailerons/flaperons +-21.5 deg at 80 deg/s,
rudder +-30 deg at 120 deg/s)::

    d(delta)/dt = sat_rate( LAG_RAD_S * (delta_cmd - delta) ),   |delta| <= POSITION_LIMIT_RAD

integrated exactly over each JSBSim step dt: delta+ = c + (delta - c) exp(-LAG_RAD_S dt) with
c = clip(delta_cmd, +-limit), then the change is clipped to +-RATE_LIMIT_RAD_S * dt.
Sign convention: stabilators and flaperons trailing edge down positive, rudder trailing edge
left positive (JSBSim's).

Mixing (``aircraft`` module): the stock aerodynamics see v = MIXING @ delta, rows
(elevator, aileron, flaperon-mix, rudder) in rad::

    elevator = (LS + RS)/2
    aileron  = (LF - RF)/2 + k (LS - RS)/2      (positive rolls right)
    flaperon = LF + RF
    rudder   = RUD

k = DIFFERENTIAL_TAIL_ROLL_SHARE = 0.5 is a modelling choice: JSBSim's F-16 tables have no
separate differential-tail data, so a differential stabilator deflection is credited with half
the roll (and adverse-yaw, side-force) effectiveness of the same flaperon deflection.  A stuck
left stabilator therefore produces pitch AND roll/yaw moments, as on the aircraft.

Failures (``failures`` module) act inside :class:`ActuatorBank.step`:
``complete`` returns the surface to its trim deflection at the rate limit and holds it there
(the paper's model: the command has no effect), ``stuck`` holds it where it is, ``hardover``
drives it at the rate limit to a position limit (``value`` = +1 / -1 selects the side),
``loss`` lets it move but the aerodynamics see only trim + value * (delta - trim)
(0 <= value < 1; ``loss`` with value 0 is ``complete`` without the return transient).
"""
from __future__ import annotations

import math

import numpy as np

from ..names import ACTUATORS

_DEG = math.pi / 180.0
#: First-order lag break frequency (rad/s), all surfaces (Stevens & Lewis F-16).
LAG_RAD_S: tuple[float, ...] = (20.2,) * 5
#: Position limits (rad), order LS RS LF RF RUD: 25, 25, 21.5, 21.5, 30 deg.
POSITION_LIMIT_RAD: tuple[float, ...] = (25 * _DEG, 25 * _DEG, 21.5 * _DEG, 21.5 * _DEG, 30 * _DEG)
#: Rate limits (rad/s): 60, 60, 80, 80, 120 deg/s.
RATE_LIMIT_RAD_S: tuple[float, ...] = (60 * _DEG, 60 * _DEG, 80 * _DEG, 80 * _DEG, 120 * _DEG)
#: Roll effectiveness of stabilator differential relative to flaperon differential.
DIFFERENTIAL_TAIL_ROLL_SHARE = 0.5
#: Rows of MIXING: the stock JSBSim control properties the mixer writes.
MIXED_CONTROLS: tuple[str, ...] = ("elevator_rad", "aileron_rad", "flaperon_mix_rad", "rudder_rad")
_k = DIFFERENTIAL_TAIL_ROLL_SHARE
#: (4, 5) map from surface positions (LS RS LF RF RUD, rad) to the four JSBSim controls (rad).
MIXING = np.array([
    [0.5, 0.5, 0.0, 0.0, 0.0],
    [0.5 * _k, -0.5 * _k, 0.5, -0.5, 0.0],
    [0.0, 0.0, 1.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 0.0, 1.0],
])
MIXING.setflags(write=False)
#: Scale (rad per unit) of JSBSim's normalized elevator/aileron/rudder commands, used only by
#: the trim routine (equals the stock aerosurface ranges: 25, 21.5, 30 deg).
TRIM_COMMAND_SCALE_RAD: tuple[float, float, float] = (0.436, 0.375, 0.524)

#: Failure modes of an actuator, in the issue's order.
ACTUATOR_MODES: tuple[str, ...] = ("complete", "stuck", "hardover", "loss")
#: Default ``value`` per mode (None: the mode takes none).
ACTUATOR_MODE_DEFAULT_VALUE: dict[str, float | None] = {
    "complete": None, "stuck": None, "hardover": 1.0, "loss": 0.5,
}

_NORMAL, _COMPLETE, _STUCK, _HARDOVER, _LOSS = range(5)
_MODE_CODE = {"complete": _COMPLETE, "stuck": _STUCK, "hardover": _HARDOVER, "loss": _LOSS}
#: Failure mode -> code, the codes of ``ActuatorMode`` in cpp/truth/truth_frame.h.
MODE_CODE: dict[str, int] = dict(_MODE_CODE)


class ActuatorBank:
    """The five actuators, stepped at the JSBSim rate.

    trim_rad (5,): trim deflections (rad), also the initial positions; dt_s: step (s).
    ``step(cmd)`` takes five commands (rad) and returns the five EFFECTIVE positions (rad) to
    write into the aircraft; ``position_rad`` holds the physical positions.
    """

    def __init__(self, trim_rad, dt_s: float):
        self.trim_rad = [float(x) for x in trim_rad]
        if len(self.trim_rad) != 5:
            raise ValueError(f"trim_rad needs 5 entries ({', '.join(ACTUATORS)}), got {len(self.trim_rad)}")
        self.dt_s = float(dt_s)
        self._decay = [math.exp(-a * self.dt_s) for a in LAG_RAD_S]
        self._max_step = [r * self.dt_s for r in RATE_LIMIT_RAD_S]
        self.position_rad = list(self.trim_rad)
        self._mode = [_NORMAL] * 5
        self._value = [0.0] * 5

    @property
    def decay(self) -> list[float]:
        """exp(-LAG_RAD_S dt_s) per actuator: the lag's factor over one step."""
        return list(self._decay)

    @property
    def max_step_rad(self) -> list[float]:
        """RATE_LIMIT_RAD_S dt_s per actuator: the largest move in one step (rad)."""
        return list(self._max_step)

    def fail(self, index: int, mode: str, value: float | None = None) -> None:
        """Fail actuator ``index`` (0..4) with ``mode`` from ACTUATOR_MODES from now on."""
        if mode not in _MODE_CODE:
            raise ValueError(f"unknown actuator failure mode {mode!r}; valid: {', '.join(ACTUATOR_MODES)}")
        if value is None:
            value = ACTUATOR_MODE_DEFAULT_VALUE[mode]
        self._mode[index] = _MODE_CODE[mode]
        self._value[index] = float(value) if value is not None else 0.0

    def step(self, cmd_rad) -> list[float]:
        """Advance one JSBSim step with commands ``cmd_rad`` (5, rad); return effective positions."""
        out = [0.0] * 5
        pos = self.position_rad
        for i in range(5):
            mode = self._mode[i]
            lim = POSITION_LIMIT_RAD[i]
            p = pos[i]
            if mode == _STUCK:
                out[i] = p
                continue
            if mode == _COMPLETE:
                target = self.trim_rad[i]
                new = target  # reached through the rate limit below
            elif mode == _HARDOVER:
                new = lim if self._value[i] >= 0.0 else -lim
            else:
                c = cmd_rad[i]
                c = lim if c > lim else (-lim if c < -lim else c)
                new = c + (p - c) * self._decay[i]
            d = new - p
            m = self._max_step[i]
            if d > m:
                d = m
            elif d < -m:
                d = -m
            p += d
            p = lim if p > lim else (-lim if p < -lim else p)
            pos[i] = p
            if mode == _LOSS:
                t = self.trim_rad[i]
                out[i] = t + self._value[i] * (p - t)
            else:
                out[i] = p
        return out
