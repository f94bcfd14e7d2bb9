"""TruthModel: the nonlinear JSBSim F-16 with failable actuators and sensors, frame by frame.

One frame (FRAME_RATE_HZ = 64 Hz) of the closed loop (docs/INTERFACES.md)::

    z_i = truth.measure()      # sensors at t_i = i / 64 s: ideal + noise, sensor failures
    u_i = fcs.command(...)     # the caller's FCS (raw z_i or the estimator's z_hat)
    truth.advance(u_i)         # SIM_RATE_HZ / FRAME_RATE_HZ = 2 JSBSim steps of 1/128 s, u_i held;
                               # actuator lag/limits and actuator failures act at 128 Hz

A failure with onset t_f acts from the first JSBSim step (actuators) or frame (sensors) whose
time is >= t_f.  Sensor noise comes from ``numpy.random.default_rng(seed)``, turbulence from
JSBSim seeded with the same seed: the same scenario gives the same run.
``truth_log`` holds the record (true states, effective surface positions, failure truth); it
is for scoring and plots only and must never reach the estimator.
"""
from __future__ import annotations

import math

import numpy as np

from ..names import ACTUATORS, FRAME_RATE_HZ, SENSORS, SIM_RATE_HZ
from . import aircraft, turbulence
from .actuators import ActuatorBank
from .aircraft import TrimError, TrimPoint  # noqa: F401  (re-exported)
from .fcs import FlightControlSystem
from .scenario import Scenario
from .sensors import SensorSet

#: True-state channels recorded each frame (JSBSim properties), with units in the names.
STATE_LOG: tuple[tuple[str, str], ...] = (
    ("alt_ft", "position/h-sl-ft"), ("vt_fps", "velocities/vt-fps"),
    ("alpha_rad", "aero/alpha-rad"), ("beta_rad", "aero/beta-rad"),
    ("theta_rad", "attitude/theta-rad"), ("phi_rad", "attitude/phi-rad"),
    ("psi_rad", "attitude/psi-rad"),
)


class TruthModel:
    """The truth model of one ``Scenario`` (see module docstring).

    Raises ValueError for a bad scenario, ``TrimError`` (naming the flight condition) when
    JSBSim cannot trim there.  Attributes: ``trim`` (TrimPoint), ``time_s``, ``frame``,
    ``truth_log`` (dict of arrays, the record).
    """

    def __init__(self, scenario: Scenario | None = None):
        sc = scenario if scenario is not None else Scenario()
        if not isinstance(sc, Scenario):
            raise ValueError(f"TruthModel needs a Scenario, got {type(sc).__name__}")
        self.scenario = sc
        if SIM_RATE_HZ % FRAME_RATE_HZ:
            raise ValueError(f"SIM_RATE_HZ {SIM_RATE_HZ} must be a multiple of FRAME_RATE_HZ {FRAME_RATE_HZ}")
        self._steps_per_frame = SIM_RATE_HZ // FRAME_RATE_HZ
        dt = 1.0 / SIM_RATE_HZ
        self.fdm = aircraft.load_fdm(seed=sc.seed, dt_s=dt)
        self.trim: TrimPoint = aircraft.trim(self.fdm, sc.mach, sc.alt_ft)
        turbulence.apply(self.fdm, sc.turbulence)
        self.actuators = ActuatorBank(self.trim.u_rad, dt)
        self.sensors = SensorSet(self.fdm, self.trim.z, np.random.default_rng(sc.seed), noise=sc.noise)
        pm = self.fdm.get_property_manager()
        self._set_surface = [pm.get_node(p).set_double_value for p in aircraft.SURFACE_PROPERTIES]
        self._get_state = [pm.get_node(p).get_double_value for _, p in STATE_LOG]
        self._run = self.fdm.run
        self.frame = 0
        self._step = 0
        eps = 1e-6
        self._pending_act = sorted(
            ((math.ceil(f.time_s * SIM_RATE_HZ - eps), f) for f in sc.failures if f.is_actuator),
            key=lambda p: p[0])
        self._pending_sen = sorted(
            ((math.ceil(f.time_s * FRAME_RATE_HZ - eps), f) for f in sc.failures if not f.is_actuator),
            key=lambda p: p[0])
        self._onsets: list[dict] = []
        n = int(round(sc.duration_s * FRAME_RATE_HZ)) + 1
        self._log = {
            "time_s": np.zeros(n), "z": np.zeros((n, 7)), "z_ideal": np.zeros((n, 7)),
            "u_cmd_rad": np.zeros((n, 5)), "surface_rad": np.zeros((n, 5)),
            "state": np.zeros((n, len(STATE_LOG))),
        }
        self._n_meas = 0
        self._n_adv = 0

    @property
    def time_s(self) -> float:
        """Time of the current frame (s)."""
        return self.frame / FRAME_RATE_HZ

    # -- per-frame interface --------------------------------------------------------------
    def measure(self) -> np.ndarray:
        """z (7,) at the current frame: noise and sensor failures applied (units of names.SENSOR_UNITS)."""
        t = self.frame / FRAME_RATE_HZ
        while self._pending_sen and self._pending_sen[0][0] <= self.frame:
            _, f = self._pending_sen.pop(0)
            self.sensors.fail(f.index, f.mode, f.value, t)
            self._onsets.append({**f.to_dict(), "onset_s": t})
        z = self.sensors.measure(t)
        ideal = self.sensors.last_ideal
        i = self._row("_n_meas")
        log = self._log
        log["time_s"][i] = t
        log["z"][i] = z
        log["z_ideal"][i] = ideal
        log["state"][i] = [g() for g in self._get_state]
        return z

    def advance(self, u) -> None:
        """Apply surface commands ``u`` (5, rad, LS RS LF RF RUD) for one frame (2 JSBSim steps)."""
        if len(u) != 5:
            raise ValueError(f"u needs 5 surface commands ({', '.join(ACTUATORS)}), got {len(u)}")
        u = [float(x) for x in u]
        act, setters, run = self.actuators, self._set_surface, self._run
        eff = u
        for _ in range(self._steps_per_frame):
            while self._pending_act and self._pending_act[0][0] <= self._step:
                _, f = self._pending_act.pop(0)
                act.fail(f.index, f.mode, f.value)
                self._onsets.append({**f.to_dict(), "onset_s": self._step / SIM_RATE_HZ})
            eff = act.step(u)
            for s, v in zip(setters, eff):
                s(v)
            if not run():
                raise RuntimeError(f"JSBSim stopped at t = {self._step / SIM_RATE_HZ:.3f} s")
            self._step += 1
        i = self._row("_n_adv")
        self._log["u_cmd_rad"][i] = u
        self._log["surface_rad"][i] = eff
        self.frame += 1

    # -- record ---------------------------------------------------------------------------
    def _row(self, counter: str) -> int:
        i = getattr(self, counter)
        if i >= len(self._log["time_s"]):
            for k, a in self._log.items():
                self._log[k] = np.concatenate([a, np.zeros_like(a)])
        setattr(self, counter, i + 1)
        return i

    @property
    def truth_log(self) -> dict:
        """The record: time_s (n,), z (n,7) as measured, z_ideal (n,7) noise-free, u_cmd_rad
        (n,5) commands of frame i, surface_rad (n,5) effective positions at the end of frame i,
        state (n,len(STATE_LOG)) with ``state_names``, ``failures`` (scenario specs) and
        ``onsets`` (when each actually acted), ``scenario`` (dict), ``trim`` (dict)."""
        n, m = self._n_meas, self._n_adv
        out = {k: v[:n].copy() for k, v in self._log.items() if k in ("time_s", "z", "z_ideal", "state")}
        out["u_cmd_rad"] = self._log["u_cmd_rad"][:m].copy()
        out["surface_rad"] = self._log["surface_rad"][:m].copy()
        out["state_names"] = tuple(name for name, _ in STATE_LOG)
        out["sensor_names"] = SENSORS
        out["actuator_names"] = ACTUATORS
        out["failures"] = [f.to_dict() for f in self.scenario.failures]
        out["onsets"] = list(self._onsets)
        out["scenario"] = self.scenario.to_dict()
        tp = self.trim
        out["trim"] = {"u_rad": tp.u_rad.tolist(), "z": tp.z.tolist(), "throttle": tp.throttle,
                       "vt_fps": tp.vt_fps, "alpha_rad": tp.alpha_rad, "theta_rad": tp.theta_rad,
                       "mach": tp.mach, "alt_ft": tp.alt_ft, "lef_rad": tp.lef_rad,
                       "qbar_psf": tp.qbar_psf}
        return out


def fly_raw(scenario: Scenario, pilot=None, fcs_gains=None) -> tuple[TruthModel, FlightControlSystem]:
    """Fly ``scenario`` for its duration with the FCS on RAW sensor feedback (no estimator).

    Returns the finished TruthModel (its ``truth_log``) and the FCS.  The MMAE-fed loop lives
    with the estimator (``f16mmae run``); this is for truth-only runs, tests and benchmarks.
    """
    truth = TruthModel(scenario)
    fcs = FlightControlSystem(truth.trim, dither=scenario.dither, ari=scenario.ari, pilot=pilot,
                              gains=fcs_gains)
    n = int(round(scenario.duration_s * FRAME_RATE_HZ))
    measure, command, advance = truth.measure, fcs.command, truth.advance
    for i in range(n):
        z = measure()
        advance(command(z, i / FRAME_RATE_HZ))
    measure()  # the final frame's measurement closes the record
    return truth, fcs
