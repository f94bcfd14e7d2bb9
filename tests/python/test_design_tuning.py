"""Tuning files (design/tuning.py): the shipped ones load; bad files are refused with a
message naming the file, the key and the valid choices; each method's knob lands where the
paper puts it (methods 1-3 on diagonals, method 4 through a B column, eqs. 6-7)."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from f16mmae import names
from f16mmae.design import bank, discretize, model
from f16mmae.design.tuning import TuningError, available_tunings, load_tuning


def write(tmp_path, text):
    p = tmp_path / "t.toml"
    p.write_text(text)
    return p


def test_shipped_tunings_load():
    assert {"tuned", "untuned"} <= set(available_tunings())
    untuned = load_tuning("untuned")
    assert not (untuned.qd_longitudinal or untuned.r_pseudonoise or untuned.qd_lateral or untuned.actuator_q)
    tuned = load_tuning("tuned")
    assert tuned.qd_diagonal().any()


@pytest.mark.parametrize("text, message", [
    ('name = "x"\nbogus = 1\n', "unknown key 'bogus'; valid keys: name, description"),
    ('[method1_qd_longitudinal]\nr_rad_s = 1e-6\n',
     "unknown key 'r_rad_s' in \\[method1_qd_longitudinal\\]; valid keys: u_fps, alpha_rad"),
    ('[method2_r]\nAZ = -1e-4\n', "AZ = -0.0001 is not a variance"),
    ('[method3_qd_lateral]\np_rad_s = "big"\n', "p_rad_s must be a number"),
    ('[method4_actuator_q]\nLS = nan\n', "LS = nan is not a variance"),
    ('turbulence = "hurricane"\n', "turbulence 'hurricane' is not a level; valid: none, light"),
    ('gust_model = "x"\n', "gust_model 'x' is not a model; valid: gust_rate, white_gust"),
    ('name = [\n', "not valid TOML"),
    ('[estimator]\np_min = 0.5\n', r"\[estimator\] p_min = 0.5 is outside \(0, 0.01\)"),
    ('[estimator]\nthreshold = 0.4\n', r"\[estimator\] threshold = 0.4 is outside \(0.5, 1\)"),
    ('[estimator]\ndwell_s = -1\n', r"\[estimator\] dwell_s = -1 is outside \[0, 10\]"),
    ('[estimator]\nfloor = 1e-9\n',
     "unknown key 'floor' in \\[estimator\\]; valid keys: p_min, threshold, dwell_s"),
    ('[estimator]\np_min = "low"\n', r"\[estimator\] p_min must be a number"),
    ('failed_sensor_noise = "quiet"\n', "failed_sensor_noise 'quiet' is not one of design, sensor"),
])
def test_bad_tuning_files_are_refused(tmp_path, text, message):
    with pytest.raises(TuningError, match=message):
        load_tuning(write(tmp_path, text))


def test_estimator_settings_are_read_and_reach_the_bank_fields(tmp_path):
    t = load_tuning(write(tmp_path, '[estimator]\np_min = 1e-9\nthreshold = 0.95\ndwell_s = 0.5\n'))
    assert t.estimator == {"p_min": 1e-9, "threshold": 0.95, "dwell_s": 0.5}
    assert t.to_dict()["estimator"] == t.estimator
    assert load_tuning("untuned").estimator == {}      # the paper's settings: the core defaults
    tuned = load_tuning("tuned")
    from f16mmae.design import convergence
    table = tuned.estimator["dwell_nats_per_hypothesis"]   # tools/latency/dwell_per_hypothesis.py's
    assert {k: v for k, v in tuned.estimator.items() if k != "dwell_nats_per_hypothesis"} == convergence.ESTIMATOR
    d = bank.design_bank(tuning=tuned, hypotheses=(names.NONE, "LS", "RUD"))   # calibrate writes what stage 2 scored
    assert bank.to_model_bank(d).estimator_settings == {**convergence.ESTIMATOR,   # a subset takes its entries
                                                        "dwell_nats_per_hypothesis": {"LS": table["LS"]}}
    assert table["LS"] == 32.0 and table["RUD"] == 0.0
    assert "estimator" not in d.metadata()  # typed fields of the bank, not metadata text
    d = bank.design_bank(tuning=t, hypotheses=(names.NONE,))
    assert bank.to_model_bank(d).estimator_settings == t.estimator


def test_unknown_tuning_name_lists_the_shipped_ones():
    with pytest.raises(TuningError, match="unknown tuning 'nope'; shipped tunings: .*tuned"):
        load_tuning("nope")


@pytest.fixture(scope="module")
def continuous():
    lt = model.linearize_truth(0.4, 20_000.0)
    return model.build_model(lt.lin, lt.trim.vt_fps, "light", 20_000.0)


def test_methods_1_to_3_add_to_the_named_diagonal_entries(continuous, tmp_path):
    base = load_tuning("untuned")
    t = load_tuning(write(tmp_path, '[method1_qd_longitudinal]\nq_rad_s = 1e-6\n'
                                    '[method2_r]\nVEL = 0.25\n[method3_qd_lateral]\nr_rad_s = 2e-6\n'))
    d0, r0 = bank.discrete_design_model(continuous, base, 64.0)
    d1, r1 = bank.discrete_design_model(continuous, t, 64.0)
    dq = np.zeros(names.NX)
    dq[names.STATES.index("q_rad_s")] = 1e-6
    dq[names.STATES.index("r_rad_s")] = 2e-6
    assert np.allclose(d1.qd - d0.qd, np.diag(dq), atol=1e-18)
    dr = np.zeros(names.NZ)
    dr[names.SENSORS.index("VEL")] = 0.25
    assert np.array_equal(r1 - r0, np.diag(dr))


def test_method_4_enters_through_the_airframe_b_column(continuous):
    base = load_tuning("untuned")
    t = dataclasses.replace(base, actuator_q={"LS": 1e-4})
    d0, _ = bank.discrete_design_model(continuous, base, 64.0)
    d1, _ = bank.discrete_design_model(continuous, t, 64.0)
    b = continuous.b_airframe[:, [0]]
    expected = discretize.van_loan_qd(continuous.f, 1e-4 * b @ b.T, 1 / 64)
    assert np.allclose(d1.qd - d0.qd, expected, rtol=1e-6, atol=1e-16)
    assert np.linalg.eigvalsh(d1.qd - d0.qd).min() > -1e-15
    assert not b[8:].any()  # the noise drives the airframe, not the lag state


def test_a_failed_sensor_s_channel_takes_the_sensor_s_own_noise(tmp_path):
    """``failed_sensor_noise = "sensor"``: each failed sensor j's residual variance A_jj is its
    noise variance NOISE_SIGMA_j^2 where ``"design"`` (the default, the paper's) keeps R_jj with
    the method-2 pseudonoise; its H row is zero, so nothing else of any filter changes (the
    steady-state P, K and A's other entries, and every filter without a failed sensor)."""
    from f16mmae.truth import sensors

    text = 'name = "x"\n[method2_r]\nVEL = 0.39\nAZ = 0.0047\n'
    paper = load_tuning(write(tmp_path, text))
    own = load_tuning(write(tmp_path, 'failed_sensor_noise = "sensor"\n' + text))
    assert paper.failed_sensor_noise == "design" and own.failed_sensor_noise == "sensor"
    assert "failed_sensor_noise" not in paper.to_dict() and own.to_dict()["failed_sensor_noise"] == "sensor"
    hyps = (names.NONE, "LS", "VEL", "AZ", "AZ+VEL", "LS+AZ")
    a, b = (bank.design_bank(tuning=t, hypotheses=hyps) for t in (paper, own))
    for fa, fb in zip(a.filters, b.filters):
        failed = [names.SENSORS.index(c) for c in names.failed_components(fa.name) if c in names.SENSORS]
        for j in failed:
            assert not fa.model.h[j].any()
            assert fa.gains.a[j, j] == a.r[j, j] == sensors.NOISE_SIGMA[j] ** 2 + {"VEL": 0.39, "AZ": 0.0047}[names.SENSORS[j]]
            assert fb.gains.a[j, j] == sensors.NOISE_SIGMA[j] ** 2
        keep = np.ones(names.NZ, dtype=bool)
        keep[failed] = False
        assert np.array_equal(fa.gains.k, fb.gains.k) and np.array_equal(fa.gains.p_minus, fb.gains.p_minus)
        assert np.array_equal(fa.gains.a[np.ix_(keep, keep)], fb.gains.a[np.ix_(keep, keep)])
        assert np.array_equal(fa.gains.a[keep][:, ~keep], fb.gains.a[keep][:, ~keep])
        assert failed or np.array_equal(fa.gains.a, fb.gains.a)


def test_the_failed_sensor_noise_flag_designs_one_point(tmp_path, capsys):
    """``f16mmae design --failed-sensor-noise sensor``: the bank file's failed AZ reads the
    sensor's own noise where the tuning's AZ carries pseudonoise, named in the tuning; a bad value
    is refused before any work, naming the choices."""
    from f16mmae import core
    from f16mmae.cli.main import main
    from f16mmae.truth import sensors

    t = write(tmp_path, 'name = "az"\n[method2_r]\nAZ = 0.0047\n')
    out = tmp_path / "b.f16bank"
    assert main(["design", "--tuning", str(t), "--failed-sensor-noise", "sensor", "--out", str(out)]) == 0
    mb = core.load_bank(str(out))
    j = names.SENSORS.index("AZ")
    az = {h.name: np.asarray(h.a) for h in mb.hypotheses}
    assert az["AZ"][j, j] == sensors.NOISE_SIGMA[j] ** 2 and az["LS+AZ"][j, j] == az["AZ"][j, j]
    assert az["NONE"][j, j] > 0.0047 and mb.tuning == "az-noise-sensor"
    assert main(["design", "--failed-sensor-noise", "loud", "--out", str(tmp_path / "x.f16bank")]) == 2
    assert "--failed-sensor-noise 'loud': valid: design, sensor" in capsys.readouterr().err
    assert not (tmp_path / "x.f16bank").exists()


@pytest.mark.parametrize("flags", [["--failed-sensor-noise", "sensor"], ["--failure-model", "cover"]])
def test_the_turbulence_bank_set_refuses_the_member_design_flags(flags, tmp_path, capsys):
    """``design --turbulence-banks`` designs its members as it chooses: a failure model or failed
    sensors' noise given with it is refused before any work, not silently dropped."""
    from f16mmae.cli.main import main

    out = tmp_path / "s.f16set"
    assert main(["design", "--turbulence-banks", *flags, "--out", str(out)]) == 2
    assert "--turbulence-banks designs its own members" in capsys.readouterr().err and not out.exists()
