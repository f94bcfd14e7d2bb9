"""tools/schedule/floor_in_force.py: the floor in force it records is the estimator's after every
update (at the trimmable edge the least floor, 1e-9, on every frame; a given --p-min everywhere with
the rough-air floor off), and
its refusals by name (a runs file that does not exist, not two banks, no run of that seed and air,
a run that declared nothing, a figure in a folder that does not exist)."""
from __future__ import annotations

import json

import numpy as np
import pytest

import f16mmae.design.schedule  # noqa: F401 -- registers the scheduled bank's generator (designed on first use)
from f16mmae.banks import load_bank
from f16mmae.truth import Scenario

from tool_module import load_tool


@pytest.fixture(scope="module")
def tool():
    return load_tool("schedule/floor_in_force.py")


def _record(seed=5, declarations=(), **estimator):
    scenario = Scenario(mach=0.36, alt_ft=34000.0, turbulence="none", duration_s=2.0, seed=seed)
    return {"scenario": scenario.to_dict(), "estimator": {"adapt_turbulence": True, **estimator},
            "declarations": list(declarations)}


def test_the_floor_in_force_at_the_trimmable_edge(tool):
    bank = load_bank("scheduled")[2]
    result, floors = tool.fly_recording_floor(_record(), bank)
    assert len(floors) == len(result.time_s) == 128
    assert set(floors) == {1e-9}   # the nodes beside an untrimmable point at their least candidate floor
    _, given = tool.fly_recording_floor(_record(p_min=1e-5, rough_p_min=0.0), bank)
    assert np.all(given == 1e-5)   # a given p_min is the floor everywhere (node_p_min off), the rough-air floor off


def test_refusals_name_the_problem(tool, tmp_path, capsys):
    runs = tmp_path / "runs.jsonl"
    runs.write_text(json.dumps(_record(seed=5)) + "\n"
                    + json.dumps(_record(seed=6, declarations=[{"hypothesis": "RS", "time_s": 1.0}])) + "\n")
    base = ["--turbulence", "none", "--around", "1"]
    cases = [([str(tmp_path / "none.jsonl"), "--seed", "5", "--banks", "scheduled,scheduled", *base], "does not exist"),
             ([str(runs), "--seed", "5", "--banks", "scheduled", *base], "give two banks"),
             ([str(runs), "--seed", "7", "--banks", "scheduled,scheduled", *base], "has no run of seed 7 in none air"),
             ([str(runs), "--seed", "5", "--banks", "scheduled,scheduled", *base], "declared no failure"),
             ([str(runs), "--seed", "6", "--banks", "scheduled,scheduled", "--figure", str(tmp_path / "x" / "f.png"),
               *base], "does not exist"),
             ([str(runs), "--seed", "6", "--banks", "scheduled,nowhere.f16sched", *base], "--banks:")]
    for argv, message in cases:
        with pytest.raises(SystemExit) as e:
            tool.main(argv)
        assert e.value.code == 2, argv
        assert message in capsys.readouterr().err, argv
    # a run that does not fly as recorded (here: a declaration written by hand) is refused
    with pytest.raises(SystemExit, match="does not declare what its record says"):
        tool.main([str(runs), "--seed", "6", "--banks", "scheduled,scheduled", *base])
