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
    """Frame ``i``'s surface commands ``u`` (rad, names.ACTUATORS order) as an encoded
    ``lcmt_command_frame``."""
    msg = lcmt_command_frame()
    msg.utime, msg.frame = frame_utime(i, rate_hz), i
    msg.u_rad = [float(v) for v in u]
    return msg.encode()
