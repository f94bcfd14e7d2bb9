"""The duals' drift allowance at level 1 (``--level1-allowance K``, cpp/f16mmae/level1_allowance.h):
on a tuning-seed flight (campaign seed 7's single campaign, AY failed completely at 3 s, the cover
bank with partial-loss hypotheses) the level-1 bank declares AY and then a false dual RF+AY whose
log-odds against AY walk with little drift; with an allowance of 0.1 nats a frame the walk drifts
down and only AY is declared, at the same time; the setting is in run.json; a negative allowance
is refused, naming the option."""
from __future__ import annotations

import json
import math

import pytest

from f16mmae import core
from f16mmae.cli.main import main
from f16mmae.design import bank
from f16mmae.design.tuning import load_tuning, tuning_from_dict

from tool_module import load_tool


@pytest.fixture(scope="module")
def partial_bank_path(tmp_path_factory):
    tuning = tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": "cover"}, default_name="cover")
    design = bank.design_bank(0.4, 20_000.0, tuning, partial_loss=(0.5,))
    path = tmp_path_factory.mktemp("allowance") / "cover_partial.f16bank"
    core.save_bank(bank.to_model_bank(design), str(path))
    return path


def test_the_allowance_keeps_a_walking_dual_out_and_the_single_in(partial_bank_path, tmp_path, capsys):
    argv = ["run", "--seed", "606972620", "--duration", "8.0", "--turbulence", "light", "--mach", "0.4",
            "--alt-ft", "20000.0", "--feedback", "mmae", "--fail", "AY@3.0:complete", "--bank",
            str(partial_bank_path), "--dwell-s", "0.5", "--declare-components"]
    runs = {}
    for label, extra in (("none", []), ("allowance", ["--level1-allowance", "0.1"])):
        assert main([*argv, *extra, "--out", str(tmp_path / label)]) == 0
        runs[label] = json.loads((tmp_path / label / "run.json").read_text())
    capsys.readouterr()
    names = {k: [d["hypothesis"] for d in r["declarations"]] for k, r in runs.items()}
    assert names["none"][:2] == ["AY", "RF+AY"], names
    assert names["allowance"] == ["AY"], names
    assert runs["allowance"]["declarations"][0]["time_s"] == runs["none"]["declarations"][0]["time_s"]
    assert runs["allowance"]["estimator_settings"]["level1_allowance"] == 0.1
    assert "level1_allowance" not in runs["none"]["estimator_settings"]


def test_a_negative_allowance_is_refused_by_name(partial_bank_path, tmp_path, capsys):
    assert main(["run", "--seed", "1", "--duration", "1.0", "--bank", str(partial_bank_path),
                 "--level1-allowance", "-0.1", "--out", str(tmp_path / "r")]) == 2
    assert "--level1-allowance" in capsys.readouterr().err
    with pytest.raises(ValueError, match="level1_allowance"):
        core.HierarchicalBank(core.load_bank(str(partial_bank_path)), level1_allowance=float("nan"))


def _dual_rates():
    """tools/cover/dual_rates.py as a module (the tool that writes the pair table)."""
    return load_tool("cover/dual_rates.py")


def _dual_run(first, second, decl, duration=10.0):
    return {"kind": "dual", "first": first, "second": second, "hypothesis": f"{first}+{second}",
            "first_time_s": 3.0, "second_time_s": 5.0, "scenario": {"duration_s": duration},
            "estimator_settings": {"threshold": 0.9, "p_min": 1e-9, "dwell_s": 0.5},
            "declarations": [{"hypothesis": h, "time_s": t} for h, t in decl]}


def test_the_pair_rates_are_the_climb_over_its_frames():
    m = _dual_rates()
    h = math.log(9.0) - math.log(1e-9 / (1.0 - 1e-9))
    assert m.barrier(0.9, 1e-9) == pytest.approx(h) == pytest.approx(22.92, abs=0.01)
    runs = [_dual_run("AY", "RF", [("AY", 3.9), ("AY+RF", 5.0 + 0.5 + 0.5)]),     # 32 frames of climb
            _dual_run("AY", "RF", [("AY", 3.9), ("AY+RF", 5.0 + 0.5 + 1.0)]),     # 64
            _dual_run("AY", "RF", [("AY", 3.9), ("AY+RF", 5.0 + 0.5 + 0.25)]),    # 16
            _dual_run("PIT", "LS", [("PIT", 3.5)]),                               # never: the bound, 320 frames
            _dual_run("VEL", "AOA", [("AOA", 3.7), ("VEL+AOA", 6.9)]),           # VEL not declared first: skipped
            _dual_run("RUD", "AY", [("RUD", 5.2), ("RUD+AY", 7.0)])]             # after the second onset: skipped
    rates = m.pair_rates(runs)
    assert set(rates) == {"AY>RF", "PIT>LS"}
    assert rates["AY>RF"] == {"r": pytest.approx(h / 32.0), "runs": 3, "bound": False}   # the median
    assert rates["PIT>LS"] == {"r": pytest.approx(h / 320.0), "runs": 0, "bound": True}
    assert m.allowance(h / 64.0, 0.2, 0.12) == pytest.approx(0.2 * h / 64.0)   # 0.072: a r
    assert m.allowance(h / 32.0, 0.2, 0.12) == 0.12                            # 0.143: the ceiling


def test_a_pair_table_gives_the_walking_dual_its_own_allowance(partial_bank_path, tmp_path, capsys):
    table = tmp_path / "pairs.json"
    table.write_text(json.dumps({"pairs": {"AY>RF": 0.115, "AY>VEL": 0.055}}))
    out = tmp_path / "pairs"
    assert main(["run", "--seed", "606972620", "--duration", "8.0", "--turbulence", "light", "--mach", "0.4",
                 "--alt-ft", "20000.0", "--feedback", "mmae", "--fail", "AY@3.0:complete", "--bank",
                 str(partial_bank_path), "--dwell-s", "0.5", "--declare-components",
                 "--level1-allowance-pairs", str(table), "--out", str(out)]) == 0
    capsys.readouterr()
    run = json.loads((out / "run.json").read_text())
    assert [d["hypothesis"] for d in run["declarations"]] == ["AY"]
    assert run["estimator_settings"]["level1_allowance_pairs"] == str(table)


def test_a_bad_pair_table_is_refused_by_name(partial_bank_path, tmp_path, capsys):
    empty = tmp_path / "empty.json"
    empty.write_text(json.dumps({"pairs": {}}))
    assert main(["run", "--seed", "1", "--duration", "1.0", "--bank", str(partial_bank_path),
                 "--level1-allowance-pairs", str(empty), "--out", str(tmp_path / "r")]) == 2
    assert "--level1-allowance-pairs" in capsys.readouterr().err
    mb = core.load_bank(str(partial_bank_path))
    with pytest.raises(ValueError, match="level1_allowance_pairs key 'AY>XX'"):
        core.HierarchicalBank(mb, level1_allowance_pairs={"AY>XX": 0.1})
    with pytest.raises(ValueError, match="level1_allowance_pairs"):
        core.HierarchicalBank(mb, level1_allowance_pairs={"AY>RF": -1.0})
