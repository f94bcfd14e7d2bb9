"""Case evidence (rates, intervals, verdicts, censored latency) and the campaign-wide fields,
from hand-made run records."""
from __future__ import annotations

import json
from pathlib import Path

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


def _timed(outcome, latency, *names):
    """A run record whose failures are ``names`` in injection order."""
    r = rec(outcome, latency)
    r["failures"] = [{"mode": "complete", "name": n, "time_s": 3.0 + 2.0 * i} for i, n in enumerate(names)]
    return r


def test_latency_medians_per_group_vel_excepted():
    rs = [_timed("correct", 0.25, "LS"), _timed("correct", 0.75, "PIT"), _timed("correct", 1.25, "AOA"),
          _timed("correct", 2.0, "LS"), _timed("correct", 4.5, "VEL"), _timed("correct", 3.5, "VEL"),
          _timed("correct", 5.0, "VEL"),
          _timed("correct", 0.5, "VEL", "PIT"),            # a dual's latency times its second: PIT
          _timed("correct", 9.0, "PIT", "VEL"),            # ... here VEL
          _timed("missed", None, "VEL"), _timed("correct", None)]  # no latency: in no group
    # except_vel sorted: 0.25 0.5 0.75 1.25 2.0 -> 0.75; vel: 3.5 4.5 5.0 9.0 -> 4.75;
    # all: 0.25 0.5 0.75 1.25 2.0 3.5 4.5 5.0 9.0 -> 2.0
    medians, runs = evidence.latency_medians(rs)
    assert medians == {"all": 2.0, "except_vel": 0.75, "vel": 4.75}
    assert runs == {"all": 9, "except_vel": 5, "vel": 4}
    f = evidence.summary_fields(rs, [], [], {"code": "src:x"})
    assert f["latency_median_s"] == medians and f["latency_median_runs"] == runs


def test_latency_medians_without_detected_runs_are_none():
    medians, runs = evidence.latency_medians([_timed("missed", None, "VEL"), _timed("correct", 0.5, "LS")])
    assert medians == {"all": 0.5, "except_vel": 0.5, "vel": None}
    assert runs == {"all": 1, "except_vel": 1, "vel": 0}
    assert evidence.latency_medians([]) == ({"all": None, "except_vel": None, "vel": None},
                                            {"all": 0, "except_vel": 0, "vel": 0})


@pytest.mark.parametrize("kind", ["single", "dual", "envelope"])
def test_golden_summaries_hold_the_medians_of_their_records(kind):
    # the golden campaigns' records (every run the summary pools) give the stored medians,
    # computed here by sorting, apart from the code under test
    golden = json.loads((Path(__file__).with_name("golden") / f"campaign_{kind}.json").read_text())

    def median(xs):
        xs = sorted(xs)
        n = len(xs)
        return None if n == 0 else (xs[n // 2] if n % 2 else (xs[n // 2 - 1] + xs[n // 2]) / 2)

    timed = [(r["failures"][-1]["name"], r["latency_s"]) for r in golden["records"] if r["latency_s"] is not None]
    want = {"all": median([x for _, x in timed]),
            "except_vel": median([x for n, x in timed if n != "VEL"]),
            "vel": median([x for n, x in timed if n == "VEL"])}
    assert golden["summary"]["latency_median_s"] == want
    assert golden["summary"]["latency_median_runs"]["all"] == len(timed)
