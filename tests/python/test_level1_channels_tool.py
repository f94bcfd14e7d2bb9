"""tools/cover/level1_channels.py: the models' per-channel split of a dual's expected
log-likelihood ratio against its single adds up to -D(f, f+c) of design.distinguish (the
single's and the dual's failed-sensor level terms are the same filter on the same reading, so
only the quadratic terms differ), and a hypothesis that is no dual of the failure is refused."""
from __future__ import annotations

import subprocess
import sys

import pytest

from f16mmae import core
from f16mmae.design import bank
from f16mmae.design.tuning import load_tuning, tuning_from_dict

from tool_module import TOOLS, load_tool

TOOL = TOOLS / "cover" / "level1_channels.py"


def _tool():
    return load_tool("cover/level1_channels.py")


@pytest.fixture(scope="module")
def cover_bank_path(tmp_path_factory):
    tuning = tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": "cover"}, default_name="cover")
    path = tmp_path_factory.mktemp("l1") / "cover.f16bank"
    core.save_bank(bank.to_model_bank(bank.design_bank(0.4, 20_000.0, tuning)), str(path))
    return path


@pytest.mark.parametrize("single, dual", [("AY", "RF+AY"), ("PIT", "LS+PIT"), ("LS", "LS+RF")])
def test_models_split_sums_to_the_separation(cover_bank_path, single, dual):
    split, d = _tool().model_split(core.load_bank(str(cover_bank_path)), single, dual)
    assert split.shape == (7,)
    assert d > 0.0
    assert float(split.sum()) == pytest.approx(-d, rel=1e-6)
    j = 6 if single == "AY" else 2 if single == "PIT" else None
    if j is not None:  # the failed sensor's channel is scored by neither filter's quadratic term
        assert split[j] == 0.0


def test_a_hypothesis_that_is_no_dual_is_refused(cover_bank_path):
    r = subprocess.run([sys.executable, str(TOOL), "--bank", str(cover_bank_path), "--seed", "1",
                        "--fail", "AY@3.0:complete", "--dual", "LS+RS"], capture_output=True, text=True)
    assert r.returncode != 0 and "'LS+RS' is no dual of 'AY'" in r.stderr
