"""One closed-loop flight: the nonlinear truth model with the MMAE estimator in the loop.

Frame i (t_i = i / FRAME_RATE_HZ), as in docs/INTERFACES.md::

    z_i = truth.measure()                          sensors, noise and sensor failures applied
    a_i = truth.air_data                           measured Mach, pressure altitude (lag, noise)
    estimator.schedule(a_i)                        core: bank.schedule (air data for scheduling only)
    z_hat_i = estimator.update(z_i)                core: bank.update(z_i - z_trim); z_hat absolute
    u_i = fcs.command(z_fb_i, t_i)                 dither included; z_fb_i by ``feedback``:
                                                     "mmae" (paper) z_hat_i; "raw" z_i;
                                                     "reconfigure" z_i with z_hat_i on the
                                                     sensors the declared hypothesis failed
    estimator.propagate(u_i)                       core: bank.propagate(u_i - u_trim)
    truth.advance(u_i)                             SIM_RATE_HZ / FRAME_RATE_HZ truth steps

A bank that models the throttle (``f16mmae design --throttle-input``; its inputs end with
``names.THROTTLE_INPUT``) propagates ``u_i = (the five surface commands, th_i)``, th_i the
throttle command of frame i (``truth.last_throttle_command``, a command like the surfaces'), and
the truth flies the scheduled throttle dither with it (``DitherSpec.with_scheduled_throttle``:
the throttle is part of the MMAE system's excitation, as the surface dither is), unless the
scenario gives a throttle dither of its own or disables the dither.

Adaptive dither (estimator setting ``adaptive_dither``, ``--adaptive-dither``; with the
turbulence bank set, and there the default unless ``--fixed-dither``:
``estimator_options.with_closed_loop_defaults``, or with one bank's turbulence adaptation,
``--adapt-turbulence``): after ``update(z_i)`` the loop reads the set's member in force a and
its rho (the estimator's outputs, never the truth turbulence) and sets the truth's dither gains
``truth.dither.adaptive_gains(rho, ADAPTIVE_DITHER_REFERENCE[a])`` for u_i (the flaperons'
turbulence line); the estimator propagates that u_i, dither included.  With one adapted bank
rho is the adaptation's measured rho-bar and the reference
``truth.dither.adapted_dither_reference`` at the air data frame i was scheduled on (the last
finite), and the rudder's line takes its rough-air gain (``truth.dither.adaptive_rudder_gain``;
the calm-air line with ``--fixed-rudder-dither``).  Both read ``estimator.measured_power_ratio``.
Over LCM (``f16mmae hil``) a and rho are the status's ``turbulence_member`` and
``turbulence_power_ratio``, the same numbers (docs/INTERFACES.md).

Sensor-loss dither (estimator setting ``sensor_loss_dither``, ``--sensor-loss-dither``): after
``update(z_i)`` the loop reads the hypothesis the estimator declares (its own output, never the
failure truth) and sets the truth's dither gains by ``truth.dither.SensorLossDither`` (the row of
``sensor_loss_gains(declared)``, reached at a bounded rate) for u_i: larger lines on the surfaces
a declared sensor saw best.

The estimator is an :class:`~f16mmae.loop.estimator.Estimator`: built from the model bank alone, its only inputs
are the absolute vectors ``z`` (7,) and ``u`` (5,; 6 with the throttle) and the measured air data (Mach, pressure
altitude ft, from the truth model's air-data sensor, never the truth state), copied into fresh
floats at the boundary.  The failure truth lives in the scenario, which only the truth model
receives; :func:`fly` never passes anything else to the estimator, and
``tests/python/test_closedloop.py`` checks that structurally (signatures, and a replay
of the recorded (u, z, air data) through a fresh estimator reproducing every probability).

Declarations: each update reports the hypothesis the core's declarer declared on that
frame (if any); each is a declaration event ``{"hypothesis", "time_s"}`` -- a failure
declared, a dual declared at level 1, or NONE when the bank backs out to level 0.
``final_hypothesis`` is the core's current hypothesis at the end (NONE if none declared).

``FlightResult.hypotheses`` (the columns of its probabilities and of probabilities.csv): the *union* of the hypotheses
that were on line during the flight, in order of first appearance (the 13 level-0
hypotheses, then any level-1 duals); a cell is empty (NaN in memory) while its
hypothesis is off line.  The probabilities of the hypotheses on line sum to 1 per row.
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from .. import __version__, core
from ..names import FEEDBACK_MODES, FRAME_RATE_HZ, THROTTLE_INPUT
from ..truth import FlightControlSystem, Scenario, TruthModel
from ..truth.dither import ADAPTIVE_DITHER_REFERENCE, SensorLossDither, adaptive_gains, adapted_dither_reference
from .estimator import Estimator


# -- results ----------------------------------------------------------------------------------------
@dataclass
class FlightResult:
    scenario: dict
    bank_hash: str
    version: str
    feedback: str
    failures: list[dict]
    declarations: list[dict]
    final_hypothesis: str
    frame_dt_s: float
    time_s: np.ndarray = field(repr=False)
    hypotheses: tuple[str, ...] = ()
    probabilities: np.ndarray = field(default=None, repr=False)  # (frames, len(hypotheses)), NaN off line
    timing: dict = field(default_factory=dict)
    #: The estimator settings in force (``Estimator.settings``; {} for an estimator without).
    estimator_settings: dict = field(default_factory=dict)
    #: With ``fly(record_series=True)``: ``u`` (frames, 5), ``z`` (frames, 7), ``z_hat``
    #: (frames, 7), ``air_data`` (frames, 2: what the estimator was scheduled on) of each frame, and ``truth_log`` (``TruthModel.truth_log``, truth: read
    #: after the flight, for the record only); else None.
    series: dict | None = field(default=None, repr=False)
    #: The estimator's turbulence-adaptation scale s after each frame (frames,), recorded with
    #: the probabilities (1.0 throughout with the adaptation off; NaN for an estimator without
    #: one, e.g. over LCM); an empty array when probabilities are not recorded.
    turbulence_scale: np.ndarray = field(default=None, repr=False)
    #: The declarer's dwell in frames in force for its candidate after each frame (frames,), recorded
    #: with the probabilities (``Estimator.dwell_frames_in_force``: 0 with no hypothesis above the
    #: threshold; -1 for an estimator without one); an empty array when probabilities are not recorded.
    dwell_frames_in_force: np.ndarray = field(default=None, repr=False)
    #: The truth's track (``TruthModel.track``): time s, Mach and pressure altitude ft of the
    #: aircraft's ideal air data at every whole second, for scoring (never the estimator's).
    track: np.ndarray = field(default=None, repr=False)

    def probability_of(self, hypothesis: str) -> np.ndarray:
        """Probability history of one hypothesis, 0 while off line (or never on line)."""
        if hypothesis not in self.hypotheses:
            return np.zeros(len(self.time_s))
        return np.nan_to_num(self.probabilities[:, self.hypotheses.index(hypothesis)], nan=0.0)

    def run_json(self, **extra) -> dict:
        return {
            "seed": self.scenario.get("seed"),
            "scenario": self.scenario,
            "bank_hash": self.bank_hash,
            "version": self.version,
            "feedback": self.feedback,
            "failures": self.failures,
            "declarations": self.declarations,
            "final_hypothesis": self.final_hypothesis,
            "probability_columns": "union of the hypotheses on line; empty while off line",
            "timing": self.timing,
            "estimator_settings": self.estimator_settings,
            **extra,
        }


# -- the truth side ---------------------------------------------------------------------------------
def scenario_from_dict(d: dict):
    """A truth-model Scenario from plain data (``Scenario.to_dict`` layout, as records store it)."""
    return Scenario.from_dict(d)


def scenario_to_dict(scenario) -> dict:
    return scenario.to_dict()


def models_throttle(model_bank) -> bool:
    """Whether ``model_bank`` (a core.ModelBank, or None) has the throttle as an input."""
    return model_bank is not None and THROTTLE_INPUT in tuple(model_bank.input_names)


def _laid_out(events: list, p: np.ndarray, columns: dict[str, int], n_frames: int) -> np.ndarray:
    """The frames' probabilities ``p`` (frames, hypotheses on line, NaN-padded) in the flight's
    columns, one per hypothesis ever on line (``columns``, extended in order of appearance).

    ``events``: the declarations ``(frame, hypothesis, hypotheses on line from that frame)``;
    before the first, the hypotheses of ``columns``.  Each segment's rows go to its hypotheses'
    columns, NaN elsewhere; ``p`` itself when the columns never moved or nothing was recorded."""
    idx = tuple(range(len(columns)))
    segments, start = [], 0  # (first frame, end, columns of the hypotheses then on line)
    for frame, _name, online in events:
        segments.append((start, frame, idx))
        idx = tuple(columns.setdefault(h, len(columns)) for h in online)
        start = frame
    segments.append((start, n_frames, idx))
    width = len(columns)
    if not len(p) or (width == p.shape[1] and all(idx == tuple(range(width)) for *_, idx in segments)):
        return p
    out = np.full((len(p), width), np.nan)
    for start, end, idx in segments:
        out[start:end, list(idx)] = p[start:end, : len(idx)]
    return out


_FRAME_TIMES: dict[int, np.ndarray] = {}


def _frame_times(n_frames: int) -> np.ndarray:
    """``arange(n_frames) / FRAME_RATE_HZ`` as ``FlightResult.time_s`` holds it (i * dt), one
    read-only array per length, shared by the flights of a process."""
    t = _FRAME_TIMES.get(n_frames)
    if t is None:
        t = np.arange(n_frames) * (1.0 / FRAME_RATE_HZ)
        t.flags.writeable = False
        _FRAME_TIMES[n_frames] = t
    return t


def fly(scenario, model_bank, *, feedback: str | None = None, estimator_options: dict | None = None,
        record_probabilities: bool = True, on_frame=None, estimator=None,
        engine: str | None = None, record_series: bool = False) -> FlightResult:
    """Fly ``scenario`` with an estimator built from ``model_bank`` in the loop.

    ``feedback`` overrides ``scenario.feedback`` ("mmae" | "raw").  ``on_frame(t, u, z,
    air_data)``, if given, sees each frame's inputs to the estimator (for replay checks).
    ``estimator``: another object with the :class:`Estimator` interface (``schedule(mach,
    pressure_altitude_ft)``, ``update(z) -> z_hat``, ``propagate(u)``, ``hypotheses``, ``probabilities``, ``declared``,
    ``last_declaration``, ``bank_hash``) at its start state -- e.g. the executive over LCM
    (``f16mmae.hil``); default ``Estimator.fresh(model_bank, **estimator_options)``.
    ``engine``: the truth model's engine (``truth.engine``; default cpp).  On cpp with the
    in-process F-16 estimator and no ``on_frame``, the whole flight is one call
    (``TruthModel.fly_closed_loop``: the same frames in C++, the bank seeing z, u and air data only);
    otherwise each frame's truth side -- control law, actuators, JSBSim, next measurement --
    is one call (``TruthModel.step``).  A scenario's maneuvers are flown by its outer loop
    (``TruthModel.pilot``), the control law's pilot, in C++ too.  Both give the same flight
    (tests/python/test_truth_engines.py).
    ``record_series``: keep each frame's u, z and z_hat, and the truth model's log after the
    flight (``FlightResult.series``; flown frame by frame)."""
    feedback = feedback or getattr(scenario, "feedback", "mmae")
    if feedback not in FEEDBACK_MODES:
        raise ValueError(f"unknown feedback {feedback!r}; valid: {', '.join(FEEDBACK_MODES)}")
    t_start = time.perf_counter()
    throttle = models_throttle(model_bank)
    if throttle:  # the throttle dither is part of such an MMAE system's excitation
        scenario = dataclasses.replace(scenario, dither=scenario.dither.with_scheduled_throttle())
    # the only holder of the failure truth; its log is kept only for the series (nothing else reads it)
    truth = TruthModel(scenario, engine=engine, record_log=record_series)
    fcs = FlightControlSystem(truth.trim, dither=scenario.dither, ari=scenario.ari,
                              pilot=truth.pilot())  # the maneuvers' outer loop, None without
    truth.attach(fcs)
    t_truth = time.perf_counter() - t_start
    t0 = time.perf_counter()
    if estimator is None:
        estimator = Estimator.fresh(model_bank, **(estimator_options or {}))
    elif estimator_options:
        raise ValueError("estimator_options apply to the in-process estimator only, not to a given estimator")
    t_est = time.perf_counter() - t0

    dt = 1.0 / FRAME_RATE_HZ
    n_frames = int(round(scenario.duration_s * FRAME_RATE_HZ))
    use_mmae = feedback == "mmae"
    # "reconfigure": the control law is reconfigured only on a declaration (the declarer's
    # dwell-confirmed decision), and then only on the failed sensors' channels
    reconfiguration = core.SensorReconfiguration(model_bank) if feedback == "reconfigure" else None
    columns: dict[str, int] = {name: k for k, name in enumerate(estimator.hypotheses)}
    if record_series:
        rec_u, rec_z, rec_z_hat = (np.zeros((n_frames, 6 if throttle else 5)), np.zeros((n_frames, 7)),
                                   np.zeros((n_frames, 7)))
        rec_air = np.zeros((n_frames, 2))
    adaptive = bool(getattr(estimator, "settings", {}).get("adaptive_dither"))
    sensor_loss = bool(getattr(estimator, "settings", {}).get("sensor_loss_dither"))
    # one adapted bank's rudder line: its rough-air gain's bound (1: the calm-air line, --fixed-rudder-dither)
    rudder_bound = (1.0 if getattr(estimator, "settings", {}).get("fixed_rudder_dither")
                    else fcs.dither.rudder_gain_bound)
    if sensor_loss and adaptive:
        raise ValueError("--sensor-loss-dither and --adaptive-dither both set the dither's gains: give one "
                         "(with --turbulence-banks the adaptive dither is the default: add --fixed-dither)")
    sensor_loss_rule = SensorLossDither() if sensor_loss else None
    gain_now = None  # adaptive: the executive's rule, the set's member in force and its rho set the dither's gains
    air_reference = None   # adaptive, one adapted bank: rho_ref at the last finite air data (None: none yet)
    in_cpp = (not sensor_loss and truth.law_in_cpp and on_frame is None and not record_series
              and isinstance(estimator, Estimator) and estimator.fixed_size
              and not (adaptive and estimator.turbulence_member is not None)  # the set's rule: frame by frame
              and (not throttle or scenario.dither.throttle_on))  # C++ takes th_i from the dither
    if in_cpp:  # the whole flight in C++: one call, the same frames (one adapted bank's adaptive dither too)
        out = truth.fly_closed_loop(estimator.core_bank, n_frames, use_mmae, record_probabilities,
                                     reconfiguration, adapted_dither=adaptive,
                                     rudder_gain_bound=rudder_bound)
        t_truth += out["truth_s"]
        t_est += out["estimator_s"]
        events, probs, scale = out["events"], out["probabilities"], out["turbulence_scale"]
        dwell_in_force = out["dwell_frames_in_force"]
        estimator.last_declaration = events[-1][1] if out["declared_last_frame"] else None
        n_frames_python = 0
    else:
        n_frames_python = n_frames
        events = []  # as the C++ flight returns them: (frame, hypothesis, hypotheses on line)
        probs = np.full((n_frames if record_probabilities else 0, len(columns)), np.nan)
        scale = np.full(n_frames if record_probabilities else 0, np.nan)
        dwell_in_force = np.full(n_frames if record_probabilities else 0, -1, dtype=np.int32)
    clock = time.perf_counter
    step = truth.step
    a = clock()
    z = truth.measure() if n_frames_python else None
    air = truth.air_data if n_frames_python else None
    t_truth += clock() - a
    for i in range(n_frames_python):
        t = i * dt
        b = clock()
        estimator.schedule(air[0], air[1])
        z_hat = estimator.update(z)
        if adaptive:
            member, rho = estimator.turbulence_member, estimator.measured_power_ratio
            if member is not None:
                reference = ADAPTIVE_DITHER_REFERENCE[member]
            elif math.isfinite(rho):   # one adapted bank: the reference at the air data it scheduled on
                if math.isfinite(air[0]) and math.isfinite(air[1]):
                    air_reference = adapted_dither_reference(air[0], air[1])
                reference = air_reference   # None before any: the fixed dither
            else:
                raise ValueError("the adaptive dither needs the turbulence bank set's member in force and its rho, "
                                 "or one bank's turbulence adaptation and its measured rho; the estimator reports "
                                 "neither (give --adapt-turbulence; an executive over LCM: start mmae-daemon with "
                                 "the set's file and --turbulence-banks, or with --adapt-turbulence)")
            gain = adaptive_gains(rho if reference is not None else 0.0, reference or 1.0,
                                  rudder_bound=rudder_bound if member is None else None)
        elif sensor_loss:  # the hypothesis the estimator declares sets the gains (truth/dither.py)
            gain = sensor_loss_rule.gains(estimator.declared, dt)
        if (adaptive or sensor_loss) and gain != gain_now:
            truth.set_dither_gain(fcs, *gain)
            gain_now = gain
        c = clock()
        if use_mmae:
            z_fb = z_hat
        elif reconfiguration is not None:
            z_fb = reconfiguration.apply(estimator.declared, z, z_hat)
        else:
            z_fb = z
        u, z_next = step(fcs, z_fb, i + 1 < n_frames)  # u_i, then z_(i+1)
        if throttle:  # the throttle command frame i wrote (with maneuvers: the pilot's + dither)
            u = np.append(u, truth.last_throttle_command)
        air_next = truth.air_data
        d = clock()
        estimator.propagate(u)
        e = clock()
        t_truth += d - c
        t_est += (c - b) + (e - d)
        if on_frame is not None:
            on_frame(t, np.array(u, dtype=float), np.array(z, dtype=float), np.array(air, dtype=float))
        if record_series:
            rec_u[i], rec_z[i], rec_z_hat[i], rec_air[i] = u, z, z_hat, air
        z, air = z_next, air_next
        declared_now = estimator.last_declaration
        if declared_now is not None:  # the level (and the hypotheses on line) may have changed
            events.append((i, declared_now, tuple(estimator.hypotheses)))
        if record_probabilities:
            p = estimator.probabilities
            if len(p) > probs.shape[1]:
                probs = np.hstack([probs, np.full((n_frames, len(p) - probs.shape[1]), np.nan)])
            probs[i, : len(p)] = p
            scale[i] = getattr(estimator, "turbulence_scale", np.nan)
            dwell_in_force[i] = getattr(estimator, "dwell_frames_in_force", -1)
    truth.detach(fcs)
    truth.close()
    declarations = [{"hypothesis": name, "time_s": round(frame * dt, 9)} for frame, name, _ in events]
    probs = _laid_out(events, probs, columns, n_frames)
    final = estimator.declared
    wall = time.perf_counter() - t_start
    hypotheses = tuple(columns)
    failures = [f.to_dict() for f in scenario.failures]
    return FlightResult(
        scenario=scenario_to_dict(scenario),
        bank_hash=estimator.bank_hash,
        version=__version__,
        feedback=feedback,
        failures=failures,
        declarations=declarations,
        final_hypothesis=final,
        frame_dt_s=dt,
        time_s=_frame_times(n_frames),
        hypotheses=hypotheses,
        probabilities=(probs[:, : len(hypotheses)] if record_probabilities else np.zeros((n_frames, 0))),
        timing={"wall_s": round(wall, 6), "truth_s": round(t_truth, 6), "estimator_s": round(t_est, 6),
                "frames": n_frames},
        estimator_settings=dict(getattr(estimator, "settings", {})),
        turbulence_scale=scale,
        dwell_frames_in_force=dwell_in_force,
        track=truth.track,
        series=({"u": rec_u, "z": rec_z, "z_hat": rec_z_hat, "air_data": rec_air, "truth_log": truth.truth_log}
                if record_series else None),
    )
