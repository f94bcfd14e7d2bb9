"""Case evidence (rates, intervals, verdicts, censored latency) and the campaign-wide fields,
from hand-made run records."""
from __future__ import annotations

import pytest

from f16mmae.campaign.engine import evidence


def rec(outcome, latency=None, fa=False, tw=False, fd=0, free=3.0, code=None):
    return {"outcome": outcome, "latency_s": latency, "false_alarm": fa, "transient_wrong": tw,
            "false_declarations": fd, "failure_free_s": free, "code": code}


def test_failure_case_evidence():
    rs = [rec("correct", 0.4)] * 6 + [rec("correct", 1.5, tw=True), rec("correct", 2.5),
                                     rec("missed"), rec("wrong", None, fa=True, fd=2)]
    ev = evidence.case_evidence("LS", rs)
    r = ev["rates"]
    assert (r["correct"]["count"], r["missed"]["count"], r["wrong"]["count"]) == (8, 1, 1)
    assert r["transient_wrong"]["count"] == 1 and r["false_alarm"]["count"] == 1
    assert r["correct"]["verdict"] == "not met" and r["transient_wrong"]["verdict"] == "not met"
    assert "verdict" not in r["missed"]  # no goal on it
    det = ev["detection"]
    # 10 runs: 6 within 0.5 s, 7 within 2 s, 8 in flight; misses count as never detected
    assert det["within_s"] == {"0.5": 0.6, "1": 0.6, "2": 0.7} and det["in_flight"] == 0.8
    assert det["within_1s"]["verdict"] == "consistent"    # 6/10 >= 0.5, lower bound 0.26
    assert det["within_2s"]["verdict"] == "not met"       # 7/10 < 0.95
    assert ev["verdict"] == "not met"


def test_no_failure_case_has_no_detection_and_a_goal_of_zero_is_at_best_consistent():
    ev = evidence.case_evidence("NONE", [rec("correct", free=8.0)] * 30)
    assert "detection" not in ev
    assert ev["verdicts"] == {"correct": "consistent", "transient_wrong": "consistent", "false_alarm": "consistent"}
    assert ev["verdict"] == "consistent"
    lo, hi = ev["rates"]["correct"]["ci95"]["clopper_pearson"]
    assert lo == pytest.approx(0.025 ** (1 / 30), abs=1e-6) and hi == 1.0


def test_campaign_fields():
    code = {"code": "git:abc", "jsbsim": "1.3.3", "lcm": "1.5.3"}
    rs = [rec("correct", 0.5, code=code)] * 3 + [rec("correct", None, fd=1, free=8.0, code=code)]
    cases = [{"case": "LS", "evidence": evidence.case_evidence("LS", rs[:3])},
             {"case": "NONE", "evidence": evidence.case_evidence("NONE", rs[3:])}]
    f = evidence.summary_fields(rs, cases, [], code)
    fd = f["false_declarations_per_hour"]
    assert fd["events"] == 1 and fd["exposure"] == pytest.approx((3 * 3.0 + 8.0) / 3600, abs=1e-9)
    assert fd["rate"] == pytest.approx(3600 / 17.0, rel=1e-6)
    assert f["demonstration"] == {"goal": 0.99, "runs_all_correct": 368,
                                  "runs_one_failure": f["demonstration"]["runs_one_failure"]}
    assert f["verdict_counts"] == {"demonstrated": 0, "consistent": 2, "not met": 0}
    assert f["goals_met"] is True and len(f["codes_in_records"]) == 1
    assert evidence.worst(["demonstrated", "not met", "consistent"]) == "not met"
    assert evidence.worst([]) is None
