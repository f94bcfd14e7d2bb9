"""The air-data sensor: measured Mach number and pressure altitude, as the estimator may see them.

The estimator may schedule on air data (docs/INTERFACES.md, "Air data"); this module is the
truth model's air data system, the only source of what it receives.  Definitions (``ideal``;
JSBSim properties)::

    Mach   -     velocities/mach               air-relative (turbulence included), as a pitot-static
                                               system measures it
    h_p    ft    atmosphere/pressure-altitude  the standard-atmosphere altitude of the static
                                               pressure, NOT the geometric altitude position/h-sl-ft

Measurement model, sampled at the flight-control frame (dt = 1/FRAME_RATE_HZ), per channel::

    y_0 = ideal_0                                   (an aircraft already in flight: settled)
    y_i = ideal_i + (y_(i-1) - ideal_i) * decay,    decay = exp(-dt / LAG_TIME_CONSTANT_S)
    m_i = y_i + sigma * n_i,                        n_i ~ N(0, 1), white, independent per frame

i.e. a first-order lag (the pneumatic lag of the pitot-static lines plus the air data
computer's smoothing) followed by white measurement noise.  The values are assumed, chosen to
be representative of an F-16-class digital central air data computer (CADC):

* ``LAG_TIME_CONSTANT_S = 0.2`` s: static-pressure lag of fighter pitot-static installations is
  of the order of 0.1-0.3 s at altitude (longer lines and lower pressure give longer lags), and
  the CADC filters its outputs on a similar time scale;
* ``SIGMA_MACH = 0.002``: CADC Mach accuracy is typically quoted at +-0.005 (about 2.5 sigma);
* ``SIGMA_PRESSURE_ALTITUDE_FT = 10`` ft: altitude accuracy of the order of +-25 ft near the
  ground growing with altitude; 10 ft frame to frame is the short-term noise part of it.

Noise: the standard normals come from their own generator, :func:`air_data_rng` (a stream
separate from the seven flight-control sensors' ``default_rng(seed)``), so adding air data left
every other noise realisation, and every recorded flight, unchanged.  ``Scenario.noise = False``
turns the air-data noise off as well (the lag stays).  Air-data failures are out of scope.

The per-frame arithmetic's C++ twin is cpp/truth/air_data_sensor.h (same order of operations,
same doubles); the C++ truth engine draws the normals here, in bulk.
"""
from __future__ import annotations

import math

import numpy as np

from ..names import FRAME_RATE_HZ

#: JSBSim properties read: Mach number and pressure altitude (ft), in that order.
AIR_DATA_PROPERTIES: tuple[str, str] = ("velocities/mach", "atmosphere/pressure-altitude")
#: Names and units of the two air-data channels, in that order.
AIR_DATA_NAMES: tuple[str, str] = ("mach", "pressure_altitude_ft")
#: First-order lag time constant of both channels (s).
LAG_TIME_CONSTANT_S = 0.2
SIGMA_MACH = 0.002
SIGMA_PRESSURE_ALTITUDE_FT = 10.0
#: White-noise standard deviation per channel (Mach, ft).
AIR_DATA_SIGMA = np.array([SIGMA_MACH, SIGMA_PRESSURE_ALTITUDE_FT])
AIR_DATA_SIGMA.setflags(write=False)
#: The air-data noise stream's key, mixed with the flight's seed (:func:`air_data_rng`).
AIR_DATA_STREAM = 0xA1D


def air_data_rng(seed: int) -> np.random.Generator:
    """The generator of the air-data noise of the flight seeded ``seed``: its own stream
    (``SeedSequence([AIR_DATA_STREAM, seed])``), independent of ``default_rng(seed)``."""
    return np.random.default_rng([AIR_DATA_STREAM, int(seed)])


def lag_decay(dt_s: float = 1.0 / FRAME_RATE_HZ) -> float:
    """``exp(-dt_s / LAG_TIME_CONSTANT_S)``: the lag's per-frame decay."""
    return math.exp(-dt_s / LAG_TIME_CONSTANT_S)


class AirDataSensor:
    """The air data of one run (Python reference; see the module docstring).

    fdm: the aircraft; rng: the air-data generator (:func:`air_data_rng`); noise: False gives
    lagged but noise-free readings.  ``measure()`` once per frame; ``last`` and
    ``last_ideal`` hold the latest measured and ideal values (2,).
    """

    def __init__(self, fdm, rng: np.random.Generator, noise: bool = True):
        pm = fdm.get_property_manager()
        self._get = [pm.get_node(p).get_double_value for p in AIR_DATA_PROPERTIES]
        self._rng = rng
        self._sigma = AIR_DATA_SIGMA if noise else np.zeros(2)
        self._decay = lag_decay()
        self._lag: list[float] | None = None
        self.last = np.full(2, np.nan)
        self.last_ideal = np.full(2, np.nan)

    def ideal(self) -> list[float]:
        """Mach and pressure altitude (ft) now, exact."""
        return [g() for g in self._get]

    def measure(self) -> np.ndarray:
        """The measured (Mach, pressure altitude ft) of this frame (lag, then noise)."""
        n = self._rng.standard_normal(2)
        ideal = self.ideal()
        if self._lag is None:
            self._lag = list(ideal)
        lag = self._lag
        for j in range(2):
            lag[j] = ideal[j] + (lag[j] - ideal[j]) * self._decay
        out = np.array([lag[0] + n[0] * self._sigma[0], lag[1] + n[1] * self._sigma[1]])
        self.last = out
        self.last_ideal = np.array(ideal)
        return out


__all__ = ["AIR_DATA_PROPERTIES", "AIR_DATA_NAMES", "LAG_TIME_CONSTANT_S", "SIGMA_MACH",
           "SIGMA_PRESSURE_ALTITUDE_FT", "AIR_DATA_SIGMA", "AIR_DATA_STREAM", "air_data_rng", "lag_decay",
           "AirDataSensor"]
