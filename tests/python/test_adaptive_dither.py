"""The adaptive dither (truth/dither.py ``adaptive_mix`` / ``adaptive_gains``, ``--adaptive-dither``):
its rule, its two lines on both truth engines, and the option's checks; for one adapted bank
(the scheduled default) its reference on the air data, its rho, the rudder's rough-air gain
(``adaptive_rudder_gain``, ``Dither.rudder_gain_bound``), and the closed loop frame by frame and in
C++ alike."""
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
                                  ADAPTIVE_RUDDER_MAX_GAIN, ADAPTIVE_RUDDER_REFERENCE, THROTTLE_GRID_ALT_FT, THROTTLE_GRID_MACH, TURBULENCE_FLAPERON_AMPLITUDE_DEG,
                                  TURBULENCE_FLAPERON_FREQUENCY_HZ, Dither, adapted_dither_reference,
                                  adaptive_gains, adaptive_mix, adaptive_rudder_gain, amplitude_schedule)
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


def test_the_rudders_gain_is_one_up_to_its_reference_then_the_root_of_rho_up_to_its_bound():
    ref = ADAPTIVE_RUDDER_REFERENCE
    for rho in (0.0, 0.5, ref, math.nan, math.inf * 0):
        assert adaptive_rudder_gain(rho, 1.5) == 1.0
    assert adaptive_rudder_gain(ref * 1.44, 1.5) == pytest.approx(1.2)
    assert adaptive_rudder_gain(ref * 1.44, 1.1) == 1.1
    assert adaptive_rudder_gain(100.0, 1.5) == 1.5
    assert adaptive_rudder_gain(100.0, 1.0) == 1.0
    # one adapted bank's gains carry it; the set's (no bound given) keep the rudder's fixed line
    assert adaptive_gains(ref * 1.44, 10.0, rudder_bound=1.5) == ([1.0, 1.0, 1.0, 1.0, pytest.approx(1.2)],
                                                                  [0.0] * 5)
    assert adaptive_gains(ref * 1.44, 10.0)[0][4] == 1.0
    for bad in (0.99, math.nan, math.inf, -1.0):
        with pytest.raises(ValueError, match="rudder gain's bound"):
            adaptive_rudder_gain(1.0, bad)


def test_the_rudders_gain_bound_is_its_rate_share_or_the_largest_gain():
    # the design point: the line's 5.5 deg at 2.3 Hz, 79.5 deg/s; 0.75 of 120 deg/s is 1.13 of it
    d = Dither(DitherSpec())
    a, w, _ = d.terms()
    assert a[4] * w[4] == pytest.approx(math.radians(5.5) * 2 * math.pi * 2.3)
    assert d.rudder_gain_bound == pytest.approx(0.75 * 120.0 / (5.5 * 2 * math.pi * 2.3))
    assert ADAPTIVE_RATE_SHARE * RATE_LIMIT_RAD_S[4] == pytest.approx(math.radians(90.0))
    # at twice the design dynamic pressure the line is scheduled down: the largest gain binds
    high = Dither(DitherSpec(), scale=0.5)
    assert high.terms()[0][4] == pytest.approx(math.radians(5.5) * amplitude_schedule(0.5))
    assert high.rudder_gain_bound == ADAPTIVE_RUDDER_MAX_GAIN
    # at low dynamic pressure the line passes the rate share already: the bound is the fixed line
    assert Dither(DitherSpec(), scale=2.0).rudder_gain_bound == 1.0
    assert Dither(DitherSpec(enabled=False)).rudder_gain_bound == 1.0


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
    assert set(estimator_options.CLOSED_LOOP) == {"adaptive_dither", "fixed_dither", "fixed_rudder_dither",
                                                  "sensor_loss_dither"}
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
    comes in (their commands leave the fixed dither's by more than a degree) and the rudder's line
    grows (test below: so the C++ loop sets the rudder's gain as loop/flight.py does), in light air
    the flight is the fixed dither's exactly."""
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


def test_one_adapted_banks_rudder_gain_follows_its_measured_rho_within_its_bound(schedule, monkeypatch):
    """Frame by frame, the gains the loop sets: the rudder's is adaptive_rudder_gain of the
    estimator's own measured rho-bar of that frame, bounded by the control law's Dither (the design
    point's rate share, 1.13); in moderate air between 1 and the bound, 1 throughout in light air."""
    seen = []   # (rudder gain set, the Dither's bound)
    original = TruthModel.set_dither_gain

    def spy(self, fcs, gain, gain2):
        seen.append((gain[4], fcs.dither.rudder_gain_bound))
        original(self, fcs, gain, gain2)

    monkeypatch.setattr(TruthModel, "set_dither_gain", spy)
    rhos = []
    est = Estimator(schedule, adapt_turbulence=True)
    sc = Scenario(turbulence="moderate", duration_s=6.0, seed=11)

    class Recording:   # the estimator, its rho-bar read after each update as the loop reads it
        def __getattr__(self, name):
            return getattr(est, name)

        def update(self, z):
            z_hat = est.update(z)
            rhos.append(est.measured_power_ratio)
            return z_hat

    fly(sc, schedule, estimator=Recording())
    bound = seen[0][1]   # the truth's trim dynamic pressure is the design's to 1e-4
    assert bound == pytest.approx(0.75 * 120.0 / (5.5 * 2 * math.pi * 2.3), rel=1e-3)
    want = [adaptive_rudder_gain(r, bound) for r in rhos]
    # the loop sets the gains when any changes: the rudder's in the order they come are the rule's
    collapse = lambda gs: [g for i, g in enumerate(gs) if i == 0 or g != gs[i - 1]]
    assert collapse([g for g, _ in seen]) == collapse(want)
    assert any(1.0 < g < bound for g in want) and bound > 1.0
    seen.clear()
    fly(Scenario(turbulence="light", duration_s=4.0, seed=11), schedule, estimator_options={"adapt_turbulence": True},
        on_frame=lambda *a: None)
    assert seen and all(g == 1.0 for g, _ in seen)


def test_the_fixed_rudder_dither_keeps_the_calm_air_rudder_line_in_both_loops(schedule):
    """--fixed-rudder-dither: the adaptive dither as before round 50 (the rudder's line the calm-air
    one), frame by frame and in C++ alike, and a flight that differs from the default's in moderate
    air; refused without one adapted bank, and redundant with --fixed-dither (an earlier round's
    flags add both)."""
    options = {"adapt_turbulence": True, "fixed_rudder_dither": True}
    sc = Scenario(turbulence="moderate", duration_s=6.0, seed=11)
    cpp = fly(sc, schedule, estimator_options=options)
    us = []
    python = fly(sc, schedule, estimator_options=options, on_frame=lambda t, u, z, air: us.append(u))
    np.testing.assert_array_equal(cpp.probabilities, python.probabilities)
    default = fly(sc, schedule, estimator_options={"adapt_turbulence": True})
    assert not np.array_equal(cpp.probabilities, default.probabilities)
    with pytest.raises(ValueError, match="--fixed-rudder-dither applies with --adapt-turbulence"):
        estimator_options.check({"fixed_rudder_dither": True})
    calm = fly(sc, schedule, estimator_options={"adapt_turbulence": True, "fixed_dither": True})
    both = fly(sc, schedule, estimator_options={**options, "fixed_dither": True})
    np.testing.assert_array_equal(calm.probabilities, both.probabilities)
