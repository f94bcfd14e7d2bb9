"""Figures and the HTML report from campaign records (scored by the real scoring code)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from f16mmae.campaign import KINDS, dual, envelope, import_kinds  # noqa: F401 -- importing a kind registers its page
from f16mmae.campaign.engine.scoring import mean_injected_probability, score_run, summarize_case
from f16mmae.campaign.single import figures
from f16mmae.report.page import ReportError, render_report


def _records(tuning: str, cases, runs=3, dt=0.25, n=33):
    recs = []
    for case in cases:
        for k in range(runs):
            t = np.arange(n) * dt
            p = np.where(t >= 3.0 + 0.25 * k, 0.99, 0.001) if case != "NONE" else np.full(n, 0.98)
            decl = [] if case == "NONE" else [{"hypothesis": case, "time_s": 3.0 + 0.25 * k}]
            recs.append({"case": case, "tuning": tuning, "failure_time_s": None if case == "NONE" else 3.0,
                         "p_injected": p.tolist(), "p_injected_dt_s": dt,
                         **score_run(case, 3.0 if case != "NONE" else None, decl)})
    return recs


def test_mean_injected_probability_averages_runs():
    recs = _records("tuned", ["LS"], runs=3)
    t, p = mean_injected_probability(recs)
    assert t[1] == pytest.approx(0.25) and len(t) == 33
    i = int(3.25 / 0.25)  # at 3.25 s two of the three runs have switched
    assert p[i] == pytest.approx((0.99 * 2 + 0.001) / 3)


def test_mean_injected_probability_aligns_runs_on_their_failures():
    """Failures at 3.0 and 3.5 s (``--failure-jitter``): the later run drops its first 0.5 s, so both
    switch at the earliest failure's sample; the mean is cut to the shorter."""
    def run(tf, n):
        k = int(round(tf / 0.25))
        return {"failure_time_s": tf, "p_injected_dt_s": 0.25, "p_injected": [0.0] * k + [1.0] * (n - k)}
    t, p = mean_injected_probability([run(3.0, 32), run(3.5, 34)])
    assert len(t) == 32 and t[12] == pytest.approx(3.0)
    assert list(p[:12]) == [0.0] * 12 and list(p[12:]) == [1.0] * 20
    t, p = mean_injected_probability([run(3.0, 32), {**run(3.5, 34), "failure_time_s": None}])
    assert len(t) == 32 and p[12] == pytest.approx(0.5)   # a run without a failure time: no shift


def test_figures_and_report_page(tmp_path):
    cases = ["NONE", "LS", "PIT"]
    by_tuning = {"tuned": _records("tuned", cases), "untuned": _records("untuned", cases)}
    figures.probability_strips(by_tuning, tmp_path / "probability_strips.png", cases=cases)
    figures.latency_chart(by_tuning, tmp_path / "latency.png", cases=["LS", "PIT"])
    summary = {
        "kind": "single", "runs_per_case": 3, "seed": 1, "bank_hash": "abc", "version": "0.1.0",
        "tuning": "tuned", "turbulence": "light", "mach": 0.4, "alt_ft": 20000.0,
        "failure_time_s": 3.0, "duration_s": 8.0, "feedback": "mmae", "mode": "complete",
        "cases": [summarize_case(c, [r for r in by_tuning["tuned"] if r["case"] == c]) for c in cases],
        "baseline": {"tuning": "untuned", "bank_hash": "def",
                     "cases": [summarize_case(c, [r for r in by_tuning["untuned"] if r["case"] == c])
                               for c in cases]},
        "timing": {"wall_s": 1.0, "runs_executed": 18, "runs_resumed": 0, "executor": "2 local"},
        "figures": {"strips": "probability_strips.png", "latency": "latency.png"},
    }
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    page = render_report(tmp_path).read_text()
    assert page.count("data:image/png;base64,") == 2
    assert "untuned bank (baseline" in page and "<td>PIT</td>" in page
    assert "latency median" in page and "correct isolation" in page


def test_report_of_an_empty_directory_says_what_is_needed(tmp_path):
    with pytest.raises(ReportError, match="summary.json"):
        render_report(tmp_path)
    with pytest.raises(ReportError, match="not a directory"):
        render_report(tmp_path / "nope")
    (tmp_path / "summary.json").write_text('{"kind": "triple"}')
    import_kinds()
    with pytest.raises(ReportError, match="unknown campaign kind 'triple'; this version reports "
                       + ", ".join(sorted((*KINDS, "variants")))):
        render_report(tmp_path)


def test_latency_chart_does_not_depend_on_the_order_of_the_records(tmp_path):
    # overlapping translucent dots: a pool stores records in the order they finish
    recs = []
    for lat in (0.50, 0.53, 0.515, 0.56, 0.545, 0.52):
        recs += [{**r, "latency_s": lat} for r in _records("tuned", ["LS"], runs=1)]
    figures.latency_chart({"tuned": recs}, tmp_path / "a.png", cases=["LS"])
    figures.latency_chart({"tuned": recs[::-1]}, tmp_path / "b.png", cases=["LS"])
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
