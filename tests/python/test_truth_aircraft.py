"""The derived JSBSim F-16: it trims like the stock aircraft, its mixer is the documented
matrix, surfaces are set directly, and impossible trims / bad flight conditions are refused."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.truth import actuators, aircraft, sensors
from f16mmae.truth.aircraft import TrimError


@pytest.fixture(scope="module")
def nominal():
    return aircraft.trimmed_fdm(0.4, 20_000.0)


def test_derived_aircraft_trims_like_the_stock_f16(nominal):
    _, tp = nominal
    stock = aircraft.load_fdm(stock=True)
    for k, v in (("ic/h-sl-ft", 20_000.0), ("ic/mach", 0.4), ("ic/gamma-deg", 0.0),
                 ("gear/gear-cmd-norm", 0.0), ("gear/gear-pos-norm", 0.0),
                 ("propulsion/engine[0]/set-running", 1)):
        stock[k] = v
    stock.run_ic()
    stock["simulation/do_simple_trim"] = 1
    assert tp.alpha_rad == pytest.approx(stock["aero/alpha-rad"], abs=1e-4)
    assert tp.vt_fps == pytest.approx(stock["velocities/vt-fps"], abs=0.01)
    assert tp.throttle == pytest.approx(stock["fcs/throttle-cmd-norm"], abs=1e-3)
    # both stabilators carry the stock elevator deflection; flaperons and rudder at zero
    assert tp.u_rad[0] == pytest.approx(stock["fcs/elevator-pos-rad"], abs=1e-4)
    assert tp.u_rad[0] == tp.u_rad[1]
    assert np.allclose(tp.u_rad[2:], 0.0, atol=1e-6)
    assert tp.lef_rad == pytest.approx(0.262)
    # the trim commands were folded into the surfaces: no pilot command remains
    for p in ("elevator", "aileron", "rudder"):
        assert nominal[0][f"fcs/{p}-cmd-norm"] == 0.0


def test_mixer_writes_the_documented_matrix(nominal):
    fdm, tp = nominal
    rng = np.random.default_rng(5)
    delta = tp.u_rad + rng.uniform(-0.05, 0.05, 5)
    aircraft.set_surfaces(fdm, delta)
    fdm.run_ic()
    got = np.array([fdm[p] for p in aircraft.AERO_CONTROL_PROPERTIES])
    k = actuators.DIFFERENTIAL_TAIL_ROLL_SHARE
    ls, rs, lf, rf, rud = delta
    expect = [(ls + rs) / 2, (lf - rf) / 2 + k * (ls - rs) / 2, lf + rf, rud]
    assert np.allclose(got, expect, atol=1e-12)
    assert np.allclose(actuators.MIXING @ delta, expect, atol=1e-12)
    assert np.allclose(aircraft.get_surfaces(fdm), delta)
    aircraft.set_surfaces(fdm, tp.u_rad)
    fdm.run_ic()


def test_one_stabilator_makes_pitch_and_roll_moments(nominal):
    fdm, tp = nominal
    fdm2, tp2 = aircraft.trimmed_fdm(0.4, 20_000.0)
    u = tp2.u_rad.copy()
    u[0] += math.radians(2.0)  # left stabilator trailing edge down
    aircraft.set_surfaces(fdm2, u)
    fdm2.run()
    assert fdm2["accelerations/qdot-rad_sec2"] < -0.02   # nose down
    assert fdm2["accelerations/pdot-rad_sec2"] > 0.01    # roll right (left tail lift up)
    # left flaperon trailing edge down also rolls right, more strongly
    fdm3, tp3 = aircraft.trimmed_fdm(0.4, 20_000.0)
    u = tp3.u_rad.copy()
    u[2] += math.radians(2.0)
    aircraft.set_surfaces(fdm3, u)
    fdm3.run()
    assert fdm3["accelerations/pdot-rad_sec2"] > 1.5 * fdm2["accelerations/pdot-rad_sec2"]


def test_trim_point_measurements_are_the_ideal_sensors(nominal):
    fdm, tp = nominal
    assert np.allclose(tp.z, sensors.ideal(fdm), atol=1e-9)
    assert tp.z[3] == pytest.approx(1.0, abs=0.03)  # about 1 g
    assert abs(tp.z[2]) < 1e-9 and abs(tp.z[4]) < 1e-9


@pytest.mark.parametrize("mach,alt_ft", [(0.3, 5_000.0), (0.8, 5_000.0), (0.8, 35_000.0), (0.6, 20_000.0)])
def test_trims_across_the_envelope(mach, alt_ft):
    fdm, tp = aircraft.trimmed_fdm(mach, alt_ft)
    assert abs(fdm["accelerations/qdot-rad_sec2"]) < 1e-3
    assert abs(fdm["accelerations/udot-ft_sec2"]) < 1e-2
    assert tp.mach == mach and tp.alt_ft == alt_ft
    assert np.all(np.abs(tp.u_rad) < np.array(actuators.POSITION_LIMIT_RAD))


def test_impossible_trim_is_a_clear_error():
    with pytest.raises(TrimError, match=r"Mach 0.3, 35000 ft"):
        aircraft.trimmed_fdm(0.3, 35_000.0)


@pytest.mark.parametrize("mach,alt_ft,word", [(0.9, 20_000.0, "mach"), (0.2, 20_000.0, "mach"),
                                               (0.4, 40_000.0, "alt_ft"), (0.4, 1_000.0, "alt_ft"),
                                               (float("nan"), 20_000.0, "mach")])
def test_flight_condition_outside_the_envelope_is_refused(mach, alt_ft, word):
    with pytest.raises(ValueError, match=word):
        aircraft.trimmed_fdm(mach, alt_ft)


def test_seed_below_one_is_refused():
    with pytest.raises(ValueError, match="seed"):
        aircraft.load_fdm(seed=0)


#: What the comparison of the two aircraft reads at every step: the states JSBSim integrates,
#: their derivatives, and the total forces and moments they come from.
_COMPARED = ("position/h-sl-ft", "position/lat-geod-rad", "position/long-gc-rad",
             "velocities/u-fps", "velocities/v-fps", "velocities/w-fps", "velocities/p-rad_sec",
             "velocities/q-rad_sec", "velocities/r-rad_sec", "attitude/phi-rad", "attitude/theta-rad",
             "attitude/psi-rad", "aero/alpha-rad", "aero/beta-rad", "accelerations/udot-ft_sec2",
             "accelerations/vdot-ft_sec2", "accelerations/wdot-ft_sec2", "accelerations/pdot-rad_sec2",
             "accelerations/qdot-rad_sec2", "accelerations/rdot-rad_sec2", "forces/fbx-total-lbs",
             "forces/fby-total-lbs", "forces/fbz-total-lbs", "moments/l-total-lbsft",
             "moments/m-total-lbsft", "moments/n-total-lbsft", "propulsion/engine[0]/n2",
             "propulsion/total-fuel-lbs")


def test_contact_points_change_no_flight_bit():
    """The derived aircraft flies without the stock contact points (aircraft module docstring):
    the same trim and, step for step, the same states, derivatives, forces and moments as the
    aircraft with them, through 10 s of hard random surface deflections in severe turbulence
    (compared exactly, not to a tolerance)."""
    from f16mmae.truth import turbulence

    flown = []
    for contacts in (True, False):
        fdm = aircraft.load_fdm(seed=7, cxx=True, contacts=contacts)
        tp = aircraft.trim(fdm, 0.4, 20_000.0)
        assert fdm["gear/num-units"] == (10 if contacts else 0)
        turbulence.apply(fdm, "severe")
        rng = np.random.default_rng(11)
        lim = np.array(actuators.POSITION_LIMIT_RAD)
        rows, gear = [], []
        for step in range(10 * 128):
            if step % 32 == 0:  # a new deflection every 0.25 s, up to half the position limits
                aircraft.set_surfaces(fdm, tp.u_rad + rng.uniform(-0.5, 0.5, 5) * lim)
            assert fdm.run()
            rows.append([fdm[p] for p in _COMPARED])
            gear.append([fdm[p] for p in ("forces/fbx-gear-lbs", "forces/fbz-gear-lbs", "moments/m-gear-lbsft")])
        flown.append((tp, np.array(rows), np.array(gear)))
    (tp_with, with_, gear_with), (tp_without, without, gear_without) = flown
    assert np.array_equal(tp_with.u_rad, tp_without.u_rad) and np.array_equal(tp_with.z, tp_without.z)
    assert np.array_equal(gear_with, np.zeros_like(gear_with)) and np.array_equal(gear_without, gear_with)
    # the flight is a hard one, not the trim held: alpha and roll rate swing widely
    assert np.ptp(with_[:, _COMPARED.index("aero/alpha-rad")]) > math.radians(3)
    assert np.ptp(with_[:, _COMPARED.index("velocities/p-rad_sec")]) > math.radians(30)
    for k, name in enumerate(_COMPARED):
        assert np.array_equal(with_[:, k], without[:, k]), f"{name} differs"


def test_pilot_commands_act_in_trim_only():
    """After the trim the pilot command terms are switched off holding exact zeros: a command
    then moves no surface, while with TRIM_COMMANDS_PROPERTY on it moves the elevator by
    E_MAX * command (the mixer's documented row)."""
    fdm, tp = aircraft.trimmed_fdm(0.4, 20_000.0)
    assert fdm[aircraft.TRIM_COMMANDS_PROPERTY] == 0
    for term in ("elevator-term2", "elevator-term3", "aileron-term4", "aileron-term5",
                 "rudder-term1", "rudder-term2"):
        assert fdm[f"fcs/f16mmae/{term}"] == 0.0
    elevator = (tp.u_rad[0] + tp.u_rad[1]) / 2
    fdm["fcs/elevator-cmd-norm"] = 0.5
    fdm.run_ic()
    assert fdm["fcs/elevator-pos-rad"] == pytest.approx(elevator, abs=1e-15)
    fdm[aircraft.TRIM_COMMANDS_PROPERTY] = 1
    fdm.run_ic()
    e_max = actuators.TRIM_COMMAND_SCALE_RAD[0]
    assert fdm["fcs/elevator-pos-rad"] == pytest.approx(elevator + 0.5 * e_max, abs=1e-12)
