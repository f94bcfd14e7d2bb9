"""--maneuver-trim-gamma-load-factor (loop/estimator_options.py; core keyword
maneuver_trim_gamma_load_factor, cpp/f16mmae/maneuver_trim.h ClimbAngleComplement; mmae-daemon's
flag of the same name). The filter itself is checked against a hand computation, a pull-up and a
level-off in tests/cpp/test_climb_angle_complement.cpp; here:

* off is the estimator without the option bit for bit;
* on reads AZ of z: a pull of 0.01 g over the trim with the air data standing still gives the
  trim's climb angle the complement recomputed here (wings level: phi = 0; AOA the trim's), the air data's 0
  without it; the acceleration stays the air data's;
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
G = 32.174


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def _fly(bank, frames=64, **extra):
    az = list(bank.measurement_names).index("AZ")
    est = Estimator(bank, p_min=1e-9, **OPTIONS, **extra)
    z0, u0 = np.array(bank.z_trim), np.array(bank.u_trim)
    out = []
    for _ in range(frames):
        z = z0.copy()
        z[az] += 0.01
        est.schedule(float(bank.mach), float(bank.alt_ft))
        est.update(z)
        g, a, _, _ = est.core_bank.maneuver_trim
        out.append((g, a))
        est.propagate(u0)
    return np.array(out), z0


def test_off_is_bit_for_bit_and_on_reads_the_load_factor(bank):
    base, z0 = _fly(bank)
    np.testing.assert_array_equal(_fly(bank, maneuver_trim_gamma_load_factor="off")[0], base)
    assert np.all(base[:, 0] == 0.0)   # the air data stand still
    on, _ = _fly(bank, maneuver_trim_gamma_load_factor="on")
    np.testing.assert_array_equal(on[:, 1], base[:, 1])   # the acceleration the air data's
    # the complement by hand: V = the trim's VEL (the air data at the design Mach), gamma_air = 0
    n = float(z0[list(bank.measurement_names).index("AZ")]) + 0.01
    v = float(z0[list(bank.measurement_names).index("VEL")])
    aoa = float(z0[list(bank.measurement_names).index("AOA")])
    t = 0.5
    c1, c5 = 1 - math.exp(-1 / (64 * t)), 1 - math.exp(-1 / (64 * 5 * t))
    f1 = f5 = gamma = 0.0
    expect = []
    for _ in range(len(on)):
        n_w = n * math.cos(aoa) + math.sin(gamma + aoa) * math.sin(aoa)   # a = 0: the air data stand still
        w = G / v * (n_w - math.cos(gamma))
        f1 += c1 * (w - f1)
        f5 += c5 * (w - f5)
        gamma = t * (25 * f5 - f1) / 4
        expect.append(gamma)
    np.testing.assert_allclose(on[:, 0], expect, rtol=1e-9, atol=1e-15)
    assert on[-1, 0] > 0.0   # the pull read as a climb


def test_refusals_name_the_flag(bank):
    with pytest.raises(ValueError, match="--maneuver-trim-gamma-load-factor applies with --maneuver-trim only"):
        check({"maneuver_trim_gamma_load_factor": "on"})
    with pytest.raises(ValueError, match="--maneuver-trim-gamma-load-factor"):
        check({"maneuver_trim": True, "maneuver_trim_gamma_load_factor": "bogus"})
    from f16mmae import core
    with pytest.raises(ValueError, match="exclude each other"):
        core.HierarchicalBank(bank, maneuver_trim=True, maneuver_trim_rates="inertial",
                              maneuver_trim_gamma_load_factor="on")


def test_the_daemon_gets_its_flag():
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({"maneuver_trim": True, "maneuver_trim_gamma_load_factor": "on"})
    i = flags.index("--maneuver-trim-gamma-load-factor")
    assert flags[i + 1] == "on"
    assert "--maneuver-trim-gamma-load-factor" not in daemon_flags({"maneuver_trim": True})
