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
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from ...names import NONE
from ..engine import evidence, intervals

BACKED_OUT, REPLACED, FLIGHT_END = "backed out", "replaced", "flight end"


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
    ``false_declarations``, ``failure_free_s``): ``per_hour`` (Poisson rate with its interval,
    the goal and its verdict), ``flights``, ``hours``, ``flights_with_false_declaration``,
    ``hypotheses`` (declarations per hypothesis, most first), ``episodes_by_end``,
    ``first_declaration_s`` (median and least time in its flight of each flight's first false
    declaration) and ``duration_s`` (median and longest)."""
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
    }



def _first_times(records: list[dict]) -> dict:
    """When in its flight the first false declaration came, over the flights with one."""
    firsts = sorted(r["episodes"][0]["time_s"] for r in records if r["episodes"])
    if not firsts:
        return {"median": None, "min": None}
    return {"median": round(float(np.median(firsts)), 6), "min": firsts[0]}
