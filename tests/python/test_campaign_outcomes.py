"""Run-level rules (transient-wrong, failure-free time, censored latency, absolute dual rating)
on hand-made declaration histories."""
from __future__ import annotations

import pytest

from f16mmae.campaign.engine import outcomes
from f16mmae.campaign.engine.scoring import score_run


def d(h, t):
    return {"hypothesis": h, "time_s": t}


def test_transient_wrong_counts_even_when_the_run_recovers():
    history = [d("RS", 3.5), d("NONE", 4.0), d("LS", 4.2)]
    assert score_run("LS", 3.0, history)["outcome"] == "correct"  # the final outcome hides it
    assert outcomes.transient_wrong(history, 3.0, {"LS"})
    assert outcomes.transient_wrong([d("RS", 3.0), d("LS", 3.1)], 3.0, {"LS"})  # at the onset counts
    assert not outcomes.transient_wrong([d("LS", 3.4)], 3.0, {"LS"})
    assert not outcomes.transient_wrong([d("LS", 3.4), d("NONE", 5.0)], 3.0, {"LS"})  # a back-out is not wrong


def test_declarations_before_the_onset_are_false_alarms_not_transient_wrong():
    history = [d("RS", 2.0), d("NONE", 2.5), d("LS", 3.4)]
    assert not outcomes.transient_wrong(history, 3.0, {"LS"})
    assert outcomes.false_declarations(history, 3.0) == 1
    assert not outcomes.transient_wrong([d("AZ", 1.0)], None, set())  # no-failure run
    assert outcomes.false_declarations([d("AZ", 1.0), d("NONE", 2.0), d("PIT", 5.0)], None) == 2


def test_dual_allows_the_first_failure_and_the_dual():
    allowed = {"LS", "LS+PIT"}
    assert not outcomes.transient_wrong([d("LS", 2.5), d("LS+PIT", 4.3)], 2.0, allowed)
    assert outcomes.transient_wrong([d("LS", 2.5), d("LS+AZ", 4.4), d("LS+PIT", 5.0)], 2.0, allowed)


def test_failure_free_time():
    assert outcomes.failure_free_time_s(3.0, 8.0) == 3.0
    assert outcomes.failure_free_time_s(None, 8.0) == 8.0
    assert outcomes.failure_free_time_s(9.0, 8.0) == 8.0
    with pytest.raises(ValueError):
        outcomes.failure_free_time_s(None, 0.0)


def test_censored_latency_fractions_count_misses_as_never_detected():
    got = outcomes.detected_within([0.3, 0.8, 1.5, None, 2.5])
    assert got == {"runs": 5, "within_s": {"0.5": 0.2, "1": 0.4, "2": 0.6}, "in_flight": 0.8}
    assert outcomes.detected_within([1.0, 0.5])["within_s"] == {"0.5": 0.5, "1": 1.0, "2": 1.0}  # inclusive
    assert outcomes.detected_within([])["in_flight"] is None


def test_absolute_dual_rating():
    assert outcomes.rate_absolute(10, 9, 0, 0, 1.2)[0] == "Good"
    assert outcomes.rate_absolute(10, 10, 0, 0, 1.5)[0] == "Good"
    rating, why = outcomes.rate_absolute(10, 8, 1, 2, 1.6)
    assert rating == "Not good"
    assert "correct 80% < 90%" in why and "1 run(s) with a false alarm" in why
    assert "2 transient-wrong" in why and "median latency 1.60 s > 1.5 s" in why
    assert outcomes.rate_absolute(10, 10, 0, 0, None) == ("Not good", "never detected")
