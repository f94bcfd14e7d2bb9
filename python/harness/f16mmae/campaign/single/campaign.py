"""The single-failure Monte Carlo campaign (paper Sec. V, Figs. 3-6).

Cases: the no-failure case NONE and each of the twelve single failures (LS ... AY), N
seeded runs each, the failure (mode ``complete`` by default, the paper's model) at
3.0 s of an 8-s flight at the bank's design point.  The campaign runs the primary bank
(``--tuning``, default ``tuned``) and, unless ``--baseline none``, the same runs with
the baseline bank (default ``untuned``) so Figs. 3 and 6 compare side by side.

The runs, their seeds (common random numbers: tuned and untuned runs of one case and index
fly the same turbulence and noise) and the record of each: :mod:`..engine.failure_runs`.
Each run is a pure function of its spec, executed on any ``concurrent.futures.Executor``;
the parent appends each record to the results store as it finishes and skips specs already
stored (resume).  ``summary.json`` and the figures
are then computed from the stored records of this campaign's plan only.
"""
from __future__ import annotations

import dataclasses
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

from ... import __version__
from ...banks import bank_estimator_settings, load_bank
from ...loop.flight import scenario_from_dict
from ...loop.overhead import measure_overhead
from ...names import FAILURE_TIME_S, NONE
from ...truth.actuators import ACTUATOR_MODES
from ...truth.failures import modes_for
from ...truth.sensors import SENSOR_MODES
from ..engine import drilldown, evidence, identity, scoring, variants
from ..engine.config import CampaignConfig, CampaignError, split_mode
from ..engine.failure_runs import CASES, check_cases, check_failure_jitter, describe_spec, plan, run_spec
from ..engine.runner import CampaignOutcome, execute
from ..engine.store import ResultsStore, campaign_directory
from . import figures


@dataclass(frozen=True)
class SingleCampaign(CampaignConfig):
    """The arguments of ``f16mmae campaign single`` (everything that shapes the results)."""

    MODE_LIST = True

    cases: tuple[str, ...] = CASES
    baseline: str | None = "untuned"
    failure_time_s: float = FAILURE_TIME_S
    failure_jitter_s: float = 0.0  # each run's failure up to this much later (engine.failure_runs)
    mach: float | None = None  # None: the bank's design point
    alt_ft: float | None = None

    def validate(self) -> "SingleCampaign":
        self.check_common(dwell_window_s=self.duration_s)
        check_failure_jitter(self)
        check_cases(self)
        failures = [c for c in self.cases if c != NONE]
        for mode in self.modes():
            flown = mode_cases(dataclasses.replace(self, mode=mode))[0].cases
            if failures and all(c == NONE for c in flown):
                raise CampaignError(f"failure mode {mode!r} applies to none of the cases {','.join(failures)} "
                                    f"(actuators: {', '.join(ACTUATOR_MODES)}; sensors: {', '.join(SENSOR_MODES)})")
        return self


def mode_cases(cfg: SingleCampaign) -> tuple[SingleCampaign, list[str]]:
    """The cases ``cfg``'s (one) mode applies to, and those it skips: an actuator mode flies the
    actuator cases, a sensor mode the sensor cases (``complete``, ``stuck`` and ``hardover`` are
    both); NONE is flown in every mode (its run is the same in all, so it flies once)."""
    name = split_mode(cfg.mode)[0]
    keep = tuple(c for c in cfg.cases if c == NONE or name in modes_for(c))
    return dataclasses.replace(cfg, cases=keep), [c for c in cfg.cases if c not in keep]


# -- the campaign ------------------------------------------------------------------------------
def run_campaign(cfg: SingleCampaign, out_dir: str | Path, executor: Executor,
                 executor_label: str = "", show_progress: bool = True,
                 measure_cost: bool = True, allow_mixed: bool = False) -> CampaignOutcome:
    """Plan, run what is not stored yet, append records as they finish, summarize, plot;
    ``out_dir`` checked writable and locked (``store.campaign_directory``) before any flight."""
    cfg.validate()
    with campaign_directory(out_dir) as out:
        return _run_campaign(cfg, out, executor, executor_label, show_progress, measure_cost, allow_mixed)


def _run_campaign(cfg: SingleCampaign, out: Path, executor: Executor, executor_label: str,
                  show_progress: bool, measure_cost: bool, allow_mixed: bool) -> CampaignOutcome:
    label, _, bank = load_bank(cfg.tuning)
    banks = {label: (cfg.tuning, bank)}
    if cfg.baseline:
        b_label, _, b_bank = load_bank(cfg.baseline)
        if b_bank.content_hash != bank.content_hash:
            banks[b_label if b_label != label else f"{b_label}-baseline"] = (cfg.baseline, b_bank)

    def variant_summary(c: SingleCampaign, records: list[dict], d: Path) -> dict:
        summary = summarize(c, banks, label, records)
        summary["figures"] = make_figures(d, records, c)
        return summary

    summary, done = variants.fly_variants(
        cfg, out, lambda c: plan(c, banks, c.mach, c.alt_ft),
        lambda specs: execute(specs, ResultsStore(out), executor, run_spec, describe=describe_spec,
                              show_progress=show_progress, allow_mixed=allow_mixed),
        variant_summary, under_test=lambda r: r["tuning"] == label, variant=mode_cases)
    cost = {}
    if measure_cost:
        first, _ = mode_cases(dataclasses.replace(cfg, turbulence=cfg.levels()[0], mode=cfg.modes()[0]))
        specs = plan(first, banks, cfg.mach, cfg.alt_ft)
        none_spec = next((s for s in specs if s["case"] == NONE), specs[0])
        cost["overhead"] = measure_overhead(
            scenario_from_dict(none_spec["scenario"]), bank, **cfg.estimator_options())
    return done.finish(out, summary, executor_label, **cost)


def first_declaration(record: dict) -> str:
    """The first failure hypothesis a run declared at or after its failure's onset (NONE: none;
    for a no-failure run, the first failure declared at all)."""
    t_f = record["failure_time_s"] if record["failure_time_s"] is not None else float("-inf")
    for d in sorted(record["declarations"], key=lambda d: d["time_s"]):
        if d["hypothesis"] != NONE and d["time_s"] >= t_f:
            return d["hypothesis"]
    return NONE


def case_summary(case: str, records: list[dict]) -> dict:
    """``scoring.summarize_case`` and, beside the outcome of the run's last declaration (the
    score), ``first_declared_correct``: the runs whose first declaration after the onset names
    the injected failure, whatever follows it (a departing aircraft's later declarations,
    docs/results/failure_models.md); a count reported apart, never in place of the score."""
    out = scoring.summarize_case(case, records)
    out["first_declared_correct"] = sum(1 for r in records if first_declaration(r) == case)
    return out


def summarize(cfg: SingleCampaign, banks: dict, label: str, records: list[dict]) -> dict:
    def cases_of(lbl):
        return [case_summary(c, [r for r in records if r["tuning"] == lbl and r["case"] == c])
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
        "failure_jitter_s": cfg.failure_jitter_s,
        "duration_s": cfg.duration_s,
        "feedback": cfg.feedback,
        "dither_scale": cfg.dither_scale,
        "estimator": cfg.estimator_options(),
        # in force for the bank under test: its recommended settings, then the overrides
        "estimator_settings": bank_estimator_settings(bank, cfg.estimator_options()),
        "cases": cases,
        "goals": {**scoring.GOALS, "met": all(g["all"] for g in goals.values()), "per_case": goals},
        "baseline": None,
    }
    others = [lbl for lbl in banks if lbl != label]
    if others:
        b = others[0]
        summary["baseline"] = {"tuning": b, "bank_hash": banks[b][1].content_hash,
                               "estimator_settings": bank_estimator_settings(banks[b][1], cfg.estimator_options()),
                               "cases": cases_of(b)}
    order = {lbl: i for i, lbl in enumerate(banks)}
    case_order = {c: i for i, c in enumerate(cfg.cases)}
    ranked = sorted(records, key=lambda r: (order.get(r["tuning"], len(order)), case_order.get(r["case"], 0),
                                            r["run_index"]))
    # the rates, false declarations and goals are the bank under test's; the list of runs that
    # went wrong holds the baseline's too
    summary.update(evidence.summary_fields(
        [r for r in records if r["tuning"] == label], cases,
        drilldown.not_clean(ranked, lambda r: drilldown.record_command(r, cfg.dither_scale),
                            lambda r: {"tuning": r["tuning"], "case": r["case"]}),
        identity.code_identity()))
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
