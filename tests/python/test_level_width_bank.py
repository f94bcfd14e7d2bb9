"""tools/cover/level_width_bank.py: a copy of a cover bank whose failed sensor's level range W_j
is set anew. The copy's W_VEL is the one asked for (directly, or from the Occam constant
c = ln(sqrt(2 pi A_jj) / W_j) of the VEL hypothesis) in every hypothesis that reads VEL as a
level, every other number is the bank's, and its content hash differs; bad arguments are
refused, naming them."""
from __future__ import annotations

import math
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from f16mmae import core
from f16mmae.design import bank
from f16mmae.design.tuning import load_tuning, tuning_from_dict

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "cover" / "level_width_bank.py"


@pytest.fixture(scope="module")
def cover_bank_path(tmp_path_factory):
    tuning = tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": "cover"}, default_name="cover")
    path = tmp_path_factory.mktemp("width") / "cover.f16bank"
    core.save_bank(bank.to_model_bank(bank.design_bank(0.4, 20_000.0, tuning)), str(path))
    return path


def _run(*args):
    return subprocess.run([sys.executable, str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_the_copy_changes_vel_s_range_only(cover_bank_path, tmp_path):
    out = tmp_path / "vel.f16bank"
    r = _run(cover_bank_path, "--occam", "VEL=-2.1", "--out", out)
    assert r.returncode == 0, r.stderr
    a, b = core.load_bank(str(cover_bank_path)), core.load_bank(str(out))
    j = list(a.measurement_names).index("VEL")
    a_vel = float(a.hypotheses[list(a.hypothesis_names).index("VEL")].a[j, j])
    w = math.sqrt(2.0 * math.pi * a_vel) / math.exp(-2.1)
    changed = 0
    for ha, hb in zip(a.hypotheses, b.hypotheses):
        assert ha.name == hb.name
        for key in ("phi", "bd", "h", "k", "a"):
            assert np.array_equal(getattr(ha, key), getattr(hb, key))
        wa = np.asarray(ha.uninformative_width)
        wb = np.asarray(hb.uninformative_width)
        if wa.size and wa[j] > 0.0:
            assert wb[j] == pytest.approx(w, rel=1e-12)
            assert np.array_equal(np.delete(wa, j), np.delete(wb, j))
            changed += 1
        else:
            assert np.array_equal(wa, wb)
    assert changed == 12   # VEL and its 11 duals
    assert str(a.content_hash) != str(b.content_hash)


def test_bad_arguments_are_refused_by_name(cover_bank_path, tmp_path):
    r = _run(cover_bank_path, "--width", "XYZ=3", "--out", tmp_path / "x.f16bank")
    assert r.returncode == 2 and "'XYZ' is not a sensor" in r.stderr
    r = _run(cover_bank_path, "--occam", "VEL=1", "--out", tmp_path / "x.f16bank")
    assert r.returncode == 2 and "--occam" in r.stderr
