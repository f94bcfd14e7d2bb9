"""Confidence intervals of campaign rates, goal verdicts, and the runs a goal needs.

Rates of runs (k of n runs correct, missed, wrong, transient-wrong, with a false alarm):

* Clopper-Pearson (exact) interval, the one verdicts use: the ``(1 - a)`` interval
  ``[B(a/2; k, n-k+1), B(1-a/2; k+1, n-k)]`` with ``B`` the beta quantile; lower bound 0
  when ``k = 0``, upper bound 1 when ``k = n``; ``B`` is ``scipy.special.betaincinv``.
  E.g. 30/30 at 95 %: lower bound ``0.025^(1/30) = 0.8843``.
* Wilson score interval, reported beside it: centre ``(p + z^2/2n) / (1 + z^2/n)``,
  half-width ``z sqrt(p(1-p)/n + z^2/4n^2) / (1 + z^2/n)``, ``z`` the normal quantile
  (``scipy.special.ndtri``).  E.g. 30/30: lower bound ``30 / (30 + 1.96^2) = 0.8865``.

A goal on a rate is one of :data:`VERDICTS` (with the Clopper-Pearson interval ``[lo, hi]``
and the point estimate ``p = k/n``):

* ``at_least`` ``g`` (e.g. correct >= 0.99): *demonstrated* when ``lo >= g``, *consistent*
  when ``p >= g > lo``, *not met* when ``p < g``;
* ``at_most`` ``g`` (e.g. runs with a false alarm <= 0): *demonstrated* when ``hi <= g``,
  *consistent* when ``p <= g < hi``, *not met* when ``p > g``.  A goal of 0 can never be
  demonstrated by a finite number of runs (``hi > 0`` always): at best it is consistent.

Runs needed (:func:`runs_to_demonstrate`): the smallest ``n`` for which ``n - f`` successes of
``n`` give a Clopper-Pearson lower bound ``>= g``.  For ``f = 0`` the bound is
``(a/2)^(1/n)``, so ``n = ceil(ln(a/2) / ln(g))``: 368 runs for ``g = 0.99`` at 95 %.

Counts over an exposure (false declarations in failure-free flight hours): the exact
(Garwood) Poisson interval for ``k`` events, ``[chi2(a/2; 2k) / 2, chi2(1-a/2; 2k+2) / 2]``
(lower 0 when ``k = 0``; ``scipy.special.chdtri``) divided by the exposure.  E.g. 0 events: upper ``-ln(a/2) = 3.689``
events.

Every function raises ``ValueError`` naming the bad count, rate or level.  The quantiles come
from ``scipy.special`` in closed form, not from ``scipy.stats`` (whose binomial test finds
the same bounds by root search, about a thousand times slower: a campaign summary computes
thousands of them), and each interval is computed once per process (memoized).
tests/python/test_campaign_intervals.py checks them against ``scipy.stats``.
"""
from __future__ import annotations

import functools
import math

#: The confidence level of every interval in the campaigns' summaries and reports.
CONFIDENCE = 0.95
VERDICTS: tuple[str, ...] = ("demonstrated", "consistent", "not met")
DIRECTIONS: tuple[str, ...] = ("at_least", "at_most")


def _check_counts(k: int, n: int) -> None:
    if not (isinstance(k, int) and isinstance(n, int)) or n < 1 or not 0 <= k <= n:
        raise ValueError(f"a rate needs whole counts 0 <= k <= n, n >= 1; got k={k!r}, n={n!r}")


def _check_level(level: float) -> None:
    if not 0.0 < level < 1.0:
        raise ValueError(f"confidence level {level!r} must lie in (0, 1)")


def clopper_pearson(k: int, n: int, level: float = CONFIDENCE) -> tuple[float, float]:
    """Exact two-sided interval of a binomial proportion ``k / n`` (see module docstring)."""
    _check_counts(k, n)
    _check_level(level)
    return _clopper_pearson(k, n, level)


@functools.lru_cache(maxsize=65536)
def _clopper_pearson(k: int, n: int, level: float) -> tuple[float, float]:
    from scipy.special import betaincinv
    a = 1.0 - level
    lo = 0.0 if k == 0 else float(betaincinv(k, n - k + 1, a / 2))
    hi = 1.0 if k == n else float(betaincinv(k + 1, n - k, 1 - a / 2))
    return lo, hi


def wilson(k: int, n: int, level: float = CONFIDENCE) -> tuple[float, float]:
    """Wilson score interval of ``k / n`` (see module docstring)."""
    _check_counts(k, n)
    _check_level(level)
    return _wilson(k, n, level)


@functools.lru_cache(maxsize=65536)
def _wilson(k: int, n: int, level: float) -> tuple[float, float]:
    from scipy.special import ndtri
    z = float(ndtri(0.5 + 0.5 * level))
    p = k / n
    denom = 2 * (n + z * z)
    center = (2 * n * p + z * z) / denom
    half = z / denom * math.sqrt(4 * n * p * (1 - p) + z * z)
    return (0.0 if k == 0 else center - half), (1.0 if k == n else center + half)


def verdict(k: int, n: int, goal: float, direction: str = "at_least", level: float = CONFIDENCE) -> str:
    """The verdict of a goal on the rate ``k / n`` (see module docstring)."""
    if direction not in DIRECTIONS:
        raise ValueError(f"unknown goal direction {direction!r}; valid: {', '.join(DIRECTIONS)}")
    if not 0.0 <= goal <= 1.0:
        raise ValueError(f"a goal on a rate must lie in [0, 1], got {goal!r}")
    lo, hi = clopper_pearson(k, n, level)
    p = k / n
    if direction == "at_least":
        return "demonstrated" if lo >= goal else ("consistent" if p >= goal else "not met")
    return "demonstrated" if hi <= goal else ("consistent" if p <= goal else "not met")


def rate(k: int, n: int, level: float = CONFIDENCE, goal: float | None = None,
         direction: str = "at_least") -> dict:
    """A rate as stored in ``summary.json``: ``{"count", "runs", "fraction", "ci95":
    {"clopper_pearson": [lo, hi], "wilson": [lo, hi]}}`` and, with a goal, ``"goal"``,
    ``"direction"`` and ``"verdict"``.  Bounds rounded to 6 places."""
    cp = clopper_pearson(k, n, level)
    wi = wilson(k, n, level)
    out = {"count": k, "runs": n, "fraction": round(k / n, 6),
           "ci95": {"clopper_pearson": [round(cp[0], 6), round(cp[1], 6)],
                    "wilson": [round(wi[0], 6), round(wi[1], 6)]}}
    if goal is not None:
        out.update(goal=goal, direction=direction, verdict=verdict(k, n, goal, direction, level))
    return out


def runs_to_demonstrate(goal: float, failures: int = 0, level: float = CONFIDENCE,
                        limit: int = 1_000_000) -> int:
    """Smallest ``n`` whose ``n - failures`` successes demonstrate the ``at_least`` goal."""
    if not 0.0 < goal < 1.0:
        raise ValueError(f"a demonstrable goal lies in (0, 1), got {goal!r}")
    if not isinstance(failures, int) or failures < 0:
        raise ValueError(f"failures must be a whole number >= 0, got {failures!r}")
    _check_level(level)

    def enough(n: int) -> bool:
        return clopper_pearson(n - failures, n, level)[0] >= goal

    # the lower bound grows with n for a fixed number of failures: double, then bisect
    lo, hi = failures, max(failures + 1, 2)
    while not enough(hi):
        lo, hi = hi, hi * 2
        if hi > limit:
            raise ValueError(f"{failures} failure(s) cannot demonstrate {goal} within {limit} runs")
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if enough(mid) else (mid, hi)
    return hi


def poisson_rate(events: int, exposure: float, level: float = CONFIDENCE) -> dict:
    """Events per unit exposure with the exact Poisson interval (see module docstring):
    ``{"events", "exposure", "rate", "ci95": [lo, hi]}``; rate and bounds are ``None`` when
    the exposure is 0."""
    if not isinstance(events, int) or events < 0:
        raise ValueError(f"events must be a whole number >= 0, got {events!r}")
    if not exposure >= 0.0 or math.isinf(exposure):
        raise ValueError(f"exposure must be finite and >= 0, got {exposure!r}")
    _check_level(level)
    from scipy.special import chdtri  # chdtri(df, y): the chi-square quantile at 1 - y
    a = 1.0 - level
    lo = 0.0 if events == 0 else float(chdtri(2 * events, 1 - a / 2)) / 2
    hi = float(chdtri(2 * events + 2, a / 2)) / 2
    if exposure == 0.0:
        return {"events": events, "exposure": 0.0, "rate": None, "ci95": None}
    return {"events": events, "exposure": round(exposure, 9), "rate": round(events / exposure, 6),
            "ci95": [round(lo / exposure, 6), round(hi / exposure, 6)]}



def poisson_verdict(events: int, exposure: float, goal: float, level: float = CONFIDENCE) -> str:
    """The verdict of the goal "at most ``goal`` events per unit exposure": *demonstrated*
    when the upper bound of the Poisson interval is ``<= goal``, *consistent* when the rate
    is ``<= goal`` < the upper bound, *not met* when the rate exceeds ``goal``.  A goal of 0
    is at best consistent, as for rates.  ValueError for an exposure of 0 or a negative goal."""
    if not goal >= 0.0:
        raise ValueError(f"a goal on events per exposure must be >= 0, got {goal!r}")
    r = poisson_rate(events, exposure, level)
    if r["rate"] is None:
        raise ValueError("a verdict needs an exposure > 0")
    return "demonstrated" if r["ci95"][1] <= goal else ("consistent" if r["rate"] <= goal else "not met")
