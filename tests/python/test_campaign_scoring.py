"""Scoring definitions against hand-worked runs."""
from __future__ import annotations

import pytest

from f16mmae.campaign.engine.scoring import check_goals, expected_hypothesis, score_run, summarize_case


def d(h, t):
    return {"hypothesis": h, "time_s": t}


def test_correct_with_latency():
    s = score_run("LS", 3.0, [d("LS", 3.75)])
    assert s == {"final_hypothesis": "LS", "outcome": "correct", "false_alarm": False, "latency_s": 0.75}


def test_missed_when_nothing_declared_or_backed_out():
    assert score_run("PIT", 3.0, [])["outcome"] == "missed"
    s = score_run("PIT", 3.0, [d("PIT", 3.5), d("NONE", 5.0)])
    assert s["outcome"] == "missed" and s["final_hypothesis"] == "NONE"
    assert s["latency_s"] == pytest.approx(0.5)  # the first correct declaration still counts


def test_wrong_isolation_and_false_alarm_before_failure():
    s = score_run("LS", 3.0, [d("RS", 1.0), d("NONE", 1.5), d("RS", 4.0)])
    assert s["outcome"] == "wrong" and s["false_alarm"] and s["latency_s"] is None
    s = score_run("LS", 3.0, [d("AZ", 2.9), d("NONE", 3.2), d("LS", 3.4)])
    assert s["outcome"] == "correct" and s["false_alarm"] and s["latency_s"] == pytest.approx(0.4)


def test_no_failure_runs():
    assert score_run("NONE", None, []) == {
        "final_hypothesis": "NONE", "outcome": "correct", "false_alarm": False, "latency_s": None}
    s = score_run("NONE", None, [d("YAW", 6.0)])
    assert s["outcome"] == "wrong" and s["false_alarm"]
    s = score_run("NONE", None, [d("YAW", 6.0), d("NONE", 7.0)])
    assert s["outcome"] == "correct" and s["false_alarm"]


def test_declarations_are_taken_in_time_order():
    assert score_run("LS", 3.0, [d("LS", 4.0), d("RS", 3.5)])["final_hypothesis"] == "LS"


def test_expected_hypothesis():
    assert expected_hypothesis([]) == "NONE"
    assert expected_hypothesis(["PIT"]) == "PIT"
    assert expected_hypothesis(["PIT", "LS"]) == "LS+PIT"


def test_summarize_case_counts_and_percentiles():
    runs = [score_run("LS", 3.0, [d("LS", 3.0 + lat)]) for lat in (0.5, 1.0, 1.5, 2.0)]
    runs.append(score_run("LS", 3.0, []))
    runs.append(score_run("LS", 3.0, [d("RF", 1.0)]))
    s = summarize_case("LS", runs)
    assert (s["runs"], s["correct"], s["missed"], s["wrong"], s["false_alarms"]) == (6, 4, 1, 1, 1)
    assert s["latency_s"]["median"] == pytest.approx(1.25)
    assert s["latency_s"]["p95"] == pytest.approx(1.5 + 0.85 * 0.5)  # linear interpolation
    g = check_goals(s)
    assert not g["correct"] and not g["false_alarms"] and not g["latency_median"] and not g["all"]
    assert g["latency_p95"]  # 1.925 s <= 2 s


def test_goals_met_and_none_case_has_no_latency_goal():
    runs = [score_run("NONE", None, []) for _ in range(5)]
    g = check_goals(summarize_case("NONE", runs))
    assert g == {"correct": True, "false_alarms": True, "all": True}
    s = summarize_case("VEL", [score_run("VEL", 3.0, [])])
    assert s["latency_s"] == {"median": None, "p95": None}
    assert not check_goals(s)["latency_median"]
