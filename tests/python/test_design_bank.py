"""The model bank of the design (design/bank.py) and ``f16mmae design``: the bank file holds
all 79 filters, the trim and the flight condition; regenerating is deterministic and
reproduces the shipped nominal banks bit for bit; bad inputs are refused with clear messages;
the design report shows every single failure's filter winning after its failure."""
from __future__ import annotations

import json

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.cli import main as cli
from f16mmae.design import bank


@pytest.fixture(scope="module")
def tuned_design():
    return bank.design_bank(bank.NOMINAL_MACH, bank.NOMINAL_ALT_FT, "tuned")


def test_bank_holds_every_hypothesis_and_the_trim(tuned_design, tmp_path):
    mb = bank.write_bank(tuned_design, tmp_path / "b.f16bank")
    assert list(mb.hypothesis_names) == list(names.ALL_HYPOTHESES)
    assert list(mb.state_names) == list(names.STATES)
    assert mb.frame_rate_hz == names.FRAME_RATE_HZ and mb.tuning == "tuned"
    assert (mb.mach, mb.alt_ft) == (0.4, 20_000.0)
    assert np.array_equal(mb.u_trim, tuned_design.u_trim)
    assert np.array_equal(mb.z_trim, tuned_design.z_trim)
    assert np.array_equal(mb.h_output, mb["NONE"].h)
    for f in tuned_design.filters:
        h = mb[f.name]
        for key in ("phi", "bd", "h", "k", "a"):
            ours = getattr(f.model, key) if key in ("phi", "bd", "h") else getattr(f.gains, key)
            assert np.array_equal(getattr(h, key), ours), (f.name, key)
    meta = json.loads(mb.metadata)
    assert meta["tuning"]["name"] == "tuned" and meta["hypotheses"] == 79
    assert meta["command"] == "f16mmae design --mach 0.4 --alt-ft 20000 --tuning tuned"


def test_regenerating_is_deterministic(tuned_design):
    again = bank.design_bank(bank.NOMINAL_MACH, bank.NOMINAL_ALT_FT, "tuned")
    assert bank.to_model_bank(again).to_bytes() == bank.to_model_bank(tuned_design).to_bytes()


def _approx_equal_json(a, b, rel=1e-9):
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_approx_equal_json(a[k], b[k], rel) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(_approx_equal_json(x, y, rel) for x, y in zip(a, b))
    if isinstance(a, float):
        return b == pytest.approx(a, rel=rel, abs=1e-300)
    return a == b


@pytest.mark.parametrize("tuning", ["tuned", "untuned"])
def test_shipped_nominal_bank_matches_a_regeneration(tuning, tuned_design):
    """On the machine that generated them the regenerated banks are bit-identical (same
    content hash); elsewhere LAPACK/BLAS kernels may differ in the last bits, so what is
    asserted is agreement to 1e-9 relative (and equal names, shapes, tuning, metadata keys).
    A failure means the truth model, the design procedure or the tuning changed."""
    path = bank.nominal_bank_path(tuning)
    fix = f"regenerate: python -m f16mmae.design.calibrate --write (or f16mmae design --tuning {tuning} --out {path})"
    shipped = core.load_bank(path)
    fresh = bank.to_model_bank(tuned_design if tuning == "tuned" else
                               bank.design_bank(bank.NOMINAL_MACH, bank.NOMINAL_ALT_FT, tuning))
    if fresh.content_hash == shipped.content_hash:
        return
    assert list(fresh.hypothesis_names) == list(shipped.hypothesis_names), fix
    assert (fresh.tuning, fresh.mach, fresh.alt_ft) == (shipped.tuning, shipped.mach, shipped.alt_ft), fix
    for a, b in ((fresh.u_trim, shipped.u_trim), (fresh.z_trim, shipped.z_trim),
                 (fresh.h_output, shipped.h_output)):
        assert np.allclose(a, b, rtol=1e-9, atol=1e-12), fix
    for name in fresh.hypothesis_names:
        for key in ("phi", "bd", "h", "k", "a"):
            a, b = getattr(fresh[name], key), getattr(shipped[name], key)
            assert np.allclose(a, b, rtol=1e-9, atol=1e-12 * max(1.0, np.abs(b).max())), (name, key, fix)
    assert [h.dwell_nats for h in fresh.hypotheses] == [h.dwell_nats for h in shipped.hypotheses], fix
    assert _approx_equal_json(json.loads(fresh.metadata), json.loads(shipped.metadata)), fix


def test_cli_writes_a_bank(tmp_path, capsys):
    out = tmp_path / "x.f16bank"
    assert cli.main(["design", "--tuning", "untuned", "--out", str(out)]) == 0
    assert "79 hypotheses" in capsys.readouterr().out
    assert core.load_bank(out).tuning == "untuned"


@pytest.mark.parametrize("argv, message", [
    (["--mach", "0.9"], "--mach 0.9 is outside the design envelope 0.3-0.8"),
    (["--mach", "0.2"], "--mach 0.2 is outside the design envelope 0.3-0.8"),
    (["--alt-ft", "40000"], "--alt-ft 40000 is outside the design envelope 5000-35000 ft"),
    (["--alt-ft", "abc"], "--alt-ft 'abc' is not a number"),
    (["--tuning", "nope"], "unknown tuning 'nope'; shipped tunings: tuned, tuned_gust, untuned"),
])
def test_cli_refuses_bad_inputs(argv, message, tmp_path, capsys):
    assert cli.main(["design", *argv, "--out", str(tmp_path / "b.f16bank")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.startswith("f16mmae design: error:")
    assert not (tmp_path / "b.f16bank").exists()


@pytest.mark.parametrize("text, message", [
    ("[method2_r]\nAZ = -1e-4\n", "[method2_r] AZ = -0.0001 is not a variance"),
    ("[method3_qd_lateral]\nyaw = 1e-6\n", "unknown key 'yaw' in [method3_qd_lateral]"),
])
def test_cli_refuses_bad_tuning_files(text, message, tmp_path, capsys):
    p = tmp_path / "bad.toml"
    p.write_text(text)
    assert cli.main(["design", "--tuning", str(p), "--out", str(tmp_path / "b.f16bank")]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.slow
def test_report_shows_consistent_residuals_and_failure_sensitivity(tuned_design, tmp_path):
    from f16mmae.design.report import write_report

    paths = write_report(tuned_design, tmp_path)
    assert all(p.is_file() and p.stat().st_size > 0 for p in paths)
    text = paths[0].read_text()
    nis = float(text.split("NIS mean ")[1].split()[0])
    assert 5.5 < nis < 9.0, text  # tuned NONE filter in no-failure flight: NIS ~ m = 7
    verdicts = [line.split()[-1] for line in text.splitlines() if "most likely" in line and ":" in line]
    assert verdicts == ["ok"] * names.K_BANK, text


def test_the_core_filter_bank_runs_the_shipped_bank_as_designed():
    """The C++ FilterBank on the shipped bank's level-0 filters gives the residuals of the
    design's own numpy filter (design/residuals.py) on a nonlinear flight, and NONE wins."""
    from f16mmae.design.flights import fly_closed_loop
    from f16mmae.design.residuals import filter_residuals

    mb = core.load_bank(bank.nominal_bank_path("tuned"))
    level0 = [mb[n] for n in names.SINGLE_HYPOTHESES]
    fb = core.FilterBank([core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a) for h in level0])
    fl = fly_closed_loop(seed=3)
    res = np.empty((len(fl.z), names.K_BANK, names.NZ))
    for i in range(len(fl.z)):
        fb.update(fl.z[i])
        res[i] = fb.residuals
        fb.propagate(fl.u[i])
    for j, h in enumerate(level0):
        ref = filter_residuals(h.phi, h.bd, h.h, h.k, fl.u, fl.z)
        assert np.allclose(res[:, j], ref, rtol=1e-9, atol=1e-12), h.name
    assert int(np.argmax(fb.probabilities)) == 0
