"""The off-nominal campaign (paper Sec. VIII, Fig. 9): the nominal design flown away from
its design point.

The bank under test (default: the shipped ``tuned`` single-failure bank, designed at
Mach 0.4, 20,000 ft) is kept as it is -- its models, its design trim ``u_trim`` /
``z_trim`` -- while the truth model is trimmed and flown at each envelope point.  The
estimator learns the flight condition through nothing but ``u`` and ``z``: model mismatch
and trim mismatch are what the campaign measures.

Points: :mod:`.points` (default: the paper's 25 -- NOM, the local envelope 1-20
stepping 0.005 Mach / 500 ft, the extrema 21-24 at +-5,000 ft / +-0.05 Mach).

At every point the single-failure plan (:mod:`..engine.failure_runs`: NONE and the
failures, ``runs`` seeded runs each) is planned at the point's Mach and altitude and flown
with the same ``run_spec``; all points share one results store ``DIR/runs.jsonl`` (the run
key holds the scenario, so the point's Mach and altitude) and one executor, so resume
works across points (re-running skips stored runs).  Run n of case c flies the same seed
at every point (``failure_runs.run_seed``): common random numbers, so differences between
points come from the flight condition, not from the noise.

Per point, over its stored runs (``point_metrics``)::

    correct_fraction = (# failure-case runs ending with the injected failure declared)
                       / (# failure-case runs)                (None without failure cases)
    false_alarm_runs = # runs with a false alarm (scoring.score_run), NONE runs included:
                       a failure declared before the failure time, or at all in a NONE run
    latency_median_s = median detection latency over the failure-case runs that have one

``acceptable`` (the paper calls performance acceptable while false alarms stay away):
``correct_fraction >= 0.9`` (skipped when there are no failure cases) AND
``false_alarm_runs == 0``; both thresholds are fields of :class:`EnvelopeCampaign`.

Each point also records ``trim_offset``: the truth model's own trim at the point minus the
bank's design trim (stabilator deg, VEL ft/s, AOA deg, AZ g) -- the initial perturbation
error the paper names as the first cause of false alarms.  It is computed in the parent for
the report only; the estimator never receives it.
"""
from __future__ import annotations

import sys
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ... import __version__
from ...banks import bank_estimator_settings, load_bank
from ...names import FAILURE_TIME_S, NONE
from ...truth.aircraft import trimmed_fdm
from ..engine import drilldown, evidence, identity, intervals, outcomes, scoring, variants
from ..engine.config import CampaignConfig, CampaignError
from ..engine.failure_runs import CASES, check_case_failures, check_failure_jitter, plan as plan_at, run_spec
from ..engine.points import check_points
from ..engine.runner import CampaignOutcome, execute
from ..engine.store import ResultsStore, campaign_directory
from . import figures
from .points import PAPER_POINTS, EnvelopeError, EnvelopePoint

#: The default acceptability rule (module docstring).
CORRECT_FRACTION_MIN = 0.9
FALSE_ALARMS_MAX = 0


@dataclass(frozen=True)
class EnvelopeCampaign(CampaignConfig):
    """The arguments of ``f16mmae campaign envelope`` (everything that shapes the results)."""

    runs: int = 2
    points: tuple[EnvelopePoint, ...] = PAPER_POINTS
    cases: tuple[str, ...] = CASES
    failure_time_s: float = FAILURE_TIME_S
    failure_jitter_s: float = 0.0  # each run's failure up to this much later (engine.failure_runs)
    correct_fraction_min: float = CORRECT_FRACTION_MIN
    false_alarms_max: int = FALSE_ALARMS_MAX

    def validate(self) -> "EnvelopeCampaign":
        check_points(self.points)
        if not 0.0 <= self.correct_fraction_min <= 1.0:
            raise CampaignError(f"correct_fraction_min {self.correct_fraction_min} must lie in [0, 1]")
        if self.false_alarms_max < 0:
            raise CampaignError(f"false_alarms_max {self.false_alarms_max} must be >= 0")
        self.check_common(dwell_window_s=self.duration_s)
        check_failure_jitter(self)
        check_case_failures(self)
        return self


# -- per-point scoring -----------------------------------------------------------------------
def point_metrics(records: list[dict]) -> dict:
    """Counts and latency of one point's runs (module docstring)."""
    fail = [r for r in records if r["case"] != NONE]
    none = [r for r in records if r["case"] == NONE]
    lat = [r["latency_s"] for r in fail if r.get("latency_s") is not None]
    correct = sum(1 for r in fail if r["outcome"] == "correct")
    return {
        "runs": len(records),
        "failure_runs": len(fail),
        "correct": correct,
        "missed": sum(1 for r in fail if r["outcome"] == "missed"),
        "wrong": sum(1 for r in fail if r["outcome"] == "wrong"),
        "correct_fraction": correct / len(fail) if fail else None,
        "none_runs": len(none),
        "none_correct": sum(1 for r in none if r["outcome"] == "correct"),
        "false_alarm_runs": sum(1 for r in records if r["false_alarm"]),
        "latency_median_s": float(np.median(lat)) if lat else None,
    }


def acceptable(metrics: dict, correct_fraction_min: float = CORRECT_FRACTION_MIN,
               false_alarms_max: int = FALSE_ALARMS_MAX) -> bool:
    """The acceptability rule of the module docstring on ``point_metrics`` output."""
    if metrics["runs"] == 0:
        return False
    frac = metrics["correct_fraction"]
    return (frac is None or frac >= correct_fraction_min) and metrics["false_alarm_runs"] <= false_alarms_max


def point_rates(records: list[dict], correct_fraction_min: float = CORRECT_FRACTION_MIN) -> dict:
    """The point's rates with 95 % intervals and the verdicts of the acceptability rule:
    correct over the failure-case runs (goal ``>= correct_fraction_min``), runs with a false
    alarm and transient-wrong runs over all runs (goal 0 each); ``verdict`` the worst."""
    fail = [r for r in records if r["case"] != NONE]
    out = {}
    if fail:
        out["correct"] = intervals.rate(sum(r["outcome"] == "correct" for r in fail), len(fail),
                                        goal=correct_fraction_min, direction="at_least")
    if records:
        for name in ("false_alarm", "transient_wrong"):
            out[name] = intervals.rate(outcomes.count(records, name), len(records), goal=0.0, direction="at_most")
    return {"rates": out, "verdict": evidence.worst(r["verdict"] for r in out.values())}


def trim_offset(bank, point: EnvelopePoint) -> dict:
    """Truth trim at ``point`` minus the bank's design trim (report only, never to the estimator)."""
    _, tp = trimmed_fdm(point.mach, point.alt_ft)
    du = np.asarray(tp.u_rad) - np.asarray(bank.u_trim)[:len(tp.u_rad)]  # the surfaces (a throttle bank has 6)
    dz = np.asarray(tp.z) - np.asarray(bank.z_trim)
    return {"stab_deg": round(float(np.degrees(du[0])), 4), "vel_fps": round(float(dz[0]), 3),
            "aoa_deg": round(float(np.degrees(dz[1])), 4), "az_g": round(float(dz[3]), 5)}


# -- the campaign ----------------------------------------------------------------------------
def plan(cfg: EnvelopeCampaign, banks: dict) -> list[dict]:
    """Every run spec of every point (the single-failure plan at each), each tagged with its point."""
    specs = []
    for p in cfg.points:
        for s in plan_at(cfg, banks, p.mach, p.alt_ft):
            specs.append({**s, "point": p.label})
    return specs


def run_point_spec(spec: dict) -> dict:
    """One run at one point: the single campaign's run, its record labelled with the point."""
    return {**run_spec(spec), "point": spec["point"]}


#: Its record without ``point`` is ``run_spec``'s of the spec without ``point``
#: (``engine.shared_flights``: the single campaign reuses the nominal point's runs).
run_point_spec.shares = (run_spec, ("point",))


def describe_point_spec(spec: dict) -> str:
    sc = spec["scenario"]
    return (f"point {spec['point']} (Mach {sc['mach']}, {sc['alt_ft']:.0f} ft): "
            f"run {spec['run_index']} of case {spec['case']} (seed {spec['seed']})")


def run_envelope(cfg: EnvelopeCampaign, out_dir: str | Path, executor: Executor,
                 executor_label: str = "", show_progress: bool = True,
                 allow_mixed: bool = False) -> CampaignOutcome:
    """Plan every point, run what is not stored yet, summarize per point, plot; ``out_dir``
    checked writable and locked (``store.campaign_directory``) before any flight."""
    cfg.validate()
    with campaign_directory(out_dir) as out:
        return _run_envelope(cfg, out, executor, executor_label, show_progress, allow_mixed)


def _run_envelope(cfg: EnvelopeCampaign, out: Path, executor: Executor, executor_label: str,
                  show_progress: bool, allow_mixed: bool) -> CampaignOutcome:
    label, _, bank = load_bank(cfg.tuning)
    banks = {label: (cfg.tuning, bank)}
    store = ResultsStore(out)
    stored = store.keys()
    left: dict[tuple[str, str], int] = {}  # runs still to fly, per level and point
    point_of: dict[str, str] = {}

    def level_plan(c: EnvelopeCampaign) -> list[dict]:
        specs = plan(c, banks)
        for spec in specs:
            where = (c.turbulence, spec["point"])
            left[where] = left.get(where, 0) + (spec["run_key"] not in stored)
            point_of[spec["run_key"]] = spec["point"]
        return specs

    def point_progress(spec: dict) -> None:
        where = (spec["scenario"]["turbulence"], spec["point"])
        left[where] -= 1
        if show_progress and left[where] == 0:
            at = f" at {where[0]} turbulence" if len(cfg.levels()) > 1 else ""
            _note(f"point {spec['point']}{at} done (Mach {spec['scenario']['mach']:.3f}, "
                  f"{spec['scenario']['alt_ft']:.0f} ft); {sum(1 for v in left.values() if v)} point(s) to go")

    def level_summary(c: EnvelopeCampaign, records: list[dict], d: Path) -> dict:
        summary = summarize(c, banks, label, records, point_of)
        summary["figures"] = figures.make_figures(d, summary)
        return summary

    summary, done = variants.fly_variants(
        cfg, out, level_plan,
        lambda specs: execute(specs, store, executor, run_point_spec, describe=describe_point_spec,
                              progress_label=f"runs ({len(cfg.points)} points)", show_progress=show_progress,
                              after_each=point_progress, allow_mixed=allow_mixed),
        level_summary)
    return done.finish(out, summary, executor_label)


def _note(text: str) -> None:
    stream = sys.stderr
    tty = bool(getattr(stream, "isatty", lambda: False)())
    stream.write(("\r\x1b[K" if tty else "") + text + "\n")
    stream.flush()


def summarize(cfg: EnvelopeCampaign, banks: dict, label: str, records: list[dict],
              point_of: dict[str, str]) -> dict:
    """The envelope summary: the campaign's settings and one entry per point."""
    bank = banks[label][1]
    design = EnvelopePoint("design", float(bank.mach), float(bank.alt_ft), "nominal")
    points = []
    for p in cfg.points:
        recs = [r for r in records if point_of[r["run_key"]] == p.label]
        metrics = point_metrics(recs)
        points.append({
            **p.to_dict(),
            "d_mach": round(p.mach - design.mach, 6),
            "d_alt_ft": round(p.alt_ft - design.alt_ft, 3),
            "qbar_ratio": round(p.qbar_psf / design.qbar_psf, 4),
            **metrics,
            "acceptable": acceptable(metrics, cfg.correct_fraction_min, cfg.false_alarms_max),
            "evidence": point_rates(recs, cfg.correct_fraction_min),
            "trim_offset": trim_offset(bank, p),
            "cases": [scoring.summarize_case(c, [r for r in recs if r["tuning"] == label and r["case"] == c])
                      for c in cfg.cases],
        })
    return {
        "kind": "envelope",
        "runs_per_case": cfg.runs,
        "seed": cfg.seed,
        "cases": list(cfg.cases),
        "bank_hash": bank.content_hash,
        "version": __version__,
        "tuning": label,
        "design_point": {"mach": design.mach, "alt_ft": design.alt_ft,
                         "qbar_psf": round(design.qbar_psf, 3)},
        "turbulence": cfg.turbulence,
        "mode": cfg.mode,
        "failure_time_s": cfg.failure_time_s,
        "failure_jitter_s": cfg.failure_jitter_s,
        "duration_s": cfg.duration_s,
        "feedback": cfg.feedback,
        "dither": cfg.dither,
        "dither_scale": cfg.dither_scale,
        "estimator": cfg.estimator_options(),
        "estimator_settings": bank_estimator_settings(bank, cfg.estimator_options()) if cfg.points else {},
        "acceptable_rule": {"correct_fraction_min": cfg.correct_fraction_min,
                            "false_alarm_runs_max": cfg.false_alarms_max},
        "points": points,
        **evidence.summary_fields(
            records, [c for p in points for c in p["cases"]],
            drilldown.not_clean(sorted(records, key=lambda r: (r["point"], r["case"], r["run_index"])),
                                lambda r: drilldown.record_command(r, cfg.dither_scale),
                                lambda r: {"point": r["point"], "case": r["case"]}),
            identity.code_identity(), goals_met=all(p["evidence"]["verdict"] != "not met" for p in points)),
    }


__all__ = ["EnvelopeCampaign", "EnvelopeError", "acceptable", "plan",
           "point_metrics", "run_envelope", "summarize", "trim_offset"]
