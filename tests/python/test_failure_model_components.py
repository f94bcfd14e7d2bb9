"""A failure model per component (design/hypotheses.py): the forms it is written in and their
errors, a mixed bank whose other filters are the complete bank's bit for bit and whose covered
filters are the all-cover bank's, a VEL-cover filter's density against SciPy, and the bank
file saying which model each hypothesis has."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.cli.main import main
from f16mmae.design import bank
from f16mmae.design.hypotheses import (check_failure_model, component_models, failure_model_table,
                                       uninformative_width, uses_cover)
from f16mmae.design.model import linearize_truth
from f16mmae.design.tuning import TuningError, load_tuning, tuning_from_dict
from f16mmae.truth import sensors

from test_failure_models import expected_log_likelihood

COVERED = ("LS", "VEL", "AOA")
HYPOTHESES = ("NONE", "LS", "RS", "VEL", "AOA", "PIT", "AZ", "LS+VEL", "VEL+AOA", "VEL+PIT", "RS+AOA", "PIT+AZ",
              "LS+RS")


def test_every_form_reads_to_one_canonical_text():
    table = {"default": "complete", "cover": ["AOA", "VEL"]}
    for form in ("cover=VEL+AOA", "complete,cover=AOA+VEL", " cover = VEL + AOA ", table):
        assert check_failure_model(form) == "cover=VEL+AOA"
    per = component_models("cover=VEL+AOA")
    assert [c for c, m in per.items() if m == "cover"] == ["VEL", "AOA"] and len(per) == 12
    assert check_failure_model("cover,complete=PIT+ROL") == "cover,complete=PIT+ROL"
    assert component_models("cover,complete=PIT+ROL")["PIT"] == "complete"
    assert component_models("cover,complete=PIT+ROL")["LS"] == "cover"
    # one model for every component reads as its name, however it was written
    assert check_failure_model("cover=" + "+".join(names.COMPONENTS)) == "cover"
    assert check_failure_model({"default": "cover"}) == "cover" and check_failure_model("complete") == "complete"
    assert failure_model_table("cover=VEL+AOA") == {"default": "complete", "cover": ["VEL", "AOA"]}
    assert failure_model_table("cover,complete=PIT") == {"default": "cover", "complete": ["PIT"]}
    assert failure_model_table("cover") == "cover"
    assert uses_cover("cover=AZ") and not uses_cover("complete")


@pytest.mark.parametrize("bad, message", [
    ("cover=VELO", "unknown component 'VELO'; valid: LS, RS, LF, RF, RUD, VEL, AOA, PIT, AZ, ROL, YAW, AY"),
    ("partial=VEL", "'partial' is not a failure model; valid: complete, cover"),
    ("cover=VEL+AOA,complete=VEL", "component VEL is given a model twice"),
    ("cover,complete", "names more than one default model (cover, complete)"),
    ({"default": "complete", "cover": "VEL"}, "must be a list of components"),
    ({"default": "partial"}, "'partial' is not a failure model"),
    (3, "must be a model name (complete, cover, constant)"),
])
def test_a_bad_failure_model_is_refused_naming_what_is_valid(bad, message):
    with pytest.raises(ValueError) as exc:
        check_failure_model(bad)
    assert message in str(exc.value)
    with pytest.raises(TuningError) as exc:
        tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": bad}, source="t.toml")
    assert str(exc.value).startswith("t.toml: failure_model") and message in str(exc.value)


def test_the_tuning_reads_the_table_and_writes_it_back():
    t = tuning_from_dict({**load_tuning("tuned").to_dict(),
                          "failure_model": {"default": "complete", "cover": ["VEL", "AOA"]}})
    assert t.failure_model == "cover=VEL+AOA"
    back = t.to_dict()
    assert back["failure_model"] == {"default": "complete", "cover": ["VEL", "AOA"]}
    assert tuning_from_dict(back) == t
    assert "failure_model" not in load_tuning("tuned").to_dict()  # the paper's tuning keeps its bytes


@pytest.fixture(scope="module")
def banks():
    """The same linearization designed three ways: complete, all cover, cover for LS, VEL, AOA."""
    lin = linearize_truth(0.4, 20_000.0)
    base = load_tuning("tuned")
    out = {}
    for key, model in (("complete", "complete"), ("cover", "cover"), ("mixed", "+".join(COVERED))):
        fm = model if key != "mixed" else check_failure_model(f"cover={model}")
        t = dataclasses.replace(base, name=f"tuned-{fm}", failure_model=fm)
        out[key] = bank.design_bank(0.4, 20_000.0, t, hypotheses=HYPOTHESES, linearized=lin)
    return out


def _same(a, b):
    ma, mb = a.model, b.model
    return all(np.array_equal(x, y) for x, y in (
        (ma.phi, mb.phi), (ma.bd, mb.bd), (ma.h, mb.h), (ma.qd, mb.qd), (a.gains.k, b.gains.k),
        (a.gains.a, b.gains.a), (ma.uninformative_width, mb.uninformative_width),
        (ma.uninformative_level_q, mb.uninformative_level_q)))


def test_a_mixed_bank_is_the_complete_bank_but_for_its_covered_components(banks):
    for name in HYPOTHESES:
        failed = set(names.failed_components(name))
        mixed = banks["mixed"].filter(name)
        if not failed & set(COVERED):  # bit for bit the complete bank's
            assert _same(mixed, banks["complete"].filter(name)), name
        elif failed <= set(COVERED):  # bit for bit the all-cover bank's
            assert _same(mixed, banks["cover"].filter(name)), name
            assert not _same(mixed, banks["complete"].filter(name)), name
    # a hypothesis mixing the two: VEL uninformative over its range, PIT's row removed (Gaussian)
    vp = banks["mixed"].filter("VEL+PIT").model
    full = [hi - lo for lo, hi in sensors.FULL_SCALE]
    assert list(vp.uninformative_width) == [full[0]] + [0.0] * 6
    assert not vp.h[names.SENSORS.index("PIT")].any() and not vp.h[names.SENSORS.index("VEL")].any()
    ra = banks["mixed"].filter("RS+AOA").model  # RS complete: its lag keeps the no-failure dynamics
    assert np.array_equal(ra.phi, banks["complete"].filter("NONE").model.phi)
    assert np.array_equal(uninformative_width("RS+AOA", "cover=LS+VEL+AOA"), ra.uninformative_width)
    # LS covered: its lag state is a random walk; RS complete: it decays to trim
    i_ls, i_rs = (names.NX - names.NU + names.ACTUATORS.index(c) for c in ("LS", "RS"))
    assert banks["mixed"].filter("LS").model.phi[i_ls, i_ls] == 1.0
    assert banks["mixed"].filter("LS+RS").model.phi[i_rs, i_rs] < 0.75


def test_a_vel_cover_filter_density_against_scipy(banks):
    """The core's log-likelihood of the mixed bank's VEL filter (and NONE, PIT beside it) on two
    frames: a normal over six channels times 1/W, then the VEL level's predictive density."""
    d = banks["mixed"]
    models = [core.FilterModel(phi=f.model.phi, bd=f.model.bd, h=f.model.h, k=f.gains.k, a=f.gains.a,
                               uninformative_width=f.model.uninformative_width,
                               uninformative_level_q=f.model.uninformative_level_q)
              for f in (d.filter("NONE"), d.filter("VEL"), d.filter("PIT"))]
    assert models[1].uninformative_width[0] == sensors.FULL_SCALE[0][1] - sensors.FULL_SCALE[0][0]
    assert not any(models[2].uninformative_width)
    fb = core.FilterBank(models, p_min=1e-6, strip_leading_term=False)
    frames = [np.array([35.0, 0.004, 0.002, 0.03, -0.01, 0.003, 0.004]),
              np.array([35.4, 0.003, 0.001, 0.02, -0.008, 0.002, 0.006])]
    for n, z in enumerate(frames):
        fb.update(z)
        res = np.asarray(fb.residuals)
        for k, m in enumerate(models):
            assert fb.log_likelihoods[k] == pytest.approx(expected_log_likelihood(m, res[k], frames[:n + 1]),
                                                          rel=1e-9, abs=1e-9), (n, k)
        fb.propagate(np.zeros(names.NU))
    # a VEL reading 35 ft/s off trim: the VEL filter explains it, NONE does not
    assert fb.log_likelihoods[1] > fb.log_likelihoods[0] + 100


def test_the_bank_file_says_which_model_each_hypothesis_has(banks, tmp_path):
    loaded = bank.write_bank(banks["mixed"], tmp_path / "mixed.f16bank")
    meta = json.loads(loaded.metadata)
    assert meta["tuning"]["failure_model"] == {"default": "complete", "cover": ["LS", "VEL", "AOA"]}
    assert meta["command"] == "f16mmae design --mach 0.4 --alt-ft 20000 --tuning tuned --failure-model cover=LS+VEL+AOA"
    for h, f in zip(loaded.hypotheses, banks["mixed"].filters):
        assert np.array_equal(h.uninformative_width, f.model.uninformative_width)
    other = bank.write_bank(banks["cover"], tmp_path / "cover.f16bank")
    assert other.content_hash != loaded.content_hash


def test_design_reads_a_per_component_failure_model(capsys, tmp_path):
    out = tmp_path / "m.f16bank"
    assert main(["design", "--failure-model", "cover=VEL+AOA", "--out", str(out)]) == 0
    meta = json.loads(core.load_bank(str(out)).metadata)
    assert meta["tuning"]["failure_model"] == {"default": "complete", "cover": ["VEL", "AOA"]}
    assert "tuning tuned-cover=VEL+AOA" in capsys.readouterr().out
    bad = tmp_path / "bad.f16bank"
    assert main(["design", "--failure-model", "cover=VEL+AOB", "--out", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "--failure-model: failure_model cover: unknown component 'AOB'; valid: LS, RS" in err
    assert not bad.exists()
