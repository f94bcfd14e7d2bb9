"""Sensors agree with JSBSim's own state (independent formulas), noise has the documented
sigma, and the ideal function is the one the sensors use."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.truth import Scenario, TruthModel, aircraft, fly_raw, sensors
from f16mmae.truth.dither import DitherSpec


def _independent(fdm) -> np.ndarray:
    """The seven measurements from other JSBSim quantities than sensors.SENSOR_PROPERTIES."""
    vt, a, b = fdm["velocities/vt-fps"], fdm["aero/alpha-rad"], fdm["aero/beta-rad"]
    return np.array([
        vt * math.cos(a) * math.cos(b),                       # body forward airspeed
        math.atan2(fdm["velocities/w-aero-fps"], fdm["velocities/u-aero-fps"]),
        fdm["velocities/q-aero-rad_sec"] + fdm["atmosphere/q-turb-rad_sec"],
        -_specific_force_body(fdm)[2] / G0_FPS2,                # kinematics: a - g, in g
        fdm["velocities/p-aero-rad_sec"] + fdm["atmosphere/p-turb-rad_sec"],
        fdm["velocities/r-aero-rad_sec"] + fdm["atmosphere/r-turb-rad_sec"],
        _specific_force_body(fdm)[1] / G0_FPS2,
    ])


G0_FPS2 = 32.174


def _specific_force_body(fdm) -> np.ndarray:
    """Body-axis specific force (ft/s^2) from kinematics: d(v_b)/dt + omega x v_b - g_b."""
    u, v, w = fdm["velocities/u-fps"], fdm["velocities/v-fps"], fdm["velocities/w-fps"]
    p, q, r = fdm["velocities/p-rad_sec"], fdm["velocities/q-rad_sec"], fdm["velocities/r-rad_sec"]
    acc = np.array([fdm["accelerations/udot-ft_sec2"], fdm["accelerations/vdot-ft_sec2"],
                    fdm["accelerations/wdot-ft_sec2"]]) + np.cross([p, q, r], [u, v, w])
    th, ph, g = fdm["attitude/theta-rad"], fdm["attitude/phi-rad"], fdm["accelerations/gravity-ft_sec2"]
    g_b = g * np.array([-math.sin(th), math.cos(th) * math.sin(ph), math.cos(th) * math.cos(ph)])
    return acc - g_b


def test_ideal_sensors_match_jsbsim_state_while_manoeuvring():
    sc = Scenario(duration_s=3.0, turbulence="light", noise=False, feedback="raw",
                  dither=DitherSpec(amplitude_deg=(2, 1, 2, 1, 3)), seed=4)
    truth = TruthModel(sc)
    from f16mmae.truth import FlightControlSystem
    fcs = FlightControlSystem(truth.trim, sc, pilot=lambda t: (0.3, math.radians(5)))
    worst = np.zeros(7)
    for i in range(int(3.0 * 64)):
        z = truth.measure()
        assert np.array_equal(z, sensors.ideal(truth.fdm))  # noise off: z is ideal exactly
        worst = np.maximum(worst, np.abs(z - _independent(truth.fdm)))
        truth.advance(fcs.command(z, i / 64))
    tol = np.array([1e-6, 1e-9, 1e-6, 5e-3, 1e-6, 1e-6, 5e-3])  # accelerations: earth rotation
    assert np.all(worst < tol), worst
    # and the run was a manoeuvre, not a trim: rates and loads moved
    log = truth.truth_log
    assert np.ptp(log["z"][:, 3]) > 0.1 and np.ptp(log["z"][:, 4]) > math.radians(2)


def test_noise_has_the_documented_sigma_and_zero_mean():
    truth, _ = fly_raw(Scenario(duration_s=16.0, seed=9, feedback="raw"))
    log = truth.truth_log
    v = log["z"] - log["z_ideal"]
    sig = v.std(axis=0)
    assert np.allclose(sig, sensors.NOISE_SIGMA, rtol=0.1), sig / sensors.NOISE_SIGMA
    assert np.all(np.abs(v.mean(axis=0)) < 4 * sensors.NOISE_SIGMA / math.sqrt(len(v)))
    # white: lag-1 correlation near zero in every channel
    for j in range(7):
        r = np.corrcoef(v[:-1, j], v[1:, j])[0, 1]
        assert abs(r) < 0.1


def test_sensor_units_and_trim_values_are_physical():
    fdm, tp = aircraft.trimmed_fdm(0.4, 20_000.0)
    z = sensors.ideal(fdm)
    assert z[0] == pytest.approx(tp.vt_fps * math.cos(tp.alpha_rad), rel=1e-6)   # ft/s
    assert z[1] == pytest.approx(math.radians(8.12), abs=math.radians(0.05))     # rad
    assert z[3] == pytest.approx(math.cos(tp.theta_rad), abs=0.01)               # g, up positive
