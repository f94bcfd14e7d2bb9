"""Scoring and rating of dual-failure runs (paper Sec. VI, Fig. 7).

A dual run injects failure ``a`` at ``t_1`` and failure ``b`` at ``t_2 > t_1``; the
injected hypothesis is ``h* = dual_name(a, b)``.  The declarer's events are the
time-ordered ``{"hypothesis", "time_s"}`` list; the *declared* hypothesis at time ``t``
is that of the last event at or before ``t`` (NONE before the first).

**The rule for failed components.** A failure declaration is *wrong* when it names a
component that has not failed in truth by the declaration's time; a declaration naming only
components that have failed (one of them or both, in any order) is true, if incomplete
(:func:`names_only_failed`).  So:

* ``transient_wrong`` -- from ``t_1`` on, a declaration naming a component not failed by its
  time (:func:`transient_wrong`);  ``transient_wrong_strict`` keeps the former rule beside it
  (``outcomes.transient_wrong`` with the first failure and the dual allowed: the lone second
  failure declared after ``t_2`` counts there);
* a run that ends declaring only failed components but not both (the first failure alone or
  the second alone) counts as ``missed`` (a failure was missed), not wrong.

Per run (:func:`score_dual_run`), on top of ``scoring.score_run(h*, t_2, events)``
(``final_hypothesis``, ``outcome`` correct / missed / wrong, ``latency_s`` = first
declaration of ``h*`` at or after ``t_2`` minus ``t_2``), with the outcome by the rule above:

* ``false_alarm``      -- before ``t_2`` a hypothesis other than NONE and ``a`` was
  declared (the first failure's own declaration is expected, not an alarm);
* ``first_latency_s``  -- first declaration of ``a`` in ``[t_1, t_2)`` minus ``t_1``
  (None: the first failure was not declared before the second occurred);
  in both, a partial hypothesis of ``a`` (``"LF:loss=0.5"``) is ``a``'s declaration, as the
  single scoring takes it (``scoring.isolating_declarations``);
* ``hold``             -- with ``t_d = t_2 + latency_s``: the fraction of ``[t_d, T)``
  (``T`` the flight's end) during which ``h*`` stays declared (None without a latency);
* ``p_max_after``      -- the largest probability of ``h*`` at or after ``t_2`` (0 while
  it is off line).

The baseline runs (the lone single failure ``b`` at ``t_2``) get the same fields with
``h* = b`` and ``scoring.score_run``'s false alarm (any failure declared before ``t_2``).

Per pair (:func:`summarize_pair`): ``scoring.summarize_case`` (counts, latency median /
p95) plus ``hold_mean`` (mean over the runs with a latency, None if none), ``p_max`` (max
over runs), ``first_declared`` (runs whose first failure was declared before ``t_2``),
``transient_wrong_strict`` (runs transient-wrong by the former rule).

Rating of a pair against the baseline of its second failure (:func:`rate_pair`), with
``c`` / ``c_b`` the correct fractions, ``m`` / ``m_b`` the latency medians and ``h`` /
``h_b`` the mean holds of the pair / the baseline, thresholds in :data:`RATING_RULES`:

* **Good** -- ``c >= c_b - 0.10`` and ``m <= m_ref + 0.5 s`` (``m_ref = m_b``, or 2.0 s
  when the baseline never detects) and ``h >= h_b - 0.10`` (``h_b`` = 1 without one):
  as good as the lone single failure, lock and hold;
* **Fair** -- not Good, ``c > 0`` and (``c >= 0.5`` or ``c >= c_b - 0.10``): somewhat
  degraded -- later, fewer, or with dropouts from lock;
* **Poor** -- neither, but some run declared ``h*`` after ``t_2`` or its probability
  reached 0.5: spikes, no lock;
* **ND**   -- the dual was never declared and its probability never reached 0.5 (the
  second failure missed, or falsely declared as another hypothesis).

A pair not rated Good whose dual the models show indistinguishable from a rival
(``campaign.dual.models``: expected evidence per frame D <= 0) is rated
**Indistinguishable** instead, its measured rating kept beside it.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from ...names import COMPONENTS, NONE, failed_components
from ..engine import scoring

#: The rating of a pair whose dual the models cannot separate from a rival of the first
#: failure's level-1 bank (expected evidence per frame D <= 0; ``campaign.dual.models``), in
#: place of its measured Fair / Poor / ND.
INDISTINGUISHABLE = "Indistinguishable"
RATINGS: tuple[str, ...] = ("Good", "Fair", "Poor", "ND", INDISTINGUISHABLE)

#: The thresholds of the rating, all in one place (see the module docstring).
RATING_RULES = {
    "good_correct_margin": 0.10,      # Good: c >= c_b - margin
    "good_latency_margin_s": 0.5,     # Good: m <= m_ref + margin
    "reference_latency_s": 2.0,       # m_ref when the baseline never detects (single goal's p95)
    "good_hold_margin": 0.10,         # Good: h >= h_b - margin
    "fair_correct_min": 0.5,          # Fair: c >= this (or c >= c_b - margin), c > 0
    "poor_probability": 0.5,          # Poor: p of h* after t_2 reached this in some run
}


def declared_at(declarations: Sequence[dict], t: float) -> str:
    """The hypothesis declared at time ``t``: the last event at or before ``t`` (else NONE)."""
    current = NONE
    for d in sorted(declarations, key=lambda d: d["time_s"]):
        if d["time_s"] > t:
            break
        current = d["hypothesis"]
    return current


def hold_fraction(declarations: Sequence[dict], hypothesis: str, start_s: float, end_s: float) -> float:
    """Fraction of ``[start_s, end_s)`` during which ``hypothesis`` is the declared one."""
    if end_s <= start_s:
        raise ValueError(f"hold window [{start_s}, {end_s}) s is empty")
    events = sorted(declarations, key=lambda d: d["time_s"])
    state = declared_at(events, start_s)
    t = start_s
    held = 0.0
    for d in events:
        if d["time_s"] <= start_s:
            continue
        if d["time_s"] >= end_s:
            break
        if state == hypothesis:
            held += d["time_s"] - t
        state, t = d["hypothesis"], d["time_s"]
    if state == hypothesis:
        held += end_s - t
    return held / (end_s - start_s)


def names_only_failed(hypothesis: str, failures: Sequence[tuple[str, float]], t: float) -> bool:
    """True when every component ``hypothesis`` names has failed in truth by time ``t``
    (``failures``: ``(component, time_s)``); NONE names none, so it is True."""
    failed = {c for c, t_c in failures if t_c <= t}
    return set(failed_components(hypothesis)) <= failed


def transient_wrong(declarations: Sequence[dict], failures: Sequence[tuple[str, float]]) -> bool:
    """From the first failure on, a failure declaration naming a component that had not
    failed by its time (module docstring). False without failures."""
    if not failures:
        return False
    onset = min(t for _, t in failures)
    return any(d["time_s"] >= onset and not names_only_failed(d["hypothesis"], failures, d["time_s"])
               for d in declarations)


def false_alarm_before_second(declarations: Sequence[dict], first: str, second_time_s: float) -> bool:
    """A dual run's false alarm (module docstring): before ``second_time_s`` a declaration
    other than NONE and ``first``, a partial hypothesis of ``first`` counting as ``first``."""
    return any(d["time_s"] < second_time_s and d["hypothesis"] not in (NONE, first)
               for d in scoring.isolating_declarations(declarations))


def score_dual_run(injected: str, first: str | None, first_time_s: float | None,
                   second_time_s: float, end_s: float, declarations: Sequence[dict],
                   time_s: np.ndarray, p_injected: np.ndarray) -> dict:
    """Score one dual run (``first`` given) or baseline run (``first`` None); see module docstring."""
    out = scoring.score_run(injected, second_time_s, declarations)
    failures = [(c, second_time_s) for c in sorted(set(failed_components(injected)) - {first})]
    if first is not None:
        failures.insert(0, (first, first_time_s))
        final = out["final_hypothesis"]
        if final not in (injected, NONE) and names_only_failed(final, failures, end_s):
            out["outcome"] = "missed"
        out["false_alarm"] = false_alarm_before_second(declarations, first, second_time_s)
        firsts = [d["time_s"] for d in scoring.isolating_declarations(declarations)
                  if d["hypothesis"] == first and first_time_s <= d["time_s"] < second_time_s]
        out["first_latency_s"] = (firsts[0] - first_time_s) if firsts else None
    out["transient_wrong"] = transient_wrong(declarations, failures)
    lat = out["latency_s"]
    out["hold"] = None if lat is None else round(hold_fraction(declarations, injected, second_time_s + lat, end_s), 6)
    after = np.asarray(p_injected, dtype=float)[np.asarray(time_s) >= second_time_s]
    out["p_max_after"] = round(float(np.nan_to_num(after).max()), 6) if after.size else 0.0
    return out


def summarize_pair(label: str, records: Iterable[dict]) -> dict:
    """Counts, latency statistics, hold and peak probability of one pair (or baseline)."""
    rs = list(records)
    out = scoring.summarize_case(label, rs)
    holds = [r["hold"] for r in rs if r.get("hold") is not None]
    out["hold_mean"] = round(float(np.mean(holds)), 6) if holds else None
    out["p_max"] = max((r["p_max_after"] for r in rs), default=0.0)
    out["declared_runs"] = sum(1 for r in rs if r.get("latency_s") is not None)
    out["transient_wrong_strict"] = sum(1 for r in rs if r.get("transient_wrong_strict"))
    if any("first_latency_s" in r for r in rs):
        out["first_declared"] = sum(1 for r in rs if r.get("first_latency_s") is not None)
    return out


def rate_pair(pair: dict, baseline: dict) -> tuple[str, str]:
    """(rating, reason) of a pair summary against its second failure's baseline summary."""
    R = RATING_RULES
    if not pair["runs"] or not baseline["runs"]:
        raise ValueError("rating needs at least one run of the pair and of its baseline")
    c = pair["correct"] / pair["runs"]
    c_b = baseline["correct"] / baseline["runs"]
    m = pair["latency_s"]["median"]
    m_b = baseline["latency_s"]["median"]
    m_ref = m_b if m_b is not None else R["reference_latency_s"]
    h = pair.get("hold_mean")
    h_b = baseline.get("hold_mean")
    h_ref = 1.0 if h_b is None else h_b
    correct_ok = c >= c_b - R["good_correct_margin"] - 1e-12
    why = f"correct {c:.0%} vs baseline {c_b:.0%}"
    if m is not None and h is not None and correct_ok and m <= m_ref + R["good_latency_margin_s"] \
            and h >= h_ref - R["good_hold_margin"]:
        return "Good", f"{why}; latency {m:.2f} s vs {m_ref:.2f} s; hold {h:.0%} vs {h_ref:.0%}"
    if c > 0 and (c >= R["fair_correct_min"] or correct_ok):
        if not correct_ok:
            return "Fair", why
        lat = "no latency" if m is None else f"latency {m:.2f} s vs {m_ref:.2f} s"
        hold = "" if h is None else f", hold {h:.0%} vs {h_ref:.0%}"
        return "Fair", f"{why}; {lat}{hold}"
    if c > 0 or pair.get("declared_runs", 0) > 0 or pair.get("p_max", 0.0) >= R["poor_probability"]:
        return "Poor", f"{why}; declared in {pair.get('declared_runs', 0)} run(s), peak p {pair.get('p_max', 0.0):.2f}"
    return "ND", f"{why}; never declared, peak p {pair.get('p_max', 0.0):.2f}"


# -- the paper's Fig. 7, for comparison ---------------------------------------------------------
_G, _F, _P, _N, _U = "Good", "Fair", "Poor", "ND", None
#: The paper's Fig. 7 (rows: first failure, columns: second, in ``names.COMPONENTS``; "" on the
#: diagonal).  The text of the RUD row lost one cell in extraction: six ratings -- four Good,
#: ND, Good -- for the seven sensor columns.  The paper's discussion places the ND at RUD>YAW
#: ("when the rudder actuator fails, there is not enough yaw axis excitation to discover a yaw
#: sensor failure at all"), so YAW is ND and AY Good; VEL..ROL hold four Goods in five cells
#: and stay unknown (None).
PAPER_FIG7: dict[str, dict[str, str | None]] = {
    a: dict(zip(COMPONENTS, row)) for a, row in zip(COMPONENTS, (
        ("", _G, _N, _P, _G, _G, _G, _P, _G, _F, _F, _F),
        (_G, "", _P, _N, _G, _G, _G, _P, _G, _F, _F, _F),
        (_G, _G, "", _G, _G, _G, _G, _G, _G, _G, _G, _G),
        (_G, _G, _G, "", _F, _G, _F, _G, _G, _G, _G, _G),
        (_G, _G, _G, _G, "", _U, _U, _U, _U, _U, _N, _G),
        (_G, _G, _G, _G, _G, "", _G, _G, _F, _G, _G, _G),
        (_G, _G, _G, _G, _G, _G, "", _G, _F, _G, _G, _G),
        (_G, _G, _F, _F, _F, _G, _G, "", _G, _G, _G, _G),
        (_G, _G, _P, _F, _G, _G, _G, _G, "", _G, _G, _G),
        (_G, _G, _G, _G, _G, _G, _G, _G, _G, "", _G, _G),
        (_G, _G, _F, _G, _P, _G, _G, _G, _G, _G, "", _G),
        (_G, _G, _F, _F, _G, _G, _G, _G, _G, _G, _G, ""),
    ))
}


def compare_with_paper(matrix: dict[str, dict[str, str]]) -> dict:
    """Agreement of a rating matrix (first -> second -> rating) with :data:`PAPER_FIG7`:
    cells compared (paper rating known), equal, and Good-vs-not-Good agreement."""
    same = good_same = n = 0
    for a, row in matrix.items():
        for b, ours in row.items():
            theirs = PAPER_FIG7.get(a, {}).get(b)
            if not theirs or ours not in RATINGS[:4]:   # the paper's four (not Indistinguishable)
                continue
            n += 1
            same += ours == theirs
            good_same += (ours == "Good") == (theirs == "Good")
    return {"cells": n, "equal": same, "good_vs_not_good_equal": good_same}
