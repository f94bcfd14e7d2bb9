"""The duals' drift allowance at level 1 (``--level1-allowance K``, cpp/f16mmae/level1_allowance.h):
on a tuning-seed flight (campaign seed 7's single campaign, AY failed completely at 3 s, the cover
bank with partial-loss hypotheses) the level-1 bank declares AY and then a false dual RF+AY whose
log-odds against AY walk with little drift; with an allowance of 0.1 nats a frame the walk drifts
down and only AY is declared, at the same time; the setting is in run.json; a negative allowance
is refused, naming the option."""
from __future__ import annotations

import json

import pytest

from f16mmae import core
from f16mmae.cli.main import main
from f16mmae.design import bank
from f16mmae.design.tuning import load_tuning, tuning_from_dict


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
