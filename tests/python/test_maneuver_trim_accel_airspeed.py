"""--maneuver-trim-accel-airspeed (loop/estimator_options.py; core keyword
maneuver_trim_accel_airspeed_rad_s, cpp/f16mmae/maneuver_trim.h AirspeedAccel; mmae-daemon's
flag of the same name). The differentiator itself is checked against a hand computation in
tests/cpp/test_airspeed_accel.cpp; here:

* 0 is the estimator without the option bit for bit (the air data's acceleration);
* W0 > 0 reads the airspeed of z: a VEL ramp of 2 ft/s^2 with the air data standing still gives
  the trim's acceleration the differentiator's response recomputed here over 1.5 s (before the
  ramp raises a failure hypothesis to the freeze), the air data's 0 without it; the climb angle
  stays the air data's;
* the refusals by name (the option table and the core); hil's daemon flags pass it.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import check

OPTIONS = {"maneuver_trim": True}


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def _fly(bank, frames=96, **extra):
    vel = list(bank.measurement_names).index("VEL")
    est = Estimator(bank, p_min=1e-9, **OPTIONS, **extra)
    z0, u0 = np.array(bank.z_trim), np.array(bank.u_trim)
    out = []
    for k in range(frames):
        z = z0.copy()
        z[vel] += 2.0 * k / 64.0
        est.schedule(float(bank.mach), float(bank.alt_ft))
        est.update(z)
        g, a, _, _ = est.core_bank.maneuver_trim
        out.append((g, a))
        est.propagate(u0)
    return np.array(out), z0


def test_zero_is_bit_for_bit_and_w0_reads_the_airspeed(bank):
    base, z0 = _fly(bank)
    np.testing.assert_array_equal(_fly(bank, maneuver_trim_accel_airspeed_rad_s=0.0)[0], base)
    assert np.all(base[:, 1] == 0.0)   # the air data stand still
    on, _ = _fly(bank, maneuver_trim_accel_airspeed_rad_s=1.0)
    np.testing.assert_array_equal(on[:, 0], base[:, 0])   # gamma the air data's
    # the differentiator on V = VEL / cos(AOA) (AOA constant), by hand; frame 0 starts it
    aoa = float(z0[list(bank.measurement_names).index("AOA")])
    w0, zeta, dt = 1.0, 1.0 / math.sqrt(2.0), 1.0 / 64.0
    v_hat, a_hat, expect = None, 0.0, []
    for k in range(len(on)):
        vm = (float(z0[0]) + 2.0 * k / 64.0) / math.cos(aoa)
        if v_hat is None:
            v_hat = vm
        else:
            e = vm - v_hat
            v_hat += dt * (a_hat + 2 * zeta * w0 * e)
            a_hat += dt * w0 * w0 * e
        expect.append(a_hat)
    np.testing.assert_allclose(on[:, 1], expect, rtol=1e-9, atol=1e-12)
    assert on[-1, 1] > 0.5


def test_refusals_name_the_flag(bank):
    with pytest.raises(ValueError, match="--maneuver-trim-accel-airspeed applies with --maneuver-trim only"):
        check({"maneuver_trim_accel_airspeed_rad_s": 1.0})
    with pytest.raises(ValueError, match="--maneuver-trim-accel-airspeed"):
        check({"maneuver_trim": True, "maneuver_trim_accel_airspeed_rad_s": -1.0})
    from f16mmae import core
    with pytest.raises(ValueError, match="accel_airspeed_rad_s must be 0 .* got 0.01"):
        core.HierarchicalBank(bank, maneuver_trim=True, maneuver_trim_accel_airspeed_rad_s=0.01)
    with pytest.raises(ValueError, match="exclude each other"):
        core.HierarchicalBank(bank, maneuver_trim=True, maneuver_trim_rates="inertial",
                              maneuver_trim_accel_airspeed_rad_s=1.0)


def test_the_daemon_gets_its_flag():
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({"maneuver_trim": True, "maneuver_trim_accel_airspeed_rad_s": 1.5})
    i = flags.index("--maneuver-trim-accel-airspeed")
    assert float(flags[i + 1]) == 1.5
    assert "--maneuver-trim-accel-airspeed" not in daemon_flags({"maneuver_trim": True})
