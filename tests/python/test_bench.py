"""f16mmae.bench and ``f16mmae bench``: the numpy reference MMAE against a hand-computed
Bayes update and against the C++ bank (probabilities to 1e-9 on every frame), the
synthetic bank, and the command's table and JSON. Speed itself is not asserted here."""
from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.bench import estimator as bench
from f16mmae.cli.main import main



@pytest.fixture(scope="module")
def models():
    return bench.synthetic_models(seed=1)


@pytest.fixture(scope="module")
def frames(models):
    return bench.synthetic_frames(models, 400, seed=2, failed="AOA")


def test_synthetic_models_are_proper_filters_with_their_failure_removed(models):
    assert [n for n, _ in models] == list(names.SINGLE_HYPOTHESES)
    by_name = dict(models)
    np.testing.assert_array_equal(by_name["RUD"]["bd"][:, 4], 0.0)
    np.testing.assert_array_equal(by_name["AOA"]["h"][1], 0.0)
    for _, m in models:  # K = P H^T A^-1 with P the DARE's fixed point
        p_next = m["phi"] @ (m["p"] - m["k"] @ m["h"] @ m["p"]) @ m["phi"].T + m["q"]
        np.testing.assert_allclose(p_next, m["p"], atol=1e-10)
    bank = bench.synthetic_bank()
    assert bank.hypothesis_names == names.SINGLE_HYPOTHESES and bank.tuning == "synthetic"


def test_floor_keeps_ratios_above_it():
    p = np.array([0.9, 0.0995, 1e-4, 4e-4])
    out, log_out = bench._floor(p, np.log(p), 0.001)
    np.testing.assert_allclose(out[2:], 0.001)
    assert math.isclose(out.sum(), 1.0, abs_tol=1e-15)
    assert math.isclose(out[0] / out[1], 0.9 / 0.0995, rel_tol=1e-14)
    np.testing.assert_allclose(np.exp(log_out), out, rtol=1e-14)


def test_numpy_reference_matches_a_hand_computed_frame():
    """Three scalar hypotheses, x- = 0 so r = z: p_k ∝ exp(-z^2 / (2 a_k)) p_k, floored."""
    one = np.ones((1, 1))
    a = [0.25, 1.0, 4.0]  # z fits the high-variance hypotheses better: none reaches the floor
    models = [(f"H{i}", dict(phi=0.5 * one, bd=one, h=one, k=0.5 * one, a=a_i * one)) for i, a_i in enumerate(a)]
    ref = bench.NumpyMMAE(models, p_min=0.001)
    z = 1.0
    prior = np.array([0.998, 0.001, 0.001])
    post = prior * np.exp([-z * z / (2 * a_i) for a_i in a])
    post /= post.sum()
    p = ref.step(np.array([z]), np.array([0.2]))
    assert post.min() > 0.001
    np.testing.assert_allclose(p, post, rtol=1e-14)
    np.testing.assert_allclose(ref.residuals[:, 0], z)
    np.testing.assert_allclose(ref.x_prior[:, 0], 0.5 * (0.5 * z) + 0.2)  # Phi (K r) + Bd u


def test_numpy_reference_and_cpp_bank_agree_to_1e9_on_every_frame(models, frames):
    z, u = frames
    cpp, reference = bench.core_filter_bank(models), bench.NumpyMMAE(models)
    worst = 0.0
    for zi, ui in zip(z, u):
        p_cpp = np.array(cpp.step(zi, ui))
        p_ref = reference.step(zi, ui)
        worst = max(worst, float(np.max(np.abs(p_cpp - p_ref))))
    assert worst < 1e-9
    np.testing.assert_allclose(np.asarray(cpp.blended_state), reference.blended_state, atol=1e-9)
    assert bench.max_probability_difference(models, z, u) == pytest.approx(worst, abs=1e-12)


def test_the_reference_finds_the_failure_in_the_synthetic_frames(models, frames):
    z, u = frames
    reference = bench.NumpyMMAE(models)
    for i, (zi, ui) in enumerate(zip(z, u)):
        p = reference.step(zi, ui)
        if i == len(z) // 2 - 1:
            assert names.SINGLE_HYPOTHESES[int(np.argmax(p))] == names.NONE
    assert names.SINGLE_HYPOTHESES[int(np.argmax(p))] == "AOA"


def test_cpp_loop_timing_refuses_a_bank_of_the_wrong_size(frames):
    z, u = frames
    small = bench.synthetic_bank(names.SINGLE_HYPOTHESES[:5])
    with pytest.raises(ValueError, match="F-16-size bank .* got 5 hypotheses"):
        core._bench_filter_bank_loop(small, z, u)
    with pytest.raises(ValueError, match=r"z must be \(N, 7\)"):
        core._bench_filter_bank_loop(bench.synthetic_bank(), u, u)
    assert 0.0 < core._bench_filter_bank_loop(bench.synthetic_bank(), z, u, min_time_s=0.0) < 1e-3


def test_bench_command_prints_the_table_and_writes_json(tmp_path, capsys):
    out = tmp_path / "bench.json"
    assert main(["bench", "estimator", "--frames", "40", "--min-time", "0", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    for label in ("(a) C++ loop", "(b) Python call", "(c) numpy reference", "(d) filterpy"):
        assert label in text
    record = json.loads(out.read_text())
    assert record["frames"] == 40 and len(record["bank_hash"]) == 64
    assert record["us_per_frame"]["cpp_loop"] > 0 and record["us_per_frame"]["numpy"] > 0
    assert {"cpu", "cores", "python", "numpy"} <= set(record["machine"])
    assert record["f16mmae_version"]
    if record["us_per_frame"]["filterpy"] is not None:
        assert record["ratios"]["filterpy / cpp_loop"] == pytest.approx(
            record["us_per_frame"]["filterpy"] / record["us_per_frame"]["cpp_loop"])


@pytest.mark.parametrize("argv, message", [
    (["--frames", "0"], "--frames '0' must be >= 1"),
    (["--frames", "many"], "--frames 'many' is not an integer"),
    (["--min-time", "-1"], "--min-time '-1' must be >= 0.0"),
    (["--min-time", "7200"], "--min-time '7200' must be < 3600.0"),
    (["--frames", "1e12"], "--frames '1e12' is not an integer"),
    (["--frames", "100000000"], "--frames '100000000' must be < 10000000"),
    (["--json", "."], "--json '.' is a directory"),
])
def test_bench_command_refuses_bad_arguments(capsys, argv, message):
    assert main(["bench", "estimator", *argv]) == 2
    assert re.search(message, capsys.readouterr().err)


def test_bench_json_under_a_file_is_refused_before_timing(tmp_path, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    assert main(["bench", "estimator", "--frames", "40", "--json", str(blocker / "bench.json")]) == 2
    err = capsys.readouterr()
    assert "a-file" in err.err and "not a directory" in err.err and "us/frame" not in err.out


def test_bench_truth_prints_truth_bare_and_closed_loop(capsys):
    assert main(["bench", "truth", "--duration-s", "0.5", "--repeat", "1", "--campaign-runs", "1"]) == 0
    out = capsys.readouterr().out
    for label in ("bare JSBSim stock f16, stepping", "truth model, C++ engine, per flight",
                  "truth model, Python engine, per flight", "first flight of its condition",
                  "the same with the stock contact points", "derived stepping / the same with the contact points",
                  "closed loop (tuned bank, Mach 0.4, 20000 ft, probabilities recorded) / truth alone",
                  "(goal <= 1.1)", "estimator's frames", "the truth's frames slower beside it",
                  "Python around the call", "the C++ calls alone: closed loop", "dither levels",
                  "single-failure campaign, 13 flights"):
        assert label in out


def test_bench_truth_times_the_closed_loop_with_the_bank_and_options_given(capsys):
    assert main(["bench", "truth", "--duration-s", "0.5", "--repeat", "1", "--campaign-runs", "0",
                 "--mach", "0.45", "--alt-ft", "21000", "--adapt-turbulence", "--trim-tracking", "30"]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("closed loop"))
    assert line.startswith("closed loop (tuned bank, adapt_turbulence True, trim_time_constant_s 30.0, Mach 0.45, "
                           "21000 ft, probabilities recorded) / truth alone: ")
    assert "goal" not in line  # the goals are the tuned bank as designed (1.1) and the scheduled bank (1.3)


@pytest.mark.parametrize("argv, message", [
    (["--bank", "nope"], "--bank: 'nope' is neither a shipped tuning"),
    (["--mach", "3"], "--mach '3' must be <="),
    (["--trim-tracking", "-1"], "--trim-tracking -1.0 must lie in "),
    (["--duration-s", "0"], "--duration-s '0' must be > 0.0"),
    (["--duration-s", "1e12"], "--duration-s '1e12' must be < 3600.0"),
    (["--repeat", "0"], "--repeat '0' must be >= 1"),
    (["--campaign-runs", "-1"], "--campaign-runs '-1' must be >= 0"),
])
def test_bench_truth_refuses_bad_arguments(capsys, argv, message):
    assert main(["bench", "truth", *argv]) == 2
    assert re.search(message, capsys.readouterr().err)


def test_bench_lcm_hands_its_options_to_the_latency_benchmark(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["bench", "lcm", "--help"])
    assert stop.value.code == 0
    assert "--placement" in capsys.readouterr().out


def test_bench_without_a_kind_lists_the_three(capsys):
    assert main(["bench"]) == 2
    out = capsys.readouterr().out
    assert all(k in out for k in ("estimator", "truth", "lcm"))
