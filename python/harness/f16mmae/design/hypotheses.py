"""The failure hypotheses of the bank (paper Sec. II-III, Fig. 2) as changes to the
no-failure model, in one of two failure models (``FAILURE_MODELS``, the tuning's
``failure_model``):

``complete`` (the paper's; one value of each failure):

- Actuator failure j: the column j of ``B_d`` is removed (set to zero). The surface no
  longer answers its command; its first-order lag state stays in the model and, with no
  input, decays to zero, i.e. to its TRIM deflection (surface held at trim). Zeroing the
  continuous ``B`` column before discretizing gives exactly the same ``B_d`` (the column of
  ``B_d`` is ``int e^{F s} ds b_j``), so removing the discrete column is exact.
- Sensor failure i: the row i of ``H`` is removed (set to zero). The model then expects
  that channel to carry only its noise around the trim value (``z_i - z_trim,i = v_i``),
  a Gaussian factor ``N(r_i; 0, R_ii)`` of the likelihood.

``cover`` (the failure whatever value it takes):

- Actuator failure j: the surface sits at an unknown position (held at trim, stuck where it
  was, hardover) that the filter estimates. Its lag state becomes a random walk: the row of
  ``F`` is zeroed (``d(delta_j)/dt = w_j`` instead of ``-lambda (delta_j - delta_cmd)``), the
  ``B`` column is zeroed, and a white ``w_j`` of strength ``failed_surface_q`` (rad^2/s, one
  value or one per surface) drives it; ``Phi``, ``B_d`` and ``Q_d`` of that hypothesis are discretized from this
  ``F`` (``hypothesis_dynamics``), so a stuck or hardover surface is a constant the filter
  learns, and one held at trim is the constant zero.
- Sensor failure i: the row i of ``H`` is removed as above, and the reading is declared
  uninformative about the aircraft: under the hypothesis it is an unknown level anywhere in
  the sensor's full range ``W_i = FULL_SCALE_i high - low`` (``truth.sensors.FULL_SCALE``,
  the sensor's specification) plus the sensor's noise -- held at trim, zero, stuck, full
  scale, biased -- and the level wanders as a random walk of ``q_i = failed_sensor_level_q
  * NOISE_SIGMA_i^2`` per frame (drifting). The core replaces the channel's Gaussian factor by
  ``1/W_i`` on the first frame and then by the predictive density of the level's scalar
  Kalman filter (``cpp/f16mmae/steady_state_filter.h`` derives it), so hypotheses using
  different numbers of readings are densities over the same seven readings, and a reading
  held anywhere costs about ``ln(W_i / sqrt(2 pi A_ii))`` (6-7 nats) once -- and again on
  each re-entry from the probability floor: the core lowers such a hypothesis' floor by that
  Occam factor (``cpp/f16mmae/filter_bank.h``), since its level kept following the healthy
  reading while it sat there (the core's ``fresh_floor_levels``, off by default, restarts it
  there instead). With
  ``failed_sensor_level_q = 0`` the level has no memory: the reading is uniform over the
  range every frame, and a reading near trim then costs that every frame, so a sensor failed
  at or near its trim value is never isolated (docs/results/failure_models.md measures both).

``constant`` (a failed sensor reading an unknown constant near its trim; sensors only):

- Sensor failure i: the row i of ``H`` is removed as above, and the reading is an unknown
  constant level b_i plus the sensor's noise, the level uniform over ``W_i = 6 sigma_trim,i``
  (the trim value's uncertainty ``TRIM_SIGMA``, +-3 sigma) -- the paper's ``complete`` failure
  (the sensor reads its trim) without assuming that the estimator knows the trim exactly. A
  scheduled bank's trim follows the measured air data, which turbulence moves, so it is off
  the aircraft's own trim by a few sensor sigmas (docs/results/envelope_tuning.md, round 7:
  1.65 ft/s RMS for VEL against its 0.5-ft/s noise), and the ``complete`` hypothesis pays
  that offset squared over A_ii every frame. The core's ``cover`` density (first frame
  ``1/W_i``, then the predictive density of the level's Kalman filter, with a jump term)
  carries it, with the level's random walk ``q_i = CONSTANT_LEVEL_Q_RATIO * NOISE_SIGMA_i^2``
  per frame: a constant over any flight (the level's variance is A_ii / n after n readings,
  the exact predictive density of an unknown constant, for n << 1/sqrt(ratio) frames, i.e.
  hours). Its first frame costs ``ln(W_i / sqrt(2 pi A_ii))`` (2.1 nats for VEL) once, and a
  healthy reading that moves with the aircraft costs it every frame it leaves the level.
  Only sensors with a ``TRIM_SIGMA`` take it (ValueError naming them otherwise).

Partial loss (``f16mmae design --partial-loss F``, F the fraction of effectiveness lost, as
``f16mmae campaign detectability --losses``; with any failure model):

- Partial hypothesis ``"C:loss=R"`` of surface C (``partial_name``), R = 1 - F the fraction of
  its effectiveness it keeps, 0 < R < 1 -- named as the truth's failure mode it matches,
  ``C@T:loss=R`` (the surface moves R times its command about the trim). The no-failure model
  with C's column of ``B`` scaled by R = 1 - F: ``B_d`` is linear in each column of ``B``, so
  the discrete column is scaled by R exactly; ``Phi``, ``H``, ``Q_d`` are the no-failure ones.
  One such hypothesis per surface and fraction joins the level-0 bank (the core:
  cpp/f16mmae/hierarchical_bank.h); it has no duals -- its declaration brings on line the
  level-1 bank of C's failure in any form.

A dual hypothesis ``"A+B"`` applies both changes. ``R`` is the same in every hypothesis; so
are ``Phi`` and ``Q_d`` except for a ``cover`` actuator hypothesis.

Per component (``component_models``): a failure model may name one model for every component
(``"complete"``, ``"cover"``) or a default and the components that take another, as text
``"cover=VEL+AOA"`` (cover for VEL and AOA, the default ``complete`` for the other ten),
``"cover,complete=PIT+ROL"`` (default first), or as the tuning's TOML table
``failure_model = {default = "complete", cover = ["VEL", "AOA"]}``.  Each failed component of
a hypothesis takes its own model: under ``"cover=VEL+AOA"`` the hypothesis ``VEL+PIT`` has an
uninformative VEL channel and PIT's row removed in the paper's Gaussian form, and every
hypothesis without VEL or AOA is the ``complete`` one, matrix for matrix.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import names
from ..truth import sensors

#: The failure models a bank is designed with (module docstring); the first is the paper's.
FAILURE_MODELS: tuple[str, ...] = ("complete", "cover", "constant")

#: sigma of a sensor's trim value as a scheduled bank knows it, for the ``constant`` model
#: (sensor units): the RMS offset of the scheduled trim from the aircraft's own trim (what a
#: `complete` failure reads) once the air data's running mean has settled, at light turbulence
#: (tools/schedule/trim_anchor.py): VEL 1.65 ft/s (3.3 noise sigmas; docs/results/envelope_tuning.md,
#: round 7, section 1), AOA 0.00138 rad (0.8 noise sigma; round 9, section "AOA"), ROL 0.1 deg/s
#: (one noise sigma: the trim roll rate is 0 in wings-level flight and the level absorbs a
#: residual rate the scheduled trim does not carry; round 13).
TRIM_SIGMA: dict[str, float] = {"VEL": 1.65, "AOA": 0.00138, "ROL": float(sensors.NOISE_SIGMA[4])}

#: Half-width of the ``constant`` model's uniform level in units of TRIM_SIGMA (+-3 sigma).
CONSTANT_HALF_WIDTH_SIGMAS = 3.0

#: The ``constant`` model's level random walk per frame in units of the sensor's noise
#: variance: the level drifts one noise sigma in 1e6 frames (4.3 h at 64 Hz), a constant.
CONSTANT_LEVEL_Q_RATIO = 1e-6


#: The mode a partial hypothesis names (the truth's failure mode of the same meaning).
PARTIAL_MODE = "loss"


def partial_name(surface: str, fraction: float) -> str:
    """The partial hypothesis of ``surface`` keeping ``fraction`` R of its effectiveness:
    ``"LS:loss=0.5"``. ValueError for a component that is no surface or R outside (0, 1)."""
    if surface not in names.ACTUATORS:
        raise ValueError(f"a partial-loss hypothesis needs a surface, got {surface!r}; valid: "
                         f"{', '.join(names.ACTUATORS)}")
    f = float(fraction)
    if not 0.0 < f < 1.0:
        raise ValueError(f"partial loss: the remaining effectiveness must lie in (0, 1), got {fraction!r}")
    return f"{surface}:{PARTIAL_MODE}={f:g}"


def parse_partial(name: str) -> tuple[str, float] | None:
    """``(surface, R)`` (R the effectiveness kept) of a partial hypothesis name (``partial_name``), None for any other
    hypothesis name (NONE, singles, duals). ValueError for a malformed partial name."""
    if ":" not in name or "+" in name:
        return None
    surface, _, mode = name.partition(":")
    key, _, value = mode.partition("=")
    try:
        f = float(value)
    except ValueError:
        raise ValueError(f"partial hypothesis {name!r}: expected SURFACE:{PARTIAL_MODE}=R") from None
    if key != PARTIAL_MODE:
        raise ValueError(f"partial hypothesis {name!r}: expected SURFACE:{PARTIAL_MODE}=R")
    if partial_name(surface, f) != name:
        raise ValueError(f"partial hypothesis {name!r} is not in canonical form {partial_name(surface, f)!r}")
    return surface, f


def isolated_component(name: str) -> str:
    """The hypothesis a declaration of ``name`` isolates, for scoring: a partial hypothesis'
    surface (``"LS:loss=0.5" -> "LS"``; a failure of the surface in any mode), any other name
    itself."""
    p = parse_partial(name)
    return name if p is None else p[0]


def partial_hypotheses(losses) -> tuple[str, ...]:
    """One partial hypothesis per surface and fraction lost F (``names.ACTUATORS`` order within
    each F), each keeping R = 1 - F; ValueError for an F outside (0, 1) or given twice."""
    fr = [float(f) for f in losses]
    if len(set(fr)) != len(fr):
        raise ValueError(f"partial loss: a fraction is given twice in {losses!r}")
    for f in fr:
        if not 0.0 < f < 1.0:
            raise ValueError(f"partial loss: the fraction lost must lie in (0, 1), got {f!r}")
    return tuple(partial_name(s, round(1.0 - f, 12)) for f in fr for s in names.ACTUATORS)


@dataclass(frozen=True)
class HypothesisModel:
    """The discrete model presumed by one hypothesis (perturbations from trim)."""

    name: str
    phi: np.ndarray  # (nx, nx)
    bd: np.ndarray   # (nx, nu)
    h: np.ndarray    # (nz, nx)
    qd: np.ndarray   # (nx, nx) process noise of this hypothesis' filter
    uninformative_width: np.ndarray  # (nz,) W_i of an uninformative channel, 0 otherwise
    uninformative_level_q: np.ndarray  # (nz,) level random walk per frame of such a channel


def _model(model, where: str) -> str:
    if not isinstance(model, str) or model not in FAILURE_MODELS:
        raise ValueError(f"{where}{model!r} is not a failure model; valid: {', '.join(FAILURE_MODELS)}")
    return model


def _parse(failure_model) -> tuple[str, dict[str, str]]:
    """(default model, every component's model) of any form ``component_models`` reads."""
    if isinstance(failure_model, dict):
        default = _model(failure_model.get("default", "complete"), "failure_model default ")
        items = []
        for key, comps in failure_model.items():
            if key == "default":
                continue
            _model(key, "failure_model table key ")
            if isinstance(comps, str) or not isinstance(comps, (list, tuple)):
                raise ValueError(f"failure_model {key} = {comps!r} must be a list of components, "
                                 f"e.g. [\"VEL\", \"AOA\"]")
            items.append((key, list(comps)))
    elif isinstance(failure_model, str):
        parts = [p.strip() for p in failure_model.split(",")]
        bare = [p for p in parts if "=" not in p]
        if len(bare) > 1:
            raise ValueError(f"failure_model {failure_model!r} names more than one default model "
                             f"({', '.join(bare)}); give one default and MODEL=COMPONENT+COMPONENT for "
                             "the others, e.g. cover=VEL+AOA")
        default = _model(bare[0], "failure_model ") if bare else "complete"
        items = [(_model(p.split("=", 1)[0].strip(), f"failure_model {failure_model!r}: "),
                  [c.strip() for c in p.split("=", 1)[1].split("+")]) for p in parts if "=" in p]
    else:
        raise ValueError(f"failure_model {failure_model!r} must be a model name ({', '.join(FAILURE_MODELS)}), "
                         "a text like cover=VEL+AOA or a table {default = ..., cover = [...]}")
    if default == "constant":
        raise ValueError(f"failure_model constant cannot be the default (it applies to "
                         f"{', '.join(TRIM_SIGMA)} only); name them, e.g. constant=VEL")
    per = dict.fromkeys(names.COMPONENTS, default)
    given: set[str] = set()
    for model, comps in items:
        for comp in comps:
            if comp not in names.COMPONENTS:
                raise ValueError(f"failure_model {model}: unknown component {comp!r}; valid: "
                                 f"{', '.join(names.COMPONENTS)}")
            if comp in given:
                raise ValueError(f"failure_model: component {comp} is given a model twice")
            if model == "constant" and comp not in TRIM_SIGMA:
                raise ValueError(f"failure_model constant: component {comp} has no trim uncertainty; "
                                 f"constant applies to {', '.join(TRIM_SIGMA)}")
            given.add(comp)
            per[comp] = model
    return default, per


def component_models(failure_model) -> dict[str, str]:
    """Every component's failure model (``names.COMPONENTS`` order) from a failure model given
    as a model name, a per-component text (``"cover=VEL+AOA"``, ``"cover,complete=PIT"``) or
    a table ``{"default": M, OTHER: [components]}`` (module docstring).  Raises ValueError
    naming the unknown model or component and the valid ones, or a component given twice."""
    return _parse(failure_model)[1]


def check_failure_model(failure_model) -> str:
    """The canonical text of a failure model (any form ``component_models`` reads): a model
    name when every component has it, else ``[DEFAULT,]MODEL=C+C...`` with the default left
    out when it is ``complete`` and the components in ``names.COMPONENTS`` order, e.g.
    ``"cover=VEL+AOA"``.  ValueError as ``component_models``."""
    default, per = _parse(failure_model)
    if len(set(per.values())) == 1:
        return next(iter(per.values()))
    parts = [] if default == "complete" else [default]
    for model in FAILURE_MODELS:
        comps = [c for c in names.COMPONENTS if per[c] == model and model != default]
        if comps:
            parts.append(f"{model}={'+'.join(comps)}")
    return ",".join(parts)


def failure_model_table(failure_model):
    """The failure model in the tuning's TOML layout: the model name when one model covers every
    component, else ``{"default": M, OTHER: [components]}`` (what a bank's metadata records)."""
    default, per = _parse(failure_model)
    if len(set(per.values())) == 1:
        return next(iter(per.values()))
    return {"default": default, **{m: [c for c in names.COMPONENTS if per[c] == m]
                                   for m in FAILURE_MODELS if m != default and m in per.values()}}


def _failed(name: str) -> tuple[str, ...]:
    """The components hypothesis ``name`` fails whole (a partial hypothesis: none)."""
    return () if parse_partial(name) is not None else names.failed_components(name)


def uses_cover(failure_model) -> bool:
    """Whether any component takes the ``cover`` model."""
    return "cover" in component_models(failure_model).values()


def uninformative_models(failure_model) -> bool:
    """Whether any failed sensor's channel is uninformative (``cover`` or ``constant``)."""
    return bool({"cover", "constant"} & set(component_models(failure_model).values()))


def sensor_full_range() -> np.ndarray:
    """(nz,) width of each sensor's full-scale range, ``truth.sensors.FULL_SCALE``."""
    return np.array([hi - lo for lo, hi in sensors.FULL_SCALE], dtype=float)


def uninformative_level_q(name: str, failure_model, ratio) -> np.ndarray:
    """(nz,) the level random walk per frame of hypothesis ``name``'s uninformative channels,
    in units of the sensor's noise variance (``truth.sensors.NOISE_SIGMA``): ``ratio`` (one
    number, or (nz,) per sensor) on its failed sensors whose model is ``cover``,
    ``CONSTANT_LEVEL_Q_RATIO`` on ``constant`` ones, zeros otherwise."""
    noise_var = np.asarray(sensors.NOISE_SIGMA, dtype=float) ** 2
    ratio = np.broadcast_to(np.asarray(ratio, dtype=float), (names.NZ,))
    per = component_models(failure_model)
    out = np.zeros(names.NZ)
    for comp in _failed(name):
        if comp in names.SENSORS and per[comp] in ("cover", "constant"):
            j = names.SENSORS.index(comp)
            out[j] = (float(ratio[j]) if per[comp] == "cover" else CONSTANT_LEVEL_Q_RATIO) * noise_var[j]
    return out


def uninformative_width(name: str, failure_model) -> np.ndarray:
    """(nz,) the widths of hypothesis ``name``'s uninformative channels: the full ranges of its
    failed sensors whose model is ``cover``, ``2 CONSTANT_HALF_WIDTH_SIGMAS TRIM_SIGMA`` of
    ``constant`` ones, zeros for ``complete`` ones (and for sensors it keeps)."""
    out = np.zeros(names.NZ)
    per = component_models(failure_model)
    full = sensor_full_range()
    for comp in _failed(name):
        if comp in names.SENSORS and per[comp] == "cover":
            out[names.SENSORS.index(comp)] = full[names.SENSORS.index(comp)]
        elif comp in names.SENSORS and per[comp] == "constant":
            out[names.SENSORS.index(comp)] = 2.0 * CONSTANT_HALF_WIDTH_SIGMAS * TRIM_SIGMA[comp]
    return out


def covered_surfaces(name: str, failure_model) -> tuple[str, ...]:
    """The failed actuators of hypothesis ``name`` whose model is ``cover`` (a random walk)."""
    per = component_models(failure_model)
    return tuple(c for c in _failed(name) if c in names.ACTUATORS and per[c] == "cover")


def hypothesis_dynamics(name: str, f: np.ndarray, gqg: np.ndarray, failed_surface_q,
                        n_airframe: int, failure_model="cover") -> tuple[np.ndarray, np.ndarray]:
    """``(F_k, GQG_k)`` of the ``cover`` model: each failed actuator whose model is ``cover``
    (``covered_surfaces``) has its lag state (index ``n_airframe + j``) turned into a random
    walk of strength ``failed_surface_q`` (one number, or (5,) per surface in
    ``names.ACTUATORS`` order)."""
    f_k = np.array(f, dtype=float, copy=True)
    gqg_k = np.array(gqg, dtype=float, copy=True)
    walk_q = np.broadcast_to(np.asarray(failed_surface_q, dtype=float), (names.NU,))
    for comp in covered_surfaces(name, failure_model):
        j = names.ACTUATORS.index(comp)
        i = n_airframe + j
        f_k[i, :] = 0.0
        gqg_k[i, i] += walk_q[j]
    return f_k, gqg_k


def hypothesis_model(name: str, phi: np.ndarray, bd: np.ndarray, h: np.ndarray,
                     qd: np.ndarray | None = None, width: np.ndarray | None = None,
                     level_q: np.ndarray | None = None) -> HypothesisModel:
    """The model of hypothesis ``name`` (``"NONE"``, ``"LS"``, ``"PIT"``, ``"LS+PIT"``, ...)
    from ``(phi, bd, h)`` (the no-failure ones, or a ``cover`` hypothesis' own ``phi``, ``bd``):
    failed actuators' B_d columns and failed sensors' H rows set to zero; ``qd``, the
    uninformative widths and trim weights stored as given (zeros by default). Raises ValueError naming an
    unknown component."""
    bd_k = np.array(bd, dtype=float, copy=True)
    h_k = np.array(h, dtype=float, copy=True)
    partial = parse_partial(name)
    if partial is not None:
        bd_k[:, names.ACTUATORS.index(partial[0])] *= partial[1]
    for comp in (() if partial is not None else names.failed_components(name)):
        if comp in names.ACTUATORS:
            bd_k[:, names.ACTUATORS.index(comp)] = 0.0
        else:
            h_k[names.SENSORS.index(comp), :] = 0.0
    n, m = h_k.shape[1], h_k.shape[0]
    return HypothesisModel(name=name, phi=np.array(phi, dtype=float, copy=True), bd=bd_k, h=h_k,
                           qd=np.zeros((n, n)) if qd is None else np.array(qd, dtype=float, copy=True),
                           uninformative_width=np.zeros(m) if width is None else np.asarray(width, dtype=float),
                           uninformative_level_q=(np.zeros(m) if level_q is None
                                                      else np.asarray(level_q, dtype=float)))


def all_hypothesis_models(phi: np.ndarray, bd: np.ndarray, h: np.ndarray,
                          hypotheses: tuple[str, ...] = names.ALL_HYPOTHESES,
                          qd: np.ndarray | None = None) -> list[HypothesisModel]:
    """``complete`` models of every hypothesis in bank order: NONE, the 12 singles, the 66 duals."""
    return [hypothesis_model(n, phi, bd, h, qd) for n in hypotheses]
