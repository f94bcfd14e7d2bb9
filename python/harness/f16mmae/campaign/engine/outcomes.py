"""Run-level rules every campaign kind shares beyond the final outcome.

A run's declarations are the declarer's time-ordered ``{"hypothesis", "time_s"}`` events
(a back-out is a declaration of NONE).  ``onset_s`` is the time of the first injected
failure (None for a no-failure run), ``allowed`` the failure hypotheses a run may declare at
or after the onset (the injected one; for a dual, the first failure alone as well).

* **Transient-wrong** (:func:`transient_wrong`): some declaration at or after the onset
  names a failure hypothesis outside ``allowed``, whether or not the run recovers and ends
  on the right one.  Never for a no-failure run (any declaration there is a false alarm).
* **False declarations** (:func:`false_declarations`): the failure declarations (not NONE)
  made during the run's failure-free flying time.
* **Failure-free flying time** (:func:`failure_free_time_s`): the time before the onset, or
  the whole flight of a no-failure run.  Summed over a campaign it is the exposure of the
  false declarations per flight hour (``intervals.poisson_rate``).
* **Censored latency fractions** (:func:`detected_within`): over the failure runs of a case,
  the fraction whose latency is at most ``x`` for each ``x`` in :data:`LATENCY_WINDOWS_S`,
  and the fraction detected at all within the flight.  A run with no latency (never
  declared the injected hypothesis) counts in the denominator as never detected, so misses
  lower every fraction.  The median and p95 over detected runs stay beside it, labelled.
* **Absolute dual rating** (:func:`rate_absolute`): *Good* when the pair has at least 90 %
  of its runs correct, no run with a false alarm, no transient-wrong run, and a median
  latency (over detected runs, after the second failure) of at most 1.5 s; otherwise
  *Not good*, with every criterion it misses named.
"""
from __future__ import annotations

from collections.abc import Collection, Iterable, Sequence

from ...names import NONE

#: Latency windows (s) of the censored detection fractions.
LATENCY_WINDOWS_S: tuple[float, ...] = (0.5, 1.0, 2.0)

#: The absolute dual criteria (see the module docstring).
ABSOLUTE_DUAL_RULES = {"correct_fraction_min": 0.90, "false_alarm_runs_max": 0,
                       "transient_wrong_runs_max": 0, "latency_median_s_max": 1.5}
ABSOLUTE_RATINGS: tuple[str, ...] = ("Good", "Not good")


def transient_wrong(declarations: Sequence[dict], onset_s: float | None, allowed: Collection[str]) -> bool:
    """True when a failure outside ``allowed`` is declared at or after ``onset_s``."""
    if onset_s is None:
        return False
    return any(d["time_s"] >= onset_s and d["hypothesis"] not in allowed and d["hypothesis"] != NONE
               for d in declarations)


def failure_free_time_s(onset_s: float | None, duration_s: float) -> float:
    """Flying time before the first failure (the whole flight when there is none)."""
    if duration_s <= 0:
        raise ValueError(f"a flight lasts > 0 s, got {duration_s!r}")
    return float(duration_s if onset_s is None else min(max(onset_s, 0.0), duration_s))


def false_declarations(declarations: Sequence[dict], onset_s: float | None) -> int:
    """Failure declarations made before the onset (all of them in a no-failure run)."""
    return sum(1 for d in declarations
               if d["hypothesis"] != NONE and (onset_s is None or d["time_s"] < onset_s))


def detected_within(latencies: Sequence[float | None], windows_s: Sequence[float] = LATENCY_WINDOWS_S) -> dict:
    """Censored detection fractions of failure runs: ``{"runs", "within_s": {"0.5": f, ...},
    "in_flight": f}`` with ``None`` latencies counted as never detected."""
    n = len(latencies)
    if n == 0:
        return {"runs": 0, "within_s": {f"{w:g}": None for w in windows_s}, "in_flight": None}
    hits = [x for x in latencies if x is not None]
    return {"runs": n,
            "within_s": {f"{w:g}": round(sum(1 for x in hits if x <= w) / n, 6) for w in windows_s},
            "in_flight": round(len(hits) / n, 6)}


def rate_absolute(runs: int, correct: int, false_alarm_runs: int, transient_wrong_runs: int,
                  latency_median_s: float | None) -> tuple[str, str]:
    """(rating, reason) of a dual pair on the absolute criteria (module docstring)."""
    if runs < 1:
        raise ValueError("an absolute rating needs at least one run")
    R = ABSOLUTE_DUAL_RULES
    c = correct / runs
    misses = []
    if c < R["correct_fraction_min"]:
        misses.append(f"correct {c:.0%} < {R['correct_fraction_min']:.0%}")
    if false_alarm_runs > R["false_alarm_runs_max"]:
        misses.append(f"{false_alarm_runs} run(s) with a false alarm")
    if transient_wrong_runs > R["transient_wrong_runs_max"]:
        misses.append(f"{transient_wrong_runs} transient-wrong run(s)")
    if latency_median_s is None:
        misses.append("never detected")
    elif latency_median_s > R["latency_median_s_max"]:
        misses.append(f"median latency {latency_median_s:.2f} s > {R['latency_median_s_max']:g} s")
    if misses:
        return "Not good", "; ".join(misses)
    return "Good", (f"correct {c:.0%}, no false alarm, no transient-wrong, "
                    f"median latency {latency_median_s:.2f} s")


def count(records: Iterable[dict], field: str) -> int:
    """Runs whose boolean ``field`` is true (a record without it counts as false)."""
    return sum(1 for r in records if r.get(field))


def run_fields(declarations: Sequence[dict], onset_s: float | None, allowed: Collection[str],
               duration_s: float) -> dict:
    """The fields these rules add to a run record: ``transient_wrong``,
    ``false_declarations`` and ``failure_free_s``."""
    return {"transient_wrong": transient_wrong(declarations, onset_s, allowed),
            "false_declarations": false_declarations(declarations, onset_s),
            "failure_free_s": failure_free_time_s(onset_s, duration_s)}
