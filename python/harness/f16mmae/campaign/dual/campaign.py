"""The dual-failure Monte Carlo campaign (paper Sec. VI, Fig. 7).

Pairs: every ordered pair (a, b) of the twelve single failures, a != b (132), or a
subset; ``a`` fails at ``first_time_s`` (3.0 s), ``b`` at ``second_time_s`` (5.0 s; the
paper: "two or more seconds later"), mode ``complete``, in a 10-s flight at the bank's
design point with the hierarchical bank in the loop: level 0 should declare ``a``, and the
level-1 bank of ``a`` (NONE, ``a`` and its 11 duals) the dual ``h* = dual_name(a, b)``.

Baseline: for each second failure ``b`` of the plan, the lone single failure ``b`` at
``second_time_s`` in the same flight, N runs -- the "lone single failure" Fig. 7 rates
against, flown under the same conditions.

Failure offset (``failure_jitter_s`` J > 0; 0, the default: none): run n of pair (a, b) and of
the baseline of b shift both failures and the flight's end by the same J x_{b,n}
(``engine.failure_runs.failure_offset`` of the run's seed), so a pair and its baseline still fly
alike and the two seconds between the failures stay.

Seeds: run n of pair (a, b) and run n of the baseline of b both get
``seed_{b,n} = evaluation_seed("dual", S, b, n)`` (S the campaign seed; ``f16mmae.seeds``):
deterministic, >= 1, distinct from the single campaign's ("evaluation:dual:" against "evaluation:single:"), and common
random numbers along a column of Fig. 7 -- a pair and the baseline it is rated against fly
the same turbulence and sensor noise, so the difference is the first failure's.

Scoring per run, per pair and the rating Good / Fair / Poor / ND: see
:mod:`f16mmae.campaign.dual.scoring` (thresholds in ``RATING_RULES``).  In short, with c the
correct fraction, m the median latency after the second failure and h the mean hold
(fraction of the flight after the dual's declaration during which it stays declared):
Good = c >= c_b - 0.10, m <= m_b + 0.5 s and h >= h_b - 0.10 against the baseline of b;
Fair = c > 0 and (c >= 0.5 or c >= c_b - 0.10); Poor = the dual declared in some run or its
probability reached 0.5; ND = otherwise.

Runs are pure functions of their specs, executed on any ``concurrent.futures.Executor``;
records are appended to ``runs.jsonl`` (``store.ResultsStore``) as they finish and a
campaign started again skips the run keys already stored.
"""
from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

from ... import __version__
from ...banks import bank_estimator_settings, load_bank
from ...loop.flight import fly, scenario_from_dict
from ...names import COMPONENTS, FAILURE_TIME_S, THRESHOLD_DEFAULT, dual_name
from ..engine import drilldown, evidence, identity, outcomes, variants
from ..engine.config import CampaignConfig, CampaignError
from ..engine.failure_runs import P_INJECTED_DECIMATION, check_failure_jitter, failure_offset, stored_history
from ..engine.runner import CampaignOutcome, execute, planned_bank
from ..engine.seeds import evaluation_seed
from ..engine.store import ResultsStore, campaign_directory, run_key
from . import figures
from . import models
from . import scoring

#: Every ordered (first, second) pair of failures (``names.COMPONENTS``, Fig. 7): 132.
ALL_PAIRS: tuple[tuple[str, str], ...] = tuple((a, b) for a in COMPONENTS for b in COMPONENTS if a != b)


def pair_label(first: str, second: str) -> str:
    """``FIRST>SECOND``: the ordered pair (the hypothesis is ``dual_name``, unordered)."""
    return f"{first}>{second}"


def run_seed(campaign_seed: int, second: str, run_index: int) -> int:
    """Seed of run ``run_index`` of every pair whose second failure is ``second`` and of
    that failure's baseline (>= 1); see the module docstring."""
    return evaluation_seed("dual", campaign_seed, second, run_index)


@dataclass(frozen=True)
class DualCampaign(CampaignConfig):
    """The arguments of ``f16mmae campaign dual`` (everything that shapes the results)."""

    runs: int = 3
    duration_s: float = 10.0
    pairs: tuple[tuple[str, str], ...] = ALL_PAIRS
    first_time_s: float = FAILURE_TIME_S
    second_time_s: float = 5.0
    failure_jitter_s: float = 0.0  # both failures and the end up to this much later (module docstring)
    mach: float | None = None  # None: the bank's design point
    alt_ft: float | None = None

    @property
    def seconds(self) -> tuple[str, ...]:
        """The second failures of the plan (each gets a baseline), in the paper's order."""
        return tuple(f for f in COMPONENTS if any(b == f for _, b in self.pairs))

    def validate(self) -> "DualCampaign":
        self.check_common(dwell_window_s=self.duration_s - self.second_time_s,
                     dwell_window_text=" (the flight time after the second failure)")
        if not self.pairs:
            raise CampaignError(f"no pair to fly; pairs are FIRST+SECOND of {', '.join(COMPONENTS)}")
        for p in self.pairs:
            if len(p) != 2 or p[0] not in COMPONENTS or p[1] not in COMPONENTS:
                raise CampaignError(f"unknown pair {'+'.join(map(str, p))}; each of FIRST+SECOND "
                                    f"must be one of {', '.join(COMPONENTS)}")
            if p[0] == p[1]:
                raise CampaignError(f"pair {p[0]}+{p[1]} fails one component twice; "
                                    f"a dual needs two different failures")
        if len(set(self.pairs)) != len(self.pairs):
            raise CampaignError("a pair is listed twice")
        check_failure_jitter(self)
        if not 0 < self.first_time_s < self.second_time_s < self.duration_s:
            raise CampaignError(
                f"the failure times must satisfy 0 < first ({self.first_time_s} s) < second "
                f"({self.second_time_s} s) < duration ({self.duration_s} s)")
        return self


# -- one run (executed in workers) -----------------------------------------------------------
def run_spec(spec: dict) -> dict:
    """Fly one dual run (``spec["first"]`` set) or baseline run and return its record."""
    bank = planned_bank(spec)
    scenario = scenario_from_dict(spec["scenario"])
    result = fly(scenario, bank, estimator_options=spec["estimator"], record_probabilities=True)
    first, second = spec["first"], spec["second"]
    t1 = scenario.failures[0].time_s if first else None
    t2 = scenario.failures[-1].time_s
    injected = dual_name(first, second) if first else second
    p_inj = result.probability_of(injected)
    scored = scoring.score_dual_run(injected, first, t1, t2, scenario.duration_s,
                                         result.declarations, result.time_s, p_inj)
    record = {
        "run_key": spec["run_key"], "kind": spec["kind"], "pair": spec["pair"],
        "first": first, "second": second, "hypothesis": injected,
        "run_index": spec["run_index"], "seed": spec["seed"], "tuning": spec["tuning"],
        "bank": spec["bank"], "bank_hash": spec["bank_hash"], "version": spec["version"], "scenario": spec["scenario"],
        "estimator": spec["estimator"], "estimator_settings": result.estimator_settings,
        "first_time_s": t1, "second_time_s": t2, "failures": result.failures,
        "declarations": result.declarations,
        # the former rule (anything but the first failure and the dual from the first onset on)
        # kept as transient_wrong_strict; transient_wrong is the scoring's rule for failed components
        **{("transient_wrong_strict" if k == "transient_wrong" else k): v for k, v in outcomes.run_fields(
            result.declarations, t1 if first else t2, {first, injected} if first else {injected},
            scenario.duration_s).items()},
        **scored,
        "p_injected": stored_history(p_inj),
        "p_injected_dt_s": P_INJECTED_DECIMATION * result.frame_dt_s,
        "timing": result.timing,
    }
    if first:
        record["p_first"] = stored_history(result.probability_of(first))
    return record


# -- planning --------------------------------------------------------------------------------
def plan(cfg: DualCampaign, tuning_label: str, bank) -> list[dict]:
    """Every run spec: the baselines of the second failures, then the pairs."""
    cases = [(None, b) for b in cfg.seconds] + list(cfg.pairs)
    specs = []
    for first, second in cases:
        kind = "dual" if first else "dual-baseline"
        for n in range(cfg.runs):
            seed = run_seed(cfg.seed, second, n)
            offset = failure_offset(seed, cfg.failure_jitter_s)
            failures = ((first, cfg.first_time_s + offset),) if first else ()
            failures += ((second, cfg.second_time_s + offset),)
            try:
                scenario = cfg.scenario_dict(bank, failures, seed, cfg.mach, cfg.alt_ft,
                                             duration_s=cfg.duration_s + offset)
            except ValueError as exc:
                raise CampaignError(f"failures {', '.join(n for n, _ in failures)}: {exc}") from None
            identity = {"kind": kind, "scenario": scenario, "estimator": cfg.estimator_options(),
                        "bank_hash": bank.content_hash, "version": __version__}
            specs.append({
                "run_key": run_key(identity), "kind": kind, "first": first, "second": second,
                "pair": pair_label(first, second) if first else second, "run_index": n, "seed": seed,
                "tuning": tuning_label, "bank": cfg.tuning, "bank_hash": bank.content_hash,
                "version": __version__, "scenario": scenario, "estimator": cfg.estimator_options(),
            })
    return specs


# -- the campaign ------------------------------------------------------------------------------
def run_campaign(cfg: DualCampaign, out_dir: str | Path, executor: Executor,
                 executor_label: str = "", show_progress: bool = True,
                 allow_mixed: bool = False) -> CampaignOutcome:
    """Plan, fly what is not stored yet (appending records as they finish), summarize, plot;
    ``out_dir`` checked writable and locked (``store.campaign_directory``) before any flight."""
    cfg.validate()
    with campaign_directory(out_dir) as out:
        return _run_campaign(cfg, out, executor, executor_label, show_progress, allow_mixed)


def _run_campaign(cfg: DualCampaign, out: Path, executor: Executor, executor_label: str,
                  show_progress: bool, allow_mixed: bool) -> CampaignOutcome:
    label, _, bank = load_bank(cfg.tuning)

    def level_summary(c: DualCampaign, records: list[dict], d: Path) -> dict:
        summary = summarize(c, label, bank, records)
        summary["figures"] = {
            "matrix": figures.rating_matrix(summary, d / "dual_matrix.png").name,
            "probabilities": figures.probability_grid(records, summary, d / "dual_probabilities.png").name,
        }
        return summary

    summary, done = variants.fly_variants(
        cfg, out, lambda c: plan(c, label, bank),
        lambda specs: execute(specs, ResultsStore(out), executor, run_spec, show_progress=show_progress,
                              describe=lambda s: f"run {s['run_index']} of {s['pair']} (seed {s['seed']})",
                              allow_mixed=allow_mixed),
        level_summary)
    return done.finish(out, summary, executor_label)


def summarize(cfg: DualCampaign, label: str, bank, records: list[dict]) -> dict:
    """Per-baseline and per-pair summaries, ratings, the matrix and the paper comparison."""
    baselines = {b: scoring.summarize_pair(b, [r for r in records if r["kind"] == "dual-baseline"
                                                    and r["second"] == b]) for b in cfg.seconds}
    pairs = []
    matrix: dict[str, dict[str, str]] = {}
    for a, b in cfg.pairs:
        s = scoring.summarize_pair(pair_label(a, b), [r for r in records if r["kind"] == "dual"
                                                           and r["first"] == a and r["second"] == b])
        s.update(first=a, second=b, hypothesis=dual_name(a, b))
        s["rating"], s["rating_reason"] = scoring.rate_pair(s, baselines[b])
        if s["runs"]:
            s["absolute_rating"], s["absolute_rating_reason"] = outcomes.rate_absolute(
                s["runs"], s["correct"], s["false_alarms"], s["evidence"]["rates"]["transient_wrong"]["count"],
                s["latency_s"]["median"])
            s["absolute_rating_strict"] = outcomes.rate_absolute(
                s["runs"], s["correct"], s["false_alarms"], s["transient_wrong_strict"], s["latency_s"]["median"])[0]
        pairs.append(s)
    settings = bank_estimator_settings(bank, cfg.estimator_options())
    window = cfg.duration_s - cfg.second_time_s - settings.get("dwell_s", 0.25)
    models_evaluated = models.annotate(pairs, bank, cfg.turbulence, cfg.mode,
                                       window_frames=int(window * bank.frame_rate_hz),
                                       threshold=settings.get("threshold", THRESHOLD_DEFAULT),
                                       dither_scale=cfg.dither_scale if cfg.dither else None)
    for s in pairs:
        matrix.setdefault(s["first"], {})[s["second"]] = s["rating"]
    return {
        "kind": "dual",
        "runs_per_pair": cfg.runs,
        "seed": cfg.seed,
        "bank_hash": bank.content_hash,
        "version": __version__,
        "tuning": label,
        "turbulence": cfg.turbulence,
        "mode": cfg.mode,
        "mach": float(cfg.mach if cfg.mach is not None else bank.mach),
        "alt_ft": float(cfg.alt_ft if cfg.alt_ft is not None else bank.alt_ft),
        "first_time_s": cfg.first_time_s,
        "second_time_s": cfg.second_time_s,
        "failure_jitter_s": cfg.failure_jitter_s,
        "duration_s": cfg.duration_s,
        "feedback": cfg.feedback,
        "dither": cfg.dither,
        "dither_scale": cfg.dither_scale,
        "estimator": cfg.estimator_options(),
        "estimator_settings": settings,
        "rating_rules": dict(scoring.RATING_RULES),
        "ratings": {k: sum(1 for p in pairs if p["rating"] == k) for k in scoring.RATINGS},
        "models": models_evaluated,
        "matrix": matrix,
        "paper_comparison": scoring.compare_with_paper(matrix),
        "baselines": [baselines[b] for b in cfg.seconds],
        "pairs": pairs,
        "absolute_rules": dict(outcomes.ABSOLUTE_DUAL_RULES),
        "absolute_ratings": {k: sum(1 for p in pairs if p.get("absolute_rating") == k)
                             for k in outcomes.ABSOLUTE_RATINGS},
        # the same under the former transient-wrong rule (scoring: the rule for failed components)
        "strict_rule": {"transient_wrong_runs": sum(p["transient_wrong_strict"] for p in pairs),
                        "absolute_ratings": {k: sum(1 for p in pairs if p.get("absolute_rating_strict") == k)
                                             for k in outcomes.ABSOLUTE_RATINGS}},
        **evidence.summary_fields(
            records, [baselines[b] for b in cfg.seconds] + pairs,
            drilldown.not_clean(sorted(records, key=lambda r: (r["kind"], r["pair"], r["run_index"])),
                                lambda r: drilldown.record_command(r, cfg.dither_scale),
                                lambda r: {"pair": r["pair"]}),
            identity.code_identity(), goals_met=all(p.get("absolute_rating") == "Good" for p in pairs)),
    }
