"""The sensor-loss dither (truth/dither.py ``sensor_loss_gains``, ``--sensor-loss-dither``): its
rule, its table within the subliminal criterion, and the closed loop that sets it from the
estimator's declaration."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from f16mmae.loop import estimator_options
from f16mmae.names import ACTUATORS, SENSORS
from f16mmae.truth import Scenario, fly_raw
from f16mmae.truth.dither import (CRITERION, SENSOR_LOSS_GAIN_RATE, SENSOR_LOSS_GAINS, DitherSpec,
                                  SensorLossDither, sensor_loss_gains)

#: The lines: name -> (surfaces, RS in opposite phase).
LINES = {"stabilators": ((0, 1), False), "opposite": ((0, 1), True), "flaperons": ((2, 3), False),
         "rudder": ((4,), False)}


def test_the_rule_reads_the_declared_sensor_alone():
    for sensor, row in SENSOR_LOSS_GAINS.items():
        assert sensor in SENSORS and len(row) == 5
        g, h = sensor_loss_gains(sensor)
        assert g == list(row) and h == [0.0] * 5
        # the flaperons share a line: one gain; the stabilators may differ (their line then has a
        # part in opposite phase), the pair's mean at least 1
        assert row[2] == row[3] and row[0] + row[1] >= 2.0
        assert all(x > 0.0 for x in row) and max(row) > 1.0
    fixed = ([1.0] * 5, [0.0] * 5)
    listed = next(iter(SENSOR_LOSS_GAINS))
    # nothing declared, a surface, a partial loss, a dual with the sensor in it: the fixed dither
    for name in ("NONE", "LS", "RS:loss=0.5", f"LS+{listed}", *(s for s in SENSORS if s not in SENSOR_LOSS_GAINS)):
        assert sensor_loss_gains(name) == fixed
    with pytest.raises(ValueError, match="unknown component 'XYZ'"):
        sensor_loss_gains("XYZ")
    with pytest.raises(ValueError, match="must be a name"):
        sensor_loss_gains(None)


def test_the_ramp_moves_at_its_rate_and_lands_on_each_row():
    rule = SensorLossDither(rate=2.0)
    row = SENSOR_LOSS_GAINS["PIT"]
    dt = 1.0 / 64.0
    g, h = rule.gains("NONE", dt)
    assert g == [1.0] * 5 and h == [0.0] * 5
    g, _ = rule.gains("PIT", dt)  # one frame: 2 dt up where the row is above 1
    assert g == pytest.approx([1.0 + 2.0 * dt if x > 1.0 else 1.0 for x in row])
    steps = int(np.ceil((max(row) - 1.0) / (2.0 * dt)))
    for _ in range(steps):
        g, _ = rule.gains("PIT", dt)
    assert g == list(row)  # exactly the row
    for _ in range(steps):
        g, _ = rule.gains("LS+PIT", dt)  # a dual: back to the fixed dither, exactly
    assert g == [1.0] * 5
    assert SensorLossDither().rate == SENSOR_LOSS_GAIN_RATE
    for bad in (0.0, -1.0, float("nan"), True):
        with pytest.raises(ValueError, match="gain rate"):
            SensorLossDither(rate=bad)
    with pytest.raises(ValueError, match="positive finite time"):
        rule.gains("PIT", 0.0)


def _line_peaks():
    """Each line alone at the nominal point (no noise, no turbulence, the control law on the
    sensors): peak |Delta n_z| g, |p|, |q|, |r| deg/s, |Delta n_y| g over the last 6 of 8 s."""
    base = DitherSpec()
    out = {}
    for name, (idx, opposite) in LINES.items():
        amp = tuple(a if j in idx else 0.0 for j, a in enumerate(base.amplitude_deg))
        phase = tuple(ph + (np.pi if opposite and j == 1 else 0.0) for j, ph in enumerate(base.phase_rad))
        truth, _ = fly_raw(Scenario(duration_s=8.0, noise=False, feedback="raw",
                                    dither=dataclasses.replace(base, amplitude_deg=amp, phase_rad=phase)))
        log = truth.truth_log
        dz = (log["z_ideal"] - truth.trim.z)[log["time_s"] >= 2.0]
        p = np.abs(dz).max(axis=0)
        out[name] = np.array([p[3], np.degrees(p[4]), np.degrees(p[2]), np.degrees(p[5]), p[6]])
    return out


def test_every_row_keeps_the_lines_bound_within_the_criterion():
    """The peak of a sum of lines is at most the sum of their peaks; each row's gains on the lines
    (the stabilators': their mean in phase, half their difference in opposite phase) times the
    measured peaks of the lines stays below 0.95 of the criterion on every channel."""
    a = _line_peaks()
    crit = np.array([CRITERION["nz_g"], CRITERION["rate_deg_s"], CRITERION["rate_deg_s"],
                     CRITERION["rate_deg_s"], CRITERION["ny_g"]])
    for sensor, row in SENSOR_LOSS_GAINS.items():
        bound = ((row[0] + row[1]) / 2 * a["stabilators"] + abs(row[0] - row[1]) / 2 * a["opposite"]
                 + row[2] * a["flaperons"] + row[4] * a["rudder"])
        assert np.all(bound < 0.95 * crit), (sensor, bound / crit)


def test_the_option_is_the_closed_loops_and_the_daemon_takes_no_flag_for_it():
    opt = estimator_options.BY_KEY["sensor_loss_dither"]
    assert opt.flag == "--sensor-loss-dither" and opt.kind == "switch" and not opt.in_daemon
    assert "sensor_loss_dither" in estimator_options.HARNESS_ONLY
    # the truth side's rule: the executive needs no flag (it reads the status's declared hypothesis)
    assert "sensor_loss_dither" in estimator_options.CLOSED_LOOP
    from f16mmae.lcm.daemon import daemon_flags
    assert daemon_flags({"sensor_loss_dither": True, "p_min": 1e-9}) == ("--p-min", "1e-09")


def test_the_loop_raises_the_line_after_the_sensor_is_declared():
    """A pitch-rate gyro failed at 1 s in calm air without noise: with the option the commands
    equal the fixed dither's flight up to the frame the estimator declares PIT, and from then on
    the stabilators' 1.7-Hz line is the table's gain larger."""
    from f16mmae.banks import load_bank
    from f16mmae.loop.flight import fly, scenario_from_dict
    _, _, bank = load_bank("tuned")
    sc = {"mach": 0.4, "alt_ft": 20000.0, "turbulence": "none", "noise": False, "duration_s": 6.0, "seed": 1,
          "feedback": "mmae", "failures": [{"name": "PIT", "time_s": 1.0, "mode": "complete"}]}
    runs = {on: fly(scenario_from_dict(sc), bank, estimator_options={"sensor_loss_dither": True} if on else {},
                    record_probabilities=False, record_series=True) for on in (False, True)}
    off, on = runs[False], runs[True]
    assert on.declarations[0]["hypothesis"] == "PIT"
    k = int(round(on.declarations[0]["time_s"] * 64))
    u_off, u_on = off.series["u"], on.series["u"]
    np.testing.assert_array_equal(u_off[:k], u_on[:k])
    assert not np.array_equal(u_off[k:], u_on[k:])
    # the 1.7-Hz amplitude of LS over the last 3 s: the gain's ratio, to the control law's share
    t = np.arange(len(u_on))[-192:] / 64.0
    basis = np.column_stack([np.ones_like(t), t, np.sin(2 * np.pi * 1.7 * t), np.cos(2 * np.pi * 1.7 * t)])
    amp = [np.hypot(*np.linalg.lstsq(basis, u[-192:, 0], rcond=None)[0][2:]) for u in (u_off, u_on)]
    g = SENSOR_LOSS_GAINS["PIT"][ACTUATORS.index("LS")]
    assert amp[1] / amp[0] == pytest.approx(g, rel=0.15)
    # and the aircraft's response from the declaration on, ramp included, within the criterion
    log = on.series["truth_log"]
    dz = (log["z_ideal"] - log["z_ideal"][0])[log["time_s"] >= on.declarations[0]["time_s"]]
    p = np.abs(dz).max(axis=0)
    assert p[3] < CRITERION["nz_g"] and p[6] < CRITERION["ny_g"]
    assert np.all(np.degrees(p[[2, 4, 5]]) < CRITERION["rate_deg_s"]), np.degrees(p[[2, 4, 5]])
    assert np.degrees(p[2]) > 0.7  # the larger line shows in q (0.63 deg/s with the fixed dither)


def test_the_loop_refuses_both_rules_of_the_gains():
    from f16mmae.loop.flight import fly, scenario_from_dict

    class Both:  # an estimator whose settings ask for both rules
        settings = {"sensor_loss_dither": True, "adaptive_dither": True}
        hypotheses = ("NONE",)

    sc = {"mach": 0.4, "alt_ft": 20000.0, "duration_s": 1.0, "seed": 1, "feedback": "mmae"}
    with pytest.raises(ValueError, match="give one"):
        fly(scenario_from_dict(sc), None, estimator=Both())
    # and before any flight, where the options are checked (the CLI, every campaign)
    for given in ({"sensor_loss_dither": True, "turbulence_banks": True},
                  {"sensor_loss_dither": True, "turbulence_banks": True, "adaptive_dither": True}):
        with pytest.raises(ValueError, match="add --fixed-dither"):
            estimator_options.check(given)
    estimator_options.check({"sensor_loss_dither": True, "turbulence_banks": True, "fixed_dither": True})
