"""A failed cover sensor's level range as a design choice (design/level_width.py, the tuning's
``failed_sensor_level_width``, ``f16mmae design --failed-sensor-level-width``): the derived
range against closed forms on a system whose answer is known, the design with the key against
the one without it (only the named sensor's width differs; without it the bank is the one it
always was), and the refusals."""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.cli import main as cli
from f16mmae.design import bank, level_width
from f16mmae.design.tuning import TuningError, load_tuning, tuning_from_dict
from f16mmae.truth import dither as dither_mod
from f16mmae.truth import sensors

RATE = names.FRAME_RATE_HZ


def test_reading_sigma_matches_closed_forms():
    """Seven decoupled first-order readings x_j' = a_j x_j + w_j, z_j = x_j + v_j; only LS's
    dither line drives reading 0. Stationary variance q/(1 - a^2) + r; the LS line's steady
    sinusoid at w has amplitude |1 / (e^{i w T} - a)| times the line's, mean square half its
    square (17 whole periods of the 1.7-Hz line in the 10 s kept)."""
    a = np.array([0.9, 0.5, 0.95, 0.0, 0.8, 0.7, 0.3])
    q = np.array([1e-4, 2e-3, 3e-6, 1e-2, 5e-5, 1e-6, 4e-4])
    r = np.array([0.25, 1e-6, 3e-6, 1e-4, 3e-6, 3e-6, 2.5e-5])
    phi, qd, rr, h = np.diag(a), np.diag(q), np.diag(r), np.eye(7)
    bd = np.zeros((7, names.NU))
    bd[0, 0] = 1.0
    amp, w, _ = dither_mod.Dither().terms()
    line = amp[0] * abs(1.0 / (np.exp(1j * w[0] / RATE) - a[0]))
    expected = q / (1.0 - a * a) + r
    expected[0] += line ** 2 / 2.0
    assert level_width.reading_sigma(phi, bd, qd, rr, h, RATE) == pytest.approx(np.sqrt(expected), rel=1e-6)


def test_width_is_the_gaussians_entropy():
    """W = sqrt(2 pi e) sigma: the uniform's entropy ln W equals the Gaussian's; the constant
    then is ln(sqrt(A) / sigma) - 1/2."""
    sigma, a_jj = 0.012, 3.0e-6
    w = level_width.width_from_sigma(sigma)
    assert math.log(w) == pytest.approx(0.5 * math.log(2.0 * math.pi * math.e * sigma ** 2), rel=1e-12)
    assert level_width.occam_nats(w, a_jj) == pytest.approx(math.log(math.sqrt(a_jj) / sigma) - 0.5, rel=1e-12)


def test_unstable_modes_are_left_out_of_the_spread():
    """Modes on or outside the unit circle carry no stationary spread: on decoupled readings the
    stable ones keep their closed forms (dither line included), an unstable or marginal one reads
    its noise alone; coupled through a rotation (the modes no longer the axes) the same answer,
    rotated. A model that is not finite is refused."""
    a = np.array([0.9, 1.02, 0.95, 1.0, 0.8, 0.7, 0.3])
    q = np.array([1e-4, 2e-3, 3e-6, 1e-2, 5e-5, 1e-6, 4e-4])
    r = np.array([0.25, 1e-6, 3e-6, 1e-4, 3e-6, 3e-6, 2.5e-5])
    bd = np.zeros((7, names.NU))
    bd[0, 0] = 1.0
    amp, w, _ = dither_mod.Dither().terms()
    stable = np.abs(a) < 1.0
    expected = r.copy()
    expected[stable] += q[stable] / (1.0 - a[stable] ** 2)
    expected[0] += (amp[0] * abs(1.0 / (np.exp(1j * w[0] / RATE) - a[0]))) ** 2 / 2.0
    sigma = level_width.reading_sigma(np.diag(a), bd, np.diag(q), np.diag(r), np.eye(7), RATE)
    assert sigma == pytest.approx(np.sqrt(expected), rel=1e-6)
    rot, _ = np.linalg.qr(np.random.default_rng(3).normal(size=(7, 7)))   # x = rot y, y the decoupled states
    coupled = level_width.reading_sigma(rot @ np.diag(a) @ rot.T, rot @ bd, rot @ np.diag(q) @ rot.T,
                                        np.diag(r), rot.T, RATE)
    assert coupled == pytest.approx(np.sqrt(expected), rel=1e-6)
    with pytest.raises(ValueError, match="not finite"):
        level_width.reading_sigma(np.full((7, 7), np.nan), bd, np.eye(7), np.eye(7), np.eye(7), RATE)


@pytest.fixture(scope="module")
def cover_pair():
    """The cover design with PIT's full range (``PIT=range``, the former rule) and with its
    default, the derived width, on a few hypotheses."""
    cover = dataclasses.replace(load_tuning("tuned"), name="tuned-cover", failure_model="cover")
    hyps = ("NONE", "PIT", "LS", "ROL", "LS+PIT", "PIT+ROL")
    plain = dataclasses.replace(cover, name="tuned-cover-wPIT", failed_sensor_level_width={"PIT": "range"})
    return bank.design_bank(tuning=plain, hypotheses=hyps), bank.design_bank(tuning=cover, hypotheses=hyps)


def test_design_with_the_key_changes_only_the_named_width(cover_pair):
    plain, wide = cover_pair
    j = names.SENSORS.index("PIT")
    entry = wide.level_widths["PIT"]
    for f0, f1 in zip(plain.filters, wide.filters):
        for key in ("phi", "bd", "h", "qd", "uninformative_level_q"):
            assert np.array_equal(getattr(f0.model, key), getattr(f1.model, key)), (f0.name, key)
        assert np.array_equal(f0.gains.k, f1.gains.k) and np.array_equal(f0.gains.a, f1.gains.a)
        w0, w1 = np.array(f0.model.uninformative_width), np.array(f1.model.uninformative_width)
        if "PIT" in names.failed_components(f0.name):
            assert w0[j] == pytest.approx(sensors.FULL_SCALE[j][1] - sensors.FULL_SCALE[j][0])
            assert w1[j] == entry["width"]
            # the constant the core charges, from the filter's own A_jj
            a_jj = float(f1.gains.a[j, j])
            assert level_width.occam_nats(w1[j], a_jj) == pytest.approx(entry["occam_nats"], rel=1e-12)
            w0[j] = w1[j]
        assert np.array_equal(w0, w1), f0.name


def test_derived_pitch_gyro_constant_is_the_models_spread(cover_pair):
    """sigma_PIT from the no-failure model (Lyapunov plus the dither's response) and the
    constant it gives, against an independent sum: P as the series sum_k Phi^k Q Phi^k', 2^40
    terms by doubling (P_2n = P_n + Phi^n P_n Phi^n'), not the Lyapunov solver."""
    _, wide = cover_pair
    d, j = wide.discrete, names.SENSORS.index("PIT")
    hj = wide.continuous.h[j]
    p, a = d.qd.copy(), d.phi.copy()
    for _ in range(40):
        p = p + a @ p @ a.T
        a = a @ a
    total = float(hj @ p @ hj)
    dith = level_width.dither_response(d.phi, d.bd, wide.continuous.h, RATE)[j]
    sigma = math.sqrt(total + wide.r[j, j] + dith)
    entry = wide.level_widths["PIT"]
    assert entry["sigma"] == pytest.approx(sigma, rel=1e-4)
    assert entry["occam_nats"] == pytest.approx(math.log(math.sqrt(wide.r[j, j]) / sigma) - 0.5, abs=1e-4)
    assert -3.0 < entry["occam_nats"] < -2.0  # well above the full range's -6.17


def test_metadata_records_the_widths_and_the_command(cover_pair):
    plain, wide = cover_pair
    meta0, meta1 = plain.metadata(), wide.metadata()
    assert "level_widths" not in meta0 and meta0["tuning"]["failed_sensor_level_width"] == {"PIT": "range"}
    assert meta0["command"].endswith("--tuning tuned --failure-model cover --failed-sensor-level-width PIT=range")
    # the default: the derived width recorded, the tuning and command as they always were
    assert meta1["level_widths"]["PIT"] == wide.level_widths["PIT"] and list(meta1["level_widths"]) == ["PIT"]
    assert "failed_sensor_level_width" not in meta1["tuning"]
    assert meta1["command"].endswith("--tuning tuned --failure-model cover")
    # the metadata's tuning designs the same widths again
    again = tuning_from_dict(json.loads(json.dumps(meta0["tuning"])))
    assert again.failed_sensor_level_width == {"PIT": "range"}


def test_without_the_key_the_tuning_and_bank_are_unchanged():
    t = load_tuning("tuned")
    assert t.failed_sensor_level_width == {} and "failed_sensor_level_width" not in t.to_dict()
    shipped = core.load_bank(bank.nominal_bank_path("tuned"))
    assert "level_widths" not in json.loads(shipped.metadata)


@pytest.mark.parametrize("value, message", [
    ({"PIT": -1.0}, "failed_sensor_level_width.PIT = -1.0 must be a finite number > 0"),
    ({"PIT": "wide"}, "failed_sensor_level_width.PIT = 'wide' must be a finite number > 0"),
    ({"PITCH": "reading"}, "unknown sensor 'PITCH' in failed_sensor_level_width"),
    ("reading", "failed_sensor_level_width must be a table of sensors"),
])
def test_tuning_refuses_bad_widths(value, message):
    with pytest.raises(TuningError, match=message.replace("(", r"\(").replace(".", r"\.")):
        tuning_from_dict({"failure_model": "cover", "failed_sensor_level_width": value})


def test_width_of_a_sensor_not_covered_is_refused():
    t = tuning_from_dict({"failure_model": "cover=VEL", "failed_sensor_level_width": {"PIT": 0.05}})
    with pytest.raises(ValueError, match="names PIT, whose failure model is complete"):
        bank.design_bank(tuning=t, hypotheses=("NONE", "PIT"))


@pytest.mark.parametrize("argv, message", [
    (["--failed-sensor-level-width", "PIT=reading"], "the sensor's failure model is complete"),
    (["--failure-model", "cover", "--failed-sensor-level-width", "PIT"], "give SENSOR=W, SENSOR=reading or SENSOR=range"),
    (["--failure-model", "cover", "--failed-sensor-level-width", "PIT=-2"], "must be a finite number > 0"),
    (["--schedule", "--failed-sensor-level-width", "PIT=reading"], "designs one point's bank"),
])
def test_cli_refuses_bad_widths(argv, message, tmp_path, capsys):
    assert cli.main(["design", *argv, "--out", str(tmp_path / "b.f16bank")]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert not (tmp_path / "b.f16bank").exists()
