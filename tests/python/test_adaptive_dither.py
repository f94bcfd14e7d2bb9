"""The adaptive dither (truth/dither.py ``adaptive_mix`` / ``adaptive_gains``, ``--adaptive-dither``):
its rule, its two lines on both truth engines, and the option's checks."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.loop import estimator_options
from f16mmae.names import FRAME_RATE_HZ
from f16mmae.truth import DitherSpec, FlightControlSystem, Scenario, TruthModel
from f16mmae.truth.actuators import RATE_LIMIT_RAD_S
from f16mmae.truth.dither import (ADAPTIVE_FULL_RATIO, ADAPTIVE_RATE_SHARE, TURBULENCE_FLAPERON_AMPLITUDE_DEG,
                                  TURBULENCE_FLAPERON_FREQUENCY_HZ, Dither, adaptive_gains, adaptive_mix)


def test_the_mix_is_zero_up_to_the_reference_and_one_from_the_full_ratio():
    ref = 0.9
    for rho in (0.0, 0.5, ref, math.nan, math.inf * 0):
        assert adaptive_mix(rho, ref) == 0.0
    assert adaptive_mix(ref * ADAPTIVE_FULL_RATIO ** 2, ref) == pytest.approx(1.0)
    assert adaptive_mix(100.0, ref) == 1.0
    # halfway in sqrt(rho / ref) between 1 and the full ratio: half the turbulence line
    mid = ref * ((1.0 + ADAPTIVE_FULL_RATIO) / 2.0) ** 2
    assert adaptive_mix(mid, ref) == pytest.approx(0.5)
    g, h = adaptive_gains(mid, ref)
    assert g == pytest.approx([1.0, 1.0, 0.5, 0.5, 1.0]) and h == pytest.approx([0.0, 0.0, 0.5, 0.5, 0.0])
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ValueError, match="reference rho"):
            adaptive_mix(1.0, bad)


def test_the_two_lines_add_as_the_rule_says():
    d = Dither(DitherSpec())
    a, w, ph = d.terms()
    b, v, ph2 = d.turbulence_terms()
    # the turbulence line at the nominal point: its amplitude, within the rate share
    assert b[2] == b[3] == pytest.approx(math.radians(TURBULENCE_FLAPERON_AMPLITUDE_DEG))
    assert v[2] == pytest.approx(2 * math.pi * TURBULENCE_FLAPERON_FREQUENCY_HZ)
    assert b[2] * v[2] <= ADAPTIVE_RATE_SHARE * RATE_LIMIT_RAD_S[2] + 1e-12
    assert b[0] == b[1] == b[4] == 0.0
    t = 1.2345
    fixed = d.value(t)
    d.set_gain([1.0, 1.0, 0.7, 0.7, 1.0], [0.0, 0.0, 0.3, 0.3, 0.0])
    got = d.value(t)
    for j in range(5):
        want = a[j] * math.sin(w[j] * t + ph[j])
        if j in (2, 3):
            want = 0.7 * want + 0.3 * b[j] * math.sin(v[j] * t + ph2[j])
        assert got[j] == pytest.approx(want, abs=1e-15)
    assert got[0] == fixed[0] and got[4] == fixed[4]
    d.set_gain([1.0] * 5, [0.0] * 5)
    assert d.value(t) == fixed  # bit for bit the fixed dither
    with pytest.raises(ValueError, match="5 finite values"):
        d.set_gain([1.0] * 4, [0.0] * 5)
    with pytest.raises(ValueError, match="turbulence line gain"):
        d.set_gain([1.0] * 5, [0.0, 0.0, -0.1, 0.0, 0.0])
    # a large low-q̄ schedule keeps the turbulence line within the rate share
    big = Dither(DitherSpec(), scale=3.0)
    b3, v3, _ = big.turbulence_terms()
    assert b3[2] * v3[2] == pytest.approx(ADAPTIVE_RATE_SHARE * RATE_LIMIT_RAD_S[2])
    assert Dither(DitherSpec(enabled=False)).turbulence_terms()[0] == [0.0] * 5


def _fly(engine: str, change: bool = True) -> dict:
    """Frame by frame on the FCS, the gains changed twice on the way (if ``change``)."""
    sc = Scenario(duration_s=1.0, turbulence="severe", seed=3)
    truth = TruthModel(sc, engine=engine)
    fcs = FlightControlSystem(truth.trim, dither=sc.dither, ari=sc.ari)
    truth.attach(fcs)
    z = truth.measure()
    n = int(round(sc.duration_s * FRAME_RATE_HZ))
    us = []
    for i in range(n):
        if change and i == n // 3:
            truth.set_dither_gain(fcs, [1.0, 1.0, 0.4, 0.4, 1.0], [0.0, 0.0, 0.6, 0.6, 0.0])
        if change and i == 2 * n // 3:
            truth.set_dither_gain(fcs, [1.0] * 5, [0.0, 0.0, 1.0, 1.0, 0.0])
        u, z = truth.step(fcs, z, measure_next=True)
        us.append(np.array(u, dtype=float))
    truth.detach(fcs)
    truth.close()
    return {"u": np.array(us), "z": truth.truth_log["z"]}


def test_both_engines_fly_the_adaptive_dither_bit_for_bit():
    ref, cpp = _fly("python"), _fly("cpp")
    assert np.array_equal(ref["u"], cpp["u"])
    assert np.array_equal(ref["z"], cpp["z"])
    # the gains act from the frame they are set: the flight without them is the same before
    fixed = _fly("cpp", change=False)
    third = len(ref["u"]) // 3
    assert np.array_equal(fixed["u"][:third], cpp["u"][:third])
    assert np.abs(fixed["u"][third:, 2] - cpp["u"][third:, 2]).max() > 1e-3


def test_the_option_needs_the_turbulence_set_and_stays_out_of_the_core():
    with pytest.raises(ValueError, match="--adaptive-dither applies with --turbulence-banks"):
        estimator_options.check({"adaptive_dither": True})
    estimator_options.check({"adaptive_dither": True, "turbulence_banks": True})
    assert "adaptive_dither" in estimator_options.HARNESS_ONLY
    assert not estimator_options.BY_KEY["adaptive_dither"].in_daemon
    assert estimator_options.command_line_flags({"adaptive_dither": True, "turbulence_banks": True}) == [
        "--turbulence-banks", "--adaptive-dither"]


def test_the_adaptive_dither_is_the_sets_default_and_the_fixed_one_stays_selectable():
    """With --turbulence-banks the settings in force hold the adaptive dither unless --fixed-dither;
    the two exclude each other; without the set neither applies (and nothing is added)."""
    defaults = estimator_options.with_closed_loop_defaults
    assert defaults({"turbulence_banks": True}) == {"turbulence_banks": True, "adaptive_dither": True}
    assert defaults({"turbulence_banks": True, "fixed_dither": True}) == {"turbulence_banks": True,
                                                                        "fixed_dither": True}
    assert defaults({"p_min": 1e-9}) == {"p_min": 1e-9}
    with pytest.raises(ValueError, match="--fixed-dither applies with --turbulence-banks"):
        estimator_options.check({"fixed_dither": True})
    with pytest.raises(ValueError, match="exclude each other"):
        estimator_options.check({"turbulence_banks": True, "fixed_dither": True, "adaptive_dither": True})
    estimator_options.check({"turbulence_banks": True, "fixed_dither": True})
    assert set(estimator_options.CLOSED_LOOP) == {"adaptive_dither", "fixed_dither", "sensor_loss_dither"}
    assert set(estimator_options.CLOSED_LOOP) <= set(estimator_options.HARNESS_ONLY)


def test_the_light_members_reference_is_the_sets_floor_rho():
    # the turbulence line and the selector's floor turn at the same rho of the light member
    # (truth/dither.py ADAPTIVE_DITHER_REFERENCE, design/turbulence_banks.py FLOOR_RHO)
    from f16mmae.design.turbulence_banks import FLOOR_RHO, MEDIAN_RHO
    from f16mmae.truth.dither import ADAPTIVE_DITHER_REFERENCE

    assert len(ADAPTIVE_DITHER_REFERENCE) == len(MEDIAN_RHO)
    assert ADAPTIVE_DITHER_REFERENCE[1] == FLOOR_RHO
    assert ADAPTIVE_DITHER_REFERENCE[0] == pytest.approx(math.sqrt(11.63 * 84.51), abs=0.005)
