"""Detectability curves: detection probability against the size of a partial failure.

Families of failure (the truth model's modes, :mod:`f16mmae.truth.failures`), each flown at
a list of sizes, ``runs`` seeded runs per (component, size), the failure at
``failure_time_s`` of a ``duration_s`` flight at the bank's design point:

* ``bias``  -- each sensor ``j`` (VEL ... AY) reads ``ideal + noise + b`` from the onset on,
  ``b = s * sigma_j`` for each size ``s`` (a multiple of ``sigma_j``);
* ``drift`` -- each sensor reads ``ideal + noise + r * sigma_j * (t - t_f)``, ``r`` in sigma per s;
* ``loss``  -- each actuator (LS ... RUD) keeps ``1 - L`` of its effectiveness (the truth's
  ``loss`` value is the remaining fraction ``1 - L``), ``L`` the lost fraction, ``0 < L <= 1``.

``sigma_j`` is the truth model's white-noise standard deviation of sensor ``j``
(``truth.sensors.NOISE_SIGMA``), which the bank's measurement noise was designed from.

Per run (:func:`score_detection`), ``h*`` the failed component's hypothesis and ``t_f`` the onset:

* ``detected`` -- ``h*`` is declared at some time ``>= t_f`` within the flight (it need
  not be the final declaration); ``latency_s`` = the first such time minus ``t_f``;
* ``any_declared`` -- some failure hypothesis (not NONE) is declared at a time ``>= t_f``;
  ``any_declared`` without ``detected`` is a mis-isolation;
* ``false_alarm`` -- a failure hypothesis declared before ``t_f``.

Per (family, component, size) (:func:`summarize_point`): the rates of ``detected``,
``any_declared`` and ``false_alarm`` over its runs, each with its 95 % Clopper-Pearson
and Wilson intervals (``engine.intervals.rate``), the median latency over detected runs,
and ``declared_instead``: of the runs that declared another failure after the onset, the
first such hypothesis of each, counted (the three most frequent, ties by name).

Seeds (common random numbers across sizes and families): run ``n`` of component ``c`` flies
``evaluation_seed("detectability", S, c, n)`` at every size of every family, so a curve's
points differ by the failure's size alone.

Failure offset (``failure_jitter_s`` J > 0; 0, the default: none): that run fails at
``failure_time_s + J x`` and flies ``duration_s + J x``, x in [0, 1) drawn from its seed
(``engine.failure_runs.failure_offset``, as the single-failure campaign does), the same offset at
every size: the run meets another phase of the deterministic surface dither, and a curve's
points still differ by the size alone.
"""
from __future__ import annotations

from collections import Counter
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ... import __version__
from ...banks import bank_estimator_settings, load_bank
from ...loop.flight import fly, scenario_from_dict
from ...names import ACTUATORS, FAILURE_TIME_S, NONE, SENSORS
from ...truth.failures import make_failure
from ...truth.sensors import NOISE_SIGMA
from ..engine import drilldown, evidence, identity, outcomes, scoring
from ..engine.config import CampaignConfig, CampaignError
from ..engine.failure_runs import check_failure_jitter, failure_offset
from ..engine.intervals import rate
from ..engine.runner import CampaignOutcome, execute, planned_bank
from ..engine.seeds import evaluation_seed
from ..engine.store import ResultsStore, campaign_directory, run_key
from . import figures

#: family -> (truth failure mode, the components it applies to, unit of its sizes)
FAMILIES: dict[str, tuple[str, tuple[str, ...], str]] = {
    "bias": ("bias", SENSORS, "sigma"),
    "drift": ("drift", SENSORS, "sigma/s"),
    "loss": ("loss", ACTUATORS, "lost"),
}
COMPONENTS: tuple[str, ...] = SENSORS + ACTUATORS
DEFAULT_SIZES: tuple[float, ...] = (1.0, 2.0, 3.0, 5.0, 10.0, 20.0)
DEFAULT_RATES: tuple[float, ...] = (0.5, 1.0, 2.0, 5.0, 10.0)
DEFAULT_LOSSES: tuple[float, ...] = (0.1, 0.25, 0.5, 0.75, 1.0)
#: The largest bias (sigma) and drift rate (sigma/s) a campaign flies.
SIZE_MAX = 1000.0
#: How many of the hypotheses declared instead of the failed component a point lists.
DECLARED_INSTEAD_SHOWN = 3
#: The most sizes per family.
SIZES_MAX_COUNT = 20


def sigma_of(sensor: str) -> float:
    """The truth model's noise standard deviation of ``sensor`` (its unit: ft/s, rad, rad/s, g)."""
    return float(NOISE_SIGMA[SENSORS.index(sensor)])


def truth_value(family: str, component: str, size: float) -> float:
    """The truth failure's ``value`` for a size: bias/drift ``size * sigma``, loss ``1 - size``."""
    if family == "loss":
        return 1.0 - size
    return size * sigma_of(component)


@dataclass(frozen=True)
class DetectabilityCampaign(CampaignConfig):
    """The arguments of ``f16mmae campaign detectability`` (everything that shapes the results)."""

    components: tuple[str, ...] = COMPONENTS
    sizes: tuple[float, ...] = DEFAULT_SIZES    # bias, multiples of sigma
    rates: tuple[float, ...] = DEFAULT_RATES    # drift, sigma per s
    losses: tuple[float, ...] = DEFAULT_LOSSES  # loss, fraction of effectiveness lost
    failure_time_s: float = FAILURE_TIME_S
    failure_jitter_s: float = 0.0  # each run's failure up to this much later (module docstring)
    mode: str = "complete"  # not flown: each family sets its own truth mode (FAMILIES)

    def family_sizes(self) -> dict[str, tuple[float, ...]]:
        return {"bias": self.sizes, "drift": self.rates, "loss": self.losses}

    def validate(self) -> "DetectabilityCampaign":
        self.check_common(dwell_window_s=self.duration_s)
        bad = [c for c in self.components if c not in COMPONENTS]
        if bad or not self.components:
            raise CampaignError(f"unknown component(s) {', '.join(bad) or '(none given)'}; "
                                f"valid: {', '.join(COMPONENTS)}")
        if len(set(self.components)) != len(self.components):
            raise CampaignError(f"a component is listed twice in {','.join(self.components)}")
        limits = {"--sizes": (self.sizes, SIZE_MAX), "--rates": (self.rates, SIZE_MAX), "--losses": (self.losses, 1.0)}
        for option, (values, top) in limits.items():
            check_sizes(option, values, top)
        check_failure_jitter(self)
        if not 0 < self.failure_time_s < self.duration_s:
            raise CampaignError(f"the failure time {self.failure_time_s} s must lie inside the flight "
                                f"(0, {self.duration_s}) s")
        return self


def check_sizes(option: str, values, top: float) -> None:
    """CampaignError unless ``values`` is 1..SIZES_MAX_COUNT distinct numbers in (0, top]."""
    if not 1 <= len(values) <= SIZES_MAX_COUNT:
        raise CampaignError(f"{option} needs 1 to {SIZES_MAX_COUNT} values, got {len(values)}")
    for v in values:
        if not (isinstance(v, (int, float)) and np.isfinite(v) and 0.0 < v <= top):
            raise CampaignError(f"{option} value {v!r} must lie in (0, {top:g}]")
    if len(set(values)) != len(values):
        raise CampaignError(f"{option} lists a value twice: {','.join(f'{v:g}' for v in values)}")


# -- planning and one run --------------------------------------------------------------------
def plan(cfg: DetectabilityCampaign, tuning_arg: str, bank) -> list[dict]:
    """Every run spec: family x component (of that family, in ``cfg.components``) x size x run."""
    specs = []
    for family, sizes in cfg.family_sizes().items():
        mode, members, _ = FAMILIES[family]
        for component in (c for c in cfg.components if c in members):
            for size in sizes:
                value = truth_value(family, component, size)
                for n in range(cfg.runs):
                    seed = evaluation_seed("detectability", cfg.seed, component, n)
                    offset = failure_offset(seed, cfg.failure_jitter_s)
                    failure = make_failure(component, cfg.failure_time_s + offset, mode, value)
                    scenario = cfg.scenario_dict(bank, (failure,), seed, duration_s=cfg.duration_s + offset)
                    ident = {"kind": "detectability", "scenario": scenario, "estimator": cfg.estimator_options(),
                             "bank_hash": bank.content_hash, "version": __version__}
                    specs.append({"run_key": run_key(ident), "family": family, "component": component,
                                  "size": size, "value": value, "run_index": n, "seed": seed,
                                  "bank": tuning_arg, "tuning": tuning_arg, "bank_hash": bank.content_hash, "version": __version__,
                                  "scenario": scenario, "estimator": cfg.estimator_options()})
    return specs


def score_detection(component: str, onset_s: float, declarations: list[dict], duration_s: float) -> dict:
    """One run's fields: the single-failure scoring (``engine.scoring.score_run``: outcome,
    final hypothesis, false alarm, latency), the shared run rules (``engine.outcomes.run_fields``)
    and ``detected`` / ``any_declared`` (module docstring)."""
    scored = scoring.score_run(component, onset_s, declarations)
    return {**scored, "detected": scored["latency_s"] is not None,
            "any_declared": any(d["time_s"] >= onset_s and d["hypothesis"] != NONE for d in declarations),
            **outcomes.run_fields(declarations, onset_s, {component}, duration_s)}


def run_spec(spec: dict) -> dict:
    """Fly one run and return its record: a pure function of ``spec``."""
    bank = planned_bank(spec)
    scenario = scenario_from_dict(spec["scenario"])
    result = fly(scenario, bank, estimator_options=spec["estimator"])
    onset = scenario.failures[0].time_s
    keep = ("run_key", "family", "component", "size", "value", "run_index", "seed", "bank", "tuning", "bank_hash",
            "version", "scenario", "estimator")
    return {**{k: spec[k] for k in keep}, "kind": "detectability", "failure_time_s": onset,
            "declarations": scoring.isolating_declarations(result.declarations),   # partial: its surface
            **score_detection(spec["component"], onset, scoring.isolating_declarations(result.declarations),
                              scenario.duration_s), "timing": result.timing}


def describe_spec(spec: dict) -> str:
    return (f"run {spec['run_index']} of {spec['component']} {spec['family']} {spec['size']:g} "
            f"(seed {spec['seed']})")


# -- summary ---------------------------------------------------------------------------------
def _first_other(record: dict) -> list[dict]:
    """The first declaration after the onset of a failure other than the run's component (or none)."""
    return [d for d in record.get("declarations", ()) if d["time_s"] >= record["failure_time_s"]
            and d["hypothesis"] not in (NONE, record["component"])][:1]


def summarize_point(size: float, value: float, records: list[dict]) -> dict:
    """The rates of one (family, component, size) from its run records (module docstring)."""
    n = len(records)
    lat = [r["latency_s"] for r in records if r["latency_s"] is not None]
    instead = Counter(d["hypothesis"] for r in records for d in _first_other(r))
    out = {"size": size, "value": value, "runs": n,
           "latency_median_s": float(np.median(lat)) if lat else None,
           # most frequent first, ties by name: independent of the order runs finished in
           "declared_instead": dict(sorted(instead.items(), key=lambda hk: (-hk[1], hk[0]))[:DECLARED_INSTEAD_SHOWN])}
    for field in ("detected", "any_declared", "false_alarm"):
        out[field] = rate(sum(1 for r in records if r[field]), n) if n else None
    return out


def summarize(cfg: DetectabilityCampaign, label: str, bank, records: list[dict]) -> dict:
    families = {}
    for family, sizes in cfg.family_sizes().items():
        _, members, unit = FAMILIES[family]
        comps = []
        for component in (c for c in cfg.components if c in members):
            points = []
            for size in sizes:
                rs = [r for r in records if r["family"] == family and r["component"] == component
                      and r["size"] == size]
                points.append(summarize_point(size, truth_value(family, component, size), rs))
            comps.append({"component": component, "points": points})
        if comps:
            families[family] = {"unit": unit, "components": comps}
    return {
        "kind": "detectability", "runs_per_size": cfg.runs, "seed": cfg.seed, "bank_hash": bank.content_hash,
        "version": __version__, "tuning": label, "turbulence": cfg.turbulence, "mode": "|".join(FAMILIES),
        "mach": float(bank.mach), "alt_ft": float(bank.alt_ft), "failure_time_s": cfg.failure_time_s,
        "failure_jitter_s": cfg.failure_jitter_s, "duration_s": cfg.duration_s, "feedback": cfg.feedback,
        "dither_scale": cfg.dither_scale,
        "estimator": cfg.estimator_options(),
        "estimator_settings": bank_estimator_settings(bank, cfg.estimator_options()),
        "sigma": {s: sigma_of(s) for s in SENSORS},
        "families": families,
        **_campaign_fields(cfg, records),
    }


def _campaign_fields(cfg: DetectabilityCampaign, records: list[dict]) -> dict:
    """The campaign-wide fields every summary adds (``engine.evidence.summary_fields``), without
    the per-case verdicts a curve has not.  ``not_clean`` lists the runs that declared something
    wrong -- a false alarm, or another failure after the onset (transient-wrong) -- with the
    command that flies each again; a run that merely missed a small failure is a point of the
    curve, not listed.  No goal is set on a curve: ``goals_met`` (``--check``) is "no run had a
    false alarm"."""
    order = {(f, c, x): i for i, (f, c, x) in enumerate(
        (f, c, x) for f, xs in cfg.family_sizes().items() for c in cfg.components for x in xs)}
    wrong = [r for r in records if r["false_alarm"] or r["transient_wrong"]]
    ranked = sorted(wrong, key=lambda r: (order.get((r["family"], r["component"], r["size"]), 0), r["run_index"]))
    fields = evidence.summary_fields(
        records, [], drilldown.not_clean(ranked, lambda r: drilldown.record_command(r, cfg.dither_scale),
                                         lambda r: {k: r[k] for k in ("family", "component", "size")}),
        identity.code_identity(), goals_met=not any(r["false_alarm"] for r in records))
    for key in ("demonstration", "verdict_counts"):
        del fields[key]
    return fields


def run_campaign(cfg: DetectabilityCampaign, out_dir: str | Path, executor: Executor, executor_label: str = "",
                 show_progress: bool = True, allow_mixed: bool = False) -> CampaignOutcome:
    """Plan, fly what is not stored, summarize, plot; ``out_dir`` checked and locked first."""
    cfg.validate()
    with campaign_directory(out_dir) as out:
        label, _, bank = load_bank(cfg.tuning)
        try:
            specs = plan(cfg, cfg.tuning, bank)
        except ValueError as exc:
            raise CampaignError(str(exc)) from None
        done = execute(specs, ResultsStore(out), executor, run_spec, describe=describe_spec,
                       show_progress=show_progress, allow_mixed=allow_mixed)
        summary = summarize(cfg, label, bank, done.records)
        summary["figures"] = figures.curves(out, summary)
        return done.finish(out, summary, executor_label)
