"""A Block-40-style flight control system producing the five surface commands (64 Hz).

Perturbations from the trim: dz = z_feedback - z_trim (z order VEL AOA PIT AZ ROL YAW AY).
Gains are those at the design dynamic pressure Q0 = 109 psf (20,000 ft, Mach 0.4) times
s = Q0 / qbar_trim (gain schedule on the trim dynamic pressure: control power ~ qbar).

Pitch, normal-acceleration / pitch-rate command with integral action (C*-like)::

    n_D  = sat(K_D (dVEL - x_V) / T_V, 0.05 g),   x_V += dt/T_V (dVEL - x_V)   (~ K_D du/dt)
    e    = dAZ + K_C dq - nz_cmd - n_D - sat(K_V dVEL, 0.05 g)    (g)
    x_I += e dt                                                   (anti-windup: |K_I x_I| <= 10 deg)
    de   = s (K_Q dq + K_N (dAZ - nz_cmd - n_D) + K_I x_I)        (rad, both stabilators)

  The airspeed terms (throttle is fixed at trim) are weak and saturated at 0.05 g, so a failed
  VEL sensor cannot command more than that: K_V (pitch to hold airspeed) removes the slow
  speed divergence of an n_z-hold loop, K_D (a washed-out du/dt) damps the phugoid.
Roll, roll-rate command with feedforward::    da = s (K_PFF p_cmd - K_P (dp - p_cmd))
Yaw, yaw damper (washed-out r) + lateral acceleration + aileron-to-rudder interconnect (ARI)::

    x_W += dt/T_W (dr - x_W),     dr_cmd = s (K_R (dr - x_W) + K_AY dAY) + K_ARI da   (ARI switchable)

Surfaces (rad): LS = LS0 + de + G_DT da, RS = RS0 + de - G_DT da, LF = LF0 + da, RF = RF0 - da,
RUD = RUD0 + dr_cmd, plus dither (its amplitudes hold at Q0 and are scaled by s too, so the
aircraft's response to it stays about the same across the envelope), clipped to the position
limits.  G_DT = 0.5 is the differential-tail share of the roll command.

Closed-loop eigenvalues with the linearized airframe (finite differences of the derived
aircraft) and the actuator lags, continuous time, trim-qbar schedule -- the design check:
at 20,000 ft / M 0.4: short period -1.06 +- 0.70j (zeta 0.83), pitch integrator -3.41,
Dutch roll -0.80 +- 1.13j (zeta 0.58), roll / yaw-damper pair -2.49 +- 0.64j, phugoid
-0.096 +- 0.093j (zeta 0.72), speed -0.091.  At M 0.3/5,000, 0.3/10,000, 0.6/20,000,
0.8/5,000, 0.8/35,000, 0.45/35,000 ft every oscillatory mode has zeta >= 0.5 (fast) and
>= 0.58 (phugoid); the only unstable roots are spiral-like reals of at most 0.027 /s
(time to double >= 26 s, MIL-F-8785C Level 1 spiral), largest at Mach 0.8
(tests/python/test_truth_fcs_linear.py recomputes all this).  Gains are moderate (no
high-frequency gain above 3 rad per rad/s), so the loop also tolerates the estimator's z_hat
as feedback.  With no failure and no pilot input the
FCS holds the trim: every term is zero at z = z_trim.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..names import FRAME_RATE_HZ
from .actuators import POSITION_LIMIT_RAD
from .dither import Dither, DitherSpec
from .outer_loop import OuterLoop

#: Dynamic pressure (psf) at which the gains below hold (20,000 ft, Mach 0.4).
DESIGN_QBAR_PSF = 109.0


@dataclass(frozen=True)
class FcsGains:
    """Gains at DESIGN_QBAR_PSF.  Units: k_q rad/(rad/s), k_n rad/g, k_i rad/(g s),
    k_c g/(rad/s), k_v g/(ft/s), k_d g/(ft/s^2), speed_filter_s (T_V) s, k_p and k_pff
    rad/(rad/s), k_r rad/(rad/s), k_ay rad/g, k_ari rad/rad, g_dt rad/rad, washout_s (T_W) s."""

    k_q: float = 1.0
    k_n: float = 0.2
    k_i: float = 0.2
    k_c: float = 0.5
    k_v: float = 0.003
    k_d: float = 0.05
    speed_filter_s: float = 4.0
    k_p: float = 0.4
    k_pff: float = 0.6
    k_r: float = 3.0
    k_ay: float = -1.0
    k_ari: float = -0.3
    g_dt: float = 0.5
    washout_s: float = 1.0


#: A pilot: time_s -> (nz_cmd_g, p_cmd_rad_s), perturbations from trim.
Pilot = Callable[[float], tuple[float, float]]


class FlightControlSystem:
    """``command(z_feedback, time_s) -> u`` (5 surface commands, rad, dither included).

    trim: a ``TrimPoint`` (u_rad, z, qbar_psf); scenario: a truth ``Scenario`` (its dither and
    ari are used) or None; dither: DitherSpec (None: the scenario's, else no dither);
    ari: aileron-to-rudder interconnect on/off (None: the scenario's, else on);
    pilot: optional Pilot; gains: FcsGains.
    ``z_feedback`` is the raw measurement z or the estimator's z_hat (absolute values).
    """

    def __init__(self, trim, scenario=None, *, dither: DitherSpec | None = None,
                 ari: bool | None = None, pilot: Pilot | None = None,
                 gains: FcsGains | None = None, frame_rate_hz: float = FRAME_RATE_HZ):
        if isinstance(scenario, DitherSpec):
            scenario, dither = None, scenario if dither is None else dither
        if scenario is not None:  # a truth Scenario: its dither and ARI unless overridden
            dither = scenario.dither if dither is None else dither
            ari = scenario.ari if ari is None else ari
        self.gains = gains or FcsGains()
        self.ari = True if ari is None else bool(ari)
        self.pilot = pilot
        self.dt_s = 1.0 / frame_rate_hz
        self.u_trim = [float(x) for x in trim.u_rad]
        self.z_trim = [float(x) for x in trim.z]
        self.schedule = DESIGN_QBAR_PSF / float(trim.qbar_psf)
        self.dither = Dither(dither if dither is not None else DitherSpec(enabled=False),
                             scale=self.schedule)
        g, s = self.gains, self.schedule
        self._kq, self._kn, self._ki = s * g.k_q, s * g.k_n, s * g.k_i
        self._kp, self._kr, self._kay = s * g.k_p, s * g.k_r, s * g.k_ay
        self._kpff = s * g.k_pff
        self._kari = g.k_ari if self.ari else 0.0
        self._xi_max = math.radians(10.0) / self._ki if self._ki > 0 else math.inf
        self.reset()

    def linear_model(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The control law without saturations or pilot, as continuous-time state space
        x_c' = Ac x_c + Bc dz,  du = Cc x_c + Dc dz; x_c = (x_I, x_W, x_V), dz (7,), du (5,).
        ``command`` is its forward-Euler discretization at the frame rate."""
        g = self.gains
        kd = g.k_d / g.speed_filter_s
        ac = np.zeros((3, 3))
        bc = np.zeros((3, 7))
        cc = np.zeros((5, 3))
        dc = np.zeros((5, 7))
        ac[0, 2] = kd
        bc[0, 3], bc[0, 2], bc[0, 0] = 1.0, g.k_c, -g.k_v - kd
        ac[1, 1], bc[1, 5] = -1.0 / g.washout_s, 1.0 / g.washout_s
        ac[2, 2], bc[2, 0] = -1.0 / g.speed_filter_s, 1.0 / g.speed_filter_s
        pitch_d = np.zeros(7)
        pitch_d[2], pitch_d[3], pitch_d[0] = self._kq, self._kn, -self._kn * kd
        pitch_c = np.array([self._ki, 0.0, self._kn * kd])
        roll_d = np.zeros(7)
        roll_d[4] = -self._kp
        for j, sign in ((0, 1.0), (1, -1.0)):
            dc[j] = pitch_d + sign * g.g_dt * roll_d
            cc[j] = pitch_c
        dc[2], dc[3] = roll_d, -roll_d
        dc[4, 5], dc[4, 6] = self._kr, self._kay
        dc[4] += self._kari * roll_d
        cc[4, 1] = -self._kr
        return ac, bc, cc, dc

    def coefficients(self) -> dict:
        """The scheduled coefficients and current states of this control law, for the C++
        frames (``core.TruthFrames.set_fcs``, cpp/truth/truth_frame.h).  A pilot other than the
        maneuvers' outer loop (which has its own C++ twin) is flown only by :meth:`command`
        (ValueError here)."""
        if self.pilot is not None and not isinstance(self.pilot, OuterLoop):
            raise ValueError("a FlightControlSystem with a pilot flies on the python truth engine only")
        g = self.gains
        amplitude, omega, phase = self.dither.terms()
        return {"u_trim": self.u_trim, "limit_rad": list(POSITION_LIMIT_RAD), "z_trim": self.z_trim,
                "kq": self._kq, "kn": self._kn, "ki": self._ki, "kp": self._kp, "kpff": self._kpff,
                "kr": self._kr, "kay": self._kay, "kari": self._kari, "k_c": g.k_c, "k_v": g.k_v,
                "k_d": g.k_d, "speed_filter_s": g.speed_filter_s, "washout_s": g.washout_s,
                "g_dt": g.g_dt, "xi_max": self._xi_max, "dt_s": self.dt_s,
                "dither_enabled": self.dither.enabled, "dither_amplitude_rad": amplitude,
                "dither_omega_rad_s": omega, "dither_phase_rad": phase,
                "dither_gain": list(self.dither.gain), "dither_gain2": list(self.dither.gain2),
                **dict(zip(("dither2_amplitude_rad", "dither2_omega_rad_s", "dither2_phase_rad"),
                           self.dither.turbulence_terms())),
                "x_int": self.x_int, "x_wash": self.x_wash, "x_vel": self.x_vel}

    def reset(self) -> None:
        """Zero the integrator and the washout (back at trim)."""
        self.x_int = 0.0
        self.x_wash = 0.0
        self.x_vel = 0.0

    def command(self, z_feedback, time_s: float) -> list[float]:
        """Surface commands (rad, LS RS LF RF RUD) for feedback ``z_feedback`` (7,) at ``time_s``."""
        g = self.gains
        zt = self.z_trim
        dvel = z_feedback[0] - zt[0]
        dq = z_feedback[2] - zt[2]
        daz = z_feedback[3] - zt[3]
        dp = z_feedback[4] - zt[4]
        dr = z_feedback[5] - zt[5]
        day = z_feedback[6] - zt[6]
        nz_cmd, p_cmd = self.pilot(time_s) if self.pilot is not None else (0.0, 0.0)
        # pitch: Nz/q command, PI
        spd = g.k_v * dvel
        spd = 0.05 if spd > 0.05 else (-0.05 if spd < -0.05 else spd)
        nd = g.k_d * (dvel - self.x_vel) / g.speed_filter_s
        nd = 0.05 if nd > 0.05 else (-0.05 if nd < -0.05 else nd)
        self.x_vel += (dvel - self.x_vel) * self.dt_s / g.speed_filter_s
        de = self._kq * dq + self._kn * (daz - nz_cmd - nd) + self._ki * self.x_int
        xi = self.x_int + (daz + g.k_c * dq - nz_cmd - nd - spd) * self.dt_s
        m = self._xi_max
        self.x_int = m if xi > m else (-m if xi < -m else xi)
        # roll: rate command
        da = self._kpff * p_cmd - self._kp * (dp - p_cmd)
        # yaw: washed-out yaw damper, Ay feedback, ARI
        dr_cmd = self._kr * (dr - self.x_wash) + self._kay * day + self._kari * da
        self.x_wash += (dr - self.x_wash) * self.dt_s / g.washout_s
        gdt = g.g_dt
        d = self.dither.value(time_s)
        ut = self.u_trim
        u = [ut[0] + de + gdt * da + d[0], ut[1] + de - gdt * da + d[1],
             ut[2] + da + d[2], ut[3] - da + d[3], ut[4] + dr_cmd + d[4]]
        for i in range(5):
            lim = POSITION_LIMIT_RAD[i]
            if u[i] > lim:
                u[i] = lim
            elif u[i] < -lim:
                u[i] = -lim
        return u
