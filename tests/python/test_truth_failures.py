"""Every failure mode changes what it should: actuators (unit level, exact) and in flight
(the surface stops / runs away / the airframe answers through the mixer), sensors (each mode
reads what it says), and the ``--fail`` parser refuses bad input naming the valid choices."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.names import ACTUATORS, SENSORS
from f16mmae.truth import Scenario, fly_raw, parse_fail, parse_fail_args, sensors
from f16mmae.truth.actuators import (ACTUATOR_MODES, LAG_RAD_S, POSITION_LIMIT_RAD,
                                     RATE_LIMIT_RAD_S, ActuatorBank)
from f16mmae.truth.dither import DitherSpec
from f16mmae.truth.failures import FailureSpec, make_failure
from f16mmae.truth.sensors import SENSOR_MODES

DT = 1.0 / 128


# -- parser ------------------------------------------------------------------------------------
def test_parse_fail_accepts_the_cli_syntax():
    assert parse_fail("LS@3.0") == FailureSpec("LS", 3.0, "complete", None)
    assert parse_fail("pit@5:Stuck") == FailureSpec("PIT", 5.0, "stuck", None)
    assert parse_fail(" az@2:bias=0.2 ") == FailureSpec("AZ", 2.0, "bias", 0.2)
    assert parse_fail("RUD@1:hardover=-1").value == -1.0
    specs = parse_fail_args(["PIT@5.0:stuck", "LS@3.0"])
    assert [s.name for s in specs] == ["LS", "PIT"]


@pytest.mark.parametrize("text,words", [
    ("XX@3", ["unknown failure name", "LS", "AY"]),
    ("LS@-1", ["time", ">= 0"]),
    ("LS@abc", ["not a number"]),
    ("LS@3:null", ["unknown failure mode", "complete, stuck, hardover, loss"]),
    ("PIT@3:loss", ["unknown failure mode", "complete, null, stuck, hardover, bias, drift"]),
    ("LS3", ["NAME@TIME"]),
    ("LS@", ["missing time"]),
    ("LS@1:loss=1.5", ["[0, 1)"]),
    ("LS@1:stuck=2", ["takes no value"]),
    ("LS@1:hardover=0", ["+1 or -1"]),
    ("LS@inf", [">= 0"]),
])
def test_parse_fail_refuses_bad_input_clearly(text, words):
    with pytest.raises(ValueError) as exc:
        parse_fail(text)
    for w in words:
        assert w in str(exc.value)


def test_a_component_fails_only_once():
    with pytest.raises(ValueError, match="more than once"):
        parse_fail_args(["LS@1", "ls@2:stuck"])


# -- actuators, unit level -----------------------------------------------------------------------
def test_actuator_is_the_exact_first_order_lag_inside_its_limits():
    bank = ActuatorBank([0.0] * 5, DT)
    cmd = [0.001, -0.001, 0.002, -0.002, 0.003]   # small: no rate limit
    for n in range(1, 20):
        out = bank.step(cmd)
    expect = [c * (1 - math.exp(-LAG_RAD_S[i] * DT * 19)) for i, c in enumerate(cmd)]
    assert np.allclose(out, expect, rtol=1e-12)


def test_actuator_rate_and_position_limits():
    bank = ActuatorBank([0.0] * 5, DT)
    out = bank.step([1.0] * 5)   # far beyond every limit: runs at the rate limit
    assert np.allclose(out, [r * DT for r in RATE_LIMIT_RAD_S])
    for _ in range(400):
        out = bank.step([1.0] * 5)
    assert np.allclose(out, POSITION_LIMIT_RAD)


@pytest.mark.parametrize("mode", ACTUATOR_MODES)
def test_actuator_failure_modes_unit(mode):
    trim = [0.01, 0.01, 0.0, 0.0, 0.0]
    bank = ActuatorBank(trim, DT)
    cmd = [0.05, 0.05, 0.05, 0.05, 0.05]
    for _ in range(10):
        bank.step(cmd)
    before = list(bank.position_rad)
    bank.fail(0, mode)
    outs = [bank.step([-0.05] * 5) for _ in range(200)]
    ls = np.array([o[0] for o in outs])
    if mode == "complete":
        assert ls[-1] == trim[0] and np.all(np.abs(np.diff(ls)) <= RATE_LIMIT_RAD_S[0] * DT + 1e-15)
    elif mode == "stuck":
        assert np.all(ls == before[0])
    elif mode == "hardover":
        assert ls[-1] == POSITION_LIMIT_RAD[0]
        assert np.allclose(np.diff(ls[:5]), RATE_LIMIT_RAD_S[0] * DT)
    elif mode == "loss":   # default: half effectiveness about trim
        assert ls[-1] == pytest.approx(trim[0] + 0.5 * (bank.position_rad[0] - trim[0]))
        assert bank.position_rad[0] == pytest.approx(-0.05, abs=1e-6)   # the surface itself moves
    # the other actuators are untouched
    assert outs[-1][1] == pytest.approx(-0.05, abs=1e-6)


# -- actuators in flight -------------------------------------------------------------------------
def _fly(failures, duration_s=4.0, **kw):
    sc = Scenario(duration_s=duration_s, feedback="raw", noise=False,
                  failures=tuple(parse_fail(f) for f in failures), **kw)
    truth, _ = fly_raw(sc)
    return truth, truth.truth_log


@pytest.fixture(scope="module")
def nominal_log():
    return _fly([])[1]


@pytest.mark.parametrize("name", ACTUATORS)
def test_stuck_surface_stops_moving_and_others_keep_moving(name):
    truth, log = _fly([f"{name}@1.0:stuck"])
    j = ACTUATORS.index(name)
    t = log["time_s"][: len(log["surface_rad"])]
    after = log["surface_rad"][t >= 1.0, j]
    assert np.ptp(after) == 0.0
    others = [k for k in range(5) if k != j]
    assert np.all(np.ptp(log["surface_rad"][t >= 1.0][:, others], axis=0) > 1e-3)
    assert log["onsets"] == [{"name": name, "time_s": 1.0, "mode": "stuck", "onset_s": 1.0}]


def test_complete_failure_holds_trim_exactly(nominal_log):
    truth, log = _fly(["RF@1.0"])
    t = log["time_s"][: len(log["surface_rad"])]
    assert np.all(log["surface_rad"][t >= 1.05, 3] == truth.trim.u_rad[3])
    assert np.ptp(nominal_log["surface_rad"][t >= 1.05, 3]) > 0.01   # it moved when healthy


def test_stuck_left_stabilator_rolls_and_pitches_the_aircraft(nominal_log):
    # LS jammed 3 deg trailing edge down: the mixer turns it into pitch AND roll
    truth, log = _fly(["LS@0.5:hardover"], dither=DitherSpec(enabled=False), duration_s=1.0)
    ls = log["surface_rad"][:, 0]
    assert ls[-1] > ls[0] + math.radians(10)    # ran away at 60 deg/s
    z = log["z_ideal"] - truth.trim.z
    t = log["time_s"]
    assert np.max(np.abs(z[t > 0.5, 4])) > math.radians(3)    # roll rate builds
    assert np.max(np.abs(z[t > 0.5, 2])) > math.radians(1)    # pitch rate builds
    # the FCS fights it with the other surfaces
    assert np.ptp(log["surface_rad"][:, 1]) > math.radians(1)


def test_loss_reduces_the_surface_effect():
    _, full = _fly([], dither=DitherSpec(amplitude_deg=(0, 0, 0, 0, 2.0)), duration_s=3.0)
    _, lossy = _fly(["RUD@0:loss=0.25"], dither=DitherSpec(amplitude_deg=(0, 0, 0, 0, 2.0)),
                    duration_s=3.0)
    r_full = np.ptp(full["z_ideal"][64:, 5])
    r_loss = np.ptp(lossy["z_ideal"][64:, 5])
    assert r_loss < 0.5 * r_full


# -- sensors in flight -----------------------------------------------------------------------------
@pytest.mark.parametrize("mode", SENSOR_MODES)
def test_sensor_failure_modes_read_what_they_say(mode):
    name, j, tf = "PIT", SENSORS.index("PIT"), 1.0
    sc = Scenario(duration_s=3.0, feedback="raw", seed=2, failures=(make_failure(name, tf, mode),))
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    t, z, zi = log["time_s"], log["z"][:, j], log["z_ideal"][:, j]
    after, before = t >= tf, t < tf
    sig = sensors.NOISE_SIGMA[j]
    if mode == "complete":
        assert np.all(np.abs(z[after] - truth.trim.z[j]) < 5 * sig)
        assert np.std(z[after]) == pytest.approx(sig, rel=0.25)
    elif mode == "null":
        assert np.all(z[after] == 0.0)
    elif mode == "stuck":
        assert np.all(z[after] == z[before][-1])
    elif mode == "hardover":
        assert np.all(z[after] == sensors.FULL_SCALE[j][1])
    elif mode == "bias":
        assert np.mean(z[after] - zi[after]) == pytest.approx(sensors.BIAS_DEFAULT[j], abs=3 * sig / 8)
    elif mode == "drift":
        slope = np.polyfit(t[after] - tf, z[after] - zi[after], 1)[0]
        assert slope == pytest.approx(sensors.DRIFT_DEFAULT[j], rel=0.05)
    # before the onset: healthy (noise about the truth), other sensors healthy throughout
    assert np.all(np.abs(z[before] - zi[before]) < 5 * sig)
    k = SENSORS.index("ROL")
    assert np.all(np.abs(log["z"][:, k] - log["z_ideal"][:, k]) < 5 * sensors.NOISE_SIGMA[k])
    assert log["onsets"][0]["onset_s"] == tf


def test_several_failures_in_one_run_each_at_its_time():
    sc = Scenario(duration_s=3.0, feedback="raw", failures=(
        parse_fail("AZ@0.5:null"), parse_fail("LF@1.25:stuck"), parse_fail("YAW@2:hardover=-1")))
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    assert [o["onset_s"] for o in log["onsets"]] == [0.5, 1.25, 2.0]
    t = log["time_s"]
    assert np.all(log["z"][t >= 0.5, 3] == 0.0) and np.all(log["z"][t < 0.5, 3] != 0.0)
    assert np.all(log["z"][t >= 2.0, 5] == sensors.FULL_SCALE[5][0])
