"""Maneuvers: the grammar and its errors, the schedule checks, the scenario field (absent from
an unmaneuvered record), the outer loop's references against hand-computed values, and the
maneuvers flown on the nonlinear truth (climb, speed change, level turn reach their targets;
both engines fly the same doubles; the throttle finds a new trim by itself)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.cli.main import main
from f16mmae.truth import FlightControlSystem, Scenario, TruthModel, fly_raw
from f16mmae.truth.maneuvers import FORMS, ManeuverError, check_schedule, parse_maneuver
from f16mmae.truth.outer_loop import INSTRUMENTS, THROTTLE_PROPERTY, OuterLoop, Reference


# -- grammar ---------------------------------------------------------------------------------
@pytest.mark.parametrize("text, canonical", [
    ("climb@5:to=25000ft:rate=3000fpm", "climb@5:to=25000ft:rate=3000fpm"),
    ("CLIMB@5:to=25000", "climb@5:to=25000ft"),
    ("descend@1.5:to=15000ft", "descend@1.5:to=15000ft"),
    ("accel@40:to=0.6mach", "accel@40:to=0.6mach"),
    ("decel@4:to=0.35:rate=0.01mach/s", "decel@4:to=0.35mach:rate=0.01mach/s"),
    ("turn@20:bank=30", "turn@20:bank=30deg"),
    ("turn@20:bank=-45deg:for=10s", "turn@20:bank=-45deg:for=10s"),
])
def test_parse_gives_the_canonical_form(text, canonical):
    m = parse_maneuver(text)
    assert str(m) == canonical
    assert parse_maneuver(str(m)) == m


@pytest.mark.parametrize("text, expected", [
    ("loop@5", "unknown kind 'loop'"),
    ("climb:to=25000ft", "has no start time"),
    ("climb@x:to=25000ft", "start time 'x' is not a number"),
    ("climb@5", "needs to=..."),
    ("climb@5:to=25000m", "to '25000m' is not a number (in ft)"),
    ("climb@5:to=40000ft", "altitude 40000 ft outside 5000-35000 ft"),
    ("climb@5:to=25000ft:rate=0fpm", "rate 0 fpm must lie in (0, 10000]"),
    ("climb@5:to=25000ft:bank=3", "bad field 'bank=3'; a climb takes to=...ft, rate=...fpm"),
    ("climb@5:to=25000ft:to=26000ft", "gives to twice"),
    ("accel@5:to=0.9mach", "Mach 0.9 outside 0.3-0.8"),
    ("turn@5:bank=75", "bank 75 deg must lie in [-60, 60]"),
    ("turn@-1:bank=30", "start time -1 s must be >= 0"),
])
def test_bad_specs_name_the_token_and_the_valid_forms(text, expected):
    with pytest.raises(ManeuverError) as exc:
        parse_maneuver(text)
    assert expected in str(exc.value)
    assert repr(text) in str(exc.value)


def test_the_forms_are_in_the_unknown_kind_message():
    with pytest.raises(ManeuverError, match="valid forms: climb@T"):
        parse_maneuver("barrel@3")
    assert "turn@T:bank=Bdeg[:for=Ss]" in FORMS


def test_schedule_checks_direction_and_overlap():
    ms = check_schedule(["turn@20:bank=30", "climb@5:to=21000ft:rate=3000fpm"], 0.4, 20_000.0)
    assert [m.kind for m in ms] == ["climb", "turn"]  # sorted by time; channels may overlap
    with pytest.raises(ManeuverError, match="not above 20000"):
        check_schedule(["climb@5:to=19000ft"], 0.4, 20_000.0)
    with pytest.raises(ManeuverError, match="not below 0.4"):
        check_schedule(["decel@5:to=0.5mach"], 0.4, 20_000.0)
    # 1,000 ft at 2,000 fpm takes 30 s: a second climb at 20 s overlaps it
    with pytest.raises(ManeuverError, match="starts before climb@5:to=21000ft has finished .at 35 s"):
        check_schedule(["climb@5:to=21000ft", "climb@20:to=22000ft"], 0.4, 20_000.0)
    check_schedule(["climb@5:to=21000ft", "descend@35:to=20000ft"], 0.4, 20_000.0)
    with pytest.raises(ManeuverError, match="starts before turn@5:bank=30deg:for=10s"):
        check_schedule(["turn@5:bank=30:for=10", "turn@12:bank=-30"], 0.4, 20_000.0)


# -- the scenario ----------------------------------------------------------------------------
def test_scenario_toml_round_trip_and_unmaneuvered_record_unchanged():
    sc = Scenario.from_toml('maneuvers = ["turn@20:bank=30", "climb@5:to=25000ft:rate=3000fpm"]\nduration_s = 60\n')
    d = sc.to_dict()
    assert d["maneuvers"] == ["climb@5:to=25000ft:rate=3000fpm", "turn@20:bank=30deg"]
    assert Scenario.from_dict(d) == sc
    assert "maneuvers" not in Scenario().to_dict()  # run keys of today's records stay what they were
    with pytest.raises(ValueError, match="starts after the end of the run"):
        Scenario(duration_s=8.0, maneuvers=("turn@9:bank=30",))
    with pytest.raises(ValueError, match="must be a list of strings"):
        Scenario.from_dict({"maneuvers": "turn@2:bank=30"})


# -- references ------------------------------------------------------------------------------
def test_references_hand_computed():
    ms = check_schedule(["climb@10:to=21000ft:rate=3000fpm"], 0.4, 20_000.0)
    ref = Reference(20_000.0, ms, lambda m: m.rate_value / 60.0)
    assert ref.at(5.0) == (20_000.0, 0.0)
    assert ref.at(14.0) == pytest.approx((20_200.0, 50.0))  # 4 s at 50 ft/s
    assert ref.at(40.0) == (21_000.0, 0.0)  # 1,000 ft at 50 ft/s ends at 30 s
    turn = check_schedule(["turn@2:bank=30:for=5"], 0.4, 20_000.0)
    bank = Reference(0.0, turn, lambda m: math.inf)
    assert [bank.at(t)[0] for t in (1.0, 2.0, 6.9, 7.0)] == [0.0, 30.0, 30.0, 0.0]


# -- flown on the truth ------------------------------------------------------------------------
def _fly(maneuvers, duration_s, engine="cpp", turbulence="light"):
    sc = Scenario(turbulence=turbulence, duration_s=duration_s, seed=11, maneuvers=tuple(maneuvers))
    truth, fcs = fly_raw(sc, engine=engine)
    log = truth.truth_log
    names = log["state_names"]
    return {n: log["state"][:, names.index(n)] for n in names}, log, fcs


def test_climb_reaches_the_target_and_holds_speed():
    s, log, _ = _fly(["climb@2:to=21000ft:rate=3000fpm"], 45.0)
    t = log["time_s"]
    assert abs(s["alt_ft"][-1] - 21_000.0) < 60.0
    mid = (t > 8.0) & (t < 20.0)  # climbing at about 3,000 fpm = 50 ft/s
    rate = np.polyfit(t[mid], s["alt_ft"][mid], 1)[0]
    assert rate == pytest.approx(50.0, rel=0.25)
    a = 1116.45 * math.sqrt(1 - 6.875e-6 * s["alt_ft"][-1])  # ISA speed of sound (ft/s), troposphere
    assert s["vt_fps"][-1] / a == pytest.approx(0.4, abs=0.01)


def test_acceleration_reaches_the_mach_target_and_the_throttle_a_new_trim():
    sc = Scenario(turbulence="none", duration_s=40.0, seed=3, maneuvers=("accel@2:to=0.5mach:rate=0.01mach/s",))
    truth = TruthModel(sc)
    throttle_0 = truth.fdm[THROTTLE_PROPERTY]
    truth.close()
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    vt = log["state"][:, log["state_names"].index("vt_fps")]
    alt = log["state"][:, log["state_names"].index("alt_ft")]
    a = 1116.45 * math.sqrt(1 - 6.875e-6 * alt[-1])
    assert vt[-1] / a == pytest.approx(0.5, abs=0.01)
    assert abs(alt[-1] - 20_000.0) < 100.0
    mach = vt / (1116.45 * np.sqrt(1 - 6.875e-6 * alt))
    assert np.ptp(mach[-128:]) < 0.005  # settled
    # the new trim's throttle (lower: Mach 0.4 at 20,000 ft is near the drag bucket's slow side) was found
    assert abs(truth.fdm[THROTTLE_PROPERTY] - throttle_0) > 0.01


def test_level_turn_banks_and_holds_altitude():
    s, log, _ = _fly(["turn@2:bank=30"], 25.0)
    t = log["time_s"]
    late = t > 10.0
    assert np.degrees(s["phi_rad"][late]).mean() == pytest.approx(30.0, abs=2.0)
    assert np.abs(s["alt_ft"][late] - 20_000.0).max() < 100.0
    assert np.unwrap(s["psi_rad"])[-1] - s["psi_rad"][0] > 0.3  # turning right


def test_engines_fly_the_same_maneuvering_flight():
    mans = ["climb@1:to=20500ft:rate=3000fpm", "turn@2:bank=-30"]
    _, cpp, _ = _fly(mans, 6.0, engine="cpp")
    _, py, _ = _fly(mans, 6.0, engine="python")
    for key in ("z", "u_cmd_rad", "surface_rad", "state"):
        np.testing.assert_array_equal(cpp[key], py[key])


def test_outer_loop_reads_instruments_and_throttle_only():
    reads, writes = [], []

    class Aircraft(dict):  # a property store standing in for the aircraft's instruments
        def __getitem__(self, k):
            reads.append(k)
            return super().__getitem__(k)

        def __setitem__(self, k, v):
            writes.append(k)
            super().__setitem__(k, v)

    ac = Aircraft({p: v for p, v in zip(INSTRUMENTS, (20_000.0, 0.0, 0.4, 0.0))})
    dict.__setitem__(ac, THROTTLE_PROPERTY, 0.25)
    pilot = OuterLoop(ac, check_schedule(["turn@0:bank=30"], 0.4, 20_000.0))
    nz, p = pilot(0.0)
    assert set(reads) == set(INSTRUMENTS) | {THROTTLE_PROPERTY} and writes == [THROTTLE_PROPERTY]
    # level, wings level, at the start condition, commanded 30 deg: pure roll command at its limit
    assert nz == 0.0 and p == pytest.approx(math.radians(20.0))
    assert ac[THROTTLE_PROPERTY] == 0.25


# -- CLI -------------------------------------------------------------------------------------
def test_run_refuses_a_bad_maneuver_naming_it(capsys):
    assert main(["run", "--maneuver", "climb@2:to=99000ft"]) == 2
    err = capsys.readouterr().err
    assert "--maneuver" in err and "'climb@2:to=99000ft'" in err and "99000 ft outside" in err
    assert main(["run", "--maneuver", "turn@9:bank=30"]) == 2
    assert "not inside the 8.0-s flight" in capsys.readouterr().err


def test_maneuvering_flight_estimator_sees_u_z_and_air_data_only():
    """The maneuvers go to the truth's pilot, never to the estimator: replaying the recorded
    (u, z, air data) through a fresh estimator reproduces the flight's probabilities and
    declarations."""
    from f16mmae.banks import load_bank
    from f16mmae.loop.estimator import Estimator
    from f16mmae.loop.flight import fly

    bank = load_bank("tuned")[2]
    sc = Scenario(duration_s=5.0, seed=4, turbulence="light", maneuvers=("turn@1:bank=30", "climb@2:to=20300ft"))
    frames = []
    r = fly(sc, bank, on_frame=lambda t, u, z, a: frames.append((t, u, z, a)))
    assert r.scenario["maneuvers"] == ["turn@1:bank=30deg", "climb@2:to=20300ft"]  # by start time
    est = Estimator(bank)
    decl = []
    for i, (t, u, z, a) in enumerate(frames):
        est.schedule(*a)
        est.update(z)
        est.propagate(u)
        if est.last_declaration is not None:
            decl.append({"hypothesis": est.last_declaration, "time_s": round(t, 9)})
        np.testing.assert_array_equal([r.probabilities[i, r.hypotheses.index(h)] for h in est.hypotheses],
                                      est.probabilities)
    assert decl == r.declarations
    assert fly(sc, bank).declarations == r.declarations  # the same flight again (in one call's path)


def test_cpp_engine_flies_the_outer_loop_in_cpp_and_the_closed_loop_in_one_call():
    """The C++ twin (cpp/truth/truth_frame.h OuterLoopLaw) is attached on the cpp engine; a
    maneuvering closed-loop flight in one C++ call equals the same flight frame by frame
    (``on_frame``) and the Python engine's (the Python outer loop and control law)."""
    from f16mmae.banks import load_bank
    from f16mmae.loop.flight import fly

    sc = Scenario(duration_s=4.0, seed=9, turbulence="light", maneuvers=("turn@0.5:bank=-30", "accel@1:to=0.45mach"))
    truth = TruthModel(sc)
    truth.attach(FlightControlSystem(truth.trim, sc, pilot=truth.pilot()))
    assert truth.law_in_cpp
    truth.close()
    bank = load_bank("tuned")[2]
    one_call = fly(sc, bank)                                   # whole flight in C++
    per_frame = fly(sc, bank, on_frame=lambda t, u, z, a: None)   # frame by frame (C++ law)
    python = fly(sc, bank, engine="python")                    # the Python reference
    for other in (per_frame, python):
        assert other.declarations == one_call.declarations
        np.testing.assert_array_equal(other.probabilities, one_call.probabilities)
