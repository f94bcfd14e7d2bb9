"""The single-failure Monte Carlo campaign (paper Sec. V, Figs. 3-6).

Cases: the no-failure case NONE and each of the twelve single failures (LS ... AY), N
seeded runs each, the failure (mode ``complete`` by default, the paper's model) at
3.0 s of an 8-s flight at the bank's design point.  The campaign runs the primary bank
(``--tuning``, default ``tuned``) and, unless ``--baseline none``, the same runs with
the baseline bank (default ``untuned``) so Figs. 3 and 6 compare side by side.

Seeds: run n of case c gets ``seed_{c,n} = 1 + (SHA-256("single:S:c:n") mod (2^31 - 2))``
with S the campaign seed -- deterministic, >= 1 (JSBSim maps 0 to 1), independent of the
executor, of the order runs finish and of the tuning (tuned and untuned runs of one
(c, n) fly the same turbulence and noise: common random numbers).

Each run is a pure function of its spec (:func:`run_spec`), executed on any
``concurrent.futures.Executor``; the parent appends each record to the results store as
it finishes and skips specs already stored (resume).  ``summary.json`` and the figures
are then computed from the stored records of this campaign's plan only.
"""
from __future__ import annotations

import functools
import json
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path

from .. import __version__
from ..names import NONE, SINGLE_HYPOTHESES
from . import figures, scoring
from .runner import CampaignError, derived_seed, execute
from .store import ResultsStore, run_key

#: Cases of the single campaign, in the paper's order.
CASES: tuple[str, ...] = SINGLE_HYPOTHESES
TURBULENCE_LEVELS = ("none", "light", "moderate", "severe")
FEEDBACK_MODES = ("mmae", "raw")
SHIPPED_TUNINGS = ("tuned", "untuned")
#: How often the stored probability history of the injected hypothesis is sampled.
P_INJECTED_DECIMATION = 2  # every 2nd frame: 32 Hz at the 64-Hz frame rate


def run_seed(campaign_seed: int, case: str, run_index: int) -> int:
    """The seed of run ``run_index`` of ``case`` (>= 1), see the module docstring."""
    return derived_seed("single", campaign_seed, case, run_index)


@dataclass(frozen=True)
class SingleCampaign:
    """The arguments of ``f16mmae campaign single`` (everything that shapes the results)."""

    runs: int = 10
    seed: int = 1
    cases: tuple[str, ...] = CASES
    tuning: str = "tuned"  # "tuned" | "untuned" | path to a bank file
    baseline: str | None = "untuned"
    turbulence: str = "light"
    mode: str = "complete"
    failure_time_s: float = 3.0
    duration_s: float = 8.0
    feedback: str = "mmae"
    dither: bool = True
    dither_scale: float = 1.0  # multiplies the truth model's default dither amplitudes
    mach: float | None = None  # None: the bank's design point
    alt_ft: float | None = None
    #: Estimator settings passed to core.HierarchicalBank (None: the core's default):
    #: declaration threshold, dwell (s) and probability floor p_min.
    threshold: float | None = None
    dwell_s: float | None = None
    p_min: float | None = None

    def estimator_options(self) -> dict:
        return estimator_options_of(self)

    def validate(self) -> "SingleCampaign":
        check_common(self, dwell_window_s=self.duration_s)
        bad = [c for c in self.cases if c not in CASES]
        if bad or not self.cases:
            raise CampaignError(
                f"unknown case(s) {', '.join(bad) or '(none given)'}; valid: {', '.join(CASES)}"
            )
        if len(set(self.cases)) != len(self.cases):
            raise CampaignError(f"a case is listed twice in {','.join(self.cases)}")
        if not 0 < self.failure_time_s < self.duration_s:
            raise CampaignError(
                f"the failure time {self.failure_time_s} s must lie inside the flight (0, {self.duration_s}) s"
            )
        return self


def estimator_options_of(cfg) -> dict:
    """The estimator settings a campaign config overrides (``threshold``, ``dwell_s``,
    ``p_min``; unset ones stay the bank's recommended)."""
    return {k: getattr(cfg, k) for k in ("threshold", "dwell_s", "p_min") if getattr(cfg, k) is not None}


def check_common(cfg, dwell_window_s: float, dwell_window_text: str = "") -> None:
    """The checks every campaign config shares (CampaignError naming the bad value): runs,
    seed, turbulence, feedback, dither scale and the estimator overrides; the dwell must fit
    in ``dwell_window_s``, the flight time in which a declaration can still come."""
    if cfg.runs < 1:
        raise CampaignError(f"--runs must be >= 1, got {cfg.runs}")
    if cfg.seed < 1:
        raise CampaignError(f"--seed must be >= 1 (JSBSim treats 0 as 1), got {cfg.seed}")
    if cfg.turbulence not in TURBULENCE_LEVELS:
        raise CampaignError(f"unknown turbulence {cfg.turbulence!r}; valid: {', '.join(TURBULENCE_LEVELS)}")
    if cfg.feedback not in FEEDBACK_MODES:
        raise CampaignError(f"unknown feedback {cfg.feedback!r}; valid: {', '.join(FEEDBACK_MODES)}")
    if not 0.0 <= cfg.dither_scale <= 5.0:
        raise CampaignError(f"--dither-scale {cfg.dither_scale} must lie in [0, 5]")
    if cfg.threshold is not None and not 0.5 < cfg.threshold < 1.0:
        raise CampaignError(f"--threshold {cfg.threshold} must lie in (0.5, 1)")
    if cfg.dwell_s is not None and not 0.0 <= cfg.dwell_s < dwell_window_s:
        raise CampaignError(f"--dwell-s {cfg.dwell_s} must lie in [0, {dwell_window_s}) s{dwell_window_text}")
    if cfg.p_min is not None and not 0.0 <= cfg.p_min < 1.0 / len(CASES):
        raise CampaignError(f"--p-min {cfg.p_min} must lie in [0, 1/{len(CASES)})")


# -- banks ---------------------------------------------------------------------------------
def bank_path(tuning: str) -> Path:
    """The bank file for ``tuned`` / ``untuned`` (shipped nominal banks) or a FILE path."""
    if tuning in SHIPPED_TUNINGS:
        return Path(__file__).resolve().parent.parent / "data" / f"nominal_{tuning}.f16bank"
    p = Path(tuning)
    if not p.is_file():
        raise CampaignError(
            f"{tuning!r} is neither a shipped tuning ({', '.join(SHIPPED_TUNINGS)}) "
            f"nor a readable bank file"
        )
    return p.resolve()


@functools.lru_cache(maxsize=8)
def _load_bank_cached(path: str):
    from .. import core

    return core.load_bank(path)


def load_bank(tuning: str):
    """(label, path, ModelBank) of a tuning name or bank file; clear error if unreadable."""
    path = bank_path(tuning)
    if not path.is_file():
        raise CampaignError(
            f"the shipped {tuning!r} bank {path} is missing; build it with "
            f"'f16mmae design --mach 0.4 --alt-ft 20000 --tuning {tuning} --out {path}'"
        )
    try:
        bank = _load_bank_cached(str(path))
    except (RuntimeError, ValueError) as exc:
        raise CampaignError(f"cannot load bank {path}: {exc}") from None
    label = tuning if tuning in SHIPPED_TUNINGS else (bank.tuning or path.stem)
    return label, path, bank


# -- one run (executed in workers) -----------------------------------------------------------
def run_spec(spec: dict) -> dict:
    """Fly one run of the campaign and return its record (without the store's bookkeeping).

    A pure function of ``spec``: the scenario (seeded), the bank (checked against the
    spec's hash) and the estimator settings."""
    from ..closedloop import fly, scenario_from_dict

    _, _, bank = load_bank(spec["bank"])
    if bank.content_hash != spec["bank_hash"]:
        raise CampaignError(
            f"bank {spec['bank']} on this worker has hash {bank.content_hash}, the campaign "
            f"planned {spec['bank_hash']}: the file changed, or workers run another install"
        )
    scenario = scenario_from_dict(spec["scenario"])
    result = fly(scenario, bank, estimator_options=spec["estimator"], record_probabilities=True)
    case = spec["case"]
    failure_time = scenario.failures[0].time_s if case != NONE else None
    scored = scoring.score_run(case, failure_time, result.declarations)
    p_inj = result.probability_of(case)[::P_INJECTED_DECIMATION]
    return {
        "run_key": spec["run_key"],
        "kind": "single",
        "case": case,
        "run_index": spec["run_index"],
        "seed": spec["seed"],
        "tuning": spec["tuning"],
        "bank_hash": spec["bank_hash"],
        "version": spec["version"],
        "scenario": spec["scenario"],
        "estimator": spec["estimator"],
        "estimator_settings": result.estimator_settings,  # in force: bank's recommended + overrides
        "failure_time_s": failure_time,
        "failures": result.failures,
        "declarations": result.declarations,
        **scored,
        "p_injected": [round(float(x), 5) for x in p_inj],
        "p_injected_dt_s": P_INJECTED_DECIMATION * result.frame_dt_s,
        "timing": result.timing,
    }


def describe_spec(spec: dict) -> str:
    """The run a spec stands for, for messages."""
    return f"run {spec['run_index']} of case {spec['case']} ({spec['tuning']} bank, seed {spec['seed']})"


# -- planning --------------------------------------------------------------------------------
def _scenario_dict(cfg: SingleCampaign, bank, case: str, seed: int) -> dict:
    """The run's scenario as the truth model's own plain data (``Scenario.to_dict``), so the
    record holds every truth setting (dither amplitudes, ARI, noise) and the run key
    changes when a truth default does."""
    from ..truth import Scenario
    from ..truth.failures import make_failure

    try:
        failures = () if case == NONE else (make_failure(case, cfg.failure_time_s, cfg.mode),)
        scenario = Scenario(
            mach=float(cfg.mach if cfg.mach is not None else bank.mach),
            alt_ft=float(cfg.alt_ft if cfg.alt_ft is not None else bank.alt_ft),
            turbulence=cfg.turbulence, dither=dither_spec(cfg), failures=failures,
            duration_s=cfg.duration_s, seed=seed, feedback=cfg.feedback,
        )
    except ValueError as exc:
        raise CampaignError(f"case {case}: {exc}") from None
    return scenario.to_dict()


def dither_spec(cfg):
    """The truth model's dither for a campaign config (its ``dither`` switch and ``dither_scale``)."""
    from ..truth import DitherSpec

    base = DitherSpec(enabled=cfg.dither)
    if cfg.dither_scale == 1.0:
        return base
    return DitherSpec(enabled=cfg.dither, amplitude_deg=tuple(a * cfg.dither_scale for a in base.amplitude_deg),
                      frequency_hz=base.frequency_hz, phase_rad=base.phase_rad)


def plan(cfg: SingleCampaign, banks: dict[str, tuple[str, object]]) -> list[dict]:
    """Every run spec of the campaign: ``banks`` maps label -> (tuning arg, ModelBank)."""
    specs = []
    for label, (tuning_arg, bank) in banks.items():
        for case in cfg.cases:
            for n in range(cfg.runs):
                seed = run_seed(cfg.seed, case, n)
                scenario = _scenario_dict(cfg, bank, case, seed)
                identity = {"kind": "single", "scenario": scenario, "estimator": cfg.estimator_options(),
                            "bank_hash": bank.content_hash, "version": __version__}
                specs.append({
                    "run_key": run_key(identity), "case": case, "run_index": n, "seed": seed,
                    "tuning": label, "bank": tuning_arg, "bank_hash": bank.content_hash,
                    "version": __version__, "scenario": scenario, "estimator": cfg.estimator_options(),
                })
    return specs


# -- the campaign ------------------------------------------------------------------------------
@dataclass
class CampaignOutcome:
    summary: dict
    summary_path: Path
    executed: int
    resumed: int
    records: list[dict] = field(default_factory=list)


def run_campaign(cfg: SingleCampaign, out_dir: str | Path, executor: Executor,
                 executor_label: str = "", show_progress: bool = True,
                 measure_cost: bool = True) -> CampaignOutcome:
    """Plan, run what is not stored yet, append records as they finish, summarize, plot."""
    cfg.validate()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    label, _, bank = load_bank(cfg.tuning)
    banks = {label: (cfg.tuning, bank)}
    if cfg.baseline:
        b_label, _, b_bank = load_bank(cfg.baseline)
        if b_bank.content_hash != bank.content_hash:
            banks[b_label if b_label != label else f"{b_label}-baseline"] = (cfg.baseline, b_bank)
    specs = plan(cfg, banks)
    done = execute(specs, ResultsStore(out), executor, run_spec, describe=describe_spec,
                   show_progress=show_progress)
    records = done.records
    summary = summarize(cfg, banks, label, records)
    summary["timing"] = done.timing(executor_label)
    if measure_cost:
        from ..closedloop import measure_overhead, scenario_from_dict

        none_spec = next((s for s in specs if s["case"] == NONE), specs[0])
        summary["timing"]["overhead"] = measure_overhead(
            scenario_from_dict(none_spec["scenario"]), bank, **cfg.estimator_options())
    summary["figures"] = make_figures(out, records, cfg)
    path = out / "summary.json"
    path.write_text(json.dumps(summary, indent=1) + "\n")
    return CampaignOutcome(summary, path, len(done.executed_records), done.resumed, records)


def summarize(cfg: SingleCampaign, banks: dict, label: str, records: list[dict]) -> dict:
    from ..closedloop import bank_estimator_settings

    def cases_of(lbl):
        return [scoring.summarize_case(c, [r for r in records if r["tuning"] == lbl and r["case"] == c])
                for c in cfg.cases]

    bank = banks[label][1]
    cases = cases_of(label)
    goals = {c["case"]: scoring.check_goals(c) for c in cases}
    summary = {
        "kind": "single",
        "runs_per_case": cfg.runs,
        "seed": cfg.seed,
        "bank_hash": bank.content_hash,
        "version": __version__,
        "tuning": label,
        "turbulence": cfg.turbulence,
        "mode": cfg.mode,
        "mach": float(cfg.mach if cfg.mach is not None else bank.mach),
        "alt_ft": float(cfg.alt_ft if cfg.alt_ft is not None else bank.alt_ft),
        "failure_time_s": cfg.failure_time_s,
        "duration_s": cfg.duration_s,
        "feedback": cfg.feedback,
        "dither_scale": cfg.dither_scale,
        "estimator": cfg.estimator_options(),
        # in force for the bank under test: its recommended settings, then the overrides
        "estimator_settings": {**bank_estimator_settings(bank), **cfg.estimator_options()},
        "cases": cases,
        "goals": {**scoring.GOALS, "met": all(g["all"] for g in goals.values()), "per_case": goals},
        "baseline": None,
    }
    others = [lbl for lbl in banks if lbl != label]
    if others:
        b = others[0]
        summary["baseline"] = {"tuning": b, "bank_hash": banks[b][1].content_hash,
                               "estimator_settings": {**bank_estimator_settings(banks[b][1]),
                                                      **cfg.estimator_options()},
                               "cases": cases_of(b)}
    return summary


def make_figures(out: Path, records: list[dict], cfg: SingleCampaign) -> dict:
    by_tuning: dict[str, list[dict]] = {}
    for r in records:
        by_tuning.setdefault(r["tuning"], []).append(r)
    if not by_tuning:
        return {}
    strips = figures.probability_strips(by_tuning, out / "probability_strips.png", cases=cfg.cases)
    failure_cases = [c for c in cfg.cases if c != NONE]
    result = {"strips": strips.name}
    if failure_cases:
        lat = figures.latency_chart(by_tuning, out / "latency.png", cases=failure_cases)
        result["latency"] = lat.name
    return result
