"""Dither: continuous subliminal sinusoids added to the five surface commands (paper Sec. II).

    d_j(t) = a_j sin(2 pi f_j t + phi_j),   j = LS RS LF RF RUD   (rad)

Each surface gets its own frequency, so that the failure of any one surface removes a
distinct line from the spectrum of the measurements (LS vs RS and LF vs RF separate, not only
stabilator vs flaperon), and every sensor channel sees activity: the stabilators excite
u, alpha, q, n_z (and p through the differential-tail share), the flaperons p and (through
their lift) n_z, the rudder r, n_y and p.

Criterion (subliminal to the pilot): in closed loop with the FCS at the nominal point
(20,000 ft, Mach 0.4), no turbulence, peak |Delta n_z| < 0.05 g, peak |p|, |q|, |r| < 1 deg/s,
peak |Delta n_y| < 0.02 g.  Defaults below meet it with margin; ``python -m
f16mmae.truth.bench`` and tests/python/test_truth_dither.py measure and print the levels.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

#: Default amplitude per surface (deg), order LS RS LF RF RUD.
DEFAULT_AMPLITUDE_DEG: tuple[float, ...] = (0.8, 0.8, 0.6, 0.6, 1.6)
#: Default frequency per surface (Hz): all distinct, none a multiple of another below 10 Hz.
DEFAULT_FREQUENCY_HZ: tuple[float, ...] = (1.3, 1.7, 1.1, 1.5, 0.9)
#: Default phase per surface (rad).
DEFAULT_PHASE_RAD: tuple[float, ...] = (0.0, 0.0, 0.0, 0.0, 0.0)
#: Subliminal criterion (peak values) the defaults are checked against.
CRITERION = {"nz_g": 0.05, "rate_deg_s": 1.0, "ny_g": 0.02}


@dataclass(frozen=True)
class DitherSpec:
    """Dither settings: ``enabled``; per-surface ``amplitude_deg`` (deg), ``frequency_hz`` (Hz),
    ``phase_rad`` (rad), order LS RS LF RF RUD."""

    enabled: bool = True
    amplitude_deg: tuple[float, ...] = field(default=DEFAULT_AMPLITUDE_DEG)
    frequency_hz: tuple[float, ...] = field(default=DEFAULT_FREQUENCY_HZ)
    phase_rad: tuple[float, ...] = field(default=DEFAULT_PHASE_RAD)

    def __post_init__(self):
        for name in ("amplitude_deg", "frequency_hz", "phase_rad"):
            vals = tuple(float(x) for x in getattr(self, name))
            if len(vals) != 5:
                raise ValueError(f"dither {name} needs 5 values (LS RS LF RF RUD), got {len(vals)}")
            if not all(math.isfinite(x) for x in vals):
                raise ValueError(f"dither {name} must be finite, got {vals}")
            object.__setattr__(self, name, vals)
        if any(a < 0 or a > 5.0 for a in self.amplitude_deg):
            raise ValueError(f"dither amplitude_deg must lie in [0, 5] deg, got {self.amplitude_deg}")
        if any(f < 0 or f > 16.0 for f in self.frequency_hz):
            raise ValueError(f"dither frequency_hz must lie in [0, 16] Hz (frame rate 64 Hz), "
                             f"got {self.frequency_hz}")

    def to_dict(self) -> dict:
        return {"enabled": self.enabled, "amplitude_deg": list(self.amplitude_deg),
                "frequency_hz": list(self.frequency_hz), "phase_rad": list(self.phase_rad)}


class Dither:
    """Evaluates the dither of a DitherSpec: ``value(t) -> [5 rad]`` (zeros when disabled).

    scale multiplies every amplitude (the FCS passes its gain schedule Q0 / qbar_trim, so the
    amplitudes of a DitherSpec are those at the design dynamic pressure of 109 psf).
    """

    def __init__(self, spec: DitherSpec | None = None, scale: float = 1.0):
        self.spec = spec if spec is not None else DitherSpec()
        on = self.spec.enabled
        self._a = [math.radians(a) * scale if on else 0.0 for a in self.spec.amplitude_deg]
        self._w = [2.0 * math.pi * f for f in self.spec.frequency_hz]
        self._ph = list(self.spec.phase_rad)
        self.enabled = on and any(self._a)

    def value(self, time_s: float) -> list[float]:
        """Dither (rad) on LS RS LF RF RUD at ``time_s`` (s)."""
        if not self.enabled:
            return [0.0] * 5
        sin = math.sin
        return [a * sin(w * time_s + p) for a, w, p in zip(self._a, self._w, self._ph)]
