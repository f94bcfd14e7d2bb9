"""The adaptive dither (truth/dither.py ``adaptive_mix`` / ``adaptive_gains``, ``--adaptive-dither``):
its rule, its two lines on both truth engines, and the option's checks; for one adapted bank
(the scheduled default) its reference on the air data, its rho, and the closed loop frame by frame
and in C++ alike."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.loop import estimator_options
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import FRAME_RATE_HZ
from f16mmae.truth import DitherSpec, FlightControlSystem, Scenario, TruthModel
from f16mmae.truth.actuators import RATE_LIMIT_RAD_S
from f16mmae.truth.dither import (ADAPTED_DITHER_REFERENCE, ADAPTIVE_FULL_RATIO, ADAPTIVE_RATE_SHARE,
                                  THROTTLE_GRID_ALT_FT, THROTTLE_GRID_MACH, TURBULENCE_FLAPERON_AMPLITUDE_DEG,
                                  TURBULENCE_FLAPERON_FREQUENCY_HZ, Dither, adapted_dither_reference,
                                  adaptive_gains, adaptive_mix)
from f16mmae.truth.failures import make_failure
from schedule_support import one_node_schedule


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


def test_the_option_needs_the_set_or_the_adaptation_and_stays_out_of_the_core():
    with pytest.raises(ValueError, match="--adaptive-dither applies with --turbulence-banks or --adapt-turbulence"):
        estimator_options.check({"adaptive_dither": True})
    estimator_options.check({"adaptive_dither": True, "turbulence_banks": True})
    estimator_options.check({"adaptive_dither": True, "adapt_turbulence": True})
    estimator_options.check({"fixed_dither": True, "adapt_turbulence": True})
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
    with pytest.raises(ValueError, match="--fixed-dither applies with --turbulence-banks or --adapt-turbulence"):
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


def test_one_adapted_banks_reference_is_the_table_bilinear_on_the_air_data():
    """At the grid's points the table's own values; between, the mean of the cell's corners at its
    middle; outside, the nearest edge; a non-finite air datum refused, naming it."""
    for i, m in enumerate(THROTTLE_GRID_MACH):
        for j, h in enumerate(THROTTLE_GRID_ALT_FT):
            assert adapted_dither_reference(m, h) == pytest.approx(ADAPTED_DITHER_REFERENCE[i][j], rel=1e-12)
    m = (THROTTLE_GRID_MACH[2] + THROTTLE_GRID_MACH[3]) / 2
    h = (THROTTLE_GRID_ALT_FT[4] + THROTTLE_GRID_ALT_FT[5]) / 2
    corners = [ADAPTED_DITHER_REFERENCE[i][j] for i in (2, 3) for j in (4, 5)]
    assert adapted_dither_reference(m, h) == pytest.approx(sum(corners) / 4, rel=1e-12)
    assert adapted_dither_reference(0.1, 1000.0) == ADAPTED_DITHER_REFERENCE[0][0]
    assert adapted_dither_reference(0.95, 45000.0) == ADAPTED_DITHER_REFERENCE[-1][-1]
    # rising with altitude at every Mach: stronger gusts of one level higher up
    for row in ADAPTED_DITHER_REFERENCE:
        assert row[0] < row[-1]
    for bad in ((math.nan, 20000.0), (0.4, math.inf)):
        with pytest.raises(ValueError, match="air data must be finite"):
            adapted_dither_reference(*bad)


@pytest.fixture(scope="module")
def schedule(tmp_path_factory):
    return one_node_schedule(tmp_path_factory.mktemp("adapted"))


def test_the_scheduled_default_flies_it_and_reads_the_adaptations_measured_rho(schedule):
    """A scheduled bank with --adapt-turbulence holds the adaptive dither in its settings (off with
    --fixed-dither); its rho is the adaptation's measured rho-bar, NaN without the adaptation."""
    est = Estimator(schedule, adapt_turbulence=True)
    assert est.settings["adaptive_dither"] is True and est.turbulence_member is None
    assert "adaptive_dither" not in Estimator(schedule, adapt_turbulence=True, fixed_dither=True).settings
    assert "adaptive_dither" not in Estimator(schedule).settings
    assert math.isnan(Estimator(schedule).measured_power_ratio)
    rng = np.random.default_rng(3)
    for _ in range(40):
        est.update(np.asarray(schedule.z_trim) + 0.05 * rng.standard_normal(7))
        est.propagate(np.asarray(schedule.u_trim))
        assert est.measured_power_ratio == est.core_bank.measured_power_ratio > 0.0


def _flight(schedule, level: str, frame_by_frame: bool, **options):
    sc = Scenario(turbulence=level, duration_s=6.0, seed=11, failures=(make_failure("LF", 3.0),))
    us = []
    run = fly(sc, schedule, estimator_options={"adapt_turbulence": True, **options},
              on_frame=(lambda t, u, z, air: us.append(u)) if frame_by_frame else None)
    return run, np.array(us)


def test_one_adapted_banks_adaptive_dither_is_the_same_in_cpp_and_frame_by_frame(schedule):
    """The C++ closed loop (TruthFrames.set_adapted_dither) and the frame-by-frame loop
    (loop/flight.py) fly the same flight bit for bit; in severe air the flaperons' turbulence line
    comes in (their commands leave the fixed dither's by more than a degree), in light air the
    flight is the fixed dither's exactly."""
    cpp, _ = _flight(schedule, "severe", False)
    python, u = _flight(schedule, "severe", True)
    np.testing.assert_array_equal(cpp.probabilities, python.probabilities)
    assert cpp.declarations == python.declarations
    _, u_fixed = _flight(schedule, "severe", True, fixed_dither=True)
    lf = 2   # LS RS LF RF RUD
    assert np.abs(u[:, lf] - u_fixed[:, lf]).max() > math.radians(1.0)
    light, _ = _flight(schedule, "light", False)
    light_fixed, _ = _flight(schedule, "light", False, fixed_dither=True)
    np.testing.assert_array_equal(light.probabilities, light_fixed.probabilities)
