"""What a case's runs show, with 95 % intervals and goal verdicts, and the campaign's false
declarations per flight hour.

Per case (:func:`case_evidence`, from the run records' scored fields ``outcome``,
``false_alarm``, ``transient_wrong``, ``latency_s``):

* ``rates`` -- correct, missed, wrong, transient_wrong and false_alarm (runs with one), each
  an ``intervals.rate`` record (count, runs, fraction, Clopper-Pearson and Wilson 95 %
  intervals) with a verdict where :data:`GOALS` sets a goal;
* ``detection`` (failure cases) -- ``outcomes.detected_within``: the fraction of runs
  detected within 0.5, 1 and 2 s and within the flight, a missed run counting as never
  detected; plus ``within_1s`` / ``within_2s`` as rates with verdicts.  The latency goals
  are judged in this censored form: "median latency <= 1 s" as "at least half the runs
  detected within 1 s", "p95 <= 2 s" as "at least 95 % detected within 2 s";
  The median and p95 over the detected runs only stay in the case summary's ``latency_s``
  (``scoring.summarize_case``), beside ``latency_detected_runs``, how many runs those are;
* ``verdicts`` (goal -> verdict) and ``verdict``, the worst of them
  (not met < consistent < demonstrated).

Per campaign (:func:`false_declaration_rate`): false declarations (failure declarations in
failure-free flying time, ``outcomes.false_declarations``) summed over the runs, per hour of
failure-free flying time summed likewise, with the exact Poisson 95 % interval.  And
(:func:`latency_medians`) the median detection latency over the detected runs in three groups:
``all``, ``except_vel`` and ``vel``, by the failure the run's ``latency_s`` times (the last one
injected: a dual run's second); every latency goal reads "median <= X, VEL excepted".
"""
from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from ...names import NONE
from . import identity, intervals, outcomes

#: Goals on rates: name -> (goal, direction); see the module docstring.
GOALS: dict[str, tuple[float, str]] = {
    "correct": (0.99, "at_least"),
    "false_alarm": (0.0, "at_most"),
    "transient_wrong": (0.0, "at_most"),
    "within_1s": (0.5, "at_least"),    # median latency <= 1 s, misses counted
    "within_2s": (0.95, "at_least"),   # p95 latency <= 2 s, misses counted
}
RATES: tuple[str, ...] = ("correct", "missed", "wrong", "transient_wrong", "false_alarm")
_ORDER = {v: i for i, v in enumerate(reversed(intervals.VERDICTS))}  # not met 0 < consistent < demonstrated


def worst(verdicts: Iterable[str]) -> str | None:
    """The worst of some verdicts (None for none)."""
    vs = list(verdicts)
    return min(vs, key=_ORDER.__getitem__) if vs else None


def _rate(name: str, k: int, n: int) -> dict:
    goal = GOALS.get(name)
    return intervals.rate(k, n) if goal is None else intervals.rate(k, n, goal=goal[0], direction=goal[1])


def case_evidence(case: str, records: Iterable[dict], expected: str | None = None) -> dict:
    """The evidence of one case (module docstring); ``expected`` is the injected hypothesis
    (default ``case``), NONE for a no-failure case."""
    rs = list(records)
    n = len(rs)
    if n == 0:
        return {"rates": {}, "verdicts": {}, "verdict": None}
    counts = {"correct": sum(r["outcome"] == "correct" for r in rs),
              "missed": sum(r["outcome"] == "missed" for r in rs),
              "wrong": sum(r["outcome"] == "wrong" for r in rs),
              "transient_wrong": outcomes.count(rs, "transient_wrong"),
              "false_alarm": outcomes.count(rs, "false_alarm")}
    out: dict = {"rates": {k: _rate(k, counts[k], n) for k in RATES}}
    if (expected or case) != NONE:
        lat = [r.get("latency_s") for r in rs]
        det = outcomes.detected_within(lat)
        for w, name in ((1.0, "within_1s"), (2.0, "within_2s")):
            det[name] = _rate(name, sum(1 for x in lat if x is not None and x <= w), n)
        out["detection"] = det
    verdicts = {k: r["verdict"] for k, r in out["rates"].items() if "verdict" in r}
    for name in ("within_1s", "within_2s"):
        if "detection" in out:
            verdicts[name] = out["detection"][name]["verdict"]
    out["verdicts"] = verdicts
    out["verdict"] = worst(verdicts.values())
    return out


def false_declaration_rate(records: Iterable[dict]) -> dict:
    """False declarations per failure-free flight hour over ``records`` (fields
    ``false_declarations``, ``failure_free_s``), with the Poisson 95 % interval."""
    rs = list(records)
    events = sum(int(r.get("false_declarations", 0)) for r in rs)
    hours = sum(float(r.get("failure_free_s", 0.0)) for r in rs) / 3600.0
    out = intervals.poisson_rate(events, hours)
    out["exposure_unit"] = "failure-free flight hours"
    return out


#: The groups of :func:`latency_medians`: name -> does a run whose timed failure is VEL belong.
LATENCY_GROUPS: dict[str, tuple[bool, ...]] = {"all": (False, True), "except_vel": (False,), "vel": (True,)}


def timed_failure(record: dict) -> str | None:
    """The failure whose detection a run's ``latency_s`` times: the last one injected (a dual
    run's second), None for a run without a failure."""
    failures = record.get("failures") or []
    return failures[-1]["name"] if failures else None


def latency_medians(records: Iterable[dict]) -> tuple[dict, dict]:
    """The median ``latency_s`` (numpy's median: the mean of the two middle values for an even
    count) over the runs that have one, per group of :data:`LATENCY_GROUPS`, and how many runs
    each median is over; a group without a detected run has median None."""
    lat = [(timed_failure(r) == "VEL", float(r["latency_s"])) for r in records
           if r.get("latency_s") is not None]
    medians, runs = {}, {}
    for name, vel in LATENCY_GROUPS.items():
        xs = [x for is_vel, x in lat if is_vel in vel]
        medians[name] = float(np.median(xs)) if xs else None
        runs[name] = len(xs)
    return medians, runs


def demonstration_note(goal: float = GOALS["correct"][0]) -> dict:
    """How many runs of a case demonstrate ``goal`` with all runs correct, and with one failure."""
    return {"goal": goal, "runs_all_correct": intervals.runs_to_demonstrate(goal),
            "runs_one_failure": intervals.runs_to_demonstrate(goal, failures=1)}


def verdict_counts(evidences: Iterable[dict]) -> dict:
    """How many cases got each overall verdict."""
    out = {v: 0 for v in intervals.VERDICTS}
    for e in evidences:
        if e.get("verdict"):
            out[e["verdict"]] += 1
    return out


def summary_fields(records: Iterable[dict], cases: Iterable[dict], not_clean: list[dict], code: dict,
                   goals_met: bool | None = None) -> dict:
    """The campaign-wide fields every summary adds (docs/INTERFACES.md): ``code``,
    ``codes_in_records``, ``totals`` (correct, runs with a false alarm and transient-wrong runs
    pooled over ``records``, with intervals), ``false_declarations_per_hour`` (over ``records``, the bank under
    test), ``demonstration``, ``verdict_counts``, ``goals_met`` (default: no case's verdict
    is *not met*), ``latency_median_s`` with ``latency_median_runs`` (:func:`latency_medians`
    over ``records``) and ``not_clean``."""
    rs = list(records)
    evs = [c.get("evidence", {}) for c in cases]
    mixed: dict[str, int] = {}
    for r in rs:
        key = identity.describe(r.get("code"))
        mixed[key] = mixed.get(key, 0) + 1
    n = len(rs)
    totals = {} if not n else {
        "correct": intervals.rate(sum(r["outcome"] == "correct" for r in rs), n),
        "false_alarm": intervals.rate(outcomes.count(rs, "false_alarm"), n),
        "transient_wrong": intervals.rate(outcomes.count(rs, "transient_wrong"), n)}
    medians, median_runs = latency_medians(rs)
    return {
        "code": code,
        "codes_in_records": mixed,
        "totals": totals,
        "false_declarations_per_hour": false_declaration_rate(rs),
        "latency_median_s": medians,
        "latency_median_runs": median_runs,
        "demonstration": demonstration_note(),
        "verdict_counts": verdict_counts(evs),
        "goals_met": (all(e.get("verdict") != "not met" for e in evs) if goals_met is None else goals_met),
        "not_clean": not_clean,
    }

