"""tools/latency/dwell_nats_table.py: its rows from campaign records written by hand -- the
counts and Wilson intervals, the latency median VEL apart, the soak's summary per level -- and
its refusal of a directory without records."""
from __future__ import annotations

import json
import pathlib
import subprocess
import sys

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "latency" / "dwell_nats_table.py"


def _campaign(d: pathlib.Path, runs: list[dict], summary: dict | None = None) -> pathlib.Path:
    d.mkdir()
    (d / "runs.jsonl").write_text("".join(json.dumps(r) + "\n" for r in runs))
    if summary is not None:
        (d / "summary.json").write_text(json.dumps(summary))
    return d


def _run(case, outcome, latency, false_alarm=False, transient_wrong=False):
    return {"kind": "single", "case": case, "outcome": outcome, "latency_s": latency, "false_alarm": false_alarm,
            "transient_wrong": transient_wrong, "scenario": {"turbulence": "light"}}


def test_rows_from_hand_written_records(tmp_path):
    single = _campaign(tmp_path / "single", [
        _run("LS", "correct", 0.5), _run("AY", "correct", 0.3), _run("YAW", "correct", 0.2),
        _run("VEL", "correct", 3.0), _run("RS", "wrong", None, transient_wrong=True),
        _run("NONE", "correct", None, false_alarm=True)])
    soak = _campaign(tmp_path / "soak", [{"kind": "soak", "case": "NONE", "scenario": {"turbulence": "light"}}],
                     {"levels": [{"level": "light", "hours": 10.0, "hypotheses": {"RF": 1},
                                  "per_hour": {"events": 1, "ci95": [0.0025, 0.557]}}]})
    r = subprocess.run([sys.executable, str(TOOL), f"table={single},{soak}"], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    row = next(line for line in lines if line.startswith("| table | single |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[2].startswith("4/5 [") and cells[3].startswith("1/5 [") and cells[4].startswith("1/6 [")
    assert cells[5] == "0.30 / 0.48"   # LS, AY, YAW: VEL apart
    assert cells[6] == "0.50" and cells[7] == "0.25"   # the surfaces' (LS) and the sensors' (AY, YAW) medians
    assert "| table | soak | light | 1 in 10.00 h = 0.10/h [0.00-0.56] | RF 1 |" in lines
    assert "| VEL | 3.00 |" in lines


def test_a_directory_without_records_is_refused(tmp_path):
    r = subprocess.run([sys.executable, str(TOOL), f"x={tmp_path}"], capture_output=True, text=True, timeout=60)
    assert r.returncode != 0 and "holds no runs.jsonl" in r.stderr
