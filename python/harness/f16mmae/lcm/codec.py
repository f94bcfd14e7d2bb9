"""Frames on the wire: a frame's simulation time and its encoded sensor and command messages
(docs/INTERFACES.md)."""
from __future__ import annotations

import math

from ..lcmt_command_frame import lcmt_command_frame
from ..lcmt_sensor_frame import lcmt_sensor_frame
from ..names import FRAME_RATE_HZ


def frame_utime(i: int, rate_hz: float = FRAME_RATE_HZ) -> int:
    """Simulation time of frame i in microseconds (exact for 64 Hz: 15625 us per frame)."""
    return int(round(i * 1e6 / rate_hz))


def sensor_frame_bytes(i: int, z, air_data=(math.nan, math.nan), valid: bool = True,
                       rate_hz: float = FRAME_RATE_HZ) -> bytes:
    """Frame ``i``'s measurements ``z`` (absolute, names.SENSORS order) and measured air data
    ``air_data`` = (Mach, pressure altitude ft) as an encoded ``lcmt_sensor_frame`` (utime =
    i / rate_hz); ``valid`` flags every sensor.  Without ``air_data`` (a sender with no air data
    system) both fields are NaN: the executive keeps its schedule and counts the frame."""
    msg = lcmt_sensor_frame()
    msg.utime, msg.frame = frame_utime(i, rate_hz), i
    msg.z = [float(v) for v in z]
    msg.valid = [bool(valid)] * len(msg.z)
    msg.mach, msg.pressure_altitude_ft = (float(v) for v in air_data)
    return msg.encode()


def command_frame_bytes(i: int, u, rate_hz: float = FRAME_RATE_HZ) -> bytes:
    """Frame ``i``'s commands ``u`` as an encoded ``lcmt_command_frame``: the five surface
    commands (rad, names.ACTUATORS order), then, when ``u`` has six elements (a bank that models
    the throttle: names.INPUTS_WITH_THROTTLE), the throttle command; with five the throttle
    field is NaN (a sender without a throttle command: a 5-input bank does not use it)."""
    u = [float(v) for v in u]
    if len(u) not in (5, 6):
        raise ValueError(f"a command frame carries 5 surface commands and optionally the throttle, got {len(u)} values")
    msg = lcmt_command_frame()
    msg.utime, msg.frame = frame_utime(i, rate_hz), i
    msg.u_rad = u[:5]
    msg.throttle = u[5] if len(u) == 6 else math.nan
    return msg.encode()


def command_of(frame) -> list[float]:
    """A decoded ``lcmt_command_frame``'s command as the executive takes it: u_rad, then the
    throttle (names.INPUTS_WITH_THROTTLE order; NaN from a sender without one)."""
    return [*frame.u_rad, frame.throttle]
