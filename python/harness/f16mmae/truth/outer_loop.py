"""The pilot side of the truth FCS: altitude, Mach and bank-angle hold with commanded changes.

The outer loop flies the scenario's maneuvers (:mod:`.maneuvers`) through the inner flight
control law (:mod:`.fcs`): it is that law's ``pilot`` (normal-acceleration command ``nz_cmd``
in g and roll-rate command ``p_cmd`` in rad/s, perturbations) and it sets the throttle
(``fcs/throttle-cmd-norm``).  It reads the pilot's instruments from the aircraft -- altitude
h (ft), vertical speed hdot (ft/s), Mach M, bank angle phi (rad) -- never the FCS sensors z,
and it is NOT handed any trim: at t = 0 it reads the instruments and the throttle lever of the
trimmed aircraft as it is in flight, holds that, and finds every new trim by integral action.

References (piecewise: each channel's maneuvers, :func:`reference`)::

    h_ref(t)   ramps from the altitude the last vertical maneuver left to its target at its
               rate; hdot_ff = dh_ref/dt (the commanded climb rate while ramping, else 0)
    M_ref(t)   likewise from the speed maneuvers
    phi_ref(t) the bank of the turn in force (0 before, after it rolls out)

Control law at the frame rate (dt = 1/64 s); x_h, x_M, x_phi integrators::

    hdot_cmd = hdot_ff + K_H (h_ref - h)
    nz_cmd   = sat(K_HD (hdot_cmd - hdot) + K_HI x_h + (1/cos phi - 1), NZ_MIN..NZ_MAX)
               x_h += (hdot_cmd - hdot) dt         (level-turn feedforward: n = 1/cos phi)
    p_cmd    = sat(K_PHI (phi_ref - phi) + K_PHI_I x_phi, +-P_MAX),  x_phi += (phi_ref - phi) dt
    throttle = sat(throttle_0 + K_M (M_ref - M) + K_MI x_M, 0..1),  x_M += (M_ref - M) dt
               (x_M frozen while the throttle saturates in the direction of the error)

Each integrator is limited so that its term stays within the saturation of its output.
Gains (:class:`OuterLoopGains`): with h_ddot = g n_z the altitude loop is about
h'' + g K_HD h' + g (K_HD K_H + K_HI) h = 0, i.e. omega 0.24 rad/s, zeta 1.0 before the inner
loop's lag; measured at Mach 0.4, 20,000 ft, light turbulence: a 1,000-ft climb at 3,000 fpm
climbs at 55-60 ft/s and overshoots by about 120 ft, a 30 deg turn holds bank within 2 deg and
altitude within 20 ft, +0.1 Mach at 0.01 Mach/s overshoots by 0.016 Mach and settles in 25 s
(``tests/python/test_truth_maneuvers.py``).
The C++ twin is ``OuterLoopLaw`` in cpp/truth/truth_frame.h (same order of operations, the same
doubles: the cpp engine flies a maneuvering flight in C++, closed loop included, from
:meth:`OuterLoop.coefficients`).  With no maneuver the outer loop is not flown at all (:func:`make_pilot` returns None): a flight
without maneuvers is the unmaneuvered flight, bit for bit.  Turns are coordinated by the inner
law's yaw damper, lateral-acceleration feedback and aileron-to-rudder interconnect.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..names import FRAME_RATE_HZ
from .maneuvers import LATERAL, SPEED, VERTICAL, ManeuverSpec

#: The pilot's instruments (JSBSim properties) and the throttle lever.
INSTRUMENTS = ("position/h-sl-ft", "velocities/h-dot-fps", "velocities/mach", "attitude/phi-rad")
THROTTLE_PROPERTY = "fcs/throttle-cmd-norm"


@dataclass(frozen=True)
class OuterLoopGains:
    """k_h 1/s, k_hd g/(ft/s), k_hi g/ft, nz_min_g / nz_max_g (perturbation, g), k_phi 1/s,
    k_phi_i 1/s^2, p_max_rad_s, k_m throttle/Mach, k_mi throttle/(Mach s)."""

    k_h: float = 0.1
    k_hd: float = 0.015
    k_hi: float = 0.0003
    nz_min_g: float = -1.0
    nz_max_g: float = 2.0
    k_phi: float = 1.0
    k_phi_i: float = 0.1
    p_max_rad_s: float = math.radians(20.0)
    k_m: float = 8.0
    k_mi: float = 1.0


def _sat(x: float, lo: float, hi: float) -> float:
    return hi if x > hi else (lo if x < lo else x)


class Reference:
    """A channel's piecewise reference: ``value(t)`` and its slope ``rate(t)`` (per s)."""

    def __init__(self, start: float, maneuvers, per_s):
        self.segments = []  # (t0, v0, v1, slope per s; inf for a step)
        v = start
        for m in maneuvers:
            slope = per_s(m)
            self.segments.append((m.time_s, v, m.target, slope))
            v = m.target
            if m.kind in LATERAL and m.rate is not None:  # roll out after `for`
                self.segments.append((m.time_s + m.rate, v, 0.0, math.inf))
                v = 0.0
        self.start = start

    def at(self, t: float) -> tuple[float, float]:
        """(value, slope) at time t."""
        seg = None
        for s in self.segments:
            if s[0] <= t:
                seg = s
            else:
                break
        if seg is None:
            return self.start, 0.0
        t0, v0, v1, slope = seg
        if math.isinf(slope):
            return v1, 0.0
        step = slope * (t - t0)
        if step >= abs(v1 - v0):
            return v1, 0.0
        sign = 1.0 if v1 > v0 else -1.0
        return v0 + sign * step, sign * slope


class OuterLoop:
    """The pilot of :class:`~f16mmae.truth.fcs.FlightControlSystem` for ``maneuvers``
    (checked ManeuverSpecs) on aircraft ``fdm`` (``fdm[prop]`` read and write).  Called once
    per frame, ``pilot(time_s) -> (nz_cmd_g, p_cmd_rad_s)``; it writes the throttle."""

    def __init__(self, fdm, maneuvers: tuple[ManeuverSpec, ...], gains: OuterLoopGains | None = None,
                 frame_rate_hz: float = FRAME_RATE_HZ):
        self.fdm = fdm
        self.maneuvers = tuple(maneuvers)
        self.gains = gains or OuterLoopGains()
        self.dt_s = 1.0 / frame_rate_hz
        self._started = False
        self.x_h = self.x_m = self.x_phi = 0.0

    def _start(self) -> None:
        h, _, mach, _ = (self.fdm[p] for p in INSTRUMENTS)
        self.throttle_0 = self.fdm[THROTTLE_PROPERTY]
        by = lambda kinds: [m for m in self.maneuvers if m.kind in kinds]  # noqa: E731
        self.h_ref = Reference(h, by(VERTICAL), lambda m: m.rate_value / 60.0)
        self.m_ref = Reference(mach, by(SPEED), lambda m: m.rate_value)
        self.phi_ref = Reference(0.0, [ManeuverSpec(m.kind, m.time_s, math.radians(m.target), m.rate)
                                       for m in by(LATERAL)], lambda m: math.inf)
        self._started = True

    def coefficients(self) -> dict:
        """The gains, references and states of this loop for the C++ frames
        (``core.TruthFrames.set_outer_loop``, cpp/truth/truth_frame.h ``OuterLoopLaw``); the
        start values are read now if they were not yet (the aircraft as it is in flight)."""
        if not self._started:
            self._start()
        g = self.gains
        ref = lambda r: {"start": r.start, "segments": [list(x) for x in r.segments]}  # noqa: E731
        return {"k_h": g.k_h, "k_hd": g.k_hd, "k_hi": g.k_hi, "nz_min_g": g.nz_min_g, "nz_max_g": g.nz_max_g,
                "k_phi": g.k_phi, "k_phi_i": g.k_phi_i, "p_max_rad_s": g.p_max_rad_s, "k_m": g.k_m,
                "k_mi": g.k_mi, "dt_s": self.dt_s, "throttle_0": self.throttle_0,
                "h_ref": ref(self.h_ref), "m_ref": ref(self.m_ref), "phi_ref": ref(self.phi_ref),
                "x_h": self.x_h, "x_m": self.x_m, "x_phi": self.x_phi}

    def references(self, time_s: float) -> dict:
        """The references at ``time_s`` (h_ref_ft, hdot_ff_fps, mach_ref, phi_ref_rad)."""
        if not self._started:
            self._start()
        h, hdot = self.h_ref.at(time_s)
        return {"h_ref_ft": h, "hdot_ff_fps": hdot, "mach_ref": self.m_ref.at(time_s)[0],
                "phi_ref_rad": self.phi_ref.at(time_s)[0]}

    def __call__(self, time_s: float) -> tuple[float, float]:
        g, dt, fdm = self.gains, self.dt_s, self.fdm
        ref = self.references(time_s)
        h, hdot, mach, phi = (fdm[p] for p in INSTRUMENTS)
        # vertical: climb-rate command from the altitude error, nz from the climb-rate error
        e_hd = ref["hdot_ff_fps"] + g.k_h * (ref["h_ref_ft"] - h) - hdot
        x_lim = max(-g.nz_min_g, g.nz_max_g) / g.k_hi if g.k_hi > 0 else math.inf
        self.x_h = _sat(self.x_h + e_hd * dt, -x_lim, x_lim)
        turn_ff = 1.0 / math.cos(_sat(phi, -1.2, 1.2)) - 1.0
        nz_cmd = _sat(g.k_hd * e_hd + g.k_hi * self.x_h + turn_ff, g.nz_min_g, g.nz_max_g)
        # lateral: bank-angle hold through the roll-rate command
        e_phi = ref["phi_ref_rad"] - phi
        phi_lim = g.p_max_rad_s / g.k_phi_i if g.k_phi_i > 0 else math.inf
        self.x_phi = _sat(self.x_phi + e_phi * dt, -phi_lim, phi_lim)
        p_cmd = _sat(g.k_phi * e_phi + g.k_phi_i * self.x_phi, -g.p_max_rad_s, g.p_max_rad_s)
        # speed: Mach hold through the throttle
        e_m = ref["mach_ref"] - mach
        raw = self.throttle_0 + g.k_m * e_m + g.k_mi * self.x_m
        if not ((raw >= 1.0 and e_m > 0) or (raw <= 0.0 and e_m < 0)):
            self.x_m += e_m * dt
        fdm[THROTTLE_PROPERTY] = _sat(self.throttle_0 + g.k_m * e_m + g.k_mi * self.x_m, 0.0, 1.0)
        return nz_cmd, p_cmd


def make_pilot(fdm, maneuvers, gains: OuterLoopGains | None = None) -> OuterLoop | None:
    """The outer loop for a scenario's maneuvers on ``fdm``, or None without maneuvers."""
    return OuterLoop(fdm, maneuvers, gains) if maneuvers else None


__all__ = ["INSTRUMENTS", "OuterLoop", "OuterLoopGains", "Reference", "THROTTLE_PROPERTY", "make_pilot"]
