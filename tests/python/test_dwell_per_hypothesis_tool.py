"""tools/latency/dwell_per_hypothesis.py: the excursions it finds in a probability history
written by hand (their frames, their log-odds excess summed by hand, false or not, rejected by
the dwell in force -- ended without their declaration -- or not), and its refusal of the
evaluation seeds' campaigns."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from tool_module import TOOLS, load_tool

TOOL = TOOLS / "latency" / "dwell_per_hypothesis.py"
EXCESS_99 = math.log(99.0) - math.log(9.0)   # 0.99 above the threshold 0.9: 2.3979 nats a frame


@pytest.fixture(scope="module")
def tool():
    return load_tool("latency/dwell_per_hypothesis.py")


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
    ex = tool.excursions(names, p, [{"hypothesis": "A", "time_s": time_s[17]}], time_s, 0.9,
                         lambda i: "B" if i >= 10 else "NONE")
    got = [(e["hypothesis"], e["start"], e["frames"], e["false"], e["rejected"]) for e in ex]
    assert got == [("A", 3, 2, True, True), ("B", 10, 4, False, True), ("A", 14, 4, True, False)]
    assert ex[0]["E"] == pytest.approx(2 * EXCESS_99)
    assert ex[1]["E"] == pytest.approx(4 * EXCESS_99)   # every frame until it ended
    assert ex[2]["E"] == pytest.approx(4 * EXCESS_99)   # every frame up to its declaration


@pytest.mark.parametrize("seed", [1, 2])
def test_an_evaluation_seed_campaign_is_refused(tool, tmp_path, seed):
    (tmp_path / "summary.json").write_text(json.dumps({"seed": seed}))
    (tmp_path / "runs.jsonl").write_text("")
    with pytest.raises(SystemExit, match="an evaluation seed"):
        tool.campaign_records(tmp_path)


@pytest.mark.slow
def test_the_tool_flies_a_tuning_campaign_again_and_writes_the_table(tmp_path):
    """A two-run tuning campaign of the scheduled bank with the frame dwell alone: every flight
    flown again declares as recorded, and the table names each failure hypothesis once, at the
    floor or above; a campaign flown with an evidence dwell is refused."""
    import subprocess
    import sys

    from f16mmae.cli.main import main
    from f16mmae.names import NONE, SINGLE_HYPOTHESES
    base = ["campaign", "single", "--runs", "1", "--cases", "LS,NONE", "--seed", "7", "--tuning", "scheduled",
            "--adapt-turbulence", "--baseline", "none", "--workers", "1", "--quiet"]
    assert main([*base, "--dwell-nats", "0", "--out", str(tmp_path / "c")]) == 0
    out = tmp_path / "n.txt"
    r = subprocess.run([sys.executable, str(TOOL), str(tmp_path / "c"), "--out", str(out), "--floor", "40"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "flown again 2/2" in r.stderr
    table = {line.split()[0]: float(line.split()[1]) for line in out.read_text().splitlines()
             if line.strip() and not line.startswith("#")}
    assert set(table) == set(SINGLE_HYPOTHESES) - {NONE} and min(table.values()) >= 40.0
    assert main([*base, "--out", str(tmp_path / "d")]) == 0   # the scheduled default's evidence dwell
    r = subprocess.run([sys.executable, str(TOOL), str(tmp_path / "d"), "--out", str(out)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode != 0 and "was flown with an evidence dwell" in r.stderr


def test_an_excursion_is_bounded_by_each_frames_dwell_in_force(tool):
    """On frame t the evidence dwell asks N_k f_t / D of the sum so far: an excursion's bound is
    max_t E_t D / f_t with the dwell in force the flight recorded on each frame (here 16 frames,
    then rough air's 128 from the excursion's third frame on), by hand."""
    names = ["NONE", "A"]
    p = np.array([[0.99, 0.005]] * 2 + [[0.005, 0.99]] * 6 + [[0.99, 0.005]] * 2)
    time_s = np.arange(len(p)) / 64.0
    frames = np.array([16, 16, 16, 16, 128, 128, 128, 128, 16, 16])
    (e,) = tool.excursions(names, p, [], time_s, 0.9, lambda i: "NONE", frames_in_force=frames, dwell_frames=16)
    assert (e["start"], e["frames"], e["rejected"]) == (2, 6, True)
    assert e["E"] == pytest.approx(6 * EXCESS_99)
    assert e["B"] == pytest.approx(max(2 * EXCESS_99, 6 * EXCESS_99 * 16 / 128))
    (plain,) = tool.excursions(names, p, [], time_s, 0.9, lambda i: "NONE")
    assert plain["B"] == pytest.approx(6 * EXCESS_99)   # 16 frames throughout: B = E


def test_the_largest_excursion_is_named_with_the_command_that_flies_its_run_again(tool, tmp_path):
    """Each run's label names its campaign and its seed, kind, point, maneuver, turbulence, case and
    index; the line under a hypothesis' N_k names the excursion that set it, its frames, and the run's
    ``f16mmae run`` command (the campaigns' drill-down command)."""
    record = {"kind": "single", "point": "R7", "case": "AOA", "run_index": 4, "bank": "scheduled",
              "tuning": "scheduled",
              "scenario": {"seed": 11, "duration_s": 8.0, "turbulence": "light", "mach": 0.4, "alt_ft": 20000.0,
                           "feedback": "mmae", "failures": [{"name": "AOA", "time_s": 3.0, "mode": "complete"}]},
              "estimator": {"dwell_nats": 0.0}}
    label = tool.run_label(tmp_path / "SETTLED", 8, record)
    assert label == "SETTLED@seed8:single:R7:-:light:AOA:4"
    line = tool.provenance({"run": label, "start": 1465, "frames": 13}, {label: tool.record_command(record)})
    assert line.startswith("#   largest: SETTLED@seed8:single:R7:-:light:AOA:4, frames 1465-1477: "
                           "f16mmae run --seed 11 ")
    assert "--fail AOA@3.0:complete" in line and "--bank scheduled" in line and "--dwell-nats 0" in line
