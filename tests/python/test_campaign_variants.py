"""A campaign flown at several turbulence levels or failure modes: common seeds, each variant's
summary exactly the one-variant campaign's, the side-by-side rows against hand counts, modes
flying only the cases they apply to, the page, the Markdown and the console table."""
from __future__ import annotations

import json

import pytest

from f16mmae.campaign.engine.executor import InlineExecutor
from f16mmae.campaign.engine.variants import LEVEL_CORRECT_GOALS, variant_row
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
    assert s["kind"] == "variants" and s["campaign"] == "single" and s["turbulence"] == "none,moderate"
    assert s["axes"] == ["turbulence"] and s["mode"] == "complete"
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
        row = next(x for x in s["variants"] if x["turbulence"] == level)
        assert row["runs"] == 2 and row["correct"]["count"] == sum(r["outcome"] == "correct" for r in recs)
        assert row["correct"]["goal"] == 0.99 and row["correct"]["direction"] == "at_least"
        fd = row["false_declarations_per_hour"]
        assert fd["events"] == sum(r["false_declarations"] for r in recs)
        assert fd["exposure"] == pytest.approx((8.0 + 3.0) / 3600)  # NONE flies 8 s failure-free, LS 3 s
        assert row["goals_met"] == sub["goals_met"]
    assert s["goals_met"] == all(x["goals_met"] for x in s["variants"])
    assert (tmp_path / "both" / s["figures"]["variants"]).stat().st_size > 0


def test_variant_row_latency_and_counts():
    recs = [{"outcome": "correct", "latency_s": 0.5, "false_declarations": 0, "failure_free_s": 3.0,
             "scenario": {"failures": [{"name": "LS"}]}},
            {"outcome": "correct", "latency_s": 1.5, "false_declarations": 1, "failure_free_s": 3.0,
             "scenario": {"failures": [{"name": "LS"}]}},
            {"outcome": "missed", "latency_s": None, "false_declarations": 0, "failure_free_s": 3.0,
             "scenario": {"failures": [{"name": "LS"}]}},
            {"outcome": "wrong", "latency_s": None, "false_declarations": 2, "failure_free_s": 9.0,
             "scenario": {"failures": []}}]
    row = variant_row("severe", {"goals_met": False}, recs)
    assert row["correct"]["count"] == 2 and row["runs"] == 4
    assert row["latency_s"] == {"median": 1.0, "p95": pytest.approx(0.5 + 0.95 * 1.0), "detected_runs": 2,
                                "failure_runs": 3}
    assert row["false_declarations_per_hour"]["events"] == 3
    assert row["false_declarations_per_hour"]["rate"] == pytest.approx(3 / (18 / 3600), rel=1e-6)
    assert "verdict" not in row["correct"]


@pytest.mark.parametrize("correct, runs, verdict", [(20, 20, "consistent"), (19, 20, "consistent"),
                                                    (18, 20, "not met"), (72, 72, "demonstrated")])
def test_variant_row_severe_goal_verdict(correct, runs, verdict):
    # severe turbulence asks >= 95 % correct: 19/20 is 0.95 (consistent); 72/72 has the
    # Clopper-Pearson lower bound 0.025^(1/72) = 0.950 (demonstrated); 18/20 is below the goal
    recs = [{"outcome": "correct" if i < correct else "missed", "latency_s": 0.5 if i < correct else None,
             "false_declarations": 0, "failure_free_s": 3.0, "scenario": {"failures": [{"name": "LS"}]}}
            for i in range(runs)]
    row = variant_row("severe", {"goals_met": False}, recs, LEVEL_CORRECT_GOALS["severe"])
    assert row["correct"]["goal"] == 0.95 and row["correct"]["verdict"] == verdict


def test_cli_levels_console_page_and_markdown(tmp_path, capsys):
    out = tmp_path / "cli"
    assert main(["campaign", "single", "--runs", "1", "--cases", "NONE", "--baseline", "none",
                 "--turbulence", "none,light", "--workers", "1", "--quiet", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "turbulence side by side" in text and "=== none (" in text
    page = (out / "report.html").read_text()
    assert "single campaign in 2 variants of turbulence" in page and "none/report.html" in page
    assert (out / "none" / "report.html").exists() and (out / "light" / "report.html").exists()
    md = tmp_path / "levels.md"
    assert main(["report", str(out), "--markdown", str(md)]) == 0
    body = md.read_text()
    assert "| none | 1 |" in body and "| light | 1 |" in body and "--turbulence none,light" in body
    assert main(["campaign", "single", "--turbulence", "light,light", "--out", str(tmp_path / "x")]) == 2
    assert "twice" in capsys.readouterr().err


def test_modes_fly_the_cases_they_apply_to(tmp_path):
    cfg = SingleCampaign(runs=1, cases=("NONE", "LS", "PIT"), baseline=None, mode="complete,null,loss=0.5")
    done = run_campaign(cfg, tmp_path, InlineExecutor(), show_progress=False, measure_cost=False)
    s = done.summary
    assert s["axes"] == ["mode"] and [v["mode"] for v in s["variants"]] == ["complete", "null", "loss=0.5"]
    # NONE is the same run in every mode: flown once; null is a sensor mode, loss an actuator one
    assert len(done.records) == 1 + 2 + 1 + 1
    assert [v["cases_skipped"] for v in s["variants"]] == [[], ["LS"], ["PIT"]]
    loss = next(r for r in done.records if r["case"] == "LS" and r["scenario"]["failures"][0]["mode"] == "loss")
    assert loss["scenario"]["failures"][0]["value"] == 0.5
    sub = json.loads((tmp_path / "loss=0.5" / "summary.json").read_text())
    assert sub["mode"] == "loss=0.5" and [c["case"] for c in sub["cases"]] == ["NONE", "LS"]
    assert sub["cases_skipped"] == ["PIT"]
    # the complete mode is the one-mode campaign exactly
    alone = run_campaign(SingleCampaign(runs=1, cases=("NONE", "LS", "PIT"), baseline=None), tmp_path / "alone",
                         InlineExecutor(), show_progress=False, measure_cost=False)
    assert _strip(json.loads((tmp_path / "complete" / "summary.json").read_text())) == \
        _strip(json.loads(json.dumps(alone.summary)))


@pytest.mark.parametrize("args, message", [
    (["--mode", "null", "--cases", "LS,RS"], "applies to none of the cases"),
    (["--mode", "loss=half"], "not a number"),
    (["--mode", "complete,complete"], "twice"),
    (["--mode", "wobble"], "unknown failure mode"),
])
def test_cli_bad_modes(tmp_path, capsys, args, message):
    assert main(["campaign", "single", "--runs", "1", "--workers", "1", "--out", str(tmp_path / "m"), *args]) == 2
    assert message in capsys.readouterr().err


def test_dual_takes_one_mode(tmp_path, capsys):
    assert main(["campaign", "dual", "--runs", "1", "--mode", "complete,stuck", "--out", str(tmp_path / "d")]) == 2
    assert "one failure mode" in capsys.readouterr().err
