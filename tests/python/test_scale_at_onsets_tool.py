"""tools/soak/scale_at_onsets.py: the onset it finds in a probability history written by hand
(the last frame before the declared hypothesis passed 0.5, NONE's declarations skipped), a short
soak read end to end with and without a setting, and its refusals by name (a directory without
runs.jsonl, a figure in a folder that does not exist, a setting that is not KEY=VALUE)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from f16mmae.cli.main import main as f16mmae

from tool_module import load_tool


@pytest.fixture(scope="module")
def tool():
    return load_tool("soak/scale_at_onsets.py")


def test_onsets_against_a_hand_written_history(tool):
    p = np.array([[1.0, 0.0, 0.0]] * 10 + [[0.4, 0.6, 0.0]] * 3 + [[0.05, 0.95, 0.0]] * 20 + [[1.0, 0.0, 0.0]] * 5
                 + [[np.nan, np.nan, np.nan]] * 2 + [[0.3, 0.0, 0.7]] * 4)
    result = SimpleNamespace(hypotheses=("NONE", "A", "B"), probabilities=p,
                             declarations=[{"hypothesis": "A", "time_s": 20 / 64}, {"hypothesis": "NONE", "time_s": 33 / 64},
                                           {"hypothesis": "B", "time_s": 43 / 64}])
    # A passed 0.5 on frame 10 (onset: frame 9) and was declared on frame 20; B passed it on frame 40
    # (the NaN frames off line read as 0), declared on 43
    assert tool.onsets(result, 64.0) == [("A", 9, 20), ("B", 39, 43)]


def test_a_short_soak_with_and_without_a_setting(tool, tmp_path, capsys):
    out = tmp_path / "soak"
    assert f16mmae(["campaign", "soak", "--hours", "0.02", "--turbulence", "moderate", "--tuning", "scheduled",
                    "--adapt-turbulence", "--seed", "3", "--workers", "1", "--quiet", "--out", str(out)]) == 0
    capsys.readouterr()
    assert tool.main([str(out), "--without", "adapt_floor_time_constant_s=0", "--figure",
                      str(tmp_path / "f.png")]) == 0
    printed = capsys.readouterr().out
    for line in printed.splitlines():   # each false declaration's line names its onset and s there
        assert line.startswith(("run ", "    with ", "figure: ")), line
    # a record whose declarations its flight does not repeat (here: one written by hand) is refused
    import json
    records = [json.loads(line) for line in (out / "runs.jsonl").read_text().splitlines()]
    records[0]["false_declarations"] = 1
    records[0]["declarations"] = [{"hypothesis": "RF", "time_s": 5.0}, {"hypothesis": "NONE", "time_s": 6.0}]
    (out / "runs.jsonl").write_text("".join(json.dumps(r) + "\n" for r in records))
    with pytest.raises(SystemExit, match="flown again does not declare what its record says"):
        tool.main([str(out)])


def test_refusals_name_the_problem(tool, tmp_path, capsys):
    with pytest.raises(SystemExit):
        tool.main([str(tmp_path)])
    assert "runs.jsonl does not exist: give a soak campaign's output directory" in capsys.readouterr().err
    (tmp_path / "runs.jsonl").write_text("")
    with pytest.raises(SystemExit):
        tool.main([str(tmp_path), "--figure", str(tmp_path / "no" / "f.png")])
    assert "the folder" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        tool.main([str(tmp_path), "--without", "adapt_floor_time_constant_s"])
    assert "--without takes KEY=VALUE, got 'adapt_floor_time_constant_s'" in capsys.readouterr().err
