"""Partial-loss hypotheses (``f16mmae design --partial-loss F``, issue 13): the partial
hypothesis' B_d column is F times the no-failure one (against an independent discretization of
the continuous model), the rest of its model is the no-failure model's and its gains its own
Riccati solution; the bank file carries it and the hierarchical bank puts it on line at level 0;
a filter taken off line (``FilterBank.set_live``) leaves the others a Bayes update computed by
hand; a partial declaration is scored as its surface's isolation; bad input is refused."""
from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.linalg import expm, solve_discrete_are

from f16mmae import core, names
from f16mmae.campaign.engine import outcomes, scoring
from f16mmae.cli.main import main
from f16mmae.design import bank, hypotheses
from f16mmae.design.tuning import load_tuning, tuning_from_dict

PARTIALS = tuple(f"{s}:loss=0.5" for s in names.ACTUATORS)


@pytest.fixture(scope="module")
def partial_design():
    tuning = tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": "cover"}, default_name="cover")
    return bank.design_bank(0.4, 20_000.0, tuning, partial_loss=(0.5,))


def test_names_round_trip_and_bad_names_are_refused():
    assert hypotheses.partial_name("RUD", 0.5) == "RUD:loss=0.5"
    assert hypotheses.parse_partial("LF:loss=0.25") == ("LF", 0.25)
    assert hypotheses.parse_partial("LF") is None and hypotheses.parse_partial("LS+PIT") is None
    assert hypotheses.isolated_component("RS:loss=0.5") == "RS"
    assert hypotheses.isolated_component("RS+PIT") == "RS+PIT"
    assert names.failed_components("RS:loss=0.5") == ("RS",)   # the dual campaign scores a partial as its surface
    with pytest.raises(ValueError, match="unknown component 'XX'"):
        names.failed_components("XX:loss=0.5")
    assert hypotheses.partial_hypotheses((0.5,)) == PARTIALS
    assert hypotheses.partial_hypotheses((0.25,))[0] == "LS:loss=0.75"   # F lost, R = 1 - F kept
    with pytest.raises(ValueError, match="needs a surface"):
        hypotheses.partial_name("PIT", 0.5)
    with pytest.raises(ValueError, match=r"must lie in \(0, 1\)"):
        hypotheses.partial_name("LS", 1.0)
    with pytest.raises(ValueError, match="expected SURFACE:loss=R"):
        hypotheses.parse_partial("LS:stuck=0.5")
    with pytest.raises(ValueError, match=r"fraction lost must lie in \(0, 1\)"):
        hypotheses.partial_hypotheses((1.0,))
    with pytest.raises(ValueError, match="given twice"):
        hypotheses.partial_hypotheses((0.5, 0.5))


def test_the_partial_filter_is_the_no_failure_model_with_its_column_scaled(partial_design):
    d = partial_design
    assert [f.name for f in d.filters][-5:] == list(PARTIALS)
    none = d.filter("NONE").model
    # an independent B_d: the zero-order hold of the continuous model, by one matrix exponential
    cont = d.continuous
    n, m = cont.f.shape[0], cont.b.shape[1]
    big = np.zeros((n + m, n + m))
    big[:n, :n], big[:n, n:] = cont.f, cont.b
    e = expm(big / names.FRAME_RATE_HZ)
    phi, bd = e[:n, :n], e[:n, n:]
    for j, name in enumerate(PARTIALS):
        p = d.filter(name)
        want = bd.copy()
        want[:, j] *= 0.5
        np.testing.assert_allclose(p.model.bd, want, rtol=1e-9, atol=1e-12 * np.abs(bd).max())
        np.testing.assert_allclose(p.model.phi, phi, rtol=1e-9, atol=1e-12)
        assert np.array_equal(p.model.bd[:, j], 0.5 * none.bd[:, j])
        for key in ("phi", "h", "qd"):
            assert np.array_equal(getattr(p.model, key), getattr(none, key)), (name, key)
        assert not p.model.uninformative_width.any()
        # its own gains: the a-priori Riccati solution of its model
        pp = solve_discrete_are(p.model.phi.T, p.model.h.T, p.model.qd, d.r)
        a = p.model.h @ pp @ p.model.h.T + d.r
        np.testing.assert_allclose(p.gains.a, a, rtol=1e-7, atol=1e-9 * np.abs(a).max())
        k = pp @ p.model.h.T @ np.linalg.inv(a)
        np.testing.assert_allclose(p.gains.k, k, rtol=1e-6, atol=1e-8 * np.abs(k).max())


def test_the_bank_file_carries_them_and_level_zero_holds_them(partial_design, tmp_path):
    mb = bank.write_bank(partial_design, tmp_path / "p.f16bank")
    assert list(mb.hypothesis_names)[-5:] == list(PARTIALS)
    meta = json.loads(mb.metadata)
    assert meta["partial_loss"] == [0.5] and meta["command"].endswith("--partial-loss 0.5")
    again = core.load_bank(str(tmp_path / "p.f16bank"))
    assert np.array_equal(again["LS:loss=0.5"].bd, partial_design.filter("LS:loss=0.5").model.bd)
    hb = core.HierarchicalBank(mb)
    assert list(hb.hypotheses) == list(names.SINGLE_HYPOTHESES) + list(PARTIALS)


def test_no_partial_loss_changes_nothing(partial_design):
    d = bank.design_bank(0.4, 20_000.0, partial_design.tuning, hypotheses=names.SINGLE_HYPOTHESES + ("LS+PIT",),
                         linearized=partial_design.linearized)
    assert "partial_loss" not in d.metadata() and "--partial-loss" not in d.metadata()["command"]
    for f in d.filters:
        assert np.array_equal(f.gains.k, partial_design.filter(f.name).gains.k)


def _small_models():
    rng = np.random.default_rng(3)
    phi = np.diag([0.9, 0.8, 0.7]) + 0.05 * rng.standard_normal((3, 3))
    h = np.array([[1.0, 0.2, 0.0], [0.0, 1.0, 0.3], [0.4, 0.0, 1.0]])
    r = np.diag([0.1, 0.2, 0.05])
    out = []
    for scale in (1.0, 2.0, 0.5, 3.0):
        pp = solve_discrete_are(phi.T, h.T, scale * np.diag([0.02, 0.03, 0.01]), r)
        a = h @ pp @ h.T + r
        out.append(core.FilterModel(phi=phi, bd=np.eye(3)[:, :2], h=h, k=pp @ h.T @ np.linalg.inv(a), a=a))
    return out


def test_set_live_leaves_the_others_a_bayes_update_computed_by_hand():
    models = _small_models()
    prior = np.array([0.4, 0.3, 0.2, 0.1])
    fb = core.FilterBank(models, p_min=0.0, initial_probabilities=prior)
    fb.set_live(2, False)
    assert not fb.live(2) and fb.live(1)
    live = [0, 1, 3]
    np.testing.assert_allclose(fb.probabilities[live], prior[live] / 0.8, rtol=1e-14)
    assert fb.probabilities[2] == 0.0
    z = np.array([0.3, -0.2, 0.5])
    p = fb.update(z)   # first frame from x = 0: r = z
    like = np.array([np.exp(-0.5 * z @ np.linalg.solve(np.asarray(m.a), z)) for m in models])
    want = np.zeros(4)
    want[live] = prior[live] * like[live]
    want /= want.sum()
    np.testing.assert_allclose(p, want, rtol=1e-12, atol=1e-300)
    assert p[2] == 0.0
    with pytest.raises(ValueError, match="filter 0 stays live"):
        fb.set_live(0, False)


def test_a_partial_declaration_scores_as_its_surface():
    decl = [{"hypothesis": "LS:loss=0.5", "time_s": 3.6}, {"hypothesis": "LS+PIT", "time_s": 5.0}]
    iso = scoring.isolating_declarations(decl[:1])
    assert iso == [{"hypothesis": "LS", "time_s": 3.6}]
    s = scoring.score_run("LS", 3.0, iso)
    assert s["outcome"] == "correct" and s["latency_s"] == pytest.approx(0.6)
    assert scoring.score_run("RS", 3.0, iso)["outcome"] == "wrong"
    assert not outcomes.transient_wrong(iso, 3.0, {"LS"})
    assert outcomes.transient_wrong(scoring.isolating_declarations(decl), 3.0, {"LS"})
    plain = [{"hypothesis": "LF", "time_s": 3.5}]
    assert scoring.isolating_declarations(plain) == plain


@pytest.mark.parametrize("argv, text", [
    (["--partial-loss", "1.5"], "must lie in (0, 1)"),
    (["--partial-loss", "0.5,0.5"], "given twice"),
    (["--partial-loss", "x"], "--partial-loss"),
    (["--partial-loss", "0.5", "--schedule"], "not supported with --schedule"),
    (["--partial-loss", "0.5", "--turbulence-banks"], "not supported with --schedule or --turbulence-banks"),
])
def test_bad_partial_loss_is_refused(capsys, tmp_path, argv, text):
    assert main(["design", *argv, "--out", str(tmp_path / "b.f16bank")]) == 2
    err = capsys.readouterr().err
    assert text in err and "Traceback" not in err


def test_declare_components_reaches_the_core_and_declares_a_split_surface(partial_design, tmp_path, capsys):
    """A tuning-seed flight (campaign seed 7's detectability, LF three quarters lost) in which LF's
    two forms share the mass: each hypothesis alone declares nothing, the components declare LF
    (cpp/f16mmae/declarer.h); the flag is recorded in run.json."""
    path = tmp_path / "partial.f16bank"
    core.save_bank(bank.to_model_bank(partial_design), str(path))
    argv = ["run", "--seed", "287851534", "--duration", "8.0", "--turbulence", "light", "--mach", "0.4",
            "--alt-ft", "20000.0", "--feedback", "mmae", "--fail", "LF@3.0:loss=0.25", "--bank", str(path),
            "--dwell-s", "0.5"]   # the dwell `f16mmae design` calibrates for this bank
    runs = {}
    for label, extra in (("alone", []), ("components", ["--declare-components"])):
        assert main([*argv, *extra, "--out", str(tmp_path / label)]) == 0
        runs[label] = json.loads((tmp_path / label / "run.json").read_text())
    capsys.readouterr()
    assert runs["alone"]["declarations"] == []
    decl = runs["components"]["declarations"]
    assert decl and decl[0]["hypothesis"] in ("LF", "LF:loss=0.5") and decl[0]["time_s"] > 3.0
    assert runs["components"]["estimator_settings"]["declare_components"] is True
    assert "declare_components" not in runs["alone"]["estimator_settings"]


def test_the_partial_floor_reaches_the_core_and_shortens_the_climb(partial_design, tmp_path, capsys):
    """``--partial-p-min``: a tuning-seed flight (campaign seed 7's single campaign, RUD half lost
    at 3 s) declares RUD (either form) earlier from a partial floor of 1e-5 than from the
    level-0 floor (cpp/f16mmae/level_floors.h: ln(1e-5 / 1e-9) nats less to climb); the
    setting is in run.json; a bank without partial hypotheses is refused, naming the problem."""
    path = tmp_path / "partial.f16bank"
    core.save_bank(bank.to_model_bank(partial_design), str(path))
    argv = ["run", "--seed", "1213139639", "--duration", "8.0", "--turbulence", "light", "--mach", "0.4",
            "--alt-ft", "20000.0", "--feedback", "mmae", "--fail", "RUD@3.0:loss=0.5", "--bank", str(path),
            "--dwell-s", "0.5", "--declare-components"]
    runs = {}
    for label, extra in (("common", []), ("partial", ["--partial-p-min", "1e-5"])):
        assert main([*argv, *extra, "--out", str(tmp_path / label)]) == 0
        runs[label] = json.loads((tmp_path / label / "run.json").read_text())
    capsys.readouterr()
    first = {k: r["declarations"][0] for k, r in runs.items()}
    assert all(d["hypothesis"] in ("RUD", "RUD:loss=0.5") for d in first.values()), first
    assert 3.0 < first["partial"]["time_s"] < first["common"]["time_s"], first
    assert runs["partial"]["estimator_settings"]["partial_p_min"] == 1e-5
    assert "partial_p_min" not in runs["common"]["estimator_settings"]
    with pytest.raises(ValueError, match="no partial-loss hypothesis"):
        core.HierarchicalBank(bank.to_model_bank(bank.design_bank(0.4, 20_000.0, load_tuning("tuned"))),
                              partial_p_min=1e-5)


def test_the_reconfigure_feedback_flies_a_partial_bank(partial_design, tmp_path, capsys):
    """``--feedback reconfigure`` on a bank with partial hypotheses: a partial hypothesis names
    its surface (cpp/f16mmae/sensor_reconfiguration.h), so the control law keeps the raw sensors
    when one is declared; the tuning-seed flight of the test above declares a form of RUD."""
    path = tmp_path / "partial.f16bank"
    core.save_bank(bank.to_model_bank(partial_design), str(path))
    assert main(["run", "--seed", "1213139639", "--duration", "8.0", "--turbulence", "light", "--mach", "0.4",
                 "--alt-ft", "20000.0", "--feedback", "reconfigure", "--fail", "RUD@3.0:loss=0.5", "--bank",
                 str(path), "--dwell-s", "0.5", "--declare-components", "--partial-p-min", "1e-5",
                 "--out", str(tmp_path / "run")]) == 0
    capsys.readouterr()
    run = json.loads((tmp_path / "run" / "run.json").read_text())
    assert run["declarations"][0]["hypothesis"] in ("RUD", "RUD:loss=0.5"), run["declarations"]
    reconfiguration = core.SensorReconfiguration(bank.to_model_bank(partial_design))
    z, z_hat = np.arange(1.0, 8.0), -np.arange(1.0, 8.0)
    for name in PARTIALS:
        np.testing.assert_array_equal(reconfiguration.apply(name, z, z_hat), z)
