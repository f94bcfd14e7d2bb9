"""``f16mmae campaign paper``: the three campaigns on one pool, each written where and as its own
command writes it (the single part's records equal the single command's), every directory
checked before the first flight."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from f16mmae.campaign.engine.store import ResultsStore
from f16mmae.cli.main import main

pytestmark = pytest.mark.slow


def _records(d: Path) -> list[dict]:
    return sorted(({k: v for k, v in r.items() if k not in ("timing", "code")} for r in ResultsStore(d).records()),
                  key=lambda r: r["run_key"])


def test_paper_flies_the_three_campaigns_as_their_own_commands(tmp_path, capsys):
    out = tmp_path / "paper"
    assert main(["campaign", "paper", "--runs", "1", "--seed", "3", "--workers", "2", "--quiet",
                 "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    counts = {"single": 13, "dual": 12 + 132, "envelope": 25 * 13}
    for name, n in counts.items():
        d = out / name
        assert f"=== campaign {name} ({d}) ===" in printed
        assert len(ResultsStore(d).records()) == n
        summary = json.loads((d / "summary.json").read_text())
        assert summary["kind"] == name and summary["seed"] == 3
        extra = " --baseline none" if name == "single" else ""
        assert summary["command"] == f"f16mmae campaign {name} --runs 1 --seed 3{extra} --out {d} --quiet"
        assert (d / "report.html").is_file()
    # the single part flies nothing: its runs are the envelope's at NOM (engine.shared_flights) ...
    single = json.loads((out / "single" / "summary.json").read_text())["timing"]
    assert single["runs_executed"] == 13 and single["runs_shared"] == 13
    # ... and the single command's campaign: the same records
    alone = tmp_path / "alone"
    assert main(["campaign", "single", "--runs", "1", "--seed", "3", "--baseline", "none", "--workers", "1",
                 "--quiet", "--out", str(alone)]) == 0
    assert _records(out / "single") == _records(alone)


def test_an_unwritable_part_directory_stops_it_before_any_flight(tmp_path, capsys):
    out = tmp_path / "paper"
    out.mkdir()
    (out / "envelope").write_text("a file where the envelope campaign's directory goes")
    assert main(["campaign", "paper", "--runs", "1", "--quiet", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "envelope" in err and "is a file" in err
    assert not (out / "single" / "runs.jsonl").exists()


@pytest.mark.parametrize("argv, message", [
    (["--runs", "0"], "--runs '0' must be >= 1"),
    (["--seed", "0"], "--seed"),
    (["--workers", "0"], "--workers '0' must be >= 1"),
])
def test_bad_arguments_are_named(tmp_path, capsys, argv, message):
    assert main(["campaign", "paper", *argv, "--out", str(tmp_path / "p")]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "p" / "single").exists()
