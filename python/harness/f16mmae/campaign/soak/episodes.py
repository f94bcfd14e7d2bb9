"""False declarations of failure-free flights: each one, how long it lasted, and the rates.

A soak flight has no failure, so every failure declaration (a declaration event whose
hypothesis is not NONE, ``outcomes.false_declarations`` with no onset) is false.  Declaration
``i`` made at ``t_i`` lasts until the next declaration event of the flight, at ``t_{i+1}``
(a back-out to NONE, or another hypothesis replacing it), or until the flight's end ``T``::

    duration_i = (t_{i+1} if i is not the last event else T) - t_i
    end_i      = "backed out"   when event i+1 declares NONE
                 "replaced"     when event i+1 declares another failure (``replaced_by``)
                 "flight end"   when there is no event i+1 (the duration is censored at T)

Per level (:func:`level_rate`): false declarations summed over the flights, per flight hour
summed likewise (``evidence.false_declaration_rate``: exact Poisson 95 % interval), the
hypotheses involved (declarations per hypothesis) and the flights with at least one.

A flight counts while its aircraft flies the soak's flight condition (:func:`left_condition_s`):
in level flight (no maneuvers) within :data:`CONDITION_MACH` and :data:`CONDITION_ALT_FT` of the
Mach and altitude it was trimmed at, its ideal air data finite (with maneuvers: finite only).
From the first second of the truth's track outside them the flight is no longer failure-free
flight at the condition but an aircraft gone elsewhere: a pilotless F-16 at the trimmable edge
in moderate air could roll off into a spiral dive (Mach 0.39 to 0.73 in 75 s, then into the
ground; docs/results/envelope_scheduled.md, round 40), and what is declared there is declared of
an upset.
Its hours and declarations from then on are not counted but reported apart
(``declarations_after_leaving``, :func:`level_rate`'s ``flights_left_condition``). The bounds sit
far outside a pilotless aircraft's wander at the condition (10-h soaks, moderate air: at most
0.06 Mach and 1,100 ft at Mach 0.4, 20,000 ft).
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from ...names import NONE
from ..engine import evidence, intervals

BACKED_OUT, REPLACED, FLIGHT_END = "backed out", "replaced", "flight end"
#: A level-flight soak's flight condition: Mach and altitude (ft) within these of the trim's.
CONDITION_MACH = 0.1
CONDITION_ALT_FT = 2000.0


def left_condition_s(track: np.ndarray, mach: float, alt_ft: float, level_flight: bool) -> float | None:
    """The first time (s) of ``track`` (rows: time s, Mach, pressure altitude ft, as
    ``TruthModel.track``) at which the aircraft is off the flight condition (``mach``,
    ``alt_ft``): non-finite, or in ``level_flight`` more than CONDITION_MACH or CONDITION_ALT_FT
    from it (module docstring); None when it never is."""
    t = np.asarray(track, dtype=float).reshape(-1, 3)
    off = ~np.all(np.isfinite(t[:, 1:]), axis=1)
    if level_flight:
        with np.errstate(invalid="ignore"):
            off |= (np.abs(t[:, 1] - mach) > CONDITION_MACH) | (np.abs(t[:, 2] - alt_ft) > CONDITION_ALT_FT)
    i = np.flatnonzero(off)
    return float(t[i[0], 0]) if i.size else None


def false_episodes(declarations: Sequence[dict], duration_s: float) -> list[dict]:
    """Every failure declaration of a failure-free flight of ``duration_s`` (module docstring):
    ``{"hypothesis", "time_s", "duration_s", "end", "replaced_by"}``.  ValueError when the
    events are not time-ordered inside the flight."""
    if not duration_s > 0:
        raise ValueError(f"a flight lasts > 0 s, got {duration_s!r}")
    times = [float(d["time_s"]) for d in declarations]
    if any(b < a for a, b in zip(times, times[1:])) or any(not 0 <= t <= duration_s for t in times):
        raise ValueError(f"declaration times must be ordered inside [0, {duration_s}] s, got {times}")
    out = []
    for i, d in enumerate(declarations):
        if d["hypothesis"] == NONE:
            continue
        nxt = declarations[i + 1] if i + 1 < len(declarations) else None
        if nxt is None:
            end, until, by = FLIGHT_END, float(duration_s), None
        elif nxt["hypothesis"] == NONE:
            end, until, by = BACKED_OUT, float(nxt["time_s"]), None
        else:
            end, until, by = REPLACED, float(nxt["time_s"]), nxt["hypothesis"]
        out.append({"hypothesis": d["hypothesis"], "time_s": float(d["time_s"]),
                    "duration_s": round(until - float(d["time_s"]), 6), "end": end, "replaced_by": by})
    return out


def level_rate(records: Iterable[dict], goal_per_h: float) -> dict:
    """The false declarations of one level's flight records (fields ``episodes``,
    ``false_declarations``, ``failure_free_s``, ``left_condition_s``, ``declarations_after_leaving``;
    all counted up to the flight's leaving its condition): ``per_hour`` (Poisson rate with its interval,
    the goal and its verdict), ``flights``, ``hours``, ``flights_with_false_declaration``,
    ``hypotheses`` (declarations per hypothesis, most first), ``episodes_by_end``,
    ``first_declaration_s`` (median and least time in its flight of each flight's first false
    declaration), ``duration_s`` (median and longest), ``flights_left_condition`` and
    ``declarations_after_leaving`` (failure declarations after it, not counted)."""
    rs = list(records)
    per_hour = evidence.false_declaration_rate(rs)
    if per_hour["rate"] is not None:
        per_hour.update(goal=goal_per_h, direction="at_most",
                        verdict=intervals.poisson_verdict(per_hour["events"], per_hour["exposure"], goal_per_h))
    episodes = [e for r in rs for e in r["episodes"]]
    hyps: dict[str, int] = {}
    ends = {BACKED_OUT: 0, REPLACED: 0, FLIGHT_END: 0}
    for e in episodes:
        hyps[e["hypothesis"]] = hyps.get(e["hypothesis"], 0) + 1
        ends[e["end"]] += 1
    durations = sorted(e["duration_s"] for e in episodes)
    return {
        "flights": len(rs),
        "hours": round(sum(float(r["failure_free_s"]) for r in rs) / 3600.0, 9),
        "per_hour": per_hour,
        "flights_with_false_declaration": sum(1 for r in rs if r["false_declarations"] > 0),
        "hypotheses": dict(sorted(hyps.items(), key=lambda kv: (-kv[1], kv[0]))),
        "episodes_by_end": ends,
        "first_declaration_s": _first_times(rs),
        "duration_s": {"median": round(float(np.median(durations)), 6) if durations else None,
                       "max": durations[-1] if durations else None},
        "flights_left_condition": sum(1 for r in rs if r.get("left_condition_s") is not None),
        "declarations_after_leaving": sum(1 for r in rs for d in r.get("declarations_after_leaving", [])
                                          if d["hypothesis"] != NONE),
    }



def _first_times(records: list[dict]) -> dict:
    """When in its flight the first false declaration came, over the flights with one."""
    firsts = sorted(r["episodes"][0]["time_s"] for r in records if r["episodes"])
    if not firsts:
        return {"median": None, "min": None}
    return {"median": round(float(np.median(firsts)), 6), "min": firsts[0]}
