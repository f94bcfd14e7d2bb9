"""Interval arithmetic against hand-worked values and the binomial / Poisson tails summed by hand."""
from __future__ import annotations

import math

import pytest

from f16mmae.campaign.engine import intervals as iv

Z95 = 1.959963984540054  # the normal 97.5 % quantile


def upper_tail(k, n, p):
    """P(X >= k), X ~ Binomial(n, p), summed term by term."""
    return sum(math.comb(n, j) * p**j * (1 - p) ** (n - j) for j in range(k, n + 1))


def lower_tail(k, n, p):
    return sum(math.comb(n, j) * p**j * (1 - p) ** (n - j) for j in range(0, k + 1))


def test_clopper_pearson_hand_values():
    # k = n: lower bound (a/2)^(1/n); k = 0: upper bound 1 - (a/2)^(1/n)
    assert iv.clopper_pearson(30, 30) == pytest.approx((0.025 ** (1 / 30), 1.0), abs=1e-9)
    assert iv.clopper_pearson(30, 30)[0] == pytest.approx(0.884297, abs=1e-6)
    assert iv.clopper_pearson(0, 10) == pytest.approx((0.0, 0.308497), abs=1e-6)
    lo, hi = iv.clopper_pearson(8, 10)
    assert (lo, hi) == pytest.approx((0.4439, 0.9748), abs=1e-4)  # the textbook 8/10 interval
    # the defining tails: P(X >= 8 | lo) = P(X <= 8 | hi) = 0.025
    assert upper_tail(8, 10, lo) == pytest.approx(0.025, abs=1e-9)
    assert lower_tail(8, 10, hi) == pytest.approx(0.025, abs=1e-9)


def test_wilson_hand_values():
    # 30/30: lower bound n / (n + z^2)
    assert iv.wilson(30, 30)[0] == pytest.approx(30 / (30 + Z95**2), abs=1e-9)
    k, n = 8, 10
    p = k / n
    centre = (p + Z95**2 / (2 * n)) / (1 + Z95**2 / n)
    half = Z95 * math.sqrt(p * (1 - p) / n + Z95**2 / (4 * n * n)) / (1 + Z95**2 / n)
    assert iv.wilson(k, n) == pytest.approx((centre - half, centre + half), abs=1e-9)
    assert iv.wilson(k, n) == pytest.approx((0.490, 0.943), abs=1e-3)


def test_verdicts():
    assert iv.verdict(30, 30, 0.99) == "consistent"      # 100 % observed, lower bound 88 %
    assert iv.verdict(368, 368, 0.99) == "demonstrated"
    assert iv.verdict(367, 367, 0.99) == "consistent"
    assert iv.verdict(29, 30, 0.99) == "not met"
    assert iv.verdict(0, 10, 0.0, "at_most") == "consistent"  # a goal of 0 is never demonstrated
    assert iv.verdict(1, 10, 0.0, "at_most") == "not met"
    assert iv.verdict(0, 10, 0.5, "at_most") == "demonstrated"  # upper bound 0.3085


def test_runs_to_demonstrate():
    # n = ceil(ln 0.025 / ln 0.99): 0.99^367 = 0.02501 > 0.025 >= 0.99^368 = 0.02476
    assert 0.99**367 > 0.025 >= 0.99**368
    assert iv.runs_to_demonstrate(0.99) == 368
    for f in (1, 3):
        n = iv.runs_to_demonstrate(0.99, failures=f)
        assert upper_tail(n - f, n, 0.99) <= 0.025 < upper_tail(n - 1 - f, n - 1, 0.99)
    assert iv.runs_to_demonstrate(0.9) == math.ceil(math.log(0.025) / math.log(0.9))  # 36


def test_poisson_rate():
    r = iv.poisson_rate(0, 2.0)
    assert r["rate"] == 0.0 and r["ci95"][0] == 0.0
    assert r["ci95"][1] == pytest.approx(-math.log(0.025) / 2.0, abs=1e-6)  # 3.689 events in 2 h
    r = iv.poisson_rate(3, 1.0)
    lo, hi = r["ci95"]
    assert (lo, hi) == pytest.approx((0.6187, 8.7673), abs=1e-4)  # the Garwood table for 3 events

    def poisson_cdf(k, mu):
        return sum(math.exp(-mu) * mu**j / math.factorial(j) for j in range(k + 1))

    assert 1 - poisson_cdf(2, lo) == pytest.approx(0.025, abs=1e-5)  # P(X >= 3 | lo)
    assert poisson_cdf(3, hi) == pytest.approx(0.025, abs=1e-5)
    assert iv.poisson_rate(2, 0.0)["rate"] is None


def test_rate_record_and_errors():
    r = iv.rate(9, 10, goal=0.99)
    assert r["count"] == 9 and r["runs"] == 10 and r["fraction"] == 0.9 and r["verdict"] == "not met"
    assert r["ci95"]["clopper_pearson"] == pytest.approx(iv.clopper_pearson(9, 10), abs=1e-6)
    for bad in ((11, 10), (-1, 10), (0, 0), (1.5, 3)):
        with pytest.raises(ValueError, match="k <= n"):
            iv.clopper_pearson(*bad)
    with pytest.raises(ValueError, match="direction"):
        iv.verdict(1, 2, 0.5, "above")
    with pytest.raises(ValueError, match="confidence level"):
        iv.wilson(1, 2, level=1.5)
    with pytest.raises(ValueError, match="exposure"):
        iv.poisson_rate(1, -1.0)


def test_closed_forms_agree_with_scipy_stats():
    """The closed-form quantiles against scipy.stats' own (root search for the exact
    binomial interval, the Wilson formula, the chi-square quantile)."""
    from scipy import stats
    for n in (1, 2, 3, 7, 10, 30, 101, 368):
        for k in sorted({0, 1, n // 3, n // 2, n - 1, n}):
            for level in (0.9, 0.95, 0.99):
                t = stats.binomtest(k, n)
                cp = t.proportion_ci(confidence_level=level, method="exact")
                assert iv.clopper_pearson(k, n, level) == pytest.approx((cp.low, cp.high), abs=1e-10)
                wi = t.proportion_ci(confidence_level=level, method="wilson")
                assert iv.wilson(k, n, level) == pytest.approx((wi.low, wi.high), abs=1e-14)
    for events in (0, 1, 2, 5, 40):
        r = iv.poisson_rate(events, 1.0)
        lo = 0.0 if events == 0 else stats.chi2.ppf(0.025, 2 * events) / 2
        assert r["ci95"] == pytest.approx([round(lo, 6), round(stats.chi2.ppf(0.975, 2 * events + 2) / 2, 6)], abs=2e-6)
