"""tools/latency/dwell_per_hypothesis.py: the excursions it finds in a probability history
written by hand (their frames, their log-odds excess summed by hand, false or not, rejected by
the frame dwell or not), and its refusal of an evaluation-seed campaign."""
from __future__ import annotations

import importlib.util
import json
import math
import pathlib

import numpy as np
import pytest

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "latency" / "dwell_per_hypothesis.py"
EXCESS_99 = math.log(99.0) - math.log(9.0)   # 0.99 above the threshold 0.9: 2.3979 nats a frame


@pytest.fixture(scope="module")
def tool():
    spec = importlib.util.spec_from_file_location("dwell_per_hypothesis", TOOL)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_excursions_against_a_hand_written_history(tool):
    names = ["NONE", "A", "B"]
    rows = []
    rows += [[0.99, 0.005, 0.005]] * 3          # NONE, current: no excursion
    rows += [[0.005, 0.99, 0.005]] * 2          # A for 2 frames (false: the truth is NONE until frame 10)
    rows += [[0.99, 0.005, 0.005]] * 5
    rows += [[0.005, 0.005, 0.99]] * 4          # B from frame 10 (the failure): not false
    rows += [[0.005, 0.99, 0.005]] * 5          # A from frame 14, declared on its 4th frame (17)
    p = np.array(rows)
    time_s = np.arange(len(rows)) / 64.0
    ex = tool.excursions(names, p, [{"hypothesis": "A", "time_s": time_s[17]}], time_s, 0.9, 4,
                         lambda i: "B" if i >= 10 else "NONE")
    got = [(e["hypothesis"], e["start"], e["frames"], e["false"], e["rejected"]) for e in ex]
    assert got == [("A", 3, 2, True, True), ("B", 10, 4, False, False), ("A", 14, 4, True, False)]
    assert ex[0]["E"] == pytest.approx(2 * EXCESS_99)
    assert ex[1]["E"] == pytest.approx(3 * EXCESS_99)   # the first dwell_frames - 1 frames only
    assert ex[2]["E"] == pytest.approx(3 * EXCESS_99)


def test_an_evaluation_seed_campaign_is_refused(tool, tmp_path):
    (tmp_path / "summary.json").write_text(json.dumps({"seed": 1}))
    (tmp_path / "runs.jsonl").write_text("")
    with pytest.raises(SystemExit, match="evaluation default"):
        tool.campaign_records(tmp_path)
