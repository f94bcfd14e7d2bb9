"""The seven F-16 flight-control sensors (VEL AOA PIT AZ ROL YAW AY), ideal and as measured.

Definitions (``ideal``; JSBSim properties, all at the centre of gravity)::

    VEL  ft/s   body-axis forward AIRspeed u_a   velocities/u-aero-fps   (air data)
    AOA  rad    angle of attack alpha            aero/alpha-rad          (air data)
    PIT  rad/s  pitch rate q                     velocities/q-rad_sec    (rate gyro)
    AZ   g      normal load factor n_z, up +     -forces/fbz-total-lbs / inertia/weight-lbs
    ROL  rad/s  roll rate p                      velocities/p-rad_sec
    YAW  rad/s  yaw rate r                       velocities/r-rad_sec
    AY   g      lateral load factor n_y, right +  forces/fby-total-lbs / inertia/weight-lbs

F are the non-gravitational body forces and W the weight, so AZ is about 1 g in level flight.
(JSBSim's own ``accelerations/Nz``/``Ny`` are the same quantities one integration step late,
so they are not used.)
Without wind, VEL equals the body velocity u; in turbulence the air-data sensors see the
air-relative values, as a pitot tube and an AOA vane do.

Measurement model (``SensorSet.measure``, sampled at the flight-control frame)::

    z = ideal + v,   v ~ N(0, diag(NOISE_SIGMA^2)), white, independent per frame

NOISE_SIGMA values are assumed, representative of F-16 flight-control sensors (0.5 ft/s,
0.1 deg, 0.1 deg/s, 0.01 g, 0.1 deg/s, 0.1 deg/s, 0.005 g).
Failures (from the failure time t_f on): ``complete`` reads the trim value plus noise (the
paper's model), ``null`` reads 0, ``stuck`` holds the last value read before t_f, ``hardover``
reads full scale (FULL_SCALE high for value >= 0, low otherwise), ``bias`` adds ``value``
(default BIAS_DEFAULT), ``drift`` adds value * (t - t_f) (default DRIFT_DEFAULT per s).
"""
from __future__ import annotations

import math

import numpy as np

from ..names import SENSORS

_DEG = math.pi / 180.0
#: JSBSim property read for each sensor, order ``names.SENSORS``; AZ and AY are the body force
#: (lbs) divided by WEIGHT_PROPERTY, AZ with its sign flipped.
SENSOR_PROPERTIES: tuple[str, ...] = (
    "velocities/u-aero-fps", "aero/alpha-rad", "velocities/q-rad_sec", "forces/fbz-total-lbs",
    "velocities/p-rad_sec", "velocities/r-rad_sec", "forces/fby-total-lbs",
)
WEIGHT_PROPERTY = "inertia/weight-lbs"
#: White-noise standard deviation per sensor (ft/s, rad, rad/s, g, rad/s, rad/s, g).
NOISE_SIGMA = np.array([0.5, 0.1 * _DEG, 0.1 * _DEG, 0.01, 0.1 * _DEG, 0.1 * _DEG, 0.005])
NOISE_SIGMA.setflags(write=False)
#: Full-scale range (low, high) per sensor, read by a ``hardover`` failure (assumed ranges:
#: 0-1500 ft/s, -20..45 deg, +-60 deg/s, -3..9 g, +-300 deg/s, +-60 deg/s, +-1 g).
FULL_SCALE: tuple[tuple[float, float], ...] = (
    (0.0, 1500.0), (-20 * _DEG, 45 * _DEG), (-60 * _DEG, 60 * _DEG), (-3.0, 9.0),
    (-300 * _DEG, 300 * _DEG), (-60 * _DEG, 60 * _DEG), (-1.0, 1.0),
)
#: Default ``bias`` offset per sensor (10 ft/s, 1 deg, 1 deg/s, 0.1 g, 2 deg/s, 1 deg/s, 0.05 g).
BIAS_DEFAULT: tuple[float, ...] = (10.0, 1 * _DEG, 1 * _DEG, 0.1, 2 * _DEG, 1 * _DEG, 0.05)
#: Default ``drift`` rate per sensor (units per s): half the default bias per second.
DRIFT_DEFAULT: tuple[float, ...] = tuple(0.5 * b for b in BIAS_DEFAULT)

#: Failure modes of a sensor, in the issue's order.
SENSOR_MODES: tuple[str, ...] = ("complete", "null", "stuck", "hardover", "bias", "drift")

_NORMAL, _COMPLETE, _NULL, _STUCK, _HARDOVER, _BIAS, _DRIFT = range(7)
_MODE_CODE = {"complete": _COMPLETE, "null": _NULL, "stuck": _STUCK, "hardover": _HARDOVER,
              "bias": _BIAS, "drift": _DRIFT}
#: Failure mode -> code, the codes of ``SensorMode`` in cpp/truth/truth_frame.h.
MODE_CODE: dict[str, int] = dict(_MODE_CODE)


def ideal(fdm) -> np.ndarray:
    """Noise-free measurements z (7,) of ``fdm``'s current state, units ft/s, rad, rad/s, g,
    rad/s, rad/s, g (order ``names.SENSORS``)."""
    z = [fdm[p] for p in SENSOR_PROPERTIES]
    w = fdm[WEIGHT_PROPERTY]
    z[3] = -z[3] / w
    z[6] = z[6] / w
    return np.array(z)


def default_value(index: int, mode: str) -> float | None:
    """The ``value`` a sensor failure mode takes when none is given."""
    if mode == "hardover":
        return 1.0
    if mode == "bias":
        return BIAS_DEFAULT[index]
    if mode == "drift":
        return DRIFT_DEFAULT[index]
    return None


class SensorSet:
    """The seven sensors of one run: ideal values from cached JSBSim nodes, noise, failures.

    fdm: the aircraft; z_trim (7,): trim measurements; rng: ``numpy.random.Generator``;
    noise: False gives noise-free readings (failures still act).
    """

    def __init__(self, fdm, z_trim, rng: np.random.Generator, noise: bool = True):
        pm = fdm.get_property_manager()
        self._get = [pm.get_node(p).get_double_value for p in SENSOR_PROPERTIES]
        self._weight = pm.get_node(WEIGHT_PROPERTY).get_double_value
        self.z_trim = [float(x) for x in z_trim]
        self._rng = rng
        self._sigma = NOISE_SIGMA if noise else np.zeros(7)
        self._mode = [_NORMAL] * 7
        self._value = [0.0] * 7
        self._t_fail = [0.0] * 7
        self._held = [0.0] * 7
        self.last = np.array(self.z_trim)
        self.last_ideal = list(self.z_trim)

    def fail(self, index: int, mode: str, value: float | None, time_s: float) -> None:
        """Fail sensor ``index`` (0..6) with ``mode`` (SENSOR_MODES) from ``time_s`` on."""
        if mode not in _MODE_CODE:
            raise ValueError(f"unknown sensor failure mode {mode!r}; valid: {', '.join(SENSOR_MODES)}")
        if value is None:
            value = default_value(index, mode)
        self._mode[index] = _MODE_CODE[mode]
        self._value[index] = float(value) if value is not None else 0.0
        self._t_fail[index] = float(time_s)
        self._held[index] = float(self.last[index])

    def ideal(self) -> list[float]:
        """Noise-free values now (same definitions as :func:`ideal`)."""
        z = [g() for g in self._get]
        w = self._weight()
        z[3] = -z[3] / w
        z[6] = z[6] / w
        return z

    def measure(self, time_s: float) -> np.ndarray:
        """z (7,) at ``time_s``: ideal + noise, failures applied."""
        v = self._rng.standard_normal(7) * self._sigma
        z = self.ideal()
        self.last_ideal = list(z)
        for i in range(7):
            m = self._mode[i]
            if m == _NORMAL:
                z[i] += v[i]
            elif m == _COMPLETE:
                z[i] = self.z_trim[i] + v[i]
            elif m == _NULL:
                z[i] = 0.0
            elif m == _STUCK:
                z[i] = self._held[i]
            elif m == _HARDOVER:
                lo, hi = FULL_SCALE[i]
                z[i] = hi if self._value[i] >= 0.0 else lo
            elif m == _BIAS:
                z[i] += v[i] + self._value[i]
            else:  # drift
                z[i] += v[i] + self._value[i] * (time_s - self._t_fail[i])
        out = np.array(z)
        self.last = out
        return out


__all__ = ["SENSOR_PROPERTIES", "WEIGHT_PROPERTY", "NOISE_SIGMA", "FULL_SCALE", "BIAS_DEFAULT", "DRIFT_DEFAULT",
           "SENSOR_MODES", "ideal", "default_value", "SensorSet", "SENSORS"]
