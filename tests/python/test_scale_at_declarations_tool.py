"""tools/latency/scale_at_declarations.py: on a one-run campaign in severe air (a failed rudder,
the scheduled default), the run it flies again declares what the record declares, on the same
frame, and the scale it reads there is the estimator's own on that frame, read here by an
estimator flown independently; a directory without runs.jsonl is refused by name."""
from __future__ import annotations

import json

import pytest

from f16mmae.banks import load_bank
from f16mmae.cli.main import main as f16mmae
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict

from tool_module import load_tool


@pytest.fixture(scope="module")
def tool():
    return load_tool("latency/scale_at_declarations.py")


def test_the_scale_at_a_severe_air_rudder_declaration(tool, tmp_path, capsys):
    out = tmp_path / "c"
    assert f16mmae(["campaign", "single", "--runs", "1", "--cases", "RUD", "--turbulence", "severe",
                    "--baseline", "none", "--tuning", "scheduled", "--adapt-turbulence", "--seed", "3",
                    "--workers", "1", "--quiet", "--out", str(out)]) == 0
    record = next(json.loads(line) for line in (out / "runs.jsonl").read_text().splitlines()
                  if json.loads(line)["case"] == "RUD")
    first = record["declarations"][0]
    assert first["hypothesis"] == "RUD"
    capsys.readouterr()
    assert tool.main([str(out), "--hypothesis", "RUD"]) == 0
    lines = capsys.readouterr().out.splitlines()
    bank = load_bank("scheduled")[2]
    est = Estimator(bank, **record["estimator_settings"])
    scales = []

    def on_frame(*_):
        scales.append(est.turbulence_scale)   # after the frame's update and propagation

    fly(scenario_from_dict(record["scenario"]), bank, estimator=est, on_frame=on_frame)
    frame = int(round(first["time_s"] * 64))
    expected = scales[frame]   # s after the declaring frame's update
    assert f"RUD@{first['time_s']:.2f} s={expected:.1f}" in lines[0], lines
    assert expected > 4.0   # severe air is rough air
    assert any(line.startswith("severe: 1 failed-RUD runs") for line in lines), lines


def test_a_directory_without_records_is_refused(tool, tmp_path, capsys):
    with pytest.raises(SystemExit):
        tool.main([str(tmp_path)])
    assert "runs.jsonl: no such file" in capsys.readouterr().err
