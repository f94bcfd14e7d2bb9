"""One closed-loop flight: the nonlinear truth model with the MMAE estimator in the loop.

Frame i (t_i = i / FRAME_RATE_HZ), as in docs/INTERFACES.md::

    z_i = truth.measure()                          sensors, noise and sensor failures applied
    z_hat_i = estimator.update(z_i)                core: bank.update(z_i - z_trim); z_hat absolute
    u_i = fcs.command(z_hat_i | z_i, t_i)          "mmae" feedback (paper) or "raw", dither included
    estimator.propagate(u_i)                       core: bank.propagate(u_i - u_trim)
    truth.advance(u_i)                             SIM_RATE_HZ / FRAME_RATE_HZ truth steps

The estimator is an :class:`Estimator`: built from the model bank alone, its only inputs
are the absolute vectors ``z`` (7,) and ``u`` (5,), copied into fresh float arrays at
the boundary.  The failure truth lives in the scenario, which only the truth model
receives; :func:`fly` never passes anything else to the estimator, and
``tests/python/test_closedloop.py`` checks that structurally (signatures, and a replay
of the recorded (u, z) through a fresh estimator reproducing every probability).

Declarations: each update reports the hypothesis the core's declarer declared on that
frame (if any); each is a declaration event ``{"hypothesis", "time_s"}`` -- a failure
declared, a dual declared at level 1, or NONE when the bank backs out to level 0.
``final_hypothesis`` is the core's current hypothesis at the end (NONE if none declared).

probabilities.csv columns (``FlightResult.hypotheses``): the *union* of the hypotheses
that were on line during the flight, in order of first appearance (the 13 level-0
hypotheses, then any level-1 duals); a cell is empty (NaN in memory) while its
hypothesis is off line.  The probabilities of the hypotheses on line sum to 1 per row.
"""
from __future__ import annotations

import csv
import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import __version__
from .names import FRAME_RATE_HZ

FEEDBACK_MODES = ("mmae", "raw")


# -- the estimator side: sees u and z only ------------------------------------------------------
class Estimator:
    """The MMAE (the C++ ``core.HierarchicalBank`` through the binding) as the loop sees it.

    ``Estimator(model_bank, **options)``: the settings of ``core.HierarchicalBank``
    (``p_min``, ``threshold``, ``dwell_s``) are the bank's recommended ones
    (:func:`bank_estimator_settings`, typed fields of the bank) updated by ``options`` (which win);
    ``settings`` holds the result.  Per frame: ``update(z) -> z_hat``, then
    ``propagate(u)``; both absolute (the core subtracts the bank's z_trim / u_trim and
    returns z_hat absolute).  Nothing else flows in."""

    def __init__(self, model_bank, **options) -> None:
        from . import core

        #: The estimator settings in force: the bank's recommended ones, then ``options``.
        self.settings: dict = {**bank_estimator_settings(model_bank), **options}
        self._bank = core.HierarchicalBank(model_bank, **self.settings)
        self.bank_hash = str(model_bank.content_hash)
        #: The hypothesis declared by the last update (a back-out declares NONE), or None.
        self.last_declaration: str | None = None

    @classmethod
    def fresh(cls, model_bank, **options) -> "Estimator":
        """An estimator in its start state (level 0, NONE presumed, states zero).

        Building the 79 stored filters costs ~10 ms, a fifth of a whole 8-s flight, so
        one estimator per (bank hash, options) is kept per process and ``reset()`` for
        the next flight -- same result as a new one (tests/python/test_closedloop.py)."""
        key = (str(model_bank.content_hash), tuple(sorted(options.items())))
        est = _ESTIMATORS.pop(key, None)
        if est is None:
            est = cls(model_bank, **options)
        else:
            est.reset()
        _ESTIMATORS[key] = est
        while len(_ESTIMATORS) > 4:
            _ESTIMATORS.pop(next(iter(_ESTIMATORS)))
        return est

    def reset(self) -> None:
        self._bank.reset()
        self.last_declaration = None

    def update(self, z) -> np.ndarray:
        z = np.array(z, dtype=float).reshape(-1)  # a fresh float copy: no object crosses over
        self.last_declaration = self._bank.update(z)
        return self._bank.z_hat

    def propagate(self, u) -> None:
        self._bank.propagate(np.array(u, dtype=float).reshape(-1))

    @property
    def hypotheses(self) -> tuple[str, ...]:
        """Names of the hypotheses on line, in the order of ``probabilities``."""
        return tuple(self._bank.hypotheses)

    @property
    def probabilities(self) -> np.ndarray:
        return self._bank.probabilities

    @property
    def declared(self) -> str:
        """The hypothesis currently declared (NONE when no failure is declared)."""
        return str(self._bank.declared)

    @property
    def level(self) -> int:
        return int(self._bank.level)


_ESTIMATORS: dict[tuple, Estimator] = {}

def bank_estimator_settings(model_bank) -> dict:
    """The estimator settings a bank's design recommends: the typed fields ``p_min``,
    ``threshold`` and ``dwell_s`` of the bank file (format version 2), read by the one C++
    loader; mmae-daemon applies the same fields."""
    return dict(model_bank.estimator_settings)


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

    def write(self, out_dir: str | Path, **extra) -> dict[str, Path]:
        """run.json, probabilities.csv and probabilities.png into ``out_dir``."""
        from .campaign.figures import probability_history

        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        paths = {"run": out / "run.json", "csv": out / "probabilities.csv", "png": out / "probabilities.png"}
        paths["run"].write_text(json.dumps(self.run_json(**extra), indent=1) + "\n")
        with open(paths["csv"], "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(("time_s",) + self.hypotheses)
            for t, row in zip(self.time_s, self.probabilities):
                w.writerow([f"{t:.6f}"] + ["" if np.isnan(p) else f"{p:.6g}" for p in row])
        probability_history(self.time_s, self.hypotheses, self.probabilities, self.failures,
                            self.declarations, paths["png"],
                            title=f"MMAE hypothesis probabilities, seed {self.scenario.get('seed')}, "
                                  f"feedback {self.feedback}")
        return paths


# -- the truth side ---------------------------------------------------------------------------------
def scenario_from_dict(d: dict):
    """A truth-model Scenario from plain data (``Scenario.to_dict`` layout, as records store it)."""
    from .truth import Scenario

    return Scenario.from_dict(d)


def scenario_to_dict(scenario) -> dict:
    return scenario.to_dict()


def fly(scenario, model_bank, *, feedback: str | None = None, estimator_options: dict | None = None,
        record_probabilities: bool = True, on_frame=None, estimator=None) -> FlightResult:
    """Fly ``scenario`` with an estimator built from ``model_bank`` in the loop.

    ``feedback`` overrides ``scenario.feedback`` ("mmae" | "raw").  ``on_frame(t, u, z)``,
    if given, sees each frame's inputs to the estimator (for replay checks).
    ``estimator``: another object with the :class:`Estimator` interface (``update(z) ->
    z_hat``, ``propagate(u)``, ``hypotheses``, ``probabilities``, ``declared``,
    ``last_declaration``, ``bank_hash``) at its start state -- e.g. the executive over LCM
    (``f16mmae.hil``); default ``Estimator.fresh(model_bank, **estimator_options)``."""
    from .truth import FlightControlSystem, TruthModel

    feedback = feedback or getattr(scenario, "feedback", "mmae")
    if feedback not in FEEDBACK_MODES:
        raise ValueError(f"unknown feedback {feedback!r}; valid: {', '.join(FEEDBACK_MODES)}")
    t_start = time.perf_counter()
    truth = TruthModel(scenario)              # the only holder of the failure truth
    fcs = FlightControlSystem(truth.trim, dither=scenario.dither, ari=scenario.ari)
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
    columns: dict[str, int] = {name: k for k, name in enumerate(estimator.hypotheses)}
    idx = np.arange(len(columns))
    probs = np.full((n_frames, len(columns)), np.nan) if record_probabilities else None
    declarations: list[dict] = []
    clock = time.perf_counter
    for i in range(n_frames):
        t = i * dt
        a = clock()
        z = truth.measure()
        b = clock()
        z_hat = estimator.update(z)
        c = clock()
        u = fcs.command(z_hat if use_mmae else z, t)
        d = clock()
        estimator.propagate(u)
        e = clock()
        truth.advance(u)
        f = clock()
        t_truth += (b - a) + (d - c) + (f - e)
        t_est += (c - b) + (e - d)
        if on_frame is not None:
            on_frame(t, np.array(u, dtype=float), np.array(z, dtype=float))
        declared_now = estimator.last_declaration
        if declared_now is not None:
            declarations.append({"hypothesis": declared_now, "time_s": round(t, 9)})
            if record_probabilities:  # the level (and the hypotheses on line) may have changed
                names = estimator.hypotheses
                for name in names:
                    if name not in columns:
                        columns[name] = len(columns)
                if len(columns) > probs.shape[1]:
                    probs = np.hstack([probs, np.full((n_frames, len(columns) - probs.shape[1]), np.nan)])
                idx = np.array([columns[name] for name in names], dtype=int)
        if record_probabilities:
            probs[i, idx] = estimator.probabilities
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
        time_s=np.arange(n_frames) * dt,
        hypotheses=hypotheses,
        probabilities=(probs[:, : len(hypotheses)] if record_probabilities else np.zeros((n_frames, 0))),
        timing={"wall_s": round(wall, 6), "truth_s": round(t_truth, 6), "estimator_s": round(t_est, 6),
                "frames": n_frames},
        estimator_settings=dict(getattr(estimator, "settings", {})),
    )


def measure_overhead(scenario, model_bank, repeats: int = 5, **estimator_options) -> dict:
    """Cost of one closed-loop flight against the truth model alone, in this process.

    ``truth_only_s``: the scenario flown on raw feedback with no estimator
    (``truth.fly_raw``); ``closed_loop_s``: the same scenario through :func:`fly` with the
    estimator in the loop and the probabilities recorded.  The two alternate and the best
    of ``repeats`` of each is kept (robust to other load on the machine);
    ``ratio = closed_loop_s / truth_only_s`` (1.0 = the estimator and harness cost nothing)."""
    from .truth import fly_raw

    truth_only, closed = [], []
    fly(scenario, model_bank, estimator_options=estimator_options)  # warm: imports, estimator
    for _ in range(repeats):
        t0 = time.perf_counter()
        fly_raw(scenario)
        t1 = time.perf_counter()
        fly(scenario, model_bank, estimator_options=estimator_options)
        t2 = time.perf_counter()
        truth_only.append(t1 - t0)
        closed.append(t2 - t1)
    a, b = min(truth_only), min(closed)
    return {"truth_only_s": round(a, 6), "closed_loop_s": round(b, 6),
            "ratio": round(b / a, 4), "duration_s": scenario.duration_s}
