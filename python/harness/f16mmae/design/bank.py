"""Assemble the model bank: every hypothesis filter of one flight condition and tuning,
the trim the estimator subtracts, and the metadata that reproduces it.

Pipeline (``design_bank``)::

    truth trim + linearization (model.linearize_truth)
      -> continuous design model (model.build_model)
      -> exact discretization at FRAME_RATE_HZ: Phi, B_d, Q_d = Van Loan(G Q_c G^T
         + sum_j q_j b_j b_j^T) + diag(method 1, 3);  R = diag(sigma^2 + method 2)
      -> for each of the 79 hypotheses (NONE, 12 singles, 66 duals; hypotheses.py, in the
         tuning's failure model, per component: ``complete``, the paper's, or ``cover``, where
         a failed surface is a random-walk state discretized per hypothesis and a failed
         sensor's reading is uninformative): DARE -> K, A = H P^- H^T + R (gains.py), unstable
         filters refused
      -> core.ModelBank (u_trim, z_trim, h_output = unfailed H, the recommended estimator
         settings p_min / threshold / dwell_s, metadata JSON) -> file (format version 3)

``partial_loss=(F, ...)`` (``f16mmae design --partial-loss F``): after the 79, one partial
hypothesis per surface and fraction lost F (``"LS:loss=0.5"``: the surface keeps 1 - F of its
effectiveness, hypotheses.py), which the core puts in the level-0 bank beside the singles
(13 + 5 per fraction filters; cpp/f16mmae/hierarchical_bank.h). Off by default: the banks
without it are unchanged, byte for byte.

A tuning's ``failed_sensor_level_width`` (``f16mmae design --failed-sensor-level-width
PIT=range``): the named ``cover`` sensors' level range W_j in every hypothesis that fails
them, given, derived from the no-failure model or the full range (level_width.py); the
sensors not named take ``level_width.DEFAULT_WIDTHS`` (a cover PIT its derived width, the
others their full range).  The metadata's ``level_widths`` records each W_j not the full range,
its Occam constant c_j and, derived, the reading's sigma_j.

``throttle_input=True`` (``f16mmae design --throttle-input``): the throttle command is the
model's sixth input (model.py: its column from JSBSim's linearization), in every hypothesis;
the bank's inputs are ``names.INPUTS_WITH_THROTTLE`` (LS RS LF RF RUD THR), its u_trim ends
with the trim throttle, and the closed loop flies the truth's throttle dither with it
(loop/flight.py).  Off by default: the banks without it are unchanged, byte for byte.

Everything is deterministic: the same (mach, alt_ft, tuning, design procedure, JSBSim) gives
the same bank file, byte for byte (JSBSim's trim is deterministic). The metadata therefore
records ``design_version`` (bump it when the procedure changes) and the JSBSim version, not
the package version, so a release that does not change the design keeps the shipped banks.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .. import names
from ..truth import actuators, sensors
from .discretize import DiscreteModel, discretize
from .gains import SteadyStateGains, steady_state_gains
from .level_width import effective_spec, level_widths
from .hypotheses import (HypothesisModel, component_models, covered_surfaces, hypothesis_dynamics, hypothesis_model,
                         parse_partial, partial_hypotheses, uninformative_level_q, uninformative_width)
from .model import GUST_SCALE_LENGTH_FT, ContinuousModel, LinearizedTrim, build_model, linearize_truth
from .tuning import Tuning, TuningError, available_tunings, load_tuning

#: Where the shipped nominal banks live, and the nominal flight condition.
DATA_DIR = Path(__file__).resolve().parent.parent / "data"
NOMINAL_MACH = 0.4
NOMINAL_ALT_FT = 20_000.0
#: Version of the design procedure (bumped when the same inputs would give another bank).
DESIGN_VERSION = 1


@dataclass(frozen=True)
class FilterDesign:
    """One hypothesis filter: its model and steady-state gains."""

    model: HypothesisModel
    gains: SteadyStateGains

    @property
    def name(self) -> str:
        return self.model.name


@dataclass(frozen=True)
class BankDesign:
    """A designed bank before it is written: filters in bank order plus what made them."""

    mach: float
    alt_ft: float
    frame_rate_hz: float
    tuning: Tuning
    linearized: LinearizedTrim
    continuous: ContinuousModel
    discrete: DiscreteModel  # NONE model; qd includes every pseudonoise
    r: np.ndarray            # (7, 7) incl. method-2 pseudonoise
    filters: tuple[FilterDesign, ...]
    level_widths: dict = None  # sensor -> {width, occam_nats[, sigma]} (level_width.py); None: full ranges

    @property
    def throttle_input(self) -> bool:
        """Whether the throttle is the sixth modelled input."""
        return self.continuous.throttle_input

    @property
    def input_names(self) -> tuple[str, ...]:
        return names.INPUTS_WITH_THROTTLE if self.throttle_input else names.ACTUATORS

    @property
    def u_trim(self) -> np.ndarray:
        """Absolute trim inputs: surface commands (rad), then the trim throttle with the throttle input."""
        u = np.asarray(self.linearized.trim.u_rad, dtype=float)
        return np.append(u, self.linearized.trim.throttle) if self.throttle_input else u

    @property
    def z_trim(self) -> np.ndarray:
        return np.asarray(self.linearized.trim.z, dtype=float)

    @property
    def h_output(self) -> np.ndarray:
        return self.continuous.h

    @property
    def partial_loss(self) -> tuple[float, ...]:
        """The fractions lost F of the bank's partial hypotheses (``--partial-loss``), in order."""
        out = []
        for f in self.filters:
            p = parse_partial(f.name)
            if p is not None and round(1.0 - p[1], 12) not in out:
                out.append(round(1.0 - p[1], 12))
        return tuple(out)

    def filter(self, name: str) -> FilterDesign:
        for f in self.filters:
            if f.name == name:
                return f
        raise KeyError(f"no hypothesis {name!r} in the bank; valid: {', '.join(names.ALL_HYPOTHESES)}")

    def metadata(self) -> dict:
        """What reproduces the bank (stored as JSON text in the bank file)."""
        import jsbsim

        trim = self.linearized.trim
        out = {
            "generator": "f16mmae.design",
            "design_version": DESIGN_VERSION,
            "jsbsim_version": jsbsim.__version__,
            "command": (f"f16mmae design --mach {self.mach:g} --alt-ft {self.alt_ft:g} "
                        f"--tuning {tuning_arguments(self.tuning)}"
                        + (" --throttle-input" if self.throttle_input else "")
                        + (f" --partial-loss {','.join(f'{f:g}' for f in self.partial_loss)}"
                           if self.partial_loss else "")),
            "flight_condition": {"mach": self.mach, "alt_ft": self.alt_ft},
            "trim": {"vt_fps": trim.vt_fps, "alpha_rad": trim.alpha_rad,
                     "theta_rad": trim.theta_rad, "throttle": trim.throttle,
                     "lef_rad": trim.lef_rad, "qbar_psf": trim.qbar_psf,
                     "weight_lbs": trim.weight_lbs},
            "model": {
                "actuator_lag_rad_s": list(actuators.LAG_RAD_S),
                "mixing": actuators.MIXING.tolist(),
                "sensor_noise_sigma": list(map(float, sensors.NOISE_SIGMA)),
                "gust_level": self.tuning.turbulence,
                "gust_model": self.continuous.gust_model,
                "gust_sigma_fps_uvw": self.continuous.gust_sigma_fps.tolist(),
                "gust_scale_length_ft": GUST_SCALE_LENGTH_FT,
                "linearization_evaluations": self.linearized.lin.evaluations,
            },
            "tuning": self.tuning.to_dict(),
            "hypotheses": len(self.filters),
            "max_error_spectral_radius": max(f.gains.spectral_radius for f in self.filters),
        }
        if self.throttle_input:  # only then: the banks without it keep their bytes
            out["model"]["throttle_column_per_unit"] = self.linearized.throttle_column.tolist()
        if self.partial_loss:  # likewise
            out["partial_loss"] = list(self.partial_loss)
        if self.level_widths:  # likewise
            out["level_widths"] = {s: dict(v) for s, v in self.level_widths.items()}
        return out


def tuning_arguments(tuning: Tuning) -> str:
    """The ``--tuning ...`` arguments of ``f16mmae design`` that give ``tuning``: the CLI names
    a derived tuning ``NAME[-LEVEL][-gust][-M[-qQ]]`` (``--gust-level LEVEL``, ``--gust-states``,
    ``--failure-model M``, ``--failed-sensor-level-q Q``); this undoes that naming."""
    rest, tail = tuning.name, []
    widths = tuning.failed_sensor_level_width
    suffix = "-w" + "".join(widths)
    if widths and rest.endswith(suffix):
        rest = rest[:-len(suffix)]
        tail.insert(0, "--failed-sensor-level-width " + ",".join(f"{s}={v if isinstance(v, str) else f'{v:g}'}"
                                                                 for s, v in widths.items()))
    level_q = tuning.failed_sensor_level_q
    weight = f"-q{level_q:g}" if not isinstance(level_q, dict) else None
    if tuning.failure_model != "complete" and weight is not None and rest.endswith(weight):
        rest = rest[:-len(weight)]
        tail.insert(0, f"--failed-sensor-level-q {tuning.failed_sensor_level_q:g}")
    suffix = f"-{tuning.failure_model}"
    if tuning.failure_model != "complete" and rest.endswith(suffix):
        rest = rest[:-len(suffix)]
        tail.insert(0, f"--failure-model {tuning.failure_model}")
    if tuning.gust_model == "dryden_states" and rest.endswith("-gust"):
        rest = rest[:-len("-gust")]
        tail.insert(0, "--gust-states")
    if rest.endswith(f"-{tuning.turbulence}") and rest[:-len(tuning.turbulence) - 1] in available_tunings():
        rest = rest[:-len(tuning.turbulence) - 1]
        tail.insert(0, f"--gust-level {tuning.turbulence}")
    return " ".join([rest] + tail)


def continuous_noise(model: ContinuousModel, tuning: Tuning) -> np.ndarray:
    """(nx, nx) ``G Q_c G^T`` plus the method-4 actuator noise (eqs. 6-7)."""
    q_act = tuning.actuator_strengths()
    return model.g @ model.qc @ model.g.T + (model.b_airframe * q_act) @ model.b_airframe.T


def discrete_design_model(model: ContinuousModel, tuning: Tuning,
                          frame_rate_hz: float) -> tuple[DiscreteModel, np.ndarray]:
    """``(Phi, B_d, Q_d)`` and ``R`` of the no-failure model with the tuning's pseudonoise:
    method 4 enters the continuous noise before discretizing, methods 1/3 add to diag(Q_d),
    method 2 to diag(R)."""
    dm = discretize(model.f, model.b, np.eye(model.nx), continuous_noise(model, tuning), 1.0 / frame_rate_hz)
    qd = dm.qd + np.diag(tuning.qd_diagonal(model.nx))
    r = np.diag(model.r_diag + tuning.r_diagonal())
    return DiscreteModel(phi=dm.phi, bd=dm.bd, qd=qd, dt_s=dm.dt_s), r


def hypothesis_models(model: ContinuousModel, tuning: Tuning, discrete: DiscreteModel,
                      hypotheses: tuple[str, ...] = names.ALL_HYPOTHESES,
                      widths: dict | None = None) -> list[HypothesisModel]:
    """Every hypothesis' discrete model in the tuning's failure model (hypotheses.py, per
    component): the no-failure ``discrete`` with B_d columns / H rows removed, and for the
    failed components whose model is ``cover`` a failed surface's random walk discretized for
    its hypothesis (same pseudonoise on diag(Q_d); in a dual hypothesis the tuning's dual walk) and the failed sensors' uninformative widths
    (``widths``: sensor -> {"width": W} in place of the full range, level_width.py)."""
    per = component_models(tuning.failure_model)
    for sensor in widths or {}:
        if per[sensor] != "cover":
            raise ValueError(f"failed_sensor_level_width names {sensor}, whose failure model is "
                             f"{per[sensor]}: a level width applies to a cover sensor "
                             f"(failure_model {tuning.failure_model!r})")
    out = []
    n_air = names.NX - names.NU
    gqg = continuous_noise(model, tuning)
    for name in hypotheses:
        phi, bd, qd = discrete.phi, discrete.bd, discrete.qd
        if covered_surfaces(name, tuning.failure_model):
            walk_q = tuning.surface_walk_q(dual=name in names.DUAL_HYPOTHESES)
            f_k, gqg_k = hypothesis_dynamics(name, model.f, gqg, walk_q, n_air, tuning.failure_model)
            dm = discretize(f_k, model.b, np.eye(model.nx), gqg_k, discrete.dt_s)
            phi, bd, qd = dm.phi, dm.bd, dm.qd + np.diag(tuning.qd_diagonal(model.nx))
        width = uninformative_width(name, tuning.failure_model)
        for sensor, entry in (widths or {}).items():
            j = names.SENSORS.index(sensor)
            if width[j] > 0.0:
                width[j] = entry["width"]
        out.append(hypothesis_model(name, phi, bd, model.h, qd, width,
                                    uninformative_level_q(name, tuning.failure_model,
                                                              tuning.sensor_level_q())))
    return out


def design_filters(models: list[HypothesisModel], r: np.ndarray,
                   failed_sensor_noise: np.ndarray | None = None) -> tuple[FilterDesign, ...]:
    """Steady-state filter of every hypothesis (DesignError names an unstable one).
    ``failed_sensor_noise`` ((7,) variances, the tuning's ``failed_sensor_noise = "sensor"``):
    each failed sensor j's residual variance is A_jj = failed_sensor_noise[j] in place of R_jj.
    Its H row is zero, so A's row and column j are R's (diagonal) and K's column j is zero:
    P, K and the other channels are the same either way."""
    out = []
    for m in models:
        gains = steady_state_gains(m.phi, m.h, m.qd, r, name=f"hypothesis {m.name}")
        failed = [names.SENSORS.index(c) for c in names.failed_components(m.name) if c in names.SENSORS]
        if failed_sensor_noise is not None and failed:
            a = gains.a.copy()
            for j in failed:
                a[j, j] = float(failed_sensor_noise[j])
            gains = replace(gains, a=a)
        out.append(FilterDesign(model=m, gains=gains))
    return tuple(out)


def design_bank(mach: float = NOMINAL_MACH, alt_ft: float = NOMINAL_ALT_FT,
                tuning: Tuning | str = "tuned", frame_rate_hz: float = names.FRAME_RATE_HZ,
                hypotheses: tuple[str, ...] = names.ALL_HYPOTHESES,
                linearized: LinearizedTrim | None = None, throttle_input: bool = False,
                partial_loss=()) -> BankDesign:
    """Design the bank at (mach, alt_ft) with a tuning (a Tuning, a shipped name or a path);
    ``throttle_input``: the throttle as the sixth modelled input (module docstring; a given
    ``linearized`` must then carry its throttle column); ``partial_loss``: fractions lost F, one
    partial hypothesis per surface and F after ``hypotheses`` (module docstring; ValueError for
    an F outside (0, 1)).

    Raises ValueError for a flight condition outside Mach 0.3-0.8 / 5,000-35,000 ft,
    TuningError for a bad tuning, aircraft.TrimError when the truth cannot trim, DesignError
    when a hypothesis filter would be unstable."""
    if isinstance(tuning, (str, Path)):
        tuning = load_tuning(tuning)
    hypotheses = tuple(hypotheses) + partial_hypotheses(partial_loss)
    if not frame_rate_hz > 0:
        raise ValueError(f"frame_rate_hz must be positive, got {frame_rate_hz}")
    if linearized is None:
        linearized = linearize_truth(mach, alt_ft, throttle=throttle_input)
    if throttle_input and linearized.throttle_column is None:
        raise ValueError("throttle_input needs the throttle column: linearize_truth(..., throttle=True)")
    cont = build_model(linearized.lin, linearized.trim.vt_fps, tuning.turbulence, alt_ft,
                       tuning.gust_model, linearized.throttle_column if throttle_input else None)
    disc, r = discrete_design_model(cont, tuning, frame_rate_hz)
    per = component_models(tuning.failure_model)
    covered = tuple(s for s in names.SENSORS if per[s] == "cover")
    widths = level_widths(effective_spec(tuning.failed_sensor_level_width, covered), disc.phi, disc.bd, disc.qd, r, cont.h,
                          frame_rate_hz)
    filters = design_filters(hypothesis_models(cont, tuning, disc, hypotheses, widths), r,
                             cont.r_diag if tuning.failed_sensor_noise == "sensor" else None)
    return BankDesign(mach=float(mach), alt_ft=float(alt_ft), frame_rate_hz=float(frame_rate_hz),
                      tuning=tuning, linearized=linearized, continuous=cont, discrete=disc, r=r,
                      filters=filters, level_widths=widths or None)


def dwell_nats_of(design: BankDesign, table: dict) -> dict[str, float]:
    """The tuning's ``[estimator] dwell_nats_per_hypothesis`` for the hypotheses this design
    has (a design of a subset, e.g. the singles, takes their entries); a name that is no
    hypothesis at all is a TuningError naming it.  A partial-loss design (forms ``NAME:loss=F``)
    takes none: the table's N_k were derived for the complete-failure bank, whose hypotheses
    compete differently."""
    have = {f.name for f in design.filters}
    if any(":" in h for h in have):
        return {}
    unknown = sorted(k for k in table if k not in have and k not in names.ALL_HYPOTHESES)
    if unknown:
        raise TuningError(f"tuning {design.tuning.name!r}: [estimator] dwell_nats_per_hypothesis names "
                          f"{', '.join(unknown)}: not a hypothesis")
    return {k: float(v) for k, v in table.items() if k in have}


def to_model_bank(design: BankDesign):
    """The design as a ``core.ModelBank`` (needs the compiled extension)."""
    from .. import core

    hyps = [core.HypothesisModel(name=f.name, phi=f.model.phi, bd=f.model.bd, h=f.model.h,
                                 k=f.gains.k, a=f.gains.a, uninformative_width=f.model.uninformative_width,
                                 uninformative_level_q=f.model.uninformative_level_q)
            for f in design.filters]
    return core.ModelBank(
        hyps, state_names=list(design.continuous.state_names), input_names=list(design.input_names),
        measurement_names=list(names.SENSORS),
        u_trim=design.u_trim, z_trim=design.z_trim, h_output=design.h_output,
        frame_rate_hz=design.frame_rate_hz, mach=design.mach, alt_ft=design.alt_ft,
        tuning=design.tuning.name,
        # the estimator settings this design recommends (tuning [estimator]) as typed fields
        # of the bank (the evidence dwell table as each hypothesis' dwell_nats); absent keys
        # take the core's defaults
        **{k: (dwell_nats_of(design, v) if k == "dwell_nats_per_hypothesis" else float(v))
           for k, v in design.tuning.estimator.items()},
        metadata=json.dumps(design.metadata(), sort_keys=True, separators=(",", ":")))


def write_bank(design: BankDesign, path: str | Path):
    """Write the design to a bank file; returns the loaded-back ``core.ModelBank`` (validated,
    ``content_hash`` filled)."""
    from .. import core

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    core.save_bank(to_model_bank(design), str(path))
    return core.load_bank(str(path))


def nominal_bank_path(tuning: str = "tuned") -> Path:
    """Path of a shipped nominal bank (``data/nominal_<tuning>.f16bank``)."""
    return DATA_DIR / f"nominal_{tuning}.f16bank"
