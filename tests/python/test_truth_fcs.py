"""The Block-40-style FCS: holds the trim, tracks n_z and roll-rate commands, damps
disturbances across the envelope, ARI switchable, feedback is whatever vector it is given."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.truth import FlightControlSystem, Scenario, aircraft, fly_raw
from f16mmae.truth.dither import DitherSpec

QUIET = DitherSpec(enabled=False)


@pytest.fixture(scope="module")
def trim():
    return aircraft.trimmed_fdm(0.4, 20_000.0)[1]


def test_commands_trim_at_trim_measurements(trim):
    fcs = FlightControlSystem(trim)
    for i in range(50):
        u = fcs.command(trim.z, i / 64)
    assert np.array_equal(u, trim.u_rad.tolist())
    assert fcs.x_int == 0.0


def test_feedback_signs_oppose_the_disturbance(trim):
    fcs = FlightControlSystem(trim, ari=False)
    dz = np.zeros(7)
    dz[2] = math.radians(2)   # nose pitching up -> stabilators trailing edge down
    u = np.array(fcs.command(trim.z + dz, 0.0)) - trim.u_rad
    assert u[0] > 0 and u[1] > 0 and abs(u[0] - u[1]) < 1e-15
    fcs.reset()
    dz[:] = 0
    dz[4] = math.radians(5)   # rolling right -> left flaperon trailing edge up, right down
    u = np.array(fcs.command(trim.z + dz, 0.0)) - trim.u_rad
    assert u[2] < 0 < u[3] and u[0] < u[1] and u[4] == 0.0
    fcs.reset()
    dz[:] = 0
    dz[5] = math.radians(2)   # yawing right -> rudder trailing edge left (positive)
    u = np.array(fcs.command(trim.z + dz, 0.0)) - trim.u_rad
    assert u[4] > 0


def test_ari_moves_the_rudder_with_the_roll_command(trim):
    dz = np.zeros(7)
    dz[4] = math.radians(5)
    on = FlightControlSystem(trim, ari=True).command(trim.z + dz, 0.0)
    off = FlightControlSystem(trim, ari=False).command(trim.z + dz, 0.0)
    da = on[2] - trim.u_rad[2]
    assert off[4] == trim.u_rad[4]
    assert on[4] - trim.u_rad[4] == pytest.approx(-0.3 * da)


def test_scenario_supplies_dither_and_ari(trim):
    sc = Scenario(ari=False)
    fcs = FlightControlSystem(trim, sc)
    assert not fcs.ari and fcs.dither.enabled
    u = fcs.command(trim.z, 0.1)
    assert not np.allclose(u, trim.u_rad)   # dither on the surfaces


@pytest.mark.parametrize("mach,alt_ft", [(0.4, 20_000.0), (0.3, 5_000.0), (0.8, 5_000.0),
                                          (0.8, 35_000.0), (0.45, 35_000.0)])
def test_tracks_nz_and_roll_commands_and_settles(mach, alt_ft):
    def pilot(t):
        return (0.5 if 1.0 <= t < 4.0 else 0.0, math.radians(10) if 1.0 <= t < 2.0 else 0.0)

    sc = Scenario(mach=mach, alt_ft=alt_ft, duration_s=8.0, dither=QUIET, noise=False, feedback="raw")
    truth, _ = fly_raw(sc, pilot=pilot)
    log = truth.truth_log
    t, dz = log["time_s"], log["z_ideal"] - truth.trim.z
    nz, p = dz[:, 3], dz[:, 4]
    hold = (t >= 2.5) & (t < 4.0)
    # integral action; the saturated airspeed terms (<= 0.1 g) may take a share in long pulls
    assert np.mean(nz[hold]) == pytest.approx(0.5, abs=0.12)
    assert nz[(t > 1) & (t < 4)].max() < 0.5 * 1.3                    # overshoot < 30 %
    assert p[(t >= 1) & (t < 2)].max() > math.radians(4)              # rolls as commanded
    late = t > 6.5
    assert np.abs(nz[late]).max() < 0.25                               # back near 1 g (phugoid left)
    assert np.abs(np.diff(nz[late])).max() < 0.01                      # fast modes settled
    assert np.abs(p[late]).max() < math.radians(2.0)
    assert abs(dz[-1, 2]) < math.radians(0.5)                          # pitch rate settled
    assert np.degrees(np.abs(log["state"][:, 3]).max()) < 3.0        # sideslip stays small


def test_flies_on_any_feedback_vector(trim):
    # the paper's MMAE-based control: the FCS gets z_hat, here a smoothed stand-in
    sc = Scenario(duration_s=4.0, turbulence="light", feedback="mmae", seed=2)
    from f16mmae.truth import TruthModel
    truth = TruthModel(sc)
    fcs = FlightControlSystem(truth.trim, sc)
    z_hat = truth.trim.z.copy()
    for i in range(4 * 64):
        z = truth.measure()
        z_hat = 0.7 * z_hat + 0.3 * z
        truth.advance(fcs.command(z_hat, truth.time_s))
    st = dict(zip(truth.truth_log["state_names"], truth.truth_log["state"].T))
    assert np.abs(st["alt_ft"] - 20_000).max() < 30
    assert np.degrees(np.abs(st["phi_rad"]).max()) < 3
