"""Pseudonoise tuning (paper Sec. V, methods 1-4) as named knobs read from small TOML files.

The design model's physical noises (zero-order Dryden gusts, sensor noise) are augmented by:

- method 1 ``[method1_qd_longitudinal]``: additions to the longitudinal diagonal entries of
  ``Q_d`` (discrete, per frame, state units squared): ``u_fps, alpha_rad, q_rad_s, theta_rad``
  -- the fictitious ``w'_d`` of eq. 3.
- method 2 ``[method2_r]``: additions to the diagonal of ``R`` (sensor units squared):
  ``VEL AOA PIT AZ ROL YAW AY`` -- eq. 4, entering ``A_k`` through eq. 5.
- method 3 ``[method3_qd_lateral]``: additions to the lateral diagonal entries of ``Q_d``:
  ``beta_rad, p_rad_s, r_rad_s, phi_rad`` (the paper tunes ``Q_dr``, the yaw rate).
- method 4 ``[method4_actuator_q]``: strength ``q`` (rad^2/s, continuous) of a scalar white
  noise ``w_B`` entering through the airframe column of the surface (``LS ... RUD``), eq. 6:
  ``x' = F x + B u + G w + B_act,col w_B``; discretized with the gusts (eq. 7, Van Loan).

Top-level keys: ``name``, ``description``, ``turbulence`` (gust level the zero-order Dryden
model is designed for: none | light | moderate | severe), ``gust_model`` (``gust_rate``,
``white_gust`` or ``dryden_states`` -- gust states in the filters, see ``model.py``), ``failure_model`` (``complete``, the paper's, default;
or ``cover``: a failed surface at an unknown position, a failed sensor uninformative -- see
``hypotheses.py``; ``constant`` for VEL only: a failed sensor at an unknown constant within its
trim's uncertainty; or per component, a table ``{default = "complete", cover = ["VEL", "AOA"]}``
or its text ``"cover=VEL+AOA"``; ``Tuning.failure_model`` holds the canonical text,
``hypotheses.check_failure_model``), ``failed_surface_q`` (rad^2/s, the strength of the random walk of a
failed surface under ``cover``; a number for every surface or a table per surface,
``{LS = 3e-4, RUD = 1e-3}``; default and surfaces not named: ``FAILED_SURFACE_Q``),
``failed_surface_q_dual`` (the walk of a failed surface in the dual hypotheses of the level-2
banks, ``names.DUAL_HYPOTHESES``, both surfaces of a surface pair included: a number or a
table per surface; surfaces not named, and all without the key, take ``failed_surface_q``'s)
and ``failed_sensor_level_q``
(the random walk per frame of a failed sensor's unknown level under ``cover``, in units of
the sensor's noise variance, >= 0; 0: no memory; default ``FAILED_SENSOR_LEVEL_Q``) and
``failed_sensor_level_width`` (a table per sensor, e.g. ``{PIT = "reading"}``: the range W_j of
a failed ``cover`` sensor's unknown level, a number > 0 in the sensor's units, ``"reading"``,
derived from the design model by ``level_width.py``, or ``"range"``, its full range; sensors not
named take ``level_width.DEFAULT_WIDTHS``: a cover PIT ``"reading"``, the others ``"range"``) and
``failed_sensor_noise`` (``FAILED_SENSOR_NOISES``: the variance of a failed sensor's reading
about what its hypothesis predicts -- ``"design"``, the paper's, the design's ``R_jj`` with the
tuning's method-2 pseudonoise; or ``"sensor"``, the sensor's own noise variance
``NOISE_SIGMA_j^2`` alone. Method 2 stands for the aircraft's unmodelled response the healthy
sensor reads, which a failed one no longer reads; its H row is zero, so ``A_jj`` is the only
quantity it changes, not P, K nor the other channels; default ``"design"``).  Every variance must be finite and
>= 0; an unknown key, a wrong type or a negative value is refused with a message naming it.
Missing sections or keys mean zero.  ``untuned`` and ``tuned`` ship in ``design/tunings/``.

``[estimator]`` (optional): the estimator settings the design recommends for its bank --
``p_min`` (probability floor, 0 < p_min < 0.01), ``threshold`` (declaration threshold,
0.5 < threshold < 1), ``dwell_s`` (s, >= 0) and ``dwell_nats_per_hypothesis`` (an inline table
``{LS = 32.0, ...}``: hypothesis name -> its evidence dwell N_k in nats, 0 <= N_k <= 1e6;
cpp/f16mmae/declarer.h; written by tools/latency/dwell_per_hypothesis.py ``--tuning``).  They are
stored as typed fields of the bank file (``p_min``, ``threshold``, ``dwell_s``; each
hypothesis' ``dwell_nats``, format version 4, the names the table does not give 0: the frame
dwell alone) and used by ``loop.estimator.Estimator`` and the LCM daemon; a missing key
means the core's default (the paper's: p_min 0.001, threshold 0.9, dwell 0.25 s; no evidence
dwell).
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import names
from ..errors import F16mmaeError
from ..names import TURBULENCE_LEVELS
from .hypotheses import check_failure_model, failure_model_table
from .level_width import RANGE, READING
from .model import GUST_MODELS

TUNINGS_DIR = Path(__file__).with_name("tunings")

#: Section name -> (valid keys, index of each key in its vector, what the key is).
METHOD1_KEYS: tuple[str, ...] = names.STATES[:4]
METHOD3_KEYS: tuple[str, ...] = names.STATES[4:8]
SECTIONS: dict[str, tuple[str, ...]] = {
    "method1_qd_longitudinal": METHOD1_KEYS,
    "method2_r": names.SENSORS,
    "method3_qd_lateral": METHOD3_KEYS,
    "method4_actuator_q": names.ACTUATORS,
}
#: [estimator] key -> (lower, upper) bound of its valid range (open; closed for dwell_s).
ESTIMATOR_KEYS: dict[str, tuple[float, float]] = {
    "p_min": (0.0, 0.01), "threshold": (0.5, 1.0), "dwell_s": (0.0, 10.0),
    "dwell_nats_per_hypothesis": (0.0, 1.0e6)}   # each N_k, closed
TOP_LEVEL_KEYS: tuple[str, ...] = (("name", "description", "turbulence", "gust_model", "failure_model",
                                    "failed_surface_q", "failed_surface_q_dual", "failed_sensor_level_q",
                                    "failed_sensor_level_width", "failed_sensor_noise")
                                   + tuple(SECTIONS)
                                   + ("estimator",))
#: What a failed sensor's channel variance A_jj is (``failed_sensor_noise``): the design's R_jj
#: with the method-2 pseudonoise (the paper's), or the sensor's own noise variance alone.
FAILED_SENSOR_NOISES: tuple[str, ...] = ("design", "sensor")
#: Default random-walk strength of a failed surface's position under ``cover`` (rad^2/s), per
#: surface: the flaperons 3e-5 (about 0.3 deg of wander in 1 s; a freer flaperon absorbs roll
#: turbulence and false-alarms), the stabilators 3e-4 (follows a half-effective stabilator; 1e-3
#: lets a stabilator rival a failed pitch-rate gyro), the rudder 1e-3 (a walk that reaches a
#: rudder hardover before the failed yaw-rate gyro's hypothesis explains the yaw rate it
#: makes).  Chosen on the tuning seeds (docs/results/failure_models.md).
FAILED_SURFACE_Q: dict[str, float] = {"LS": 3.0e-4, "RS": 3.0e-4, "LF": 3.0e-5, "RF": 3.0e-5, "RUD": 1.0e-3}
#: Default random walk per frame of a failed sensor's level under ``cover``, in units of the
#: sensor's noise variance (the level filter's gain is then about its square root), per
#: sensor: AOA 1e-3 and VEL 1e-4 (with 0.01 the failed hypothesis' level follows the healthy
#: angle of attack, or the airspeed's slow wander, closely enough to be declared in
#: failure-free flight), the others 0.01 (slower, the failed PIT, ROL and YAW hypotheses lose
#: the stabilators', flaperons' and rudder's failures' first declarations to them).  Chosen on
#: the tuning seeds (docs/results/failure_models.md).
FAILED_SENSOR_LEVEL_Q: dict[str, float] = {**{s: 0.01 for s in names.SENSORS}, "AOA": 1.0e-3, "VEL": 1.0e-4}


def _per_component(value, source: str, key: str, kind: str, components, defaults: dict[str, float],
                   zero_ok: bool, unit: str = ""):
    """``key`` as read: a float (every component), or a table of ``components`` (those not
    named take their ``defaults``) as a dict over every component; TuningError names a bad
    entry (``kind``: "surface" or "sensor"; a value must be > 0, or >= 0 with ``zero_ok``)."""
    def number(v, what):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (
                math.isfinite(v) and (v >= 0.0 if zero_ok else v > 0.0)):
            raise TuningError(f"{source}: {what} = {v!r} must be a finite number {'>=' if zero_ok else '>'} 0{unit}")
        return float(v)

    if not isinstance(value, dict):
        return number(value, key)
    for name in value:
        if name not in components:
            raise TuningError(f"{source}: unknown {kind} {name!r} in {key}; valid: {', '.join(components)}")
    return {c: number(value.get(c, defaults[c]), f"{key}.{c}") for c in components}


def _surface_walk_q(value, source: str):
    """``failed_surface_q`` as read (``_per_component``; FAILED_SURFACE_Q, rad^2/s, > 0)."""
    return _per_component(value, source, "failed_surface_q", "surface", names.ACTUATORS, FAILED_SURFACE_Q,
                          zero_ok=False, unit=" (rad^2/s)")


def _surface_walk_q_dual(value, source: str, single) -> dict[str, float]:
    """``failed_surface_q_dual`` as read: every surface's dual walk (rad^2/s, > 0); the surfaces
    it does not name, and all of them without the key (``value`` None), take ``single``'s
    (``failed_surface_q`` as read). Empty when it equals ``single`` everywhere, so that a
    tuning without a different dual walk keeps its metadata."""
    per_single = single if isinstance(single, dict) else {a: single for a in names.ACTUATORS}
    if value is None:
        return {}
    read = _per_component(value, source, "failed_surface_q_dual", "surface", names.ACTUATORS, per_single,
                          zero_ok=False, unit=" (rad^2/s)")
    per = read if isinstance(read, dict) else {a: read for a in names.ACTUATORS}
    return {} if per == per_single else per


def _sensor_level_q(value, source: str) -> float | dict[str, float]:
    """``failed_sensor_level_q`` as read (``_per_component``; FAILED_SENSOR_LEVEL_Q, >= 0)."""
    return _per_component(value, source, "failed_sensor_level_q", "sensor", names.SENSORS, FAILED_SENSOR_LEVEL_Q,
                          zero_ok=True)


def _sensor_level_width(value, source: str) -> dict[str, float | str]:
    """``failed_sensor_level_width`` as read: a table of sensors, each a finite number > 0 (W in
    the sensor's units) or ``"reading"`` (level_width.py); TuningError names a bad entry."""
    if not isinstance(value, dict):
        raise TuningError(f"{source}: failed_sensor_level_width must be a table of sensors "
                          f"({', '.join(names.SENSORS)}), e.g. {{PIT = \"{READING}\"}}; got {value!r}")
    out = {}
    for name, v in value.items():
        if name not in names.SENSORS:
            raise TuningError(f"{source}: unknown sensor {name!r} in failed_sensor_level_width; valid: "
                              f"{', '.join(names.SENSORS)}")
        if v in (READING, RANGE):
            out[name] = v
        elif isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0.0):
            raise TuningError(f"{source}: failed_sensor_level_width.{name} = {v!r} must be a finite number "
                              f"> 0 (the level's range in the sensor's units), \"{READING}\" or \"{RANGE}\"")
        else:
            out[name] = float(v)
    return {s: out[s] for s in names.SENSORS if s in out}


class TuningError(F16mmaeError, ValueError):
    """A tuning file that cannot be used; the message names the file, key and valid choices."""


@dataclass(frozen=True)
class Tuning:
    """One pseudonoise tuning. Each mapping holds only non-default (non-zero) knobs."""

    name: str
    description: str = ""
    turbulence: str = "light"
    gust_model: str = "gust_rate"
    failure_model: str = "complete"  # canonical text (hypotheses.check_failure_model), per component
    failed_surface_q: float | dict[str, float] = field(default_factory=lambda: dict(FAILED_SURFACE_Q))
    # ^ one number for every surface, or per surface (names.ACTUATORS keys)
    failed_surface_q_dual: dict[str, float] = field(default_factory=dict)
    # ^ every surface's walk in the dual hypotheses; empty: failed_surface_q's
    failed_sensor_level_q: float | dict[str, float] = field(default_factory=lambda: dict(FAILED_SENSOR_LEVEL_Q))
    # ^ one number for every sensor, or per sensor (names.SENSORS keys)
    failed_sensor_level_width: dict[str, float | str] = field(default_factory=dict)
    # ^ per sensor: W in its units or "reading" (level_width.py); empty: the full ranges
    failed_sensor_noise: str = "design"   # FAILED_SENSOR_NOISES: a failed sensor's A_jj
    qd_longitudinal: dict[str, float] = field(default_factory=dict)  # method 1
    r_pseudonoise: dict[str, float] = field(default_factory=dict)    # method 2
    qd_lateral: dict[str, float] = field(default_factory=dict)       # method 3
    actuator_q: dict[str, float] = field(default_factory=dict)       # method 4
    estimator: dict[str, float] = field(default_factory=dict)        # recommended settings

    def qd_diagonal(self, nx: int = names.NX) -> np.ndarray:
        """(nx,) additions to diag(Q_d) from methods 1 and 3 (actuator and gust states get none)."""
        out = np.zeros(nx)
        for key, val in {**self.qd_longitudinal, **self.qd_lateral}.items():
            out[names.STATES.index(key)] = val
        return out

    def r_diagonal(self) -> np.ndarray:
        """(7,) additions to diag(R) from method 2."""
        out = np.zeros(names.NZ)
        for key, val in self.r_pseudonoise.items():
            out[names.SENSORS.index(key)] = val
        return out

    def surface_walk_q(self, dual: bool = False) -> np.ndarray:
        """(5,) the random-walk strength (rad^2/s) of each failed surface under ``cover``, order
        ``names.ACTUATORS`` (``failed_surface_q``: one number for all, or per surface; with
        ``dual``, in a dual hypothesis: ``failed_surface_q_dual`` where it is given)."""
        q = self.failed_surface_q_dual if dual and self.failed_surface_q_dual else self.failed_surface_q
        return np.array([q[a] for a in names.ACTUATORS] if isinstance(q, dict) else [q] * names.NU, dtype=float)

    def sensor_level_q(self) -> np.ndarray:
        """(7,) the level random walk per frame of each failed sensor under ``cover``, in units of
        its noise variance, order ``names.SENSORS`` (``failed_sensor_level_q``: one number for
        all, or per sensor)."""
        q = self.failed_sensor_level_q
        return np.array([q[s] for s in names.SENSORS] if isinstance(q, dict) else [q] * names.NZ, dtype=float)

    def actuator_strengths(self) -> np.ndarray:
        """(5,) method-4 strengths q (rad^2/s), order ``names.ACTUATORS``."""
        out = np.zeros(names.NU)
        for key, val in self.actuator_q.items():
            out[names.ACTUATORS.index(key)] = val
        return out

    def to_dict(self) -> dict:
        """Plain dict in the TOML layout (for the bank's metadata)."""
        out = {"name": self.name, "description": self.description,
               "turbulence": self.turbulence, "gust_model": self.gust_model}
        if self.failure_model != "complete":  # a paper-model tuning keeps its metadata (and hash)
            out.update(failure_model=failure_model_table(self.failure_model), failed_surface_q=self.failed_surface_q,
                       failed_sensor_level_q=self.failed_sensor_level_q)
            if self.failed_surface_q_dual:  # only then: the banks without it keep their metadata
                out["failed_surface_q_dual"] = dict(self.failed_surface_q_dual)
        if self.failed_sensor_level_width:  # only then: the banks without it keep their metadata
            out["failed_sensor_level_width"] = dict(self.failed_sensor_level_width)
        if self.failed_sensor_noise != "design":  # likewise
            out["failed_sensor_noise"] = self.failed_sensor_noise
        return {**out,
                "method1_qd_longitudinal": dict(self.qd_longitudinal),
                "method2_r": dict(self.r_pseudonoise),
                "method3_qd_lateral": dict(self.qd_lateral),
                "method4_actuator_q": dict(self.actuator_q),
                "estimator": dict(self.estimator)}


def available_tunings() -> tuple[str, ...]:
    """Names of the tunings shipped in ``design/tunings`` (file stems)."""
    return tuple(sorted(p.stem for p in TUNINGS_DIR.glob("*.toml")))


def resolve_tuning_path(name_or_path: str | Path) -> Path:
    """A shipped tuning's name (``tuned``) or a path to a TOML file -> the file's path."""
    text = str(name_or_path)
    if not text.endswith(".toml") and "/" not in text:
        path = TUNINGS_DIR / f"{text}.toml"
        if not path.is_file():
            raise TuningError(f"unknown tuning {text!r}; shipped tunings: "
                              f"{', '.join(available_tunings())} (or give a path to a .toml file)")
        return path
    path = Path(text)
    if not path.is_file():
        raise TuningError(f"tuning file {text} does not exist")
    return path


def load_tuning(name_or_path: str | Path) -> Tuning:
    """Read and check a tuning: a shipped name (``untuned``, ``tuned``) or a TOML path."""
    path = resolve_tuning_path(name_or_path)
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise TuningError(f"tuning file {path}: not valid TOML ({exc})") from None
    return tuning_from_dict(data, source=str(path), default_name=path.stem)


def tuning_from_dict(data: dict, source: str = "tuning", default_name: str = "custom") -> Tuning:
    """Check a parsed tuning (layout of the module docstring) and build a Tuning."""
    for key in data:
        if key not in TOP_LEVEL_KEYS:
            raise TuningError(f"{source}: unknown key {key!r}; valid keys: {', '.join(TOP_LEVEL_KEYS)}")
    name = data.get("name", default_name)
    description = data.get("description", "")
    turbulence = data.get("turbulence", "light")
    gust_model = data.get("gust_model", "gust_rate")
    for key, val in (("name", name), ("description", description), ("turbulence", turbulence),
                     ("gust_model", gust_model)):
        if not isinstance(val, str):
            raise TuningError(f"{source}: {key} must be a string, got {val!r}")
    if not name:
        raise TuningError(f"{source}: name must not be empty")
    if turbulence not in TURBULENCE_LEVELS:
        raise TuningError(f"{source}: turbulence {turbulence!r} is not a level; valid: "
                          f"{', '.join(TURBULENCE_LEVELS)}")
    if gust_model not in GUST_MODELS:
        raise TuningError(f"{source}: gust_model {gust_model!r} is not a model; valid: "
                          f"{', '.join(GUST_MODELS)}")
    try:
        failure_model = check_failure_model(data.get("failure_model", "complete"))
    except ValueError as exc:
        raise TuningError(f"{source}: {exc}") from None
    walk_q = _surface_walk_q(data.get("failed_surface_q", FAILED_SURFACE_Q), source)
    walk_q_dual = _surface_walk_q_dual(data.get("failed_surface_q_dual"), source, walk_q)
    level_q = _sensor_level_q(data.get("failed_sensor_level_q", FAILED_SENSOR_LEVEL_Q), source)
    level_width = _sensor_level_width(data.get("failed_sensor_level_width", {}), source)
    sensor_noise = data.get("failed_sensor_noise", "design")
    if sensor_noise not in FAILED_SENSOR_NOISES:
        raise TuningError(f"{source}: failed_sensor_noise {sensor_noise!r} is not one of "
                          f"{', '.join(FAILED_SENSOR_NOISES)}")
    sections = {}
    for section, keys in SECTIONS.items():
        table = data.get(section, {})
        if not isinstance(table, dict):
            raise TuningError(f"{source}: [{section}] must be a table of {', '.join(keys)}")
        values = {}
        for key, val in table.items():
            if key not in keys:
                raise TuningError(f"{source}: unknown key {key!r} in [{section}]; valid keys: "
                                  f"{', '.join(keys)}")
            if isinstance(val, bool) or not isinstance(val, (int, float)):
                raise TuningError(f"{source}: [{section}] {key} must be a number, got {val!r}")
            if not math.isfinite(val) or val < 0.0:
                raise TuningError(f"{source}: [{section}] {key} = {val} is not a variance: "
                                  "it must be finite and >= 0")
            if val > 0.0:
                values[key] = float(val)
        sections[section] = values
    estimator = _estimator_settings(data.get("estimator", {}), source)
    return Tuning(name=name, description=description, turbulence=turbulence, gust_model=gust_model,
                  failure_model=failure_model, failed_surface_q=walk_q, failed_surface_q_dual=walk_q_dual,
                  failed_sensor_level_q=level_q, failed_sensor_level_width=level_width,
                  failed_sensor_noise=sensor_noise,
                  qd_longitudinal=sections["method1_qd_longitudinal"],
                  r_pseudonoise=sections["method2_r"],
                  qd_lateral=sections["method3_qd_lateral"],
                  actuator_q=sections["method4_actuator_q"], estimator=estimator)


def _dwell_nats_table(table, source: str) -> dict[str, float]:
    """``[estimator] dwell_nats_per_hypothesis``: name -> N_k (nats, [0, 1e6]); the names are
    checked against the bank's hypotheses when the bank is built (core.ModelBank)."""
    where = f"{source}: [estimator] dwell_nats_per_hypothesis"
    if not isinstance(table, dict):
        raise TuningError(f"{where} must be a table NAME = nats, got {table!r}")
    lo, hi = ESTIMATOR_KEYS["dwell_nats_per_hypothesis"]
    out = {}
    for name, val in table.items():
        if isinstance(val, bool) or not isinstance(val, (int, float)):
            raise TuningError(f"{where}: {name} must be a number of nats, got {val!r}")
        if not (math.isfinite(val) and lo <= val <= hi):
            raise TuningError(f"{where}: {name} = {val} is outside [{lo:g}, {hi:g}] nats")
        out[str(name)] = float(val)
    return out


def _estimator_settings(table, source: str) -> dict:
    if not isinstance(table, dict):
        raise TuningError(f"{source}: [estimator] must be a table of {', '.join(ESTIMATOR_KEYS)}")
    out = {}
    for key, val in table.items():
        if key not in ESTIMATOR_KEYS:
            raise TuningError(f"{source}: unknown key {key!r} in [estimator]; valid keys: "
                              f"{', '.join(ESTIMATOR_KEYS)}")
        if key == "dwell_nats_per_hypothesis":
            out[key] = _dwell_nats_table(val, source)
            continue
        if isinstance(val, bool) or not isinstance(val, (int, float)):
            raise TuningError(f"{source}: [estimator] {key} must be a number, got {val!r}")
        lo, hi = ESTIMATOR_KEYS[key]
        ok = (lo <= val <= hi) if key == "dwell_s" else (lo < val < hi)
        if not (math.isfinite(val) and ok):
            rng = f"[{lo:g}, {hi:g}]" if key == "dwell_s" else f"({lo:g}, {hi:g})"
            raise TuningError(f"{source}: [estimator] {key} = {val} is outside {rng}")
        out[key] = float(val)
    return out
