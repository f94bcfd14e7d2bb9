"""The scheduled estimator's defaults (loop/estimator_options.py ``scheduled_defaults``): a
scheduled bank flown with the turbulence adaptation counts each filter's residual power per
channel it reads (own channels) unless ``adapt_all_channels`` asks for the plain minimum; the
counted channel (``adapt_counted_channel``) reaches the core as its bit; the per-hypothesis
tempering (``set_tempering``) is on at ``names.SCHEDULE_SET_TEMPERING`` (the rudder fully tempered
from the air's ``names.SCHEDULE_SET_TEMPERING_ROUGH`` on), trim tracking at
``names.SCHEDULE_TRIM_TIME_CONSTANT_S`` and VEL's least dwell at
``names.SCHEDULE_DWELL_S_PER_HYPOTHESIS`` (the rudder's in rough air at
``names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS``), the evidence dwell per hypothesis at
``names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS`` kept through the flight phases, the complete failures' held trim
``names.SCHEDULE_COMPLETE_TRIM_HOLD`` and its average ``names.SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S``
unless given, the rough-air floor ``names.SCHEDULE_ROUGH_P_MIN`` (the node floors in calm and light air,
it in moderate air), the adaptation bound's knee ``names.SCHEDULE_ADAPT_SCALE_MAX_FROM`` (reaching the core
and the daemon), and on a schedule whose nodes carry a
calm-air reference the calm-air complete model at ``names.SCHEDULE_CALM_COMPLETE``; the cached
scheduled bank's name follows every design setting of ``names.SCHEDULE_*``."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae import banks, core, names
from f16mmae.loop.estimator import Estimator, core_arguments
from f16mmae.loop.estimator_options import (bank_defaults, check, check_requirements, has_calm_reference,
                                            scheduled_defaults)
from schedule_support import floors_in_force, one_node_schedule


def test_own_channels_is_the_scheduled_default_and_all_channels_the_old_rule():
    given = {"adapt_turbulence": True}
    spared = {"set_tempering": names.SCHEDULE_SET_TEMPERING,   # the per-hypothesis tempering, whatever the rule
              "set_tempering_rough": names.SCHEDULE_SET_TEMPERING_ROUGH,   # with the rudder's in rough air
              "set_tempering_rough_weight": names.SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT,
              "trim_time_constant_s": names.SCHEDULE_TRIM_TIME_CONSTANT_S,   # trim tracking
              "dwell_s_per_hypothesis": names.SCHEDULE_DWELL_S_PER_HYPOTHESIS,   # VEL's least dwell
              "rough_dwell_s_per_hypothesis": names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS,   # the rudder's in rough air
              "rough_scale": names.SCHEDULE_ROUGH_SCALE,
              "dwell_nats_per_hypothesis": names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS,   # the evidence dwell
              "evidence_dwell_in_phases": True,   # kept through the climbs' and maneuvers' dwells
              "complete_trim_hold": names.SCHEDULE_COMPLETE_TRIM_HOLD,   # the complete failures' held trim
              "complete_trim_time_constant_s": names.SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S,   # and its average
              "maneuver_tempering_g": names.SCHEDULE_MANEUVER_TEMPERING_G,   # the load-factor tempering
              "maneuver_tempering_alpha_deg": names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG,   # the alpha tempering
              "maneuver_tempering_alpha_deadband_deg": names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG,
              "maneuver_tempering_alpha_trim_deg": names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG,   # its trim knee
              "adapt_level_scale": names.SCHEDULE_ADAPT_LEVEL_SCALE,   # the level channels' scale term
              "adapt_level_scale_channel": names.SCHEDULE_ADAPT_LEVEL_SCALE_CHANNEL.lower(),   # and VEL's at every level
              "adapt_level_scale_from": names.SCHEDULE_ADAPT_LEVEL_SCALE_FROM,
              "adapt_floor_time_constant_s": names.SCHEDULE_ADAPT_FLOOR_S,   # the lull floor
              "adapt_scale_max_from": names.SCHEDULE_ADAPT_SCALE_MAX_FROM,   # the bound's knee
              "rough_p_min": names.SCHEDULE_ROUGH_P_MIN,   # the floor in rough air
              "adaptive_dither": True,   # the closed loop's adaptive dither
              "maneuver_setting": "on", **names.SCHEDULE_MANEUVER_SETTING}   # and the maneuvering-flight setting
    assert scheduled_defaults(given, True) == {"adapt_turbulence": True, "adapt_own_channels": True,
                                               "adapt_counted_channel": "vel", **spared}
    assert given == {"adapt_turbulence": True}   # a copy
    own = {**given, "adapt_own_channels": True}   # round 13's rule: every uninformative channel left out
    assert scheduled_defaults(own, True) == {**own, **spared}
    rol = {**given, "adapt_counted_channel": "rol"}
    assert scheduled_defaults(rol, True) == {**rol, "adapt_own_channels": True, **spared}
    all_channels = {**given, "adapt_all_channels": True}
    assert scheduled_defaults(all_channels, True) == {**all_channels, **spared}
    off = {**given, "set_tempering": 1.0, "trim_time_constant_s": 0.0,   # given: kept (1, 0, VEL=0, off are off)
           "dwell_s_per_hypothesis": "VEL=0", "rough_dwell_s_per_hypothesis": "RUD=0", "dwell_nats": 0.0,
           "complete_trim_hold": "off", "complete_trim_time_constant_s": 0.0,
           "maneuver_tempering_g": 0.0, "adapt_level_scale": "off", "adapt_level_scale_channel": "none",
           "maneuver_tempering_alpha_deg": 0.0, "fixed_dither": True, "maneuver_setting": "off",
           "adapt_floor_time_constant_s": 0.0, "rough_p_min": 0.0, "set_tempering_rough": 0.0,
           "adapt_scale_max_from": 0.0}
    assert scheduled_defaults(off, True) == {**off, "adapt_own_channels": True, "adapt_counted_channel": "vel"}
    check(off)
    assert core_arguments(off)["trim_time_constant_s"] == 0.0   # the core's off
    assert core_arguments(off)["dwell_s_per_hypothesis"] == {"VEL": 0.0}
    assert "adapt_level_scale_channels" not in core_arguments(off)   # none: no channel, the core's 0
    assert "adapt_rough_tempering" not in core_arguments(off)   # 0: the rudder spared at any rho
    bound = scheduled_defaults({**given, "set_tempering_rough": 8.0}, True)   # a bound given: the full s there
    assert bound["set_tempering_rough"] == 8.0 and "set_tempering_rough_weight" not in bound
    weight = scheduled_defaults({**given, "set_tempering_rough_weight": 0.7}, True)   # a weight given: the default bound
    assert (weight["set_tempering_rough"], weight["set_tempering_rough_weight"]) == (names.SCHEDULE_SET_TEMPERING_ROUGH, 0.7)
    check({**given, "set_tempering_rough_weight": 0.7})   # waits for the bank's default bound
    for settings in (given, own, rol, all_channels, {}):   # applied twice as once (hil's --compare run)
        once = scheduled_defaults(settings, True)
        assert scheduled_defaults(once, True) == once
    sensor_loss = {**given, "sensor_loss_dither": True}   # the other rule on the dither's gains: no adaptive one
    assert "adaptive_dither" not in scheduled_defaults(sensor_loss, True)
    check(scheduled_defaults(sensor_loss, True))
    assert scheduled_defaults(given, False) == given   # a bank at one point: unchanged
    assert scheduled_defaults({}, True) == {}           # no adaptation: nothing to count
    band = {**given, "maneuver_tempering_alpha_deg": 2.0}   # the alpha term given: its dead band as given (none)
    assert "maneuver_tempering_alpha_deadband_deg" not in scheduled_defaults(band, True)
    assert "maneuver_tempering_alpha_trim_deg" not in scheduled_defaults(band, True)   # and its knee (none)
    knee = scheduled_defaults({**given, "maneuver_tempering_alpha_trim_deg": 10.0}, True)   # the knee alone: kept
    assert knee["maneuver_tempering_alpha_trim_deg"] == 10.0
    assert knee["maneuver_tempering_alpha_deg"] == names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG
    check({**given, "maneuver_tempering_alpha_trim_deg": 10.0})   # waits for a scheduled bank's default
    with pytest.raises(ValueError, match="--maneuver-tempering-alpha-deadband applies with --maneuver-tempering-alpha "
                                         "only .or with --adapt-turbulence on a scheduled bank, whose default is "
                                         "--maneuver-tempering-alpha 1"):
        check({"maneuver_tempering_alpha_deadband_deg": 0.5})
    check({**given, "maneuver_tempering_alpha_deadband_deg": 0.5})   # waits for a scheduled bank's default
    banks_set = {"adapt_turbulence": True, "turbulence_banks": True}
    assert scheduled_defaults(banks_set, True) == banks_set
    with pytest.raises(ValueError, match="--adapt-all-channels and --adapt-own-channels"):
        check({"adapt_turbulence": True, "adapt_all_channels": True, "adapt_own_channels": True})
    with pytest.raises(ValueError, match="--adapt-all-channels applies with --adapt-turbulence only"):
        check({"adapt_all_channels": True})
    with pytest.raises(ValueError, match="--adapt-counted-channel 'air' must be one of vel, aoa"):
        check({"adapt_turbulence": True, "adapt_counted_channel": "air"})


def test_the_counted_channel_reaches_the_core_as_its_bit():
    assert core_arguments({"adapt_counted_channel": "vel"})["adapt_counted_channels"] == 1
    assert core_arguments({"adapt_counted_channel": "rol"})["adapt_counted_channels"] == 1 << 4
    assert "adapt_counted_channel" not in core_arguments({"adapt_counted_channel": "vel"})


@pytest.fixture(scope="module")
def vel_rol_schedule(tmp_path_factory):
    """A one-node schedule of the constant=VEL+ROL design at Mach 0.4, 20,000 ft."""
    return one_node_schedule(tmp_path_factory.mktemp("own"))


#: The scheduled default's least dwells turned off (the core banks below fly without them).
NO_LEAST_DWELL = ",".join(f"{entry.split('=')[0]}=0" for entry in names.SCHEDULE_DWELL_S_PER_HYPOTHESIS.split(","))
NO_ROUGH_DWELL = ",".join(f"{entry.split('=')[0]}=0"
                          for entry in names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS.split(","))


def _fly(estimator_or_core, bank, frames=150):
    """rho after each frame of a flight whose measurements are the trim plus white noise (the
    same for every estimator)."""
    rng = np.random.default_rng(5)
    z0, u = np.asarray(bank.z_trim), np.asarray(bank.u_trim)
    rho = []
    for _ in range(frames):
        z = z0 + 3e-2 * rng.standard_normal(names.NZ)
        estimator_or_core.update(z)
        estimator_or_core.propagate(u)
        rho.append(estimator_or_core.turbulence_power_ratio)
    return np.array(rho)


def test_a_scheduled_estimator_flies_own_channels_unless_told_otherwise(vel_rol_schedule):
    bank = vel_rol_schedule
    # the scheduled trim tracking moves the residuals, and the least dwells move the declarations
    # (the noise below declares): the rule alone here
    rule_alone = {"trim_time_constant_s": 0.0, "dwell_s_per_hypothesis": NO_LEAST_DWELL,
                  "rough_dwell_s_per_hypothesis": NO_ROUGH_DWELL,
                  "adapt_level_scale_channel": "none", "maneuver_setting": "off"}
    est = Estimator(bank, adapt_turbulence=True, **rule_alone)
    assert est.settings["adapt_own_channels"] is True and est.settings["adapt_counted_channel"] == "vel"
    assert Estimator(bank, adapt_turbulence=True).settings["trim_time_constant_s"] == names.SCHEDULE_TRIM_TIME_CONSTANT_S
    own = core.HierarchicalBank(bank, adapt_turbulence=True, adapt_own_channels=True)
    plain = core.HierarchicalBank(bank, adapt_turbulence=True)
    counted = core.HierarchicalBank(bank, adapt_turbulence=True, adapt_own_channels=True, adapt_counted_channels=1)
    r_est, r_own, r_plain, r_counted = (_fly(b, bank) for b in (est, own, plain, counted))
    np.testing.assert_array_equal(r_est, r_counted)   # VEL's channel is bit 0 of z
    assert not np.array_equal(r_own, r_plain)   # the bank has uninformative channels: the rule matters
    assert not np.array_equal(r_counted, r_own) and not np.array_equal(r_counted, r_plain)
    old = Estimator(bank, adapt_turbulence=True, adapt_all_channels=True, **rule_alone)
    assert "adapt_own_channels" not in old.settings and old.settings["adapt_all_channels"] is True
    np.testing.assert_array_equal(_fly(old, bank), r_plain)
    np.testing.assert_array_equal(_fly(Estimator(bank, adapt_turbulence=True, adapt_own_channels=True, **rule_alone), bank), r_own)


def test_the_cached_scheduled_bank_is_named_by_every_design_setting(monkeypatch):
    first = banks.scheduled_bank_path()
    assert first == banks.scheduled_bank_path()
    for attr, value in (("SCHEDULE_GUST_STATES_BELOW_FT", 10000.0), ("SCHEDULE_GUST_NODE_CHOICE", "effort"),
                        ("SCHEDULE_FAILURE_MODEL", "constant=VEL"), ("SCHEDULE_DESIGN_REVISION", 11),
                        ("SCHEDULE_THROTTLE_INPUT", False), ("SCHEDULE_FAILED_SENSOR_NOISE", "design")):
        with monkeypatch.context() as m:
            m.setattr(banks, attr, value)
            assert banks.scheduled_bank_path() != first, attr
    assert banks.scheduled_bank_path() == first


def test_mmae_daemon_gets_the_scheduled_defaults_as_flags():
    """hil hands mmae-daemon the scheduled estimator's defaults resolved (own channels, VEL
    counted, the per-hypothesis tempering with its fully tempered hypotheses (the rudder in rough air), trim tracking, the
    load-factor tempering, the lull floor; not the closed loop's adaptive dither), so the executive over LCM runs the
    rule the estimator in process runs."""
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags(scheduled_defaults({"adapt_turbulence": True, "maneuver_setting": "off"}, True))
    assert set(flags) == {"--adapt-turbulence", "--adapt-own-channels", "--adapt-counted-channel", "vel",
                          "--set-tempering", "0.25", "--set-tempering-full", "LS,RS,LF,RF,VEL,AOA,AZ",
                          "--set-tempering-rough", str(names.SCHEDULE_SET_TEMPERING_ROUGH),
                          "--set-tempering-rough-full", "RUD,AY",
                          "--set-tempering-rough-weight", str(names.SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT),
                          "--trim-tracking", "30.0", "--dwell-s-per-hypothesis", names.SCHEDULE_DWELL_S_PER_HYPOTHESIS,
                          "--rough-dwell-s-per-hypothesis", names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS,
                          "--rough-scale", str(names.SCHEDULE_ROUGH_SCALE),
                          "--dwell-nats-per-hypothesis", names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS,
                          "--evidence-dwell-in-phases",
                          "--complete-trim-hold", names.SCHEDULE_COMPLETE_TRIM_HOLD,
                          "--complete-trim-time-constant", str(names.SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S),
                          "--maneuver-tempering", str(names.SCHEDULE_MANEUVER_TEMPERING_G),
                          "--maneuver-tempering-alpha", str(names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG),
                          "--maneuver-tempering-alpha-deadband", str(names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG),
                          "--maneuver-tempering-alpha-trim", str(names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG),
                          "--adapt-level-scale-channel", "vel", "--adapt-level-scale-from",
                          str(names.SCHEDULE_ADAPT_LEVEL_SCALE_FROM),
                          "--adapt-level-scale", names.SCHEDULE_ADAPT_LEVEL_SCALE,
                          "--adapt-floor", str(names.SCHEDULE_ADAPT_FLOOR_S),
                          "--adapt-scale-max-from", str(names.SCHEDULE_ADAPT_SCALE_MAX_FROM),
                          "--rough-p-min", str(names.SCHEDULE_ROUGH_P_MIN)}
    # the maneuvering-flight setting (on by default) as its options' own flags, none for the setting itself
    maneuvering = daemon_flags(scheduled_defaults({"adapt_turbulence": True}, True))
    assert set(maneuvering) == set(flags) | set(daemon_flags({"trim_time_constant_s": 30.0, "adapt_turbulence": True,
                                                              **names.SCHEDULE_MANEUVER_SETTING}))
    assert "--maneuver-gates-calm-scaled" in maneuvering and "--maneuver-setting" not in maneuvering
    assert flags[flags.index("--adapt-counted-channel") + 1] == "vel"
    assert "--adapt-counted-channel" not in daemon_flags(scheduled_defaults({"adapt_turbulence": True}, False))


def test_the_excluded_channel_reaches_the_core_and_the_daemon():
    assert core_arguments({"adapt_excluded_channel": "aoa"})["adapt_excluded_channels"] == 1 << 1
    assert "adapt_excluded_channel" not in core_arguments({"adapt_excluded_channel": "aoa"})
    with pytest.raises(ValueError, match="--adapt-excluded-channel 'air' must be one of vel, aoa"):
        check({"adapt_turbulence": True, "adapt_excluded_channel": "air"})
    with pytest.raises(ValueError, match="--adapt-excluded-channel applies with --adapt-turbulence only"):
        check({"adapt_excluded_channel": "aoa"})
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({"adapt_turbulence": True, "adapt_excluded_channel": "aoa"})
    assert flags[flags.index("--adapt-excluded-channel") + 1] == "aoa"


def test_the_complete_trim_hold_reaches_the_core_and_the_daemon(vel_rol_schedule):
    """``complete_trim_hold`` off|suspected|declared is the core's keyword as given, refused
    otherwise by the harness and the core alike, handed to mmae-daemon as its flag, and the
    scheduled estimator's default; in flight the reference z_trim + dz - d is the trim in force of
    an earlier frame, the same over each run of held frames, held only while a failure is
    suspected (``suspected``) or declared (``declared``), and never with ``off``."""
    assert core_arguments({"complete_trim_hold": "declared"})["complete_trim_hold"] == "declared"
    with pytest.raises(ValueError, match="--complete-trim-hold 'on' must be one of off, suspected, declared"):
        check({"complete_trim_hold": "on"})
    with pytest.raises(ValueError, match="complete_trim_hold must be 'off', 'suspected' or 'declared'"):
        core.HierarchicalBank(vel_rol_schedule, complete_trim_hold="on")
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({"complete_trim_hold": "suspected"})
    assert flags[flags.index("--complete-trim-hold") + 1] == "suspected"
    assert Estimator(vel_rol_schedule, adapt_turbulence=True).settings["complete_trim_hold"] == \
        names.SCHEDULE_COMPLETE_TRIM_HOLD
    # the trim in force ramps (set_trim_offset) under noisy readings and a stuck AOA, which raise
    # failure hypotheses and declare one
    z0, u0 = np.asarray(vel_rol_schedule.z_trim), np.asarray(vel_rol_schedule.u_trim)
    for hold in ("off", "suspected", "declared"):
        bank = core.HierarchicalBank(vel_rol_schedule, complete_trim_hold=hold)
        rng = np.random.default_rng(5)
        refs, held, at_level0, run_ref = [], 0, 0, None
        for i in range(400):
            dz = np.zeros(names.NZ)
            dz[1] = 1e-4 * max(0, i - 250)   # after ROL's declaration (at 3.4 s)
            bank.set_trim_offset(np.zeros(names.NU), dz)
            level = bank.level
            z = z0 + 3e-2 * rng.standard_normal(names.NZ)
            z[1] = z0[1]   # the AOA sensor stuck: a declaration within the flight
            bank.update(z)
            bank.propagate(u0)
            d = np.asarray(bank.complete_trim_offset)
            if not d.any():
                refs.append(dz.copy())
                run_ref = None
                continue
            held += 1
            at_level0 += level == 0
            assert any(np.allclose(dz - d, r, rtol=0, atol=1e-15) for r in refs), (hold, i)
            if run_ref is not None:   # one reference over a run of held frames
                np.testing.assert_allclose(dz - d, run_ref, rtol=0, atol=1e-15)
            run_ref = dz - d
        assert (held > 0) == (hold != "off"), hold
        if hold == "declared":
            assert at_level0 == 0   # (a declared failure is at level 1 here)


def test_the_complete_trims_average_reaches_the_core_and_the_daemon(vel_rol_schedule):
    """``complete_trim_time_constant_s`` T is the core's keyword as given, refused outside
    [0, 3600] s by the harness and the core alike and handed to mmae-daemon as its flag; in flight
    with no hold the reference z_trim + dz - d is the trim in force averaged over T (a plain mean
    over the first T f frames; computed here from the frame rate f), and with ``declared`` that average stops while a failure is declared."""
    assert core_arguments({"complete_trim_time_constant_s": 30.0})["complete_trim_time_constant_s"] == 30.0
    with pytest.raises(ValueError, match="--complete-trim-time-constant"):
        check({"complete_trim_time_constant_s": -1.0})
    with pytest.raises(ValueError, match=r"complete_trim_time_constant_s must be in \[0, 3600\] s"):
        core.HierarchicalBank(vel_rol_schedule, complete_trim_time_constant_s=4000.0)
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({"complete_trim_time_constant_s": 30.0})
    assert float(flags[flags.index("--complete-trim-time-constant") + 1]) == 30.0
    z0, u0 = np.asarray(vel_rol_schedule.z_trim), np.asarray(vel_rol_schedule.u_trim)
    t = 0.5
    gain = 1.0 - np.exp(-1.0 / (t * vel_rol_schedule.frame_rate_hz))
    for hold in ("off", "declared"):
        bank = core.HierarchicalBank(vel_rol_schedule, complete_trim_hold=hold, complete_trim_time_constant_s=t)
        rng = np.random.default_rng(5)
        ref, declared_frames, averaged = None, 0, 0
        for i in range(400):
            dz = np.zeros(names.NZ)
            dz[1] = 1e-4 * max(0, i - 250)   # the trim in force ramps on AOA from frame 250 (3.9 s)
            bank.set_trim_offset(np.zeros(names.NU), dz)
            declared = bank.level != 0
            if ref is None or not (hold == "declared" and declared):   # a plain mean first, then the average
                averaged += 1
                ref = dz.copy() if ref is None else ref + max(1.0 / averaged, gain) * (dz - ref)
            declared_frames += declared
            z = z0 + 3e-2 * rng.standard_normal(names.NZ)
            z[1] = z0[1]   # the AOA sensor stuck
            bank.update(z)
            bank.propagate(u0)
            np.testing.assert_allclose(dz - np.asarray(bank.complete_trim_offset), ref, rtol=0, atol=1e-12)
        assert np.asarray(bank.complete_trim_offset)[1] > 1e-3   # the average lags the ramp
        assert declared_frames > 100   # ROL declared at 3.4 s (the noise), before the ramp


def test_an_excluded_channel_takes_its_free_level_hypotheses_out_of_the_minimum(vel_rol_schedule):
    """VEL and ROL read their channels as a free level (constant=VEL+ROL): excluding VEL's
    channel changes rho; excluding PIT's, which no hypothesis reads so, changes nothing."""
    bank = vel_rol_schedule
    own = dict(adapt_turbulence=True, adapt_own_channels=True, adapt_counted_channels=1)
    r_own = _fly(core.HierarchicalBank(bank, **own), bank)
    r_vel = _fly(core.HierarchicalBank(bank, **own, adapt_excluded_channels=1), bank)
    r_pit = _fly(core.HierarchicalBank(bank, **own, adapt_excluded_channels=1 << 2), bank)
    np.testing.assert_array_equal(r_pit, r_own)
    assert not np.array_equal(r_vel, r_own)
    assert np.all(r_vel >= r_own)   # a minimum over fewer hypotheses is never lower
    est = Estimator(bank, adapt_turbulence=True, adapt_excluded_channel="vel", adapt_level_scale_channel="none",
                    dwell_s_per_hypothesis=NO_LEAST_DWELL, rough_dwell_s_per_hypothesis=NO_ROUGH_DWELL,
                    maneuver_setting="off")   # the core banks' declarations
    np.testing.assert_array_equal(_fly(est, bank), r_vel)


def test_the_calm_air_complete_model_is_the_default_where_the_nodes_carry_a_calm_reference(vel_rol_schedule, tmp_path):
    """``calm_complete`` ``names.SCHEDULE_CALM_COMPLETE`` on a scheduled bank whose nodes carry a
    calm-air reference (with the adaptation), unless given; its table reaches the core by
    measurement and the daemon as given; the reference scales the bound (the core reads the
    air calm below bound x reference: the complete channels in force)."""
    given = {"adapt_turbulence": True}
    assert "calm_complete" not in scheduled_defaults(given, True)
    assert scheduled_defaults(given, True, calm_reference=True)["calm_complete"] == names.SCHEDULE_CALM_COMPLETE
    off = {**given, "calm_complete": "VEL=0"}
    assert scheduled_defaults(off, True, calm_reference=True)["calm_complete"] == "VEL=0"
    assert "calm_complete" not in scheduled_defaults({}, True, calm_reference=True)   # no adaptation
    check(off)
    with pytest.raises(ValueError, match="--calm-complete applies with --adapt-turbulence only"):
        check({"calm_complete": "VEL=1"})
    with pytest.raises(ValueError, match=r"--calm-complete: VEL's bound must lie in \[0, 100\] \(0: off\), got 101"):
        check({**given, "calm_complete": "VEL=101"})
    with pytest.raises(ValueError, match="--calm-complete: expected NAME=RHO"):
        check({**given, "calm_complete": "VEL"})
    assert core_arguments({"calm_complete": "VEL=1,AZ=0.5"})["calm_complete_rho"] == {"VEL": 1.0, "AZ": 0.5}
    assert "calm_complete" not in core_arguments({"calm_complete": "VEL=1"})
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({**given, "calm_complete": "VEL=1"})
    assert flags[flags.index("--calm-complete") + 1] == "VEL=1"
    # a schedule with the reference: the default in force, and the bound relative to it
    bank = vel_rol_schedule
    assert not has_calm_reference(bank)
    node = bank.schedule["nodes"][0]
    path = tmp_path / "calm.f16sched"
    core.save_schedule([0.4], [20000.0], [(0, 0, node["bank"], np.zeros(names.NX), None, 0, 0.5)], primary=0,
                       path=str(path))
    calm = core.load_bank(str(path))
    assert has_calm_reference(calm) and calm.schedule["nodes"][0]["calm_reference"] == 0.5
    assert bank_defaults(given, calm)["calm_complete"] == names.SCHEDULE_CALM_COMPLETE
    assert "calm_complete" not in bank_defaults(given, bank)
    root_a = np.linalg.cholesky(np.asarray(bank.hypotheses[0].a))   # NONE's residual covariance
    crossed = set()
    for bound, reference, calm_below in ((1.0, calm, 0.5), (1.8, calm, 0.9), (0.9, bank, 0.9)):
        hb = core.HierarchicalBank(reference, adapt_turbulence=True, calm_complete_rho={"VEL": bound},
                                   dwell_s=float(core.MAX_DWELL_S))
        assert hb.calm_complete_channels == 1   # calm until the air is measured
        rng = np.random.default_rng(3)
        decided, last = 0, 1
        for i in range(200):   # residual power 0.8 then 1.2 times NONE's A: rho-bar about 0.7, then 1.1
            power = 0.8 if i < 100 else 1.2
            hb.update(np.asarray(reference.z_trim) + np.sqrt(power) * root_a @ rng.standard_normal(names.NZ))
            hb.propagate(np.asarray(reference.u_trim))
            p = np.asarray(hb.probabilities)
            if hb.level == 0 and p[1:].max() <= 0.05:   # no failure presumed or rising: decided
                decided += 1
                assert hb.calm_complete_channels == (1 if hb.measured_power_ratio < calm_below else 0), (bound, i)
            else:   # held
                assert hb.calm_complete_channels == last, (bound, i)
            if hb.calm_complete_channels != last:
                crossed.add(bound)
            last = hb.calm_complete_channels
        assert decided > 150
    assert crossed == {1.0, 1.8, 0.9}   # each bank leaves calm air once the air it reads is above its bound


def test_the_calm_air_measure_is_checked_and_read_by_the_core(vel_rol_schedule):
    """``--calm-measure`` and ``--calm-whiteness-bound`` are refused out of range by flag, reach
    the core as ``calm_measure`` and ``calm_whiteness_bound``, and a bank reading the whiteness
    decides calm air by W-bar against the bound where it decides at all (no failure presumed or
    rising; cpp/f16mmae/residual_whiteness.h)."""
    given = {"adapt_turbulence": True, "calm_complete": "VEL=1"}
    check({**given, "calm_measure": "either", "calm_whiteness_bound": 0.7})
    with pytest.raises(ValueError, match="--calm-measure 'white' must be one of power, whiteness, either"):
        check({**given, "calm_measure": "white"})
    with pytest.raises(ValueError, match=r"--calm-whiteness-bound 0.0 must lie in \(0, 100\]"):
        check({**given, "calm_measure": "whiteness", "calm_whiteness_bound": 0.0})
    with pytest.raises(ValueError, match="calm_measure: must be 'power', 'whiteness' or 'either', got 'white'"):
        core.HierarchicalBank(vel_rol_schedule, adapt_turbulence=True, calm_complete_rho={"VEL": 1.0},
                              calm_measure="white")
    bank = vel_rol_schedule
    power = core.HierarchicalBank(bank, adapt_turbulence=True, calm_complete_rho={"VEL": 1.0})
    assert np.isnan(power.calm_whiteness)   # the power ratio's rule reads no whiteness
    root_a = np.linalg.cholesky(np.asarray(bank.hypotheses[0].a))
    states = set()
    for bound in (0.3, 0.6, 2.0):
        hb = core.HierarchicalBank(bank, adapt_turbulence=True, calm_complete_rho={"VEL": 1.0},
                                   calm_measure="whiteness", calm_whiteness_bound=bound, dwell_s=float(core.MAX_DWELL_S))
        rng = np.random.default_rng(5)
        last, decided, slow = 1, 0, np.zeros(names.NZ)
        for i in range(600):   # white noise (the filter chases it: W-bar about 0.4), then a slow part (W-bar up)
            if i >= 300:
                slow = 0.97 * slow + 0.5 * rng.standard_normal(names.NZ)
            hb.update(np.asarray(bank.z_trim) + root_a @ (rng.standard_normal(names.NZ) + slow))
            hb.propagate(np.asarray(bank.u_trim))
            w = hb.calm_whiteness
            if i < 64 + 7:   # the first second left out, then the first block
                assert np.isnan(w) and hb.calm_complete_channels == 1, i
            elif hb.level == 0 and np.asarray(hb.probabilities)[1:].max() <= 0.05:
                decided += 1
                assert hb.calm_complete_channels == (1 if w < bound else 0), (bound, i, w)
            else:
                assert hb.calm_complete_channels == last, (bound, i)
            last = hb.calm_complete_channels
            states.add(last)
        assert decided > 300
    assert states == {0, 1}


def test_the_level_scale_reaches_the_core_and_the_daemon(vel_rol_schedule):
    """--adapt-level-scale on|off: the core's keyword takes the two words and refuses others; the
    scheduled default hands mmae-daemon its flag; without the adaptation it is refused."""
    assert core_arguments({"adapt_turbulence": True, "adapt_level_scale": "on"})["adapt_level_scale"] == "on"
    for word in ("on", "off"):
        core.HierarchicalBank(vel_rol_schedule, adapt_turbulence=True, adapt_level_scale=word)
    with pytest.raises(ValueError, match="adapt_level_scale"):
        core.HierarchicalBank(vel_rol_schedule, adapt_turbulence=True, adapt_level_scale="yes")
    with pytest.raises(ValueError, match="--adapt-level-scale applies with --adapt-turbulence only"):
        check({"adapt_level_scale": "on"})
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags(scheduled_defaults({"adapt_turbulence": True}, True))
    assert flags[flags.index("--adapt-level-scale") + 1] == "on"


def test_the_level_channels_scaled_at_every_level_reach_the_core_and_the_daemon(vel_rol_schedule):
    """--adapt-level-scale-channel NAME|none and --adapt-level-scale-from S0: the sensor's bit in z's
    order and s_0 reach the core, which refuses s_0 below 1; the scheduled default hands mmae-daemon
    both flags, none hands it neither channel nor bit; without the adaptation they are refused."""
    given = core_arguments({"adapt_turbulence": True, "adapt_level_scale_channel": "vel", "adapt_level_scale_from": 8.0})
    assert given["adapt_level_scale_channels"] == 1 << names.SENSORS.index("VEL")
    assert given["adapt_level_scale_from"] == 8.0
    assert "adapt_level_scale_channels" not in core_arguments({"adapt_turbulence": True,
                                                               "adapt_level_scale_channel": "none"})
    core.HierarchicalBank(vel_rol_schedule, **given)
    with pytest.raises(ValueError, match=r"adapt_level_scale_from must be in \[1, 1000\], got 0.5"):
        core.HierarchicalBank(vel_rol_schedule, adapt_turbulence=True, adapt_level_scale_from=0.5)
    with pytest.raises(ValueError, match="--adapt-level-scale-channel applies with --adapt-turbulence only"):
        check({"adapt_level_scale_channel": "vel"})
    with pytest.raises(ValueError, match="--adapt-level-scale-from"):
        check({"adapt_turbulence": True, "adapt_level_scale_from": 0.5})
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags(scheduled_defaults({"adapt_turbulence": True}, True))
    assert flags[flags.index("--adapt-level-scale-channel") + 1] == "vel"
    assert float(flags[flags.index("--adapt-level-scale-from") + 1]) == names.SCHEDULE_ADAPT_LEVEL_SCALE_FROM
    flags = daemon_flags(scheduled_defaults({"adapt_turbulence": True, "adapt_level_scale_channel": "none"}, True))
    assert "--adapt-level-scale-channel" not in flags and "--adapt-level-scale-from" not in flags


def test_the_maneuvering_flight_setting_is_the_default_and_off_turns_it_off():
    """``maneuver_setting`` "on" (the default with the adaptation on a scheduled bank) gives each
    entry of ``names.SCHEDULE_MANEUVER_SETTING`` not given, where what it applies with is in
    force; "off" none; its switches have a --no- form; the resolved settings, as the run
    command's flags (a record's command), resolve to themselves; an option of the setting given alone is refused naming the setting's
    value of what it needs; the core takes no keyword for the setting itself."""
    from f16mmae.cli.main import build_parser
    from f16mmae.cli.options import estimator_options_from_args
    from f16mmae.loop.estimator_options import command_line_flags
    given = {"adapt_turbulence": True}
    on = scheduled_defaults(given, True)
    assert on["maneuver_setting"] == "on"
    assert {k: on[k] for k in names.SCHEDULE_MANEUVER_SETTING} == names.SCHEDULE_MANEUVER_SETTING
    off = scheduled_defaults({**given, "maneuver_setting": "off"}, True)
    assert not set(names.SCHEDULE_MANEUVER_SETTING) & set(off)
    mine = scheduled_defaults({**given, "maneuver_dwell_s": 1.5, "maneuver_kinematics": False}, True)
    args = build_parser().parse_args(["run", "--bank", "scheduled", "--adapt-turbulence", "--no-maneuver-kinematics"])
    assert estimator_options_from_args(args)["maneuver_kinematics"] is False
    assert mine["maneuver_dwell_s"] == 1.5 and mine["maneuver_kinematics"] is False   # given: kept
    no_dwell = scheduled_defaults({**given, "maneuver_dwell_s": 0.0, "trim_time_constant_s": 0.0}, True)
    assert not {"maneuver_dwell_hold_s", "maneuver_dwell_g", "trim_steady_g", "trim_steady_air_data",
                "trim_steady_measurements"} & set(no_dwell)   # what they apply with is off
    check(no_dwell)
    assert "--no-maneuver-kinematics" in command_line_flags(mine)   # a switch the setting turns on, given off
    for settings in (on, off, mine):
        args = build_parser().parse_args(["run", "--bank", "scheduled", *command_line_flags(settings)])
        again = scheduled_defaults(estimator_options_from_args(args), True)
        assert again == settings
    assert "maneuver_setting" not in core_arguments(on)
    with pytest.raises(ValueError, match="--maneuver-dwell-hold applies with --maneuver-dwell only .or with "
                                         "--adapt-turbulence on a scheduled bank, whose default is --maneuver-dwell 0.4"):
        check({"maneuver_dwell_hold_s": 10.0})
    with pytest.raises(ValueError, match="--maneuver-dwell-hold applies with --maneuver-dwell only .the scheduled "
                                         "defaults do not give it with these settings"):
        check_requirements(scheduled_defaults({**given, "maneuver_setting": "off", "maneuver_dwell_hold_s": 10.0},
                                              True), True)
    with pytest.raises(ValueError, match="--maneuver-setting 'yes' must be one of on, off"):
        check({**given, "maneuver_setting": "yes"})


def test_an_option_riding_on_a_scheduled_default_waits_for_the_banks_defaults(tmp_path):
    """``check`` runs before the bank is read: with --adapt-turbulence an option that applies with
    a scheduled default (``SCHEDULED_DEFAULT_FLAGS``) waits; the bank's defaults then give it on a
    scheduled bank, and ``bank_defaults`` refuses it, naming why, on a bank that is not."""
    from f16mmae.cli.main import main
    from f16mmae.loop.estimator_options import SCHEDULED_DEFAULT_FLAGS
    given = {"adapt_turbulence": True, "trim_steady_measurements": "AOA,VEL", "rough_scale": 6.0}
    check(given)   # waits: trim_steady_g and rough_dwell_s_per_hypothesis are scheduled defaults
    assert {"trim_steady_g", "rough_dwell_s_per_hypothesis"} <= set(SCHEDULED_DEFAULT_FLAGS)
    scheduled = bank_defaults(given, banks.load_bank("scheduled")[2])
    assert scheduled["trim_steady_measurements"] == "AOA,VEL" and scheduled["rough_scale"] == 6.0
    assert scheduled["trim_steady_g"] == names.SCHEDULE_MANEUVER_SETTING["trim_steady_g"]
    assert scheduled["rough_dwell_s_per_hypothesis"] == names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS
    with pytest.raises(ValueError, match="--trim-tracking-steady-measurements applies with --trim-tracking-steady "
                                         r"only \(the bank is not scheduled"):
        bank_defaults(given, banks.load_bank("tuned")[2])
    with pytest.raises(ValueError, match="--trim-tracking-steady-measurements applies with --trim-tracking-steady"):
        check({"trim_steady_measurements": "AOA,VEL"})   # without --adapt-turbulence no default can give it
    out = tmp_path / "run"
    assert main(["run", "--bank", "scheduled", "--adapt-turbulence", "--trim-tracking-steady-measurements", "AOA,VEL",
                 "--duration", "1", "--out", str(out)]) == 0
    import json
    settings = json.loads((out / "run.json").read_text())["estimator_settings"]
    assert settings["trim_steady_measurements"] == "AOA,VEL" and settings["trim_time_constant_s"] == 30.0


def test_a_lull_floor_shorter_than_the_averaging_time_is_refused_before_anything_flies(tmp_path, capsys):
    from f16mmae.cli.main import main
    averaging = core.estimator_defaults()["adapt_time_constant_s"]
    assert averaging == 5.0   # the core's default, the one bank construction applies
    for tau in (0.0, averaging, names.SCHEDULE_ADAPT_FLOOR_S):
        check({"adapt_turbulence": True, "adapt_floor_time_constant_s": tau})
    with pytest.raises(ValueError, match=r"--adapt-floor 2\.0 must be 0 \(off\) or a time in \[5, 3600\] s \(at "
                                         r"least the adaptation's averaging time\)"):
        check({"adapt_turbulence": True, "adapt_floor_time_constant_s": 2.0})
    # the core refuses the same value by its own name: the two checks agree on the bound
    with pytest.raises(ValueError, match="adapt_floor_time_constant_s"):
        core.HierarchicalBank(banks.load_bank("tuned")[2], adapt_turbulence=True, adapt_floor_time_constant_s=2.0)
    out = tmp_path / "c"
    assert main(["campaign", "single", "--runs", "1", "--cases", "NONE", "--baseline", "none", "--tuning", "scheduled",
                 "--adapt-turbulence", "--adapt-floor", "2", "--quiet", "--out", str(out)]) == 2
    assert "--adapt-floor 2.0 must be 0 (off) or a time in [5, 3600] s" in capsys.readouterr().err
    assert not out.exists()   # refused before the campaign's folder or its first flight


def test_the_rough_air_floor_is_the_scheduled_default_and_its_band_is_checked():
    assert scheduled_defaults({"adapt_turbulence": True}, True)["rough_p_min"] == names.SCHEDULE_ROUGH_P_MIN
    assert "rough_p_min" not in scheduled_defaults({"adapt_turbulence": True}, False)
    assert scheduled_defaults({"adapt_turbulence": True, "rough_p_min": 0.0}, True)["rough_p_min"] == 0.0   # off
    defaults = core.estimator_defaults()
    assert (defaults["rough_p_min"], defaults["rough_p_min_from"], defaults["rough_p_min_to"]) == (0.0, 1.3, 1.5)
    check({"adapt_turbulence": True, "rough_p_min_from": 1.0})   # waits for the scheduled default's floor
    check({"adapt_turbulence": True, "rough_p_min": 1e-9, "rough_p_min_from": 1.4, "rough_p_min_to": 2.0})
    with pytest.raises(ValueError, match=r"--rough-p-min-from 1\.6 must lie below --rough-p-min-to 1\.5"):
        check({"adapt_turbulence": True, "rough_p_min": 1e-9, "rough_p_min_from": 1.6})
    with pytest.raises(ValueError, match=r"--rough-p-min-from 1\.3 must lie below --rough-p-min-to 1\.0"):
        check({"adapt_turbulence": True, "rough_p_min": 1e-9, "rough_p_min_to": 1.0})
    with pytest.raises(ValueError, match="--rough-p-min applies with --adapt-turbulence only"):
        check({"rough_p_min": 1e-9})
    with pytest.raises(ValueError, match=r"--rough-p-min 0\.08 must lie in"):
        check({"adapt_turbulence": True, "rough_p_min": 0.08})
    with pytest.raises(ValueError, match="rough_p_min reads the air from the turbulence adaptation"):
        core.HierarchicalBank(banks.load_bank("tuned")[2], rough_p_min=1e-9)
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({"adapt_turbulence": True, "rough_p_min": 1e-9, "rough_p_min_from": 1.2})
    assert flags[flags.index("--rough-p-min") + 1] == "1e-09" and flags[flags.index("--rough-p-min-from") + 1] == "1.2"


def _floors_in_force(turbulence: str, **options) -> np.ndarray:
    """The level-0 floor in force after each frame of a 40-s failure-free flight at Mach 0.45,
    15,000 ft (the scheduled default's nodes there chose 1e-5 on their light-air calibration)."""
    from f16mmae.truth import Scenario
    model_bank = banks.load_bank("scheduled")[2]
    est = Estimator.fresh(model_bank, **bank_defaults({"adapt_turbulence": True, **options}, model_bank))
    scenario = Scenario(mach=0.45, alt_ft=15000.0, turbulence=turbulence, seed=3, duration_s=40.0)
    return floors_in_force(scenario, model_bank, est)[1]


def test_the_floor_in_force_is_the_nodes_in_light_air_and_the_rough_air_floor_in_moderate_air():
    """Past the start-up second (1 s, no hypothesis weighed; the first frames' residuals read as
    rough air), light air flies the nodes' floors frame for frame as without the rough-air floor,
    moderate air the rough-air floor, where without it the nodes' 1e-5 (blended) stays."""
    light, light_off = _floors_in_force("light"), _floors_in_force("light", rough_p_min=0.0)
    moderate, moderate_off = _floors_in_force("moderate"), _floors_in_force("moderate", rough_p_min=0.0)
    start_up = 64
    assert light[0] == light_off[0] == moderate[0]   # no air measured before the first update
    assert np.array_equal(light[start_up:], light_off[start_up:]) and np.all(light_off > 1e-6)
    assert np.all(moderate[start_up:] == names.SCHEDULE_ROUGH_P_MIN) and np.all(moderate_off > 1e-6)


def test_the_bounds_knee_reaches_the_core_and_the_daemon():
    """--adapt-scale-max-from RHO: from the power ratio RHO on the bound on s rises with the air at the
    adaptation's gain (cpp/f16mmae/turbulence_adaptation.h), checked on a bank fed residuals three
    times the design's: the bound alone holds s at it, the knee lifts s to the line's parallel."""
    import subprocess

    from daemon_support import ready_line
    from f16mmae.lcm.daemon import daemon_flags, find_executable
    options = {"adapt_turbulence": True, "adapt_scale_max_from": 2.0}
    check(options)
    assert core_arguments(options)["adapt_scale_max_from"] == 2.0
    for bad in (-1.0, 101.0):
        with pytest.raises(ValueError, match=r"--adapt-scale-max-from .* must lie in \[0, 100\]"):
            check({**options, "adapt_scale_max_from": bad})
    with pytest.raises(ValueError, match="--adapt-scale-max-from applies with --adapt-turbulence"):
        check({"adapt_scale_max_from": 2.0})
    bank = banks.load_bank("tuned")[2]
    kw = dict(adapt_turbulence=True, adapt_reference=0.6, adapt_gain=20.0, adapt_scale_max=5.0, p_min=1e-9)
    bound = core.HierarchicalBank(bank, **kw)
    kneed = core.HierarchicalBank(bank, adapt_scale_max_from=2.0, **kw)
    rng = np.random.default_rng(3)
    z_trim, u_trim = np.asarray(bank.z_trim), np.asarray(bank.u_trim)
    sigma = np.sqrt(np.diag(np.asarray(bank.hypotheses[0].a)))
    lifted = 0
    for _ in range(192):
        z = z_trim + 3.0 * sigma * rng.standard_normal(len(z_trim))
        for b in (bound, kneed):
            b.update(z)
            b.propagate(u_trim)
        rho = kneed.turbulence_power_ratio
        assert rho == bound.turbulence_power_ratio   # the same residuals: the knee moves s only
        assert kneed.turbulence_scale == pytest.approx(
            min(max(1.0, 1.0 + 20.0 * (rho - 0.6)), 5.0 + 20.0 * max(rho - 2.0, 0.0)), rel=1e-12)
        assert bound.turbulence_scale == pytest.approx(min(max(1.0, 1.0 + 20.0 * (rho - 0.6)), 5.0), rel=1e-12)
        lifted += kneed.turbulence_scale > 5.0
    assert lifted > 50
    flags = daemon_flags(options)
    assert flags[flags.index("--adapt-scale-max-from") + 1] == "2.0"
    assert "bound rising from rho 2" in ready_line("--bank", banks.load_bank("tuned")[1], *flags)
    daemon = str(find_executable("mmae-daemon"))
    for bad, message in ((["--adapt-scale-max-from", "2"], "--adapt-scale-max-from applies with --adapt-turbulence"),
                         (["--adapt-turbulence", "--adapt-scale-max-from", "-1"],
                          "--adapt-scale-max-from must be a power ratio in [0, 100], got '-1'")):
        r = subprocess.run([daemon, "--bank", str(banks.load_bank("tuned")[1]), *bad], capture_output=True,
                           text=True, timeout=20)
        assert r.returncode == 2 and message in r.stdout + r.stderr, (bad, r.stdout + r.stderr)
