"""A campaign flown at several turbulence levels: common seeds, each level's summary exactly
the one-level campaign's, the side-by-side rows against hand counts, the page, the Markdown
and the console table."""
from __future__ import annotations

import json

import pytest

from f16mmae.campaign.engine.executor import InlineExecutor
from f16mmae.campaign.engine.levels import level_row
from f16mmae.campaign.single import SingleCampaign, run_campaign
from f16mmae.cli.main import main

pytestmark = pytest.mark.slow

VOLATILE = ("timing", "code", "codes_in_records", "figures")


def _strip(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in VOLATILE}


def test_two_levels_are_each_the_one_level_campaign(tmp_path):
    both = SingleCampaign(runs=1, cases=("NONE", "LS"), baseline=None, turbulence="none,moderate")
    done = run_campaign(both, tmp_path / "both", InlineExecutor(), show_progress=False, measure_cost=False)
    s = done.summary
    assert s["kind"] == "levels" and s["campaign"] == "single" and s["turbulence"] == "none,moderate"
    assert len(done.records) == 4
    # common seeds: run n of case c flies the same seed at both levels
    seeds = {(r["scenario"]["turbulence"], r["case"]): r["seed"] for r in done.records}
    assert seeds[("none", "LS")] == seeds[("moderate", "LS")] and seeds[("none", "NONE")] == seeds[("moderate", "NONE")]
    for level in ("none", "moderate"):
        alone = run_campaign(SingleCampaign(runs=1, cases=("NONE", "LS"), baseline=None, turbulence=level),
                             tmp_path / level, InlineExecutor(), show_progress=False, measure_cost=False)
        sub = json.loads((tmp_path / "both" / level / "summary.json").read_text())
        assert _strip(sub) == _strip(json.loads(json.dumps(alone.summary)))
        assert {r["run_key"] for r in alone.records} == {r["run_key"] for r in done.records
                                                       if r["scenario"]["turbulence"] == level}
        for name in sub["figures"].values():
            assert (tmp_path / "both" / level / name).exists()
        # the row against counts made by hand from the records
        recs = [r for r in done.records if r["scenario"]["turbulence"] == level]
        row = next(x for x in s["levels"] if x["level"] == level)
        assert row["runs"] == 2 and row["correct"]["count"] == sum(r["outcome"] == "correct" for r in recs)
        fd = row["false_declarations_per_hour"]
        assert fd["events"] == sum(r["false_declarations"] for r in recs)
        assert fd["exposure"] == pytest.approx((8.0 + 3.0) / 3600)  # NONE flies 8 s failure-free, LS 3 s
        assert row["goals_met"] == sub["goals_met"]
    assert s["goals_met"] == all(x["goals_met"] for x in s["levels"])
    assert (tmp_path / "both" / s["figures"]["levels"]).stat().st_size > 0


def test_level_row_latency_and_counts():
    recs = [{"outcome": "correct", "latency_s": 0.5, "false_declarations": 0, "failure_free_s": 3.0,
             "scenario": {"failures": [{"name": "LS"}]}},
            {"outcome": "correct", "latency_s": 1.5, "false_declarations": 1, "failure_free_s": 3.0,
             "scenario": {"failures": [{"name": "LS"}]}},
            {"outcome": "missed", "latency_s": None, "false_declarations": 0, "failure_free_s": 3.0,
             "scenario": {"failures": [{"name": "LS"}]}},
            {"outcome": "wrong", "latency_s": None, "false_declarations": 2, "failure_free_s": 9.0,
             "scenario": {"failures": []}}]
    row = level_row("severe", {"goals_met": False}, recs)
    assert row["correct"]["count"] == 2 and row["runs"] == 4
    assert row["latency_s"] == {"median": 1.0, "p95": pytest.approx(0.5 + 0.95 * 1.0), "detected_runs": 2,
                                "failure_runs": 3}
    assert row["false_declarations_per_hour"]["events"] == 3
    assert row["false_declarations_per_hour"]["rate"] == pytest.approx(3 / (18 / 3600), rel=1e-6)


def test_cli_levels_console_page_and_markdown(tmp_path, capsys):
    out = tmp_path / "cli"
    assert main(["campaign", "single", "--runs", "1", "--cases", "NONE", "--baseline", "none",
                 "--turbulence", "none,light", "--workers", "1", "--quiet", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "turbulence levels side by side" in text and "=== none turbulence" in text
    page = (out / "report.html").read_text()
    assert "single campaign at 2 turbulence levels" in page and "none/report.html" in page
    assert (out / "none" / "report.html").exists() and (out / "light" / "report.html").exists()
    md = tmp_path / "levels.md"
    assert main(["report", str(out), "--markdown", str(md)]) == 0
    body = md.read_text()
    assert "| none | 1 |" in body and "| light | 1 |" in body and "--turbulence none,light" in body
    assert main(["campaign", "single", "--turbulence", "light,light", "--out", str(tmp_path / "x")]) == 2
    assert "twice" in capsys.readouterr().err
