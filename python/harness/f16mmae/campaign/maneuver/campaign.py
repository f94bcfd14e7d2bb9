"""The maneuver campaign: failures injected during climbs, descents, speed changes and turns.

At every flight point (``points``: objects with ``label``, ``mach``, ``alt_ft``; the CLI takes
the envelope campaign's selections) the truth model starts trimmed and flies ONE maneuver of
``maneuvers`` from ``maneuver_time_s`` (:func:`maneuver_spec`, the truth's grammar)::

    climb    climb@T:to=(h + 4000)ft:rate=3000fpm      (h + 4000 capped at 35,000 ft)
    descend  descend@T:to=(h - 4000)ft:rate=3000fpm    (capped at 5,000 ft)
    accel    accel@T:to=(M + 0.1)mach:rate=0.01mach/s   (decel to M - 0.1 where M + 0.1 > 0.8)
    turn     turn@T:bank=30deg                          (a level 30 deg turn, held)

with the no-failure case NONE and each single failure (config ``mode``) injected at
``failure_time_s``, mid-maneuver (the defaults: maneuver at 2 s, failure at 6 s of a 14-s flight:
the climb and descent are then 200 ft into their 4,000 ft, the speed change 0.04 Mach into its
0.1, the turn established at 30 deg).  ``runs`` seeded runs per (point, maneuver, case); run n of
(maneuver, case) flies seed ``evaluation_seed("maneuver", S, maneuver, case, n)`` at every point
(common random numbers).  A run is the single campaign's run (``failure_runs.run_spec``) of a
scenario with maneuvers; the bank is the one under test (``--tuning``: the nominal bank today;
a scheduled bank file when there is one), never told of the maneuver.

Per maneuver (and per point and maneuver, for the map), over the stored runs::

    correct          failure-case runs ending with the injected failure declared / failure-case
                     runs, 95 % intervals, goal >= 0.95
    false_alarm      runs with a false alarm (a failure declared before the failure, or at
                     all in a NONE run) / runs, goal 0
    per_hour         false declarations per hour of maneuvering flight before any failure
                     (``evidence.false_declaration_rate``: exact Poisson 95 % interval)
    latency          median detection latency of the correct failure runs, VEL apart
                     (``latency_median_s`` without VEL, ``vel_latency_median_s``)
"""
from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ... import __version__
from ...banks import bank_estimator_settings, load_bank
from ...names import NONE
from ...truth import Scenario
from ...truth.aircraft import ALT_FT_RANGE, MACH_RANGE
from ..engine import drilldown, evidence, identity, intervals, outcomes, scoring
from ..engine.config import CampaignConfig, CampaignError
from ..engine.failure_runs import CASES, check_case_failures, check_failure_jitter, failure_offset, run_spec as single_run_spec
from ..engine.points import check_points
from ..engine.runner import CampaignOutcome, execute
from ..engine.seeds import evaluation_seed
from ..engine.store import ResultsStore, campaign_directory, run_key
from . import figures

MANEUVERS: tuple[str, ...] = ("climb", "descend", "accel", "turn")
CLIMB_FT = 4000.0
CLIMB_RATE_FPM = 3000.0
MACH_STEP = 0.1
MACH_RATE_PER_S = 0.01
TURN_BANK_DEG = 30.0
#: Goals of issue 12 for maneuvering flight.
CORRECT_GOAL = 0.95
LATENCY_GOAL_S = 1.0


def maneuver_spec(maneuver: str, mach: float, alt_ft: float, time_s: float) -> str:
    """The truth maneuver string of ``maneuver`` from (mach, alt_ft) (module docstring)."""
    if maneuver == "climb":
        return f"climb@{time_s:g}:to={min(alt_ft + CLIMB_FT, ALT_FT_RANGE[1]):g}ft:rate={CLIMB_RATE_FPM:g}fpm"
    if maneuver == "descend":
        return f"descend@{time_s:g}:to={max(alt_ft - CLIMB_FT, ALT_FT_RANGE[0]):g}ft:rate={CLIMB_RATE_FPM:g}fpm"
    if maneuver == "accel":
        up = round(mach + MACH_STEP, 6)
        kind, to = ("accel", up) if up <= MACH_RANGE[1] else ("decel", round(mach - MACH_STEP, 6))
        return f"{kind}@{time_s:g}:to={to:g}mach:rate={MACH_RATE_PER_S:g}mach/s"
    if maneuver == "turn":
        return f"turn@{time_s:g}:bank={TURN_BANK_DEG:g}deg"
    raise CampaignError(f"unknown maneuver {maneuver!r}; valid: {', '.join(MANEUVERS)}")


@dataclass(frozen=True)
class ManeuverCampaign(CampaignConfig):
    """The arguments of ``f16mmae campaign maneuver`` (everything that shapes the results)."""

    runs: int = 3
    points: tuple = ()
    maneuvers: tuple[str, ...] = MANEUVERS
    cases: tuple[str, ...] = CASES
    maneuver_time_s: float = 2.0
    failure_time_s: float = 6.0
    failure_jitter_s: float = 0.0  # each run's failure and end up to this much later (engine.failure_runs)
    duration_s: float = 14.0

    def validate(self) -> "ManeuverCampaign":
        check_points(self.points)
        bad = [m for m in self.maneuvers if m not in MANEUVERS]
        if bad or not self.maneuvers or len(set(self.maneuvers)) != len(self.maneuvers):
            raise CampaignError(f"--maneuvers {','.join(self.maneuvers)!r}: each of {', '.join(MANEUVERS)} at most once")
        if not 0.0 <= self.maneuver_time_s < self.duration_s:
            raise CampaignError(f"--maneuver-time {self.maneuver_time_s} s must lie in [0, {self.duration_s}) s")
        self.check_common(dwell_window_s=self.duration_s)
        check_failure_jitter(self)
        if len(self.levels()) > 1:
            raise CampaignError(f"campaign maneuver flies one turbulence level, got {self.turbulence!r}")
        check_case_failures(self)
        return self


def run_seed(campaign_seed: int, maneuver: str, case: str, run_index: int) -> int:
    return evaluation_seed("maneuver", campaign_seed, maneuver, case, run_index)


def plan(cfg: ManeuverCampaign, label: str, tuning_arg: str, bank) -> list[dict]:
    """Every run spec: point, maneuver, case, run (module docstring)."""
    specs = []
    for p in cfg.points:
        for m in cfg.maneuvers:
            text = maneuver_spec(m, p.mach, p.alt_ft, cfg.maneuver_time_s)
            for case in cfg.cases:
                for n in range(cfg.runs):
                    seed = run_seed(cfg.seed, m, case, n)
                    offset = failure_offset(seed, cfg.failure_jitter_s)
                    failures = () if case == NONE else ((case, cfg.failure_time_s + offset),)
                    try:
                        sc = cfg.scenario_dict(bank, failures, seed, p.mach, p.alt_ft,
                                               duration_s=cfg.duration_s + offset)
                        sc = Scenario.from_dict({**sc, "maneuvers": [text]}).to_dict()
                    except ValueError as exc:
                        raise CampaignError(f"point {p.label}, {m}, case {case}: {exc}") from None
                    key = run_key({"kind": "maneuver", "scenario": sc, "estimator": cfg.estimator_options(),
                                   "bank_hash": bank.content_hash, "version": __version__})
                    specs.append({"run_key": key, "case": case, "run_index": n, "seed": seed, "tuning": label,
                                  "bank": tuning_arg, "bank_hash": bank.content_hash, "version": __version__,
                                  "scenario": sc, "estimator": cfg.estimator_options(),
                                  "point": p.label, "maneuver": m})
    return specs


def run_spec(spec: dict) -> dict:
    """One run: the single campaign's run of the maneuvering scenario, labelled."""
    return {**single_run_spec(spec), "kind": "maneuver", "point": spec["point"], "maneuver": spec["maneuver"]}


def describe_spec(spec: dict) -> str:
    return (f"point {spec['point']}, {spec['maneuver']}: run {spec['run_index']} of case {spec['case']} "
            f"(seed {spec['seed']})")


def run_maneuver(cfg: ManeuverCampaign, out_dir: str | Path, executor: Executor, executor_label: str = "",
                 show_progress: bool = True, allow_mixed: bool = False) -> CampaignOutcome:
    """Plan, fly what is not stored yet, summarize, plot; ``out_dir`` checked and locked first."""
    cfg.validate()
    with campaign_directory(out_dir) as out:
        label, _, bank = load_bank(cfg.tuning)
        specs = plan(cfg, label, cfg.tuning, bank)
        done = execute(specs, ResultsStore(out), executor, run_spec, describe=describe_spec,
                       progress_label="runs", show_progress=show_progress, allow_mixed=allow_mixed)
        summary = summarize(cfg, label, bank, done.records)
        summary["figures"] = figures.make_figures(out, summary, done.records)
        return done.finish(out, summary, executor_label)


def group_metrics(records: list[dict]) -> dict:
    """Rates of a group of runs (module docstring)."""
    fail = [r for r in records if r["case"] != NONE]
    lat = [r["latency_s"] for r in fail if r.get("latency_s") is not None and r["case"] != "VEL"]
    vel = [r["latency_s"] for r in fail if r.get("latency_s") is not None and r["case"] == "VEL"]
    rates = {}
    if fail:
        rates["correct"] = intervals.rate(sum(r["outcome"] == "correct" for r in fail), len(fail),
                                          goal=CORRECT_GOAL, direction="at_least")
    if records:
        rates["false_alarm"] = intervals.rate(outcomes.count(records, "false_alarm"), len(records),
                                              goal=0.0, direction="at_most")
    per_hour = evidence.false_declaration_rate(records)
    med = float(np.median(lat)) if lat else None
    return {
        "runs": len(records), "failure_runs": len(fail),
        "correct_fraction": rates["correct"]["fraction"] if fail else None,
        "false_alarm_runs": outcomes.count(records, "false_alarm"),
        "rates": rates, "per_hour": per_hour,
        "latency_median_s": med, "latency_goal_met": None if med is None else med <= LATENCY_GOAL_S,
        "vel_latency_median_s": float(np.median(vel)) if vel else None,
        "verdict": evidence.worst(r["verdict"] for r in rates.values()),
    }


def summarize(cfg: ManeuverCampaign, label: str, bank, records: list[dict]) -> dict:
    """The maneuver campaign's ``summary.json`` (module docstring)."""
    ranked = sorted(records, key=lambda r: (r["point"], r["maneuver"], r["case"], r["run_index"]))
    rows, cells, cases = [], [], []
    for m in cfg.maneuvers:
        recs = [r for r in ranked if r["maneuver"] == m]
        rows.append({"maneuver": m, **group_metrics(recs)})
        cases += [{"maneuver": m, **scoring.summarize_case(c, [r for r in recs if r["case"] == c])}
                  for c in cfg.cases]
        for p in cfg.points:
            cell = [r for r in recs if r["point"] == p.label]
            cells.append({"point": p.label, "mach": p.mach, "alt_ft": p.alt_ft, "maneuver": m,
                          "maneuver_spec": maneuver_spec(m, p.mach, p.alt_ft, cfg.maneuver_time_s),
                          **group_metrics(cell)})
    return {
        "kind": "maneuver", "runs_per_case": cfg.runs, "seed": cfg.seed, "cases": list(cfg.cases),
        "maneuvers": list(cfg.maneuvers), "maneuver_time_s": cfg.maneuver_time_s,
        "failure_time_s": cfg.failure_time_s, "failure_jitter_s": cfg.failure_jitter_s, "duration_s": cfg.duration_s,
        "points": [{"label": p.label, "mach": p.mach, "alt_ft": p.alt_ft} for p in cfg.points],
        "tuning": label, "bank_hash": bank.content_hash, "version": __version__,
        "design_point": {"mach": float(bank.mach), "alt_ft": float(bank.alt_ft)},
        "turbulence": cfg.turbulence, "mode": cfg.mode, "feedback": cfg.feedback, "dither": cfg.dither,
        "dither_scale": cfg.dither_scale, "estimator": cfg.estimator_options(),
        "estimator_settings": bank_estimator_settings(bank, cfg.estimator_options()),
        "goals": {"correct_min": CORRECT_GOAL, "false_alarm_runs": 0, "latency_median_s_max": LATENCY_GOAL_S},
        "by_maneuver": rows, "by_point": cells, "by_case": cases,
        "overall": group_metrics(ranked),
        **evidence.summary_fields(
            ranked, cases,
            drilldown.not_clean(ranked, lambda r: drilldown.record_command(r, cfg.dither_scale),
                                lambda r: {"point": r["point"], "maneuver": r["maneuver"], "case": r["case"]}),
            identity.code_identity(), goals_met=all(r["verdict"] != "not met" for r in rows)),
    }


__all__ = ["MANEUVERS", "ManeuverCampaign", "group_metrics", "maneuver_spec", "plan", "run_maneuver", "summarize"]
