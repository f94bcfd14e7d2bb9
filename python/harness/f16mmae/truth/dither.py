"""Dither: continuous subliminal sinusoids added to the five surface commands (paper Sec. II).

    d_j(t) = a_j sin(2 pi f_j t + phi_j),   j = LS RS LF RF RUD   (rad)

The symmetric pairs share a line with phases +-phi: LS and RS at one frequency (phi = 0,
in phase), LF and RF at another (phi = 0.55 rad), the rudder at a third.  In healthy flight
the pair's roll moments add to only 2 |sin phi| of one surface's (0 for the stabilators,
1.05 for the flaperons, against 2 for one line per surface), so the roll-rate criterion (the
binding one when every surface had its own line: 0.93 of 1 deg/s with 0.6-0.8 deg per
surface) no longer limits the pairs, and their amplitudes grow until n_z and q bind; the
flaperons' small antisymmetric part spends the roll margin the rudder leaves on a larger
amplitude for the same n_z (2 a cos phi).  A failure of one surface of a pair removes its
share: the line's pitch/lift part drops and the survivor's roll shows (LS vs RS, LF vs RF:
opposite roll), so each failure keeps a distinct signature (tests/python/test_truth_dither.py).
Frequencies are set above the band where light turbulence is strong (vertical and rolling gusts mimic a
flaperon's lift/roll signature at 0.8-1.1 Hz: flaperon false alarms), within the actuator
bandwidth: stabilators 1.7 Hz (u, alpha, q, n_z), flaperons 2.9 Hz (n_z; p after a
failure), rudder 2.3 Hz (r, n_y, p).  Measured in the single-failure campaign, README
"Closed-loop failure detection".

Criterion (subliminal to the pilot): in closed loop with the FCS at the nominal point
(20,000 ft, Mach 0.4), no turbulence, peak |Delta n_z| < 0.05 g, peak |p|, |q|, |r| < 1 deg/s,
peak |Delta n_y| < 0.02 g -- also met at M 0.8 / 5,000 ft and M 0.45 / 35,000 ft through the
amplitude schedule (Dither).  At the nominal point the defaults use n_z 0.045 g, q 0.78,
p 0.80, r 0.35 deg/s, n_y 0.014 g (35,000 ft: q 0.86, p 0.86 deg/s; M 0.8: n_z 0.039 g);
``f16mmae bench truth`` and tests/python/test_truth_dither.py measure and print
the levels.

Throttle dither (optional, off by default: ``throttle_amplitude`` = 0): the truth aircraft's
throttle command about its trim, ``th(t) = th_trim + a_th sin(2 pi f_th t)`` (command units,
0..1; ``fcs/throttle-cmd-norm``), written at the start of every frame by the truth model
(truth/model.py, and its C++ twin ``ThrottleDither`` in cpp/truth/truth_frame.h).  It moves
forward speed, which no surface dither can do subliminally (docs/results/excitation.md).  Its
criterion is peak |Delta n_x| <= 0.02 g (CRITERION["nx_g"], the n_y criterion; see
design/excitation.py); a_th = 0.0239 meets it at the nominal point (JSBSim's thrust per unit
command there: 26.9 ft/s^2 of u').  Its amplitude is not scheduled over the envelope, and it
cannot be combined with maneuvers (the outer loop owns the throttle).  The estimator does not
model it yet: with it on, a bank with only the five surface inputs sees an unmodelled speed
excitation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

#: Default amplitude per surface (deg), order LS RS LF RF RUD.
DEFAULT_AMPLITUDE_DEG: tuple[float, ...] = (1.8, 1.8, 2.2, 2.2, 5.5)
#: Default frequency per surface (Hz): one per pair (in phase) and one for the rudder.
DEFAULT_FREQUENCY_HZ: tuple[float, ...] = (1.7, 1.7, 2.9, 2.9, 2.3)
#: Default phase per surface (rad): +-phi per pair (see above).
DEFAULT_PHASE_RAD: tuple[float, ...] = (0.0, 0.0, 0.55, -0.55, 0.0)
#: Largest amplitude a DitherSpec accepts (deg): well inside every surface's travel (stabilators
#: +-25, flaperons +-21.5, rudder +-30 deg); whether a dither is subliminal is a matter of the
#: response (CRITERION), not of this bound.
MAX_AMPLITUDE_DEG = 15.0
#: Subliminal criterion (peak values) the defaults are checked against.
CRITERION = {"nz_g": 0.05, "rate_deg_s": 1.0, "ny_g": 0.02, "nx_g": 0.02}
#: Largest throttle dither amplitude a DitherSpec accepts (command units; trim about 0.25).
MAX_THROTTLE_AMPLITUDE = 0.1
#: Default throttle dither frequency (Hz), used when its amplitude is set.
DEFAULT_THROTTLE_FREQUENCY_HZ = 0.2


@dataclass(frozen=True)
class DitherSpec:
    """Dither settings: ``enabled``; per-surface ``amplitude_deg`` (deg), ``frequency_hz`` (Hz),
    ``phase_rad`` (rad), order LS RS LF RF RUD; the throttle dither's ``throttle_amplitude``
    (command units, 0 = off) and ``throttle_frequency_hz`` (Hz)."""

    enabled: bool = True
    amplitude_deg: tuple[float, ...] = field(default=DEFAULT_AMPLITUDE_DEG)
    frequency_hz: tuple[float, ...] = field(default=DEFAULT_FREQUENCY_HZ)
    phase_rad: tuple[float, ...] = field(default=DEFAULT_PHASE_RAD)
    throttle_amplitude: float = 0.0
    throttle_frequency_hz: float = DEFAULT_THROTTLE_FREQUENCY_HZ

    def __post_init__(self):
        for name in ("amplitude_deg", "frequency_hz", "phase_rad"):
            vals = tuple(float(x) for x in getattr(self, name))
            if len(vals) != 5:
                raise ValueError(f"dither {name} needs 5 values (LS RS LF RF RUD), got {len(vals)}")
            if not all(math.isfinite(x) for x in vals):
                raise ValueError(f"dither {name} must be finite, got {vals}")
            object.__setattr__(self, name, vals)
        if any(a < 0 or a > MAX_AMPLITUDE_DEG for a in self.amplitude_deg):
            raise ValueError(f"dither amplitude_deg must lie in [0, {MAX_AMPLITUDE_DEG:g}] deg, "
                             f"got {self.amplitude_deg}")
        if any(f < 0 or f > 16.0 for f in self.frequency_hz):
            raise ValueError(f"dither frequency_hz must lie in [0, 16] Hz (frame rate 64 Hz), "
                             f"got {self.frequency_hz}")
        for name, hi, unit in (("throttle_amplitude", MAX_THROTTLE_AMPLITUDE, ""),
                               ("throttle_frequency_hz", 16.0, " Hz")):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (0.0 <= v <= hi):
                raise ValueError(f"dither {name} must be a number in [0, {hi:g}]{unit}, got {v!r}")
            object.__setattr__(self, name, float(v))

    @property
    def throttle_on(self) -> bool:
        """Whether the throttle dither acts (enabled, amplitude > 0)."""
        return self.enabled and self.throttle_amplitude > 0.0

    def to_dict(self) -> dict:
        """The settings; the throttle's only when its amplitude is set (records without it keep
        their form)."""
        out = {"enabled": self.enabled, "amplitude_deg": list(self.amplitude_deg),
               "frequency_hz": list(self.frequency_hz), "phase_rad": list(self.phase_rad)}
        if self.throttle_amplitude > 0.0:
            out["throttle_amplitude"] = self.throttle_amplitude
            out["throttle_frequency_hz"] = self.throttle_frequency_hz
        return out


def throttle_terms(spec: DitherSpec) -> tuple[float, float]:
    """(a_th, 2 pi f_th) of the throttle dither, (0, 0) when it is off."""
    if not spec.throttle_on:
        return 0.0, 0.0
    return spec.throttle_amplitude, 2.0 * math.pi * spec.throttle_frequency_hz


def throttle_command(trim: float, amplitude: float, omega_rad_s: float, time_s: float) -> float:
    """The truth's throttle command at ``time_s``: ``trim + a_th sin(w t)`` (the reference of
    cpp/truth/truth_frame.h ThrottleDither::command)."""
    return trim + amplitude * math.sin(omega_rad_s * time_s)


#: Extra exponent of the amplitude schedule above the design dynamic pressure (s < 1).
HIGH_QBAR_EXPONENT = 0.5


def amplitude_schedule(scale: float) -> float:
    """Amplitude multiplier for the FCS gain schedule ``scale`` = Q0 / qbar_trim (see Dither)."""
    if not (math.isfinite(scale) and scale >= 0.0):
        raise ValueError(f"dither scale must be finite and >= 0, got {scale}")
    return scale if scale >= 1.0 else scale ** (1.0 + HIGH_QBAR_EXPONENT)


class Dither:
    """Evaluates the dither of a DitherSpec: ``value(t) -> [5 rad]`` (zeros when disabled).

    scale is the FCS's gain schedule s = Q0 / qbar_trim (the amplitudes of a DitherSpec are
    those at the design dynamic pressure Q0 = 109 psf).  The amplitudes are multiplied by
    ``amplitude_schedule(s)``: s (constant control moment) at and below Q0, and
    s^(1 + HIGH_QBAR_EXPONENT) above it -- at high dynamic pressure the same moment gives
    more n_z (n_z ~ V q / g) and a faster short period, so the dither shrinks faster there
    to stay subliminal over the envelope (measured by tests/python/test_truth_dither.py at
    M 0.8 / 5,000 ft and M 0.45 / 35,000 ft).
    """

    def __init__(self, spec: DitherSpec | None = None, scale: float = 1.0):
        self.spec = spec if spec is not None else DitherSpec()
        on = self.spec.enabled
        g = amplitude_schedule(scale)
        self._a = [math.radians(a) * g if on else 0.0 for a in self.spec.amplitude_deg]
        self._w = [2.0 * math.pi * f for f in self.spec.frequency_hz]
        self._ph = list(self.spec.phase_rad)
        self.enabled = on and any(self._a)

    def terms(self) -> tuple[list[float], list[float], list[float]]:
        """(a_j in rad, scheduled, 0 when disabled; 2 pi f_j in rad/s; phi_j in rad)."""
        return list(self._a), list(self._w), list(self._ph)

    def value(self, time_s: float) -> list[float]:
        """Dither (rad) on LS RS LF RF RUD at ``time_s`` (s)."""
        if not self.enabled:
            return [0.0] * 5
        sin = math.sin
        return [a * sin(w * time_s + p) for a, w, p in zip(self._a, self._w, self._ph)]
