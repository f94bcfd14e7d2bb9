"""TruthModel: the nonlinear JSBSim F-16 with failable actuators and sensors, frame by frame.

One frame (FRAME_RATE_HZ = 64 Hz) of the closed loop (docs/INTERFACES.md)::

    z_i = truth.measure()      # sensors at t_i = i / 64 s: ideal + noise, sensor failures
    u_i = fcs.command(...)     # the caller's FCS (raw z_i or the estimator's z_hat)
    truth.advance(u_i)         # SIM_RATE_HZ / FRAME_RATE_HZ = 2 JSBSim steps of 1/128 s, u_i held;
                               # actuator lag/limits and actuator failures act at 128 Hz

A failure with onset t_f acts from the first JSBSim step (actuators) or frame (sensors) whose
time is >= t_f.  A gust burst (``Scenario.gust_burst``) changes the turbulence level before the
JSBSim steps of its first frame and back before those of its end frame (``turbulence.GustBurst``);
``fly_closed_loop`` flies the frames between such changes as separate C++ calls, which continue
each other exactly (a call ends after its last frame's steps; the next measures first).
Sensor noise comes from ``numpy.random.default_rng(seed)``, turbulence from
JSBSim seeded with the same seed: the same scenario gives the same run.  Each ``measure()`` also
samples the air-data sensor (``truth.air_data``: measured Mach and pressure altitude, lagged and
noisy, its noise from its own stream ``air_data_rng(seed)``); ``air_data`` holds this frame's
values, the only truth-side numbers besides z that the estimator may receive.
``truth_log`` holds the record (true states, effective surface positions, failure truth); it
is for scoring and plots only and must never reach the estimator.  ``record_log=False`` (the
cpp engine): the frames keep no record (a closed-loop flight whose caller never reads it,
``loop.flight.fly`` without ``record_series``); ``truth_log`` then raises RuntimeError.  The
Python engine (the reference) always keeps it.

Engines (``truth.engine``): ``cpp`` flies the frames in C++ (``core.TruthFrames``), with the
sensor noise drawn here in bulk from the same generator (``rng.standard_normal((n, 7))`` gives
the numbers that n calls of ``standard_normal(7)`` give); ``python`` is the reference.  Either
way the aircraft comes trimmed from ``pool.POOL`` and goes back when the flight is closed
(``close()``, called by ``fly_raw`` and the closed loop; also when the model is collected).
The C++ engine takes the air-data normals the same way (``air_rng.standard_normal((n, 2))``).
``step(fcs, z_feedback)`` is a whole frame -- command, advance, next measurement -- in one call.

Maneuvers (``Scenario.maneuvers``): :meth:`TruthModel.pilot` is the outer loop
(``truth.outer_loop``) on this aircraft, the FCS's pilot; it sets the throttle each frame.  On
the cpp engine it flies inside the C++ frames with the control law (``attach``); another pilot
makes the control law run in Python (the frames then fly actuators, JSBSim and sensors).  A
maneuvering flight's aircraft does not go back to the pool (the throttle and engine state it
leaves are not the trim's).

Throttle dither (``DitherSpec.throttle_amplitude`` > 0, truth.dither): the throttle command
``sat(base_i + a_th sin(2 pi f_th t_i), 0, 1)`` is written at the start of frame i, before its
JSBSim steps (``advance``; in C++ ``TruthFrames.set_throttle_dither``); base_i is the trim
throttle, or with maneuvers the outer loop's throttle command of frame i (the pilot's lever, set
by the control law's pilot before ``advance``); scheduled (``DitherSpec.throttle_schedule``),
a_th follows the air data measured with z_i (``dither.scheduled_throttle_amplitude``).
``last_throttle_command`` is the command the last ``advance`` wrote: the sixth input a throttle
bank propagates for that frame.  Such a flight's aircraft does not go back to the pool either.
"""
from __future__ import annotations

import math
import weakref

import numpy as np

from ..names import ACTUATORS, FRAME_RATE_HZ, SENSORS, SIM_RATE_HZ
from . import actuators as actuators_module
from . import air_data as air_data_module, aircraft, sensors as sensors_module, turbulence
from .air_data import AirDataSensor, air_data_rng
from .dither import (ADAPTED_DITHER_REFERENCE, ADAPTIVE_FULL_RATIO, ADAPTIVE_RUDDER_REFERENCE, G_FPS2,
                     THROTTLE_GRID_ALT_FT, THROTTLE_GRID_MACH, THROTTLE_SCHEDULE_NX_G, THRUST_ACCEL_FPS2,
                     scheduled_throttle_amplitude, throttle_command, throttle_terms)
from .actuators import ActuatorBank
from .engine import check_engine
from .pool import POOL
from .aircraft import TrimError, TrimPoint  # noqa: F401  (re-exported)
from .fcs import FlightControlSystem
from .outer_loop import INSTRUMENTS, THROTTLE_PROPERTY, OuterLoop, make_pilot
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

    def __init__(self, scenario: Scenario | None = None, engine: str | None = None, record_log: bool = True):
        sc = scenario if scenario is not None else Scenario()
        if not isinstance(sc, Scenario):
            raise ValueError(f"TruthModel needs a Scenario, got {type(sc).__name__}")
        self.scenario = sc
        self.engine = check_engine(engine)
        if SIM_RATE_HZ % FRAME_RATE_HZ:
            raise ValueError(f"SIM_RATE_HZ {SIM_RATE_HZ} must be a multiple of FRAME_RATE_HZ {FRAME_RATE_HZ}")
        self._steps_per_frame = SIM_RATE_HZ // FRAME_RATE_HZ
        dt = 1.0 / SIM_RATE_HZ
        key, held = POOL.acquire(sc.mach, sc.alt_ft, dt, sc.seed)
        self.fdm, self.trim = held[0], held[1]
        away = sc.maneuvers or sc.dither.throttle_on  # these flights move the throttle: not back to the pool
        self._release = weakref.finalize(self, POOL.discard if away else POOL.release, key, held)
        turbulence.apply(self.fdm, sc.turbulence)
        self.actuators = ActuatorBank(self.trim.u_rad, dt)
        rng = np.random.default_rng(sc.seed)
        air_rng = air_data_rng(sc.seed)
        self.frame = 0
        self._step = 0
        eps = 1e-6
        #: (step, failure) and (frame, failure) from which each failure acts, in time order.
        self._act_schedule = sorted(
            ((math.ceil(f.time_s * SIM_RATE_HZ - eps), f) for f in sc.failures if f.is_actuator),
            key=lambda p: p[0])
        self._sen_schedule = sorted(
            ((math.ceil(f.time_s * FRAME_RATE_HZ - eps), f) for f in sc.failures if not f.is_actuator),
            key=lambda p: p[0])
        self._pending_act = list(self._act_schedule)
        self._pending_sen = list(self._sen_schedule)
        #: (frame, level): turbulence changes still to come (a gust burst's start and end).
        self._pending_turb = (sc.gust_burst.schedule(sc.turbulence, FRAME_RATE_HZ)
                              if sc.gust_burst is not None else [])
        n = int(round(sc.duration_s * FRAME_RATE_HZ)) + 1
        #: Throttle dither (truth.dither): trim, amplitude, 2 pi f; written each frame when on.
        self._throttle = (self.trim.throttle, *throttle_terms(sc.dither)) if sc.dither.throttle_on else None
        if self.engine == "cpp":
            self._rng, self._air_rng = rng, air_rng
            self._noise_rows = n
            self._frames = self._make_frames(rng.standard_normal((n, 7)), air_rng.standard_normal((n, 2)), n,
                                             record_log)
            if self._throttle is not None:
                schedule = ({"target_fps2": THROTTLE_SCHEDULE_NX_G * G_FPS2, "mach": list(THROTTLE_GRID_MACH),
                             "alt_ft": list(THROTTLE_GRID_ALT_FT), "accel_fps2": [list(r) for r in THRUST_ACCEL_FPS2]}
                            if sc.dither.throttle_schedule else None)
                self._frames.set_throttle_dither(THROTTLE_PROPERTY, *self._throttle, schedule)
            self.sensors = self.air_data_sensor = None
            return
        self._frames = None
        self.sensors = SensorSet(self.fdm, self.trim.z, rng, noise=sc.noise)
        self.air_data_sensor = AirDataSensor(self.fdm, air_rng, noise=sc.noise)
        pm = self.fdm.get_property_manager()
        self._set_surface = [pm.get_node(p).set_double_value for p in aircraft.SURFACE_PROPERTIES]
        self._get_state = [pm.get_node(p).get_double_value for _, p in STATE_LOG]
        self._run = self.fdm.run
        self._log = {
            "time_s": np.zeros(n), "z": np.zeros((n, 7)), "z_ideal": np.zeros((n, 7)),
            "air_data": np.zeros((n, 2)), "air_data_ideal": np.zeros((n, 2)),
            "u_cmd_rad": np.zeros((n, 5)), "surface_rad": np.zeros((n, 5)),
            "state": np.zeros((n, len(STATE_LOG))),
        }
        self._n_meas = 0
        self._n_adv = 0

    def _make_frames(self, noise: np.ndarray, air_noise: np.ndarray, capacity: int, record_log: bool):
        """The C++ frames over this aircraft: the constants and failure schedule from this package."""
        from .. import core

        act = self.actuators
        sigma = sensors_module.NOISE_SIGMA if self.scenario.noise else np.zeros(7)
        air_sigma = air_data_module.AIR_DATA_SIGMA if self.scenario.noise else np.zeros(2)
        act_fail, sen_fail = [], []
        for at, f in self._act_schedule:
            v = f.value if f.value is not None else actuators_module.ACTUATOR_MODE_DEFAULT_VALUE[f.mode]
            act_fail.append((at, f.index, actuators_module.MODE_CODE[f.mode], float(v) if v is not None else 0.0))
        for at, f in self._sen_schedule:
            v = f.value if f.value is not None else sensors_module.default_value(f.index, f.mode)
            sen_fail.append((at, f.index, sensors_module.MODE_CODE[f.mode], float(v) if v is not None else 0.0))
        return core.TruthFrames(
            self.fdm, list(aircraft.SURFACE_PROPERTIES), list(sensors_module.SENSOR_PROPERTIES),
            sensors_module.WEIGHT_PROPERTY, [p for _, p in STATE_LOG],
            {"trim_rad": act.trim_rad, "limit_rad": actuators_module.POSITION_LIMIT_RAD,
             "decay": act.decay, "max_step_rad": act.max_step_rad},
            {"z_trim": [float(x) for x in self.trim.z], "sigma": [float(x) for x in sigma],
             "full_scale_low": [lo for lo, _ in sensors_module.FULL_SCALE],
             "full_scale_high": [hi for _, hi in sensors_module.FULL_SCALE]},
            act_fail, sen_fail, noise, list(air_data_module.AIR_DATA_PROPERTIES),
            {"decay": air_data_module.lag_decay(), "sigma": [float(x) for x in air_sigma]}, air_noise,
            self._steps_per_frame, float(FRAME_RATE_HZ), float(SIM_RATE_HZ),
            capacity, record_log)

    def pilot(self):
        """The outer loop that flies the scenario's maneuvers on this aircraft
        (``outer_loop.OuterLoop``, a ``FlightControlSystem`` pilot), or None without maneuvers."""
        return make_pilot(self.fdm, self.scenario.maneuvers)

    def close(self) -> None:
        """End the flight: the aircraft goes back to the pool (``truth_log`` stays readable)."""
        if self._frames is not None:  # its record stays in it, copied out only if truth_log is read
            self._frames_done = self._frames
            self._frames = None
        self._closed = True
        self._release()

    def _check_open(self) -> None:
        if getattr(self, "_closed", False):
            raise RuntimeError("this TruthModel's flight is closed (its aircraft went back to the pool)")

    @property
    def air_data(self) -> np.ndarray:
        """The air data measured with the last ``measure()`` (a copy): (Mach, pressure altitude ft)."""
        if self._frames is not None:
            return np.array(self._frames.air_data, dtype=float)
        return np.array(self.air_data_sensor.last, dtype=float)

    @property
    def time_s(self) -> float:
        """Time of the current frame (s)."""
        return self.frame / FRAME_RATE_HZ

    # -- per-frame interface --------------------------------------------------------------
    def measure(self) -> np.ndarray:
        """z (7,) at the current frame: noise and sensor failures applied (units of names.SENSOR_UNITS)."""
        self._check_open()
        if self._frames is not None:
            self._refill_noise()
            return self._frames.measure()
        t = self.frame / FRAME_RATE_HZ
        while self._pending_sen and self._pending_sen[0][0] <= self.frame:
            _, f = self._pending_sen.pop(0)
            self.sensors.fail(f.index, f.mode, f.value, t)
        z = self.sensors.measure(t)
        ideal = self.sensors.last_ideal
        air = self.air_data_sensor.measure()
        i = self._row("_n_meas")
        log = self._log
        log["time_s"][i] = t
        log["z"][i] = z
        log["z_ideal"][i] = ideal
        log["air_data"][i] = air
        log["air_data_ideal"][i] = self.air_data_sensor.last_ideal
        log["state"][i] = [g() for g in self._get_state]
        return z

    def advance(self, u) -> None:
        """Apply surface commands ``u`` (5, rad, LS RS LF RF RUD) for one frame (2 JSBSim steps)."""
        if len(u) != 5:
            raise ValueError(f"u needs 5 surface commands ({', '.join(ACTUATORS)}), got {len(u)}")
        self._check_open()
        self._turbulence_due()
        if self._frames is not None:
            if self._throttle is not None and self.scenario.maneuvers:  # the pilot flew in Python
                self._frames.set_throttle_base(float(self.fdm[THROTTLE_PROPERTY]))
            self._frames.advance(np.asarray(u, dtype=float))
            self.frame += 1
            return
        u = [float(x) for x in u]
        if self._throttle is not None:
            self._last_throttle = self.throttle_command()
            self.fdm[THROTTLE_PROPERTY] = self._last_throttle
        act, setters, run = self.actuators, self._set_surface, self._run
        eff = u
        for _ in range(self._steps_per_frame):
            while self._pending_act and self._pending_act[0][0] <= self._step:
                _, f = self._pending_act.pop(0)
                act.fail(f.index, f.mode, f.value)
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

    def throttle_command(self) -> float:
        """The throttle command of the current frame, written by the next ``advance``: the trim's
        without a throttle dither, else the dither's (scheduled: on the air data measured with
        this frame's z) about the trim or, with maneuvers, about the outer loop's throttle of
        this frame (so: after the control law's pilot ran, before ``advance``)."""
        if self._frames is not None:
            return float(self._frames.throttle_command()) if self._throttle is not None else float(self.trim.throttle)
        if self._throttle is None:
            return float(self.trim.throttle)
        trim, a, w = self._throttle
        base = float(self.fdm[THROTTLE_PROPERTY]) if self.scenario.maneuvers else trim  # the pilot's lever
        if self.scenario.dither.throttle_schedule:
            m, h = self.air_data_sensor.last
            a = scheduled_throttle_amplitude(float(m), float(h))
        return throttle_command(base, a, w, self.frame / FRAME_RATE_HZ)

    @property
    def last_throttle_command(self) -> float:
        """The throttle command the last ``advance`` wrote with a throttle dither (the frame's
        sixth input for a bank that models the throttle); NaN before it or without one."""
        if self._frames is not None:
            return float(self._frames.last_throttle)
        return getattr(self, "_last_throttle", math.nan)

    def attach(self, fcs: FlightControlSystem) -> None:
        """Fly ``fcs``'s control law inside the C++ frames (``step``); its coefficients and
        states are copied in now and its states copied back by ``detach``."""
        self._law_in_cpp = self._frames is not None and (fcs.pilot is None or self._cpp_pilot(fcs.pilot))
        if self._law_in_cpp:
            self._frames.set_fcs(fcs.coefficients())
            if fcs.pilot is not None:
                self._frames.set_outer_loop(fcs.pilot.coefficients(), list(INSTRUMENTS), THROTTLE_PROPERTY)

    def set_dither_gain(self, fcs: FlightControlSystem, gain, gain2) -> None:
        """The adaptive dither's gains per surface, of the calm and of the turbulence line
        (truth/dither.py ``adaptive_gains``), on ``fcs``'s dither from the next frame on, in the
        C++ frames too when the law flies there."""
        fcs.dither.set_gain(gain, gain2)
        if self.law_in_cpp:
            self._frames.set_dither_gain(fcs.dither.gain, fcs.dither.gain2)

    def _cpp_pilot(self, pilot) -> bool:
        return isinstance(pilot, OuterLoop) and pilot.fdm is self.fdm

    @property
    def law_in_cpp(self) -> bool:
        """Whether the ``attach``-ed control law (and its outer loop) flies in the C++ frames."""
        return getattr(self, "_law_in_cpp", False)

    def detach(self, fcs: FlightControlSystem) -> None:
        """Copy the control law's states back into ``fcs`` after ``step`` calls."""
        if self.law_in_cpp:
            fcs.x_int, fcs.x_wash, fcs.x_vel = self._frames.fcs_state
            if fcs.pilot is not None:
                fcs.pilot.x_h, fcs.pilot.x_m, fcs.pilot.x_phi = self._frames.outer_state

    def step(self, fcs: FlightControlSystem, z_feedback, measure_next: bool = True):
        """One frame from ``z_feedback``: u = fcs.command(z_feedback, t), advance(u), then the next
        frame's z (None if not ``measure_next``); returns (u, z).  On the C++ engine this is one
        call when ``fcs`` is ``attach``-ed and flies there (``law_in_cpp``); else its law runs here."""
        if self._frames is not None and self.law_in_cpp:
            self._refill_noise()
            self._turbulence_due()
            u, z = self._frames.step(z_feedback, measure_next)
            self.frame += 1
            return u, z
        u = fcs.command(z_feedback, self.frame / FRAME_RATE_HZ)
        self.advance(u)
        return u, (self.measure() if measure_next else None)

    def fly_frames(self, n_frames: int) -> None:
        """C++ engine, control law attached, no turbulence change due: ``n_frames`` frames on
        raw feedback, then the next frame's measurement, in one call (``fly_raw``'s flight)."""
        self._check_open()
        if self._frames is None or not self.law_in_cpp or self._pending_turb:
            raise ValueError("fly_frames needs the cpp truth engine, a control law attached there and no gust burst")
        self._refill_noise()
        self._frames.fly(n_frames)
        self.frame += n_frames

    def fly_closed_loop(self, bank, n_frames: int, use_mmae: bool, record_probabilities: bool,
                        reconfiguration=None, adapted_dither: bool = False,
                        rudder_gain_bound: float = 1.0) -> dict:
        """C++ engine only: ``n_frames`` closed-loop frames with ``bank`` (a fixed-size F-16
        ``core.HierarchicalBank``) in the loop and the ``attach``-ed control law, in one call;
        ``reconfiguration``: a ``core.SensorReconfiguration`` for the "reconfigure" feedback;
        ``adapted_dither``: the adaptive dither of one adapted bank (truth/dither.py
        ``adapted_dither_reference``, and ``adaptive_rudder_gain`` up to ``rudder_gain_bound``: the
        control law's ``Dither.rudder_gain_bound``, 1 for the calm-air rudder line; the bank's
        measured rho-bar), as loop/flight.py flies it frame by frame.  See
        ``core.TruthFrames.fly_closed_loop`` (loop/flight.py uses it)."""
        self._check_open()
        if self._frames is None or not self.law_in_cpp:
            raise ValueError("fly_closed_loop needs the cpp truth engine and a control law attached there")
        if adapted_dither:
            self._frames.set_adapted_dither(THROTTLE_GRID_MACH, THROTTLE_GRID_ALT_FT, ADAPTED_DITHER_REFERENCE,
                                            ADAPTIVE_FULL_RATIO, ADAPTIVE_RUDDER_REFERENCE, rudder_gain_bound)
        end = self.frame + n_frames
        cuts = [f for f, _ in self._pending_turb if self.frame < f < end] + [end]
        out = None
        for cut in cuts:
            self._turbulence_due()
            self._refill_noise()
            first = self.frame
            part = self._frames.fly_closed_loop(bank, cut - first, use_mmae, record_probabilities,
                                                 reconfiguration)
            self.frame = cut
            if out is None:
                out = part
                continue
            for key in ("probabilities", "turbulence_scale"):
                out[key] = np.concatenate([out[key], part[key]])
            out["events"] = list(out["events"]) + [(f + first - (end - n_frames), *rest) for f, *rest in part["events"]]
            out["truth_s"] += part["truth_s"]
            out["estimator_s"] += part["estimator_s"]
            out["declared_last_frame"] = part["declared_last_frame"]
        return out

    def _turbulence_due(self) -> None:
        """Apply the turbulence changes due at or before the current frame (gust burst)."""
        while self._pending_turb and self._pending_turb[0][0] <= self.frame:
            turbulence.apply(self.fdm, self._pending_turb.pop(0)[1])

    def _refill_noise(self) -> None:
        if self._frames.noise_left == 0:  # flown past the scenario's duration: the next draws
            self._frames.set_noise(self._rng.standard_normal((self._noise_rows, 7)))
        if self._frames.air_data_noise_left == 0:
            self._frames.set_air_data_noise(self._air_rng.standard_normal((self._noise_rows, 2)))

    # -- record ---------------------------------------------------------------------------
    def _row(self, counter: str) -> int:
        i = getattr(self, counter)
        if i >= len(self._log["time_s"]):
            for k, a in self._log.items():
                self._log[k] = np.concatenate([a, np.zeros_like(a)])
        setattr(self, counter, i + 1)
        return i

    def _onsets_so_far(self) -> list[dict]:
        """Each failure that has acted, with the time it began to act (actuators from their
        JSBSim step, sensors from their frame), in the order they acted."""
        if self._frames is not None:
            measured, steps = self._frames.measured, self._frames.step_count
        elif self.engine == "cpp":
            measured, steps = self._frames_done.measured, self._frames_done.step_count
        else:
            measured, steps = self._n_meas, self._step
        acted = [(at / FRAME_RATE_HZ, 0, f) for at, f in self._sen_schedule if at < measured]
        acted += [(at / SIM_RATE_HZ, 1, f) for at, f in self._act_schedule if at < steps]
        acted.sort(key=lambda a: a[:2])  # a frame's sensors are read before its steps run
        return [{**f.to_dict(), "onset_s": t} for t, _, f in acted]

    @property
    def track(self) -> np.ndarray:
        """(n, 3): time s, Mach and pressure altitude ft of the ideal air data at every whole
        second measured so far (frames 0, FRAME_RATE_HZ, ...), kept with or without the truth
        log: where the aircraft flew, for scoring a long flight (campaign/soak)."""
        if self.engine == "cpp":
            frames = self._frames if self._frames is not None else self._frames_done
            return np.asarray(frames.track, dtype=float)
        rows = slice(0, self._n_meas, FRAME_RATE_HZ)
        return np.column_stack([self._log["time_s"][rows], self._log["air_data_ideal"][rows]])

    @property
    def truth_log(self) -> dict:
        """The record: time_s (n,), z (n,7) as measured, z_ideal (n,7) noise-free, air_data (n,2)
        as measured and air_data_ideal (n,2) exact (Mach, pressure altitude ft), u_cmd_rad
        (n,5) commands of frame i, surface_rad (n,5) effective positions at the end of frame i,
        state (n,len(STATE_LOG)) with ``state_names``, ``failures`` (scenario specs) and
        ``onsets`` (when each actually acted), ``scenario`` (dict), ``trim`` (dict)."""
        if self.engine == "cpp":
            frames = self._frames if self._frames is not None else self._frames_done
            if not frames.records_log:
                raise RuntimeError("this TruthModel keeps no truth log (built with record_log=False)")
            out = frames.log()
        else:
            n, m = self._n_meas, self._n_adv
            out = {k: v[:n].copy() for k, v in self._log.items()
                   if k in ("time_s", "z", "z_ideal", "air_data", "air_data_ideal", "state")}
            out["u_cmd_rad"] = self._log["u_cmd_rad"][:m].copy()
            out["surface_rad"] = self._log["surface_rad"][:m].copy()
        out["state_names"] = tuple(name for name, _ in STATE_LOG)
        out["sensor_names"] = SENSORS
        out["actuator_names"] = ACTUATORS
        out["failures"] = [f.to_dict() for f in self.scenario.failures]
        out["onsets"] = self._onsets_so_far()
        out["scenario"] = self.scenario.to_dict()
        tp = self.trim
        out["trim"] = {"u_rad": tp.u_rad.tolist(), "z": tp.z.tolist(), "throttle": tp.throttle,
                       "vt_fps": tp.vt_fps, "alpha_rad": tp.alpha_rad, "theta_rad": tp.theta_rad,
                       "mach": tp.mach, "alt_ft": tp.alt_ft, "lef_rad": tp.lef_rad,
                       "qbar_psf": tp.qbar_psf}
        return out


def fly_raw(scenario: Scenario, pilot=None, fcs_gains=None,
            engine: str | None = None) -> tuple[TruthModel, FlightControlSystem]:
    """Fly ``scenario`` for its duration with the FCS on RAW sensor feedback (no estimator).

    Returns the finished (closed) TruthModel (its ``truth_log``) and the FCS.  On the C++
    engine without a pilot the whole flight is one call.  The MMAE-fed loop lives with the
    estimator (``f16mmae run``); this is for truth-only runs, tests and benchmarks.
    """
    if pilot is not None and scenario.maneuvers:
        raise ValueError("fly_raw: give a pilot or a scenario with maneuvers, not both")
    truth = TruthModel(scenario, engine=engine)
    fcs = FlightControlSystem(truth.trim, dither=scenario.dither, ari=scenario.ari,
                              pilot=pilot or truth.pilot(), gains=fcs_gains)
    n = int(round(scenario.duration_s * FRAME_RATE_HZ))
    truth.attach(fcs)
    if truth.law_in_cpp and not truth._pending_turb:
        truth.fly_frames(n)
        truth.detach(fcs)
    else:
        measure, command, advance = truth.measure, fcs.command, truth.advance
        for i in range(n):
            z = measure()
            advance(command(z, i / FRAME_RATE_HZ))
        measure()  # the final frame's measurement closes the record
    truth.close()
    return truth, fcs
