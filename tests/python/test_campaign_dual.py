"""The dual-failure campaign: config checks, seeds, per-run scoring, the rating rules on
hand-built summaries, a tiny real campaign (REAL truth model and estimator) with resume,
and the CLI's errors."""
from __future__ import annotations

import json

import pytest

from f16mmae.banks import load_bank
from f16mmae.campaign.dual import scoring as dual_scoring
from f16mmae.campaign.engine.failure_runs import run_seed as single_run_seed
from f16mmae.campaign.dual import ALL_PAIRS, DualCampaign, plan, run_campaign, run_seed
from f16mmae.report.page import render_report
from f16mmae.campaign.dual.scoring import (RATING_RULES, declared_at, hold_fraction, rate_pair,
                                           score_dual_run, summarize_pair)
from f16mmae.campaign.engine.config import CampaignError
from f16mmae.campaign.engine.store import RECORDS_FILE, ResultsStore
from f16mmae.cli.main import main

from campaign_support import CountingExecutor


# -- configuration ------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, message", [
    ({"runs": 0}, "--runs must lie in [1, 1000], got 0"),
    ({"seed": 0}, "--seed must be >= 1"),
    ({"pairs": ()}, "no pair to fly"),
    ({"pairs": (("LS", "LS"),)}, "fails one component twice"),
    ({"pairs": (("LS", "XX"),)}, "unknown pair LS+XX"),
    ({"pairs": (("LS", "PIT"), ("LS", "PIT"))}, "listed twice"),
    ({"turbulence": "huge"}, "valid: none, light, moderate, severe"),
    ({"feedback": "kalman"}, "valid: mmae, raw"),
    ({"second_time_s": 3.0}, "0 < first (3.0 s) < second (3.0 s)"),
    ({"second_time_s": 10.0}, "< duration (10.0 s)"),
    ({"estimator": {"threshold": 0.4}}, "--threshold 0.4 must lie in (0.5, 1)"),
    ({"estimator": {"dwell_s": 5.0}}, "--dwell-s 5.0 must lie in [0, 5.0) s"),
    ({"estimator": {"p_min": 0.2}}, "--p-min 0.2"),
    # (1 - 0.9) / 12 = 0.0083: above it no hypothesis of a level-1 bank can pass the threshold
    ({"estimator": {"level1_p_min": 0.0084}}, "--level1-p-min 0.0084 must lie in [0, 0.00833333)"),
    ({"dither_scale": 9.0}, "--dither-scale 9.0"),
])
def test_bad_config_is_refused_naming_the_value(kwargs, message):
    with pytest.raises(CampaignError) as err:
        DualCampaign(**kwargs).validate()
    assert message in str(err.value)


def test_all_pairs_are_the_132_ordered_pairs():
    assert len(ALL_PAIRS) == 132 == len(set(ALL_PAIRS))
    assert ("LS", "PIT") in ALL_PAIRS and ("PIT", "LS") in ALL_PAIRS and ("LS", "LS") not in ALL_PAIRS
    assert DualCampaign(pairs=(("AZ", "LS"), ("PIT", "LS"), ("LS", "RUD"))).seconds == ("LS", "RUD")


# -- seeds --------------------------------------------------------------------------------------
def test_seeds_are_deterministic_distinct_and_not_the_single_campaigns():
    names = ("LS", "RS", "PIT", "AY")
    seeds = {(b, n): run_seed(1, b, n) for b in names for n in range(40)}
    assert all(s >= 1 for s in seeds.values())
    assert len(set(seeds.values())) == len(seeds)
    assert run_seed(1, "LS", 3) == run_seed(1, "LS", 3) != run_seed(2, "LS", 3)
    singles = {single_run_seed(1, b, n) for b in names for n in range(40)}
    assert not singles & set(seeds.values())


def test_plan_shares_seeds_along_a_column_and_keys_are_unique():
    cfg = DualCampaign(runs=2, pairs=(("LS", "PIT"), ("AZ", "PIT"), ("PIT", "LS")))
    _, _, bank = load_bank("tuned")
    specs = plan(cfg, "tuned", bank)
    assert len(specs) == 2 * (3 + 2)  # pairs + baselines of PIT and LS
    assert len({s["run_key"] for s in specs}) == len(specs)
    for s in specs:
        assert s["seed"] == run_seed(1, s["second"], s["run_index"]) == s["scenario"]["seed"]
        names = [(f["name"], f["time_s"]) for f in s["scenario"]["failures"]]
        expect = ([(s["first"], 3.0)] if s["first"] else []) + [(s["second"], 5.0)]
        assert names == expect
    assert plan(cfg, "tuned", bank) == specs


# -- per-run scoring ----------------------------------------------------------------------------
EVENTS = [{"hypothesis": "LS", "time_s": 3.5}, {"hypothesis": "LS+PIT", "time_s": 5.5},
          {"hypothesis": "LS", "time_s": 7.0}, {"hypothesis": "LS+PIT", "time_s": 8.0}]


def test_declared_at_and_hold_fraction():
    assert declared_at(EVENTS, 1.0) == "NONE"
    assert declared_at(EVENTS, 5.5) == "LS+PIT"
    assert declared_at(EVENTS, 7.5) == "LS"
    # LS+PIT held on [5.5, 7) and [8, 10): 3.5 s of 4.5 s
    assert hold_fraction(EVENTS, "LS+PIT", 5.5, 10.0) == pytest.approx(3.5 / 4.5)
    assert hold_fraction(EVENTS, "LS+PIT", 6.0, 7.5) == pytest.approx(1.0 / 1.5)
    assert hold_fraction(EVENTS, "LS", 0.0, 10.0) == pytest.approx((2.0 + 1.0) / 10.0)
    with pytest.raises(ValueError):
        hold_fraction(EVENTS, "LS", 5.0, 5.0)


def test_score_dual_run_fields():
    t = [i * 0.5 for i in range(20)]
    p = [0.0] * 10 + [0.2, 0.7, 0.95] + [0.0] * 7
    s = score_dual_run("LS+PIT", "LS", 3.0, 5.0, 10.0, EVENTS, t, p)
    assert s["outcome"] == "correct" and s["latency_s"] == pytest.approx(0.5)
    assert s["first_latency_s"] == pytest.approx(0.5) and s["false_alarm"] is False
    assert s["hold"] == pytest.approx(3.5 / 4.5) and s["p_max_after"] == pytest.approx(0.95)
    # ends on the first failure alone: the second was missed; a wrong single before t_2 alarms
    missed = score_dual_run("LS+PIT", "LS", 3.0, 5.0, 10.0, EVENTS[:1], t, [0.0] * 20)
    assert (missed["outcome"], missed["latency_s"], missed["hold"], missed["p_max_after"]) == ("missed", None, None, 0.0)
    wrong = score_dual_run("LS+PIT", "LS", 3.0, 5.0, 10.0, [{"hypothesis": "RS", "time_s": 3.4}], t, [0.0] * 20)
    assert (wrong["outcome"], wrong["false_alarm"], wrong["first_latency_s"]) == ("wrong", True, None)
    # the first surface's partial hypothesis is its declaration (as in the single scoring), no alarm
    partial = score_dual_run("LF+AZ", "LF", 3.0, 5.0, 10.0,
                             [{"hypothesis": "LF:loss=0.5", "time_s": 3.6}, {"hypothesis": "LF+AZ", "time_s": 5.5}], t, p)
    assert (partial["outcome"], partial["false_alarm"], partial["first_latency_s"]) == ("correct", False, pytest.approx(0.6))
    other = score_dual_run("LF+AZ", "LF", 3.0, 5.0, 10.0, [{"hypothesis": "RF:loss=0.5", "time_s": 3.6}], t, p)
    assert other["false_alarm"] is True
    # a baseline run: the single at t_2, any failure before t_2 is a false alarm
    base = score_dual_run("PIT", None, None, 5.0, 10.0, [{"hypothesis": "PIT", "time_s": 5.25}], t, [1.0] * 20)
    assert base["outcome"] == "correct" and base["hold"] == 1.0 and "first_latency_s" not in base


# (declarations, final outcome, transient-wrong by the rule for failed components, by the former rule)
# of pair VEL>LS (VEL fails at 3 s, LS at 5 s; the dual is LS+VEL) in a 10-s flight
@pytest.mark.parametrize("events, outcome, tw, tw_strict", [
    # VEL late, LS alone first, then the dual: every declaration true -> correct, clean
    ([("LS", 6.0), ("LS+VEL", 6.8)], "correct", False, True),
    # in the failures' order
    ([("VEL", 3.5), ("LS+VEL", 5.6)], "correct", False, False),
    # ends on the second failure alone: VEL missed, not wrong
    ([("LS", 5.4)], "missed", False, True),
    # the lone second failure declared before it failed: false (and a false alarm)
    ([("LS", 4.9), ("LS+VEL", 5.5)], "correct", True, True),
    # a component that never failed: wrong, alone or in a dual with a failed one
    ([("VEL", 3.5), ("VEL+AY", 5.5), ("LS+VEL", 6.0)], "correct", True, True),
    ([("VEL", 3.5), ("LS+RS", 6.0)], "wrong", True, True),
    # a back-out to NONE names nothing
    ([("VEL", 3.5), ("NONE", 4.0)], "missed", False, False),
])
def test_rule_for_failed_components(events, outcome, tw, tw_strict):
    from f16mmae.campaign.engine.outcomes import transient_wrong as strict
    decl = [{"hypothesis": h, "time_s": t} for h, t in events]
    t = [i * 0.5 for i in range(20)]
    s = score_dual_run("LS+VEL", "VEL", 3.0, 5.0, 10.0, decl, t, [0.0] * 20)
    assert (s["outcome"], s["transient_wrong"]) == (outcome, tw)
    assert strict(decl, 3.0, {"VEL", "LS+VEL"}) is tw_strict


def test_names_only_failed_is_by_the_declarations_time():
    failures = [("VEL", 3.0), ("LS", 5.0)]
    assert dual_scoring.names_only_failed("NONE", failures, 0.0)
    assert dual_scoring.names_only_failed("VEL", failures, 3.0)
    assert not dual_scoring.names_only_failed("LS", failures, 4.99)
    assert dual_scoring.names_only_failed("LS+VEL", failures, 5.0)
    assert dual_scoring.names_only_failed("VEL+LS", failures, 9.0)   # in any order
    assert not dual_scoring.names_only_failed("LS+AY", failures, 9.0)
    assert dual_scoring.transient_wrong([{"hypothesis": "AY", "time_s": 1.0}], failures) is False  # before onset
    assert dual_scoring.transient_wrong([{"hypothesis": "AY", "time_s": 1.0}], []) is False


# -- the rating ---------------------------------------------------------------------------------
def _summary(correct, runs=10, median=None, hold=None, p_max=0.0, declared=None):
    return {"case": "X", "runs": runs, "correct": correct, "missed": runs - correct, "wrong": 0,
            "latency_s": {"median": median, "p95": median}, "hold_mean": hold, "p_max": p_max,
            "declared_runs": correct if declared is None else declared}


BASE = _summary(10, median=0.8, hold=1.0, p_max=1.0)


@pytest.mark.parametrize("pair, baseline, rating", [
    (_summary(9, median=1.3, hold=0.9, p_max=1.0), BASE, "Good"),        # at every margin's edge
    (_summary(10, median=0.5, hold=1.0, p_max=1.0), BASE, "Good"),
    (_summary(9, median=1.31, hold=1.0, p_max=1.0), BASE, "Fair"),       # later than baseline + 0.5 s
    (_summary(10, median=0.8, hold=0.85, p_max=1.0), BASE, "Fair"),      # dropouts from lock
    (_summary(5, median=0.8, hold=1.0, p_max=1.0), BASE, "Fair"),        # half correct
    (_summary(4, median=0.8, hold=1.0, p_max=1.0), BASE, "Poor"),        # fewer than half
    (_summary(0, median=None, hold=None, p_max=0.6, declared=0), BASE, "Poor"),  # a spike, no lock
    (_summary(0, median=2.0, hold=0.1, p_max=1.0, declared=2), BASE, "Poor"),    # declared, not kept
    (_summary(0, median=None, hold=None, p_max=0.49, declared=0), BASE, "ND"),
    # a baseline that is itself weak: the pair is rated relative to it
    (_summary(3, median=1.5, hold=1.0, p_max=1.0), _summary(3, median=1.2, hold=1.0), "Good"),
    (_summary(3, median=2.6, hold=1.0, p_max=1.0), _summary(0), "Fair"),  # m_ref = 2.0 s
    (_summary(3, median=2.4, hold=1.0, p_max=1.0), _summary(0), "Good"),
])
def test_rating_branches(pair, baseline, rating):
    got, reason = rate_pair(pair, baseline)
    assert got == rating, reason
    assert "correct" in reason


def test_rating_needs_runs_and_the_rules_are_in_one_place():
    with pytest.raises(ValueError):
        rate_pair(_summary(0, runs=0), BASE)
    assert set(RATING_RULES) >= {"good_correct_margin", "good_latency_margin_s", "fair_correct_min"}


def test_paper_matrix_is_complete_and_comparison_counts():
    fig7 = dual_scoring.PAPER_FIG7
    assert len(fig7) == 12 and all(len(row) == 12 and row[a] == "" for a, row in fig7.items())
    known = [(a, b) for a, row in fig7.items() for b, r in row.items() if r]
    assert len(known) == 132 - 5  # RUD>VEL..ROL: the extracted text lost one of these cells
    assert fig7["LS"]["LF"] == "ND" and fig7["YAW"]["RUD"] == "Poor" and fig7["RUD"]["YAW"] == "ND"
    assert fig7["RUD"]["AY"] == "Good" and fig7["RUD"]["PIT"] is None
    cmp_ = dual_scoring.compare_with_paper({"LS": {"LF": "ND", "RF": "Good"}, "RUD": {"YAW": "ND", "VEL": "Good"}})
    assert cmp_ == {"cells": 3, "equal": 2, "good_vs_not_good_equal": 2}


# -- a tiny real campaign -----------------------------------------------------------------------


TINY = DualCampaign(runs=1, seed=3, pairs=(("PIT", "AZ"), ("AZ", "PIT")), duration_s=8.0)


@pytest.mark.slow
def test_tiny_campaign_records_summary_figures_and_resume(tmp_path):
    out = tmp_path / "dual"
    first = run_campaign(TINY, out, CountingExecutor(), show_progress=False)
    assert (first.executed, first.resumed) == (4, 0)  # 2 pairs + 2 baselines
    stored = ResultsStore(out).records()
    assert len(stored) == 4
    for r in stored:
        assert r["seed"] >= 1 and r["scenario"]["seed"] == r["seed"] and r["bank_hash"] and r["version"]
        assert r["outcome"] in ("correct", "missed", "wrong")
        assert len(r["p_injected"]) == 8.0 / r["p_injected_dt_s"]
    by_pair = {r["pair"]: r for r in stored}
    assert set(by_pair) == {"PIT>AZ", "AZ>PIT", "PIT", "AZ"}
    assert by_pair["PIT>AZ"]["hypothesis"] == by_pair["AZ>PIT"]["hypothesis"] == "PIT+AZ"
    assert by_pair["PIT>AZ"]["seed"] == by_pair["AZ"]["seed"] != by_pair["PIT"]["seed"]
    assert "p_first" in by_pair["PIT>AZ"] and "p_first" not in by_pair["AZ"]

    summary = json.loads((out / "summary.json").read_text())
    assert summary["kind"] == "dual" and summary["runs_per_pair"] == 1
    assert summary["bank_hash"] == stored[0]["bank_hash"]
    base = {b["case"]: b for b in summary["baselines"]}
    for p in summary["pairs"]:
        recs = [r for r in stored if r["pair"] == p["case"]]
        expect = summarize_pair(p["case"], recs)
        assert {k: p[k] for k in expect} == expect
        assert p["rating"] == rate_pair(p, base[p["second"]])[0]
        assert summary["matrix"][p["first"]][p["second"]] == p["rating"]
    assert sum(summary["ratings"].values()) == 2
    for name in summary["figures"].values():
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    page = render_report(out).read_text()
    assert "PIT&gt;AZ" in page and "data:image/png;base64," in page and summary["bank_hash"] in page

    # same arguments again: nothing flies; a half-written last record flies again
    ex = CountingExecutor()
    assert run_campaign(TINY, out, ex, show_progress=False).executed == 0 and ex.submitted == 0
    path = out / RECORDS_FILE
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join(lines[:-1]) + lines[-1][: len(lines[-1]) // 2])
    ex = CountingExecutor()
    again = run_campaign(TINY, out, ex, show_progress=False)
    assert (again.executed, again.resumed, ex.submitted) == (1, 3, 1)
    strip = lambda rs: sorted((r["run_key"], r["declarations"], r["p_injected"]) for r in rs)  # noqa: E731
    assert strip(ResultsStore(out).records()) == strip(stored)


# -- the CLI ------------------------------------------------------------------------------------
@pytest.mark.parametrize("argv, expected", [
    (["--pairs", "LS+LS"], "fails LS twice"),
    (["--pairs", "LS+FOO"], "LS,RS,LF,RF,RUD,VEL,AOA,PIT,AZ,ROL,YAW,AY"),
    (["--pairs", "LS+PIT", "--first", "LS"], "--pairs or --first/--second"),
    (["--first", "XX"], "--first: unknown failure(s) XX"),
    (["--first", "LS", "--second", "LS"], "leaves no pair"),
    (["--second-time-s", "2"], "second (2.0 s)"),
    (["--turbulence", "huge"], "valid: none, light, moderate, severe"),
    (["--runs", "0"], "--runs '0' must be >= 1"),
    (["--tuning", "/no/such.f16bank"], "--tuning '/no/such.f16bank'"),
    (["--workers", "1", "--scheduler", "tcp://h:1"], "not both"),
])
def test_cli_errors_exit_2_naming_the_value(argv, expected, capsys, tmp_path):
    assert main(["campaign", "dual", *argv, "--out", str(tmp_path / "o")]) == 2
    assert expected in capsys.readouterr().err
    assert not (tmp_path / "o" / RECORDS_FILE).exists()


def test_cli_help_teaches(capsys):
    with pytest.raises(SystemExit):
        main(["campaign", "dual", "--help"])
    text = capsys.readouterr().out
    for needle in ("examples:", "dual_matrix.png", "summary.json", "Good", "Fair", "Poor", "ND", "--second-time-s"):
        assert needle in text


# -- pairs the models cannot separate ------------------------------------------------------------
def _pair(first, second, rating, absolute="Not good"):
    return {"case": f"{first}>{second}", "first": first, "second": second, "runs": 3, "rating": rating,
            "rating_reason": "measured", "absolute_rating": absolute, "absolute_rating_reason": "why"}


@pytest.mark.slow
def test_models_rate_a_blocked_pair_indistinguishable_and_leave_the_others(tmp_path, monkeypatch):
    from f16mmae.campaign.dual import models
    from f16mmae.design import distinguish

    monkeypatch.setenv("F16MMAE_CACHE_DIR", str(tmp_path))
    _, _, bank = load_bank("tuned")
    pairs = [_pair("AZ", "AOA", "ND"), _pair("PIT", "LS", "Poor"), _pair("LS", "PIT", "Good", "Good"),
             _pair("ROL", "RS", "Fair")]
    out = models.annotate(pairs, bank, "light", "complete")
    assert out == {"evaluated": 2, "indistinguishable": ["AZ>AOA"]}
    blocked, separable, good, fair = pairs
    # AZ>AOA: AZ alone explains AOA reading trim better than the dual does (D < 0), so the
    # pair is rated Indistinguishable, its measured ND kept beside it
    design, why = models.bank_design(bank)
    assert why is None
    d = distinguish.evidence_rates(design, "AOA+AZ", distinguish.level1_competitors("AZ", "AOA"))
    assert blocked["models"]["against"] == min(d, key=d.get) == "AZ" and d["AZ"] < 0
    assert blocked["models"]["rate_nats_per_frame"] == pytest.approx(d["AZ"], abs=1e-6)
    assert (blocked["rating"], blocked["measured_rating"]) == (dual_scoring.INDISTINGUISHABLE, "ND")
    assert "physically indistinguishable" in blocked["rating_reason"] and "measured" in blocked["rating_reason"]
    # PIT>LS: separable (D > 0), its measured rating stays; Good and Fair pairs are not evaluated
    assert separable["models"]["rate_nats_per_frame"] > 0 and separable["rating"] == "Poor"
    assert "measured_rating" not in separable
    assert "models" not in good and "models" not in fair and fair["rating"] == "Fair"
    # with the flight's window: AOA>AZ is separable (D > 0) but its drift against AOA alone,
    # 0.009 nats a frame, gathers ~2.7 nats in the 4.75 s after the second failure less the dwell
    # (304 frames at 64 Hz), below the 6.9 nats any admissible floor needs: the measured Poor stays
    slow = [_pair("AOA", "AZ", "Poor")]
    models.annotate(slow, bank, "light", "complete", window_frames=304, threshold=0.9)
    w = slow[0]["models"]["window"]
    assert slow[0]["rating"] == "Poor" and w["within"] is False and "not within the flight" in slow[0]["rating_reason"]
    assert w["nats"] == pytest.approx(304 * slow[0]["models"]["rate_vs_first"], abs=1e-3)
    assert 0 < w["nats"] < w["least_lift_nats"]
    # the second time the cache answers: no design is needed
    monkeypatch.setattr(models, "bank_design", lambda bank: pytest.fail("designed again"))
    again = [_pair("AZ", "AOA", "ND")]
    assert models.annotate(again, bank, "light", "complete") == {"evaluated": 1, "indistinguishable": ["AZ>AOA"]}
    assert again[0]["models"] == blocked["models"]
    # a mode or level the models do not cover: nothing evaluated, and why
    assert "not hardover in light" in models.annotate([_pair("AZ", "AOA", "ND")], bank, "light", "hardover")["why_not"]
    scaled = [_pair("AZ", "AOA", "ND")]
    assert "not 1.11 times it" in models.annotate(scaled, bank, "light", "complete", dither_scale=1.11)["why_not"]
    assert "not none" in models.annotate(scaled, bank, "light", "complete", dither_scale=None)["why_not"]
    assert scaled[0]["rating"] == "ND" and "models" not in scaled[0]


def test_least_lift_is_the_smallest_over_the_admissible_floors():
    from f16mmae.campaign.dual import models
    import numpy as np
    thr, k = 0.9, 13
    # lift from a floor P: ln(thr/(1-thr)) - ln(P / (1 - (k-1) P)), over the floors at which a
    # hypothesis can still pass thr (1 - (k-1) P > thr)
    floors = np.linspace(1e-9, (1 - thr) / (k - 1), 200001)[:-1]
    lifts = np.log(thr / (1 - thr)) - np.log(floors / (1 - (k - 1) * floors))
    assert models.least_lift_nats(thr, k) == pytest.approx(lifts.min(), rel=1e-4)
    assert models.least_lift_nats(0.9) == pytest.approx(np.log(972.0))
    w = models.window_check(0.01, 100, 0.9)
    assert (w["nats"], w["within"], w["frames_to_least_lift"]) == (1.0, False, pytest.approx(687.9, abs=0.1))
    assert models.window_check(0.1, 100, 0.9)["within"] is True
    assert models.window_check(-0.1, 100, 0.9)["frames_to_least_lift"] is None
    with pytest.raises(ValueError, match="threshold"):
        models.least_lift_nats(0.4)


def test_the_failure_jitter_shifts_both_failures_of_a_pair_and_its_baseline_alike():
    """``--failure-jitter J``: run n of pair (a, b) and of b's baseline shift both failures and the
    end by the same J x from their common seed; J = 0 plans as before."""
    from f16mmae.campaign.engine.failure_runs import failure_offset
    bank = load_bank("tuned")[2]
    base = DualCampaign(runs=4, pairs=(("LS", "PIT"),))
    spread = DualCampaign(runs=4, pairs=(("LS", "PIT"),), failure_jitter_s=1.0)
    for a, b in zip(plan(base, "tuned", bank), plan(spread, "tuned", bank)):
        assert a["seed"] == b["seed"]
        offset = failure_offset(b["seed"], 1.0)
        assert 0.0 <= offset < 1.0
        times = [f["time_s"] for f in b["scenario"]["failures"]]
        assert times == pytest.approx([f["time_s"] + offset for f in a["scenario"]["failures"]])
        assert times[-1] == pytest.approx(5.0 + offset)
        assert b["scenario"]["duration_s"] == pytest.approx(10.0 + offset)
    with pytest.raises(CampaignError, match="--failure-jitter 61 must lie in"):
        DualCampaign(failure_jitter_s=61.0).validate()
