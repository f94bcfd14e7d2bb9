"""Scoring of closed-loop runs: isolation, missed and false alarms, detection latency.

Per run (``score_run``), with ``declarations`` the time-ordered list of
``{"hypothesis", "time_s"}`` the declarer made (a back-out is a declaration of NONE),
the injected hypothesis ``h*`` (NONE, a single such as ``LS``, or a dual ``LS+PIT``)
and ``t_f`` the first failure time:

* ``final_hypothesis`` = the hypothesis of the last declaration, NONE when there is none.
* ``outcome``:
    - ``correct``  -- ``final_hypothesis == h*`` (for a no-failure run: the run ends
      believing NONE);
    - ``missed``   -- a failure was injected and the run ends with no failure declared
      (never declared, or backed out to NONE);
    - ``wrong``    -- the run ends with another failure declared than the injected one.
* ``false_alarm`` -- a failure was declared before ``t_f``; in a no-failure run, any
  failure declaration at all.
* ``latency_s`` = (time of the first declaration of ``h*`` at or after ``t_f``) - ``t_f``;
  ``None`` when there is no such declaration (and always for no-failure runs).

A partial hypothesis' declaration (``"LS:loss=0.5"``, ``f16mmae design --partial-loss``) is
scored as the isolation of its surface, in whatever mode the surface failed
(``isolating_declarations``; design/hypotheses.py ``isolated_component``): the campaign's
injected hypothesis names the component, not its mode, and the decision a declaration hands
the flight control system -- stop trusting that surface -- is the same, as a surface's own
hypothesis already counts for its partial loss.

Per case (``summarize_case``): counts of the outcomes and of runs with a false alarm;
latency median and 95th percentile (linear interpolation between order statistics,
numpy's default) over the runs that have a latency (``latency_detected_runs`` of them);
``None`` when no run has one; and ``evidence`` (``evidence.case_evidence``: every rate with
its 95 % interval and goal verdict, the detection fractions with misses counted).
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from ...names import NONE, dual_name
from . import evidence

OUTCOMES = ("correct", "missed", "wrong")


def expected_hypothesis(failure_names: Sequence[str]) -> str:
    """The hypothesis that matches a set of injected failures (NONE, single or dual)."""
    names = list(dict.fromkeys(failure_names))  # unique, order kept
    if not names:
        return NONE
    if len(names) == 1:
        return names[0]
    if len(names) == 2:
        return dual_name(names[0], names[1])
    return "+".join(names)  # no bank holds it: such a run can only be missed or wrong


def isolating_declarations(declarations: Sequence[dict]) -> list[dict]:
    """The declarations with each hypothesis replaced by what it isolates (module docstring):
    a partial hypothesis by its surface, every other name kept; the same dicts when none is
    partial."""
    from ...design.hypotheses import isolated_component

    if all(isolated_component(d["hypothesis"]) == d["hypothesis"] for d in declarations):
        return list(declarations)
    return [{**d, "hypothesis": isolated_component(d["hypothesis"])} for d in declarations]


def score_run(injected: str, failure_time_s: float | None, declarations: Sequence[dict]) -> dict:
    """Score one run; see the module docstring for the definitions."""
    decl = sorted(declarations, key=lambda d: d["time_s"])
    final = decl[-1]["hypothesis"] if decl else NONE
    failures_declared = [d for d in decl if d["hypothesis"] != NONE]
    if injected == NONE:
        outcome = "correct" if final == NONE else "wrong"
        false_alarm = bool(failures_declared)
        latency = None
    else:
        if final == injected:
            outcome = "correct"
        elif final == NONE:
            outcome = "missed"
        else:
            outcome = "wrong"
        t_f = float(failure_time_s if failure_time_s is not None else 0.0)
        false_alarm = any(d["time_s"] < t_f for d in failures_declared)
        hits = [d["time_s"] for d in decl if d["hypothesis"] == injected and d["time_s"] >= t_f]
        latency = (hits[0] - t_f) if hits else None
    return {
        "final_hypothesis": final,
        "outcome": outcome,
        "false_alarm": false_alarm,
        "latency_s": latency,
    }


def _stat(values: list[float], q: float) -> float | None:
    if not values:
        return None
    return float(np.percentile(np.asarray(values, dtype=float), q))


def summarize_case(case: str, records: Iterable[dict]) -> dict:
    """Counts and latency statistics of one case from its run records (scored fields)."""
    rs = list(records)
    counts = {o: sum(1 for r in rs if r["outcome"] == o) for o in OUTCOMES}
    latencies = [r["latency_s"] for r in rs if r.get("latency_s") is not None]
    return {
        "case": case,
        "runs": len(rs),
        "correct": counts["correct"],
        "missed": counts["missed"],
        "wrong": counts["wrong"],
        "false_alarms": sum(1 for r in rs if r["false_alarm"]),
        "latency_s": {"median": _stat(latencies, 50), "p95": _stat(latencies, 95)},
        "latency_detected_runs": len(latencies),  # latency_s is over these runs only
        "evidence": evidence.case_evidence(case, rs),
    }


#: The issue's goals at the nominal point with light turbulence.
GOALS = {
    "correct_fraction_min": 0.99,
    "false_alarms_max": 0,
    "latency_median_s_max": 1.0,
    "latency_p95_s_max": 2.0,
}


def check_goals(case_summary: dict) -> dict:
    """Which goals a case meets: ``{"correct": bool, "false_alarms": bool, ...}``."""
    runs = case_summary["runs"]
    frac = case_summary["correct"] / runs if runs else 0.0
    lat = case_summary["latency_s"]
    is_none = case_summary["case"] == NONE
    out = {
        "correct": frac >= GOALS["correct_fraction_min"],
        "false_alarms": case_summary["false_alarms"] <= GOALS["false_alarms_max"],
    }
    if not is_none:
        out["latency_median"] = lat["median"] is not None and lat["median"] <= GOALS["latency_median_s_max"]
        out["latency_p95"] = lat["p95"] is not None and lat["p95"] <= GOALS["latency_p95_s_max"]
    out["all"] = all(out.values())
    return out


def mean_injected_probability(records: Sequence[dict], key: str = "p_injected") -> tuple[np.ndarray, np.ndarray]:
    """(time_s, mean over runs of p of the injected hypothesis) from run records; ``key``: another
    history sampled alike (a dual run's ``p_first``).

    Records hold ``p_injected`` sampled at ``1 / p_injected_dt_s``. Runs whose failures come at
    different times (``--failure-jitter``: each record's ``failure_time_s``, a dual run's
    ``second_time_s``) are aligned on their failures, the earliest's time kept: a run failing k
    samples later drops its first k. Runs of unequal length are then cut to the shortest."""
    if not records:
        return np.zeros(0), np.zeros(0)
    dt = float(records[0]["p_injected_dt_s"])
    onsets = [r["failure_time_s"] if "failure_time_s" in r else r.get("second_time_s") for r in records]
    first = min(onsets) if all(t is not None for t in onsets) else None
    shifts = [0 if first is None else int(round((t - first) / dt)) for t in onsets]
    series = [r[key][k:] for r, k in zip(records, shifts)]
    n = min(len(x) for x in series)
    p = np.array([np.nan_to_num(np.asarray(x[:n], dtype=float)) for x in series])
    return np.arange(n) * dt, p.mean(axis=0)
