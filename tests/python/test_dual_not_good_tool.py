"""tools/dual/not_good.py: the flags it puts on a dual run record, against records written by hand,
and its refusal of a folder that is not a dual campaign's."""
from __future__ import annotations

import json

import pytest

from tool_module import load_tool


@pytest.fixture(scope="module")
def tool():
    return load_tool("dual/not_good.py")


def record(first, second, decl, outcome="correct", tw=False, fa=False, latency=1.0):
    return {"pair": f"{first}>{second}", "first": first, "second": second, "first_time_s": 3.0, "second_time_s": 5.0,
            "scenario": {"duration_s": 10.0}, "outcome": outcome, "transient_wrong": tw, "false_alarm": fa,
            "latency_s": latency, "declarations": [{"hypothesis": h, "time_s": t} for h, t in decl]}


def test_components_of_partial_and_dual_names(tool):
    assert tool.components("LF:loss=0.5+AZ") == {"LF", "AZ"}
    assert tool.components("NONE") == set()


def test_a_right_run_has_no_flag(tool):
    assert tool.run_flags(record("AZ", "LF", [("AZ", 3.7), ("LF+AZ", 6.3)])) == []


def test_the_starts_alarm_and_a_late_first(tool):
    # LF before any failure, backed out, VEL declared only after the second failure
    r = record("VEL", "RF", [("LF", 1.17), ("NONE", 3.0), ("RF", 6.66), ("RF+VEL", 9.12)], fa=True)
    assert tool.run_flags(r) == ["FA@start", "no-first"]


def test_an_alarm_that_is_only_the_first_surfaces_partial_hypothesis(tool):
    r = record("LF", "AZ", [("LF:loss=0.5", 3.88), ("LF+AZ", 6.19)], fa=True)
    assert tool.run_flags(r) == ["FA=partial"]
    # another surface's partial hypothesis is a real alarm
    r = record("LF", "AZ", [("RF:loss=0.5", 3.88), ("LF+AZ", 6.19)], fa=True)
    assert "FA=partial" not in tool.run_flags(r) and "FA@3.88" in tool.run_flags(r)


def test_a_transient_wrong_dual_its_time_after_the_first_failure_and_how_long_it_stood(tool):
    r = record("RS", "PIT", [("RS", 4.19), ("LS+RS", 6.91), ("RS+PIT", 9.17)], tw=True)
    assert tool.run_flags(r) == ["TW LS+RS@3.91+2.26s"]
    # read as another sensor first, never right: wrong, and the first failure never declared
    r = record("AZ", "RF", [("AOA", 3.48), ("AOA+AZ", 5.48)], outcome="wrong", tw=True, latency=None)
    assert tool.run_flags(r) == ["TW AOA@0.48+2.00s", "no-first", "wrong"]


def test_a_folder_that_is_not_a_dual_campaigns_is_refused(tool, tmp_path):
    with pytest.raises(SystemExit, match="not a dual campaign folder"):
        tool.load(str(tmp_path))
    (tmp_path / "summary.json").write_text(json.dumps({"kind": "single", "pairs": []}))
    (tmp_path / "runs.jsonl").write_text("")
    with pytest.raises(SystemExit, match="a 'single' campaign, not a dual one"):
        tool.load(str(tmp_path))
