"""tools/cover/distinguishability.py: the allowance a dual gets from its models' separation from
the single, k = min(k_max, max(0, m0 - D_s)), worked by hand; the pair table and the climb a real
dual then needs; the refusals (a bank that is not there, a pair that is not two singles, m0 < 0)."""
from __future__ import annotations

import math

import pytest

from tool_module import load_tool


def _tool():
    return load_tool("cover/distinguishability.py")


def test_the_allowance_by_hand():
    t = _tool()
    # the least separated pair asks for the most: 0.2 - 0.06 = 0.14
    assert t.allowance(0.06, 0.2, 0.3) == pytest.approx(0.14, abs=1e-15)
    assert t.allowance(0.158, 0.2, 0.3) == pytest.approx(0.042, abs=1e-15)
    # separated faster than m0: nothing
    assert t.allowance(0.25, 0.2, 0.3) == 0.0
    assert t.allowance(2.86, 0.2, 0.3) == 0.0
    # the ceiling
    assert t.allowance(0.0, 0.5, 0.3) == 0.3
    assert t.allowance(-0.1, 0.25, 1.0) == pytest.approx(0.35)   # a rival the models prefer: more still
    # below the ceiling the walk's drift -(D_s + k) reaches -m0 exactly
    for d in (0.0, 0.01, 0.06, 0.19):
        assert d + t.allowance(d, 0.2, 1.0) == pytest.approx(0.2)


def test_the_pair_table_and_the_climb():
    t = _tool()
    rates = {"PIT>LS": {"d_single": 0.06, "d_dual": 0.09}, "AZ>LF": {"d_single": 0.158, "d_dual": 0.169},
             "AY>RF": {"d_single": 2.86, "d_dual": 4.19}}
    table = t.pair_table(rates, 0.2, 0.3)
    assert list(table) == ["AY>RF", "AZ>LF", "PIT>LS"]
    assert table["PIT>LS"] == pytest.approx(0.14) and table["AZ>LF"] == pytest.approx(0.042) and table["AY>RF"] == 0.0
    h = t.barrier(0.9, 1e-9)
    assert h == pytest.approx(math.log(9.0) - math.log(1e-9 / (1.0 - 1e-9)))
    assert t.climb_frames(0.5, 0.0, h) == pytest.approx(h / 0.5)
    assert t.climb_frames(0.5, 0.1, h) == pytest.approx(h / 0.4)
    assert math.isinf(t.climb_frames(0.09, 0.14, h))   # the model's real PIT>LS dual never arrives
    # with a measured table: the larger k of the two, a pair in one table only keeps its own
    both = t.combine(table, {"PIT>LS": 0.052, "AY>RF": 0.115, "VEL>RS": 0.03})
    assert both == {"AY>RF": 0.115, "AZ>LF": pytest.approx(0.042), "PIT>LS": pytest.approx(0.14), "VEL>RS": 0.03}


def test_refusals(tmp_path, capsys):
    t = _tool()
    with pytest.raises(ValueError, match="m0 and k_max"):
        t.allowance(0.1, -0.2, 0.3)
    with pytest.raises(ValueError, match="D_s must be finite"):
        t.allowance(float("nan"), 0.2, 0.3)
    assert t.main([str(tmp_path / "missing.f16bank")]) == 2
    assert "no such file" in capsys.readouterr().err
    assert t.main([str(tmp_path / "missing.f16bank"), "--pairs", "PIT>PIT"]) == 2
    assert "two different singles" in capsys.readouterr().err
    assert t.main([str(tmp_path / "missing.f16bank"), "--m0", "-1"]) == 2
    assert "m0 and k_max" in capsys.readouterr().err
    assert t.main([str(tmp_path / "missing.f16bank"), "--level0", "PIT"]) == 2
    assert "--level0" in capsys.readouterr().err


@pytest.fixture(scope="module")
def cover_partial_bank(tmp_path_factory):
    from f16mmae import core
    from f16mmae.design import bank
    from f16mmae.design.tuning import load_tuning, tuning_from_dict

    tuning = tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": "cover"}, default_name="tuned-cover")
    design = bank.design_bank(0.4, 20_000.0, tuning, partial_loss=(0.5,))
    path = tmp_path_factory.mktemp("distinguish") / "cover_partial.f16bank"
    core.save_bank(bank.to_model_bank(design), str(path))
    return path


def test_a_cover_bank_is_redesigned_and_its_mirror_pairs_agree(cover_partial_bank, tmp_path, capsys):
    """A bank designed with the cover model and partial losses is redesigned from the tuning its
    metadata records (campaign.dual.models.bank_design; the shipped tuning its name gives designs
    other filters); the aircraft's left-right symmetry gives PIT>LS and PIT>RS the same rates, and
    k = 0.2 - D_s for them."""
    from f16mmae import core
    from f16mmae.campaign.dual import models

    design, why = models.bank_design(core.load_bank(str(cover_partial_bank)))
    assert why is None and design.filter("LS:loss=0.5") is not None
    t = _tool()
    out = tmp_path / "pairs.json"
    assert t.main([str(cover_partial_bank), "--pairs", "PIT>LS,PIT>RS", "--m0", "0.2", "--out", str(out)]) == 0
    capsys.readouterr()
    import json
    table = json.loads(out.read_text())
    ls, rs = table["rates"]["PIT>LS"], table["rates"]["PIT>RS"]
    assert ls["d_single"] == pytest.approx(rs["d_single"], rel=1e-4) and ls["d_dual"] == pytest.approx(rs["d_dual"], rel=1e-4)
    assert 0.0 < ls["d_single"] < 0.2   # separable, but slower than m0: the pair takes an allowance
    assert table["pairs"]["PIT>LS"] == pytest.approx(0.2 - ls["d_single"])


def _load(name):
    return load_tool(f"cover/{name}.py")


def test_the_walk_and_the_channel_split_by_hand():
    import numpy as np

    walk = _load("level1_walk")
    # alternating +-1: every 2-frame sum is 0 (no long-run variance), a 1-frame "sum" has variance 1
    x = np.tile([1.0, -1.0], 50)
    assert walk.long_run_variance(x, 2) == pytest.approx(0.0, abs=1e-15)
    assert walk.long_run_variance(x, 1) == pytest.approx(1.0)
    # a constant step held for 4 frames then reversed: 4-frame sums are +-4, variance 16 / 4 = 4
    y = np.tile([1.0] * 4 + [-1.0] * 4, 10)
    assert walk.long_run_variance(y, 4) == pytest.approx(4.0)
    assert walk.mismatch_rate(0.8, 132, 1e-3, 22.9) == pytest.approx(0.8 * math.log(132e3) / 45.8)
    with pytest.raises(ValueError, match="two windows"):
        walk.long_run_variance(x[:3], 2)
    with pytest.raises(ValueError, match="alpha"):
        walk.mismatch_rate(0.8, 132, 0.0, 22.9)
    chan = _load("level0_channels")
    a = np.array([[2.0, 0.5, 0.0], [0.5, 1.0, 0.0], [0.0, 0.0, 4.0]])
    a_inv = chan.scored_inverse(a, np.array([0.0, 0.0, 3.0]))
    assert a_inv[2].tolist() == [0.0, 0.0, 0.0] and a_inv[:, 2].tolist() == [0.0, 0.0, 0.0]
    assert a_inv[:2, :2] == pytest.approx(np.linalg.inv(a)[:2, :2])
    r = np.array([0.3, -1.2, 5.0])
    split = chan.channel_split(r, a_inv)
    assert split.sum() == pytest.approx(-0.5 * r @ a_inv @ r) and split[2] == 0.0
