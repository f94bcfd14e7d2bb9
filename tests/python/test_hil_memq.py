"""The HIL harness's LCM path, in one process over memq://.

* the message types round-trip through LCM with every field;
* a lockstep flight through RemoteEstimator against the in-process executive served on
  memq:// gives exactly the probabilities of the in-process closed loop (the same loop,
  the same bank, only the transport differs);
* no executive: lockstep times out with a message that says what to check, paced mode
  counts deadline misses and flies on raw z; a wrong bank is refused;
* a 19-state gust bank runs in the executive as in process, with the "reconfigure" feedback
  applied frame by frame (here) exactly as in the C++ closed loop.
"""
from __future__ import annotations

import lcm
import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.cli.main import main
from f16mmae.loop.flight import fly
from f16mmae.lcm.channels import HilError, channels
from f16mmae.lcm.hil import fly_hil
from f16mmae.lcm.remote import RemoteEstimator, level0_hypotheses
from f16mmae.lcmt_command_frame import lcmt_command_frame
from f16mmae.lcmt_mmae_status import lcmt_mmae_status
from f16mmae.lcmt_run_marker import lcmt_run_marker
from f16mmae.lcmt_sensor_frame import lcmt_sensor_frame
from f16mmae.names import SINGLE_HYPOTHESES
from f16mmae.lcm.replay import InProcessExecutive
from f16mmae.loop.estimator_options import bank_defaults
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure
from schedule_support import one_node_schedule


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def _scenario(failures=(), duration_s=1.0, seed=2):
    return Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=duration_s, seed=seed,
                    feedback="mmae", failures=tuple(make_failure(n, t) for n, t in failures))


def _lockstep_equals_in_process(mb, scenario, prefix, options=None, commands=None, **fly_kwargs):
    """Flies ``scenario`` in lockstep over memq:// against an InProcessExecutive of ``mb`` with the
    estimator ``options``, and in process with the same; checks that the two agree (hypotheses,
    probabilities to 1e-12, declarations) and returns (remote run, in-process run).  With a list
    ``commands``, also that both flew the same commands u_i, bit for bit (appended to it: the
    in-process flight's, (frames, inputs); both then fly frame by frame)."""
    if options:
        fly_kwargs["estimator_options"] = options
    lc = lcm.LCM("memq://")
    chans = channels(prefix)
    InProcessExecutive(mb, **(options or {})).serve(lc, chans)
    u_remote, u_local = [], []
    record = (lambda into: (lambda t, u, z, air: into.append(u))) if commands is not None else (lambda into: None)
    remote_run = fly_hil(scenario, mb, lc, chans, lockstep=True, timeout_s=2.0, on_frame=record(u_remote),
                         **fly_kwargs)
    local_run = fly(scenario, mb, on_frame=record(u_local), **fly_kwargs)
    assert remote_run.hypotheses == local_run.hypotheses
    np.testing.assert_array_equal(np.isnan(remote_run.probabilities), np.isnan(local_run.probabilities))
    assert np.nanmax(np.abs(remote_run.probabilities - local_run.probabilities)) <= 1e-12
    assert remote_run.declarations == local_run.declarations
    if commands is not None:
        np.testing.assert_array_equal(np.array(u_remote), np.array(u_local))
        commands.append(np.array(u_local))
    return remote_run, local_run


def test_channel_names_take_the_prefix():
    c = channels("SIM1_")
    assert (c.sensors, c.commands, c.status, c.reset, c.run_marker) == (
        "SIM1_F16_SENSORS", "SIM1_F16_COMMANDS", "SIM1_MMAE_STATUS", "SIM1_MMAE_RESET", "SIM1_F16_RUN_MARKER")
    assert channels().sensors == "F16_SENSORS"


def test_messages_round_trip_over_memq():
    lc = lcm.LCM("memq://")
    got = {}
    for ch in ("S", "C", "M", "R"):
        lc.subscribe(ch, lambda channel, data: got.__setitem__(channel, data))
    s = lcmt_sensor_frame()
    s.utime, s.frame, s.z, s.valid = 15625, 1, [414.8, 0.14, 0.0, 1.0, 0.01, -0.02, 0.003], [True] * 6 + [False]
    c = lcmt_command_frame()
    c.utime, c.frame, c.u_rad = 15625, 1, [-0.036, -0.036, 0.0, 0.0, 0.001]
    m = lcmt_mmae_status()
    m.utime, m.frame, m.bank_hash, m.bank_level, m.level_failure = 15625, 1, "ab" * 32, 1, "PIT"
    m.declared, m.declaration, m.num_hypotheses = "PIT", "PIT", 3
    m.hypothesis_names, m.probabilities = ["NONE", "PIT", "LS+PIT"], [0.001, 0.998, 0.001]
    m.z_hat, m.stale, m.frames_without_update, m.frames_dropped = [1.0] * 7, True, 2, 5
    r = lcmt_run_marker()
    r.utime, r.event, r.payload_json = 3_000_000, "failure", '{"name": "PIT"}'
    for ch, msg in (("S", s), ("C", c), ("M", m), ("R", r)):
        lc.publish(ch, msg.encode())
        lc.handle_timeout(100)
    assert list(lcmt_sensor_frame.decode(got["S"]).z) == s.z
    assert list(lcmt_sensor_frame.decode(got["S"]).valid) == s.valid
    assert list(lcmt_command_frame.decode(got["C"]).u_rad) == c.u_rad
    back = lcmt_mmae_status.decode(got["M"])
    assert list(back.hypothesis_names) == m.hypothesis_names and list(back.probabilities) == m.probabilities
    assert (back.declared, back.declaration, back.stale, back.frames_without_update) == ("PIT", "PIT", True, 2)
    assert lcmt_run_marker.decode(got["R"]).payload_json == r.payload_json


def test_lockstep_over_memq_reproduces_the_in_process_run(bank):
    # LS declared at level 0, then a dual at level 1: both levels cross the link
    scenario = _scenario([("LS", 0.5)], duration_s=4.0)
    remote_run, _ = _lockstep_equals_in_process(bank, scenario, "MQ_")
    assert [d["hypothesis"] for d in remote_run.declarations][:1] == ["LS"]
    assert any("+" in h for h in remote_run.hypotheses)  # the level-1 bank came on line
    link = remote_run.timing["link"]
    assert link["frames"] == link["statuses"] == 256 and link["deadline_misses"] == 0


def test_lockstep_without_an_executive_says_what_to_check(bank):
    lc = lcm.LCM("memq://")
    remote = RemoteEstimator(lc, channels("NOBODY_"), lockstep=True, timeout_s=0.05)
    with pytest.raises(HilError, match=r"no MMAE_STATUS for frame 0 .*NOBODY_MMAE_STATUS.*channel-prefix"):
        remote.update(np.zeros(7))


def test_paced_mode_counts_deadline_misses_and_flies_on_raw_z(bank):
    lc = lcm.LCM("memq://")
    remote = RemoteEstimator(lc, channels("NOBODY_"), lockstep=False, rate_hz=200.0,
                             initial_hypotheses=level0_hypotheses(bank))
    z = np.array(bank.z_trim) + 0.01
    for _ in range(4):
        np.testing.assert_array_equal(remote.update(z), z)
        remote.propagate(np.array(bank.u_trim))
    assert remote.link.deadline_misses == 4 and remote.link.frames == 4
    assert remote.hypotheses == SINGLE_HYPOTHESES  # before any status: the bank's level 0


def test_paced_mode_against_an_executive_misses_nothing(bank):
    lc = lcm.LCM("memq://")
    chans = channels("PACED_")
    InProcessExecutive(bank).serve(lc, chans)
    # paced at 8 Hz: each status has 125-250 ms to come back, so a loaded host's scheduling
    # cannot make a miss; what is checked is that the paced link takes every status in time
    remote = RemoteEstimator(lc, chans, lockstep=False, rate_hz=8.0, expected_bank_hash=bank.content_hash,
                             initial_hypotheses=level0_hypotheses(bank))
    result = fly_hil(_scenario(duration_s=0.25), bank, lc, chans, remote=remote)
    assert result.timing["link"]["deadline_misses"] == 0
    assert result.timing["link"]["statuses"] == 16


def test_an_executive_running_another_bank_is_refused(bank):
    lc = lcm.LCM("memq://")
    chans = channels("OTHER_")
    InProcessExecutive(bank).serve(lc, chans)
    remote = RemoteEstimator(lc, chans, lockstep=True, timeout_s=1.0, expected_bank_hash="0" * 64)
    with pytest.raises(HilError, match="start mmae-daemon with the same --bank"):
        remote.update(np.array(bank.z_trim))


@pytest.fixture(scope="module")
def gust_bank(tmp_path_factory):
    """A 19-state bank (the Dryden gust states), designed as `f16mmae design --gust-states` does."""
    path = tmp_path_factory.mktemp("gust") / "gust.f16bank"
    assert main(["design", "--tuning", "tuned_gust", "--out", str(path)]) == 0
    mb = core.load_bank(str(path))
    assert mb.nx == 19
    return path, mb


def test_a_gust_bank_over_memq_reproduces_the_in_process_run_with_reconfigured_feedback(gust_bank):
    """The executive runs the 19-state bank (its nx selects it, as in process); the loop's
    "reconfigure" feedback frame by frame (here, over LCM) equals the C++ closed loop's."""
    _, mb = gust_bank
    scenario = _scenario([("AZ", 0.5)], duration_s=3.0)
    _, local_run = _lockstep_equals_in_process(mb, scenario, "MQG_", feedback="reconfigure")
    assert [d["hypothesis"] for d in local_run.declarations][:1] == ["AZ"]
    # until AZ is declared the control law flies on the raw sensors; after it, on the
    # estimate of AZ (the pitch loop feeds it back): the flight departs from the raw one there
    recon = core.SensorReconfiguration(mb)
    assert recon.failed_sensors("AZ") == ["AZ"] and recon.failed_sensors("LF+AY") == ["AY"]
    assert recon.failed_sensors("NONE") == [] and recon.failed_sensors("PIT+ROL") == ["PIT", "ROL"]
    with pytest.raises(ValueError, match="no hypothesis 'FLAP'"):
        recon.apply("FLAP", mb.z_trim, mb.z_trim)
    raw_run = fly(scenario, mb, feedback="raw")
    first = int(round(local_run.declarations[0]["time_s"] * 64))
    cols = [local_run.hypotheses.index(h) for h in ("NONE", "AZ")]
    raw_cols = [raw_run.hypotheses.index(h) for h in ("NONE", "AZ")]
    mine, raw = local_run.probabilities[:, cols], raw_run.probabilities[:, raw_cols]
    np.testing.assert_array_equal(raw[:first + 1], mine[:first + 1])
    assert np.max(np.abs(raw[first + 1:] - mine[first + 1:])) > 0


def test_lockstep_with_the_maneuver_trim_reproduces_the_in_process_run(bank):
    # the air data's noise moves the climb and acceleration estimates, and so the trim offsets and
    # the states' shifts, frame by frame on both sides of the link
    options = dict(maneuver_trim=True, maneuver_trim_time_constant_s=0.2)
    scenario = _scenario([("LS", 0.5)], duration_s=3.0)
    _, local_run = _lockstep_equals_in_process(bank, scenario, "MT_", options)
    plain_run = fly(scenario, bank)
    # the option is in force: the flight is not the bank as designed
    assert not np.array_equal(np.nan_to_num(local_run.probabilities), np.nan_to_num(plain_run.probabilities))


def test_lockstep_with_the_maneuver_trims_inertial_rates_reproduces_the_in_process_run(bank):
    # the rates read z's gyros, AOA and VEL after each update and the freeze condition: the same
    # on both sides of the link
    options = dict(maneuver_trim=True, maneuver_trim_rates="inertial", maneuver_trim_blend_s=1.0)
    scenario = _scenario([("LS", 0.5)], duration_s=3.0)
    _, local_run = _lockstep_equals_in_process(bank, scenario, "MTI_", options)
    air_run = fly(scenario, bank, estimator_options=dict(maneuver_trim=True))
    # the option is in force: the flight is not the air data's maneuver trim
    assert not np.array_equal(np.nan_to_num(local_run.probabilities), np.nan_to_num(air_run.probabilities))


def test_lockstep_with_the_maneuver_dwell_and_level1_options_reproduces_the_in_process_run(bank):
    # the maneuver dwell's gate low (0.005 g, no hold): light turbulence opens and closes it, so
    # the dwell and reference in force change frame by frame on both sides of the link
    options = dict(adapt_turbulence=True, maneuver_dwell_s=0.75, maneuver_dwell_g=0.005,
                   maneuver_dwell_time_constant_s=0.5, maneuver_reference=0.7, level1_p_min=1e-4,
                   level1_dwell_s=0.5, departure_hold="off", maneuver_tempering_g=0.1,
                   maneuver_tempering_deadband_g=0.05, adapt_channel_weight=0.5,
                   maneuver_tempering_alpha_deg=0.5, maneuver_tempering_alpha_deadband_deg=0.1,
                   maneuver_tempering_added_g=0.05, maneuver_tempering_added_deadband_g=0.01,
                   maneuver_tempering_added_spread=3.0, maneuver_rate_gust_scaled=True, maneuver_climb_ft_s=2.0)
    scenario = _scenario([("LS", 0.5)], duration_s=3.0)
    _, local_run = _lockstep_equals_in_process(bank, scenario, "MD_", options)
    plain_run = fly(scenario, bank)
    assert [d["hypothesis"] for d in local_run.declarations][:1] == ["LS"]
    # the options are in force: the flight is not the bank as designed
    assert not np.array_equal(np.nan_to_num(local_run.probabilities), np.nan_to_num(plain_run.probabilities))


def test_lockstep_with_steady_tracking_and_calm_scaled_gates_reproduces_the_in_process_run(bank):
    # steady trim tracking of AOA, VEL and AZ with the air data's gate open and a 2-s time
    # constant (the trims move within the flight), the gates calm-scaled with a low load-factor
    # gate: the tracked offsets and the dwell in force change on both sides of the link alike
    options = dict(adapt_turbulence=True, trim_time_constant_s=2.0, trim_steady_g=0.1, trim_steady_air_data="off",
                   trim_steady_measurements="AOA,VEL,AZ", maneuver_dwell_s=0.75, maneuver_dwell_g=0.005,
                   maneuver_reference=0.7, maneuver_gates_calm_scaled=True)
    scenario = _scenario([("LS", 0.5)], duration_s=3.0)
    _, local_run = _lockstep_equals_in_process(bank, scenario, "ST_", options)
    aoa_only = fly(scenario, bank, estimator_options={k: v for k, v in options.items()
                                                      if k not in ("trim_steady_measurements", "trim_steady_air_data")})
    # the options are in force: the flight is not the steady tracking of AOA alone
    assert not np.array_equal(np.nan_to_num(local_run.probabilities), np.nan_to_num(aoa_only.probabilities))


@pytest.fixture(scope="module")
def turbulence_bank():
    """The turbulence bank set's start member (--tuning turbulence): the set flies with it."""
    return load_bank("turbulence")[2]


def _commands(scenario, mb, options) -> np.ndarray:
    """The commands u_i of ``scenario`` flown in process with ``options``, frame by frame."""
    us = []
    fly(scenario, mb, estimator_options=options, on_frame=lambda t, u, z, air: us.append(u))
    return np.array(us)


def test_lockstep_with_the_adaptive_dither_reproduces_the_in_process_run(turbulence_bank):
    """--adaptive-dither over the link: the truth side sets the dither's gains from the status's
    member in force and rho (loop/flight.py), which equal the in-process set's, so the commands
    and probabilities are the in-process flight's exactly; in severe air the member reads the
    gusts and the flaperons' turbulence line comes in (the flight departs from the fixed dither's)."""
    scenario = Scenario(mach=0.4, alt_ft=20000.0, turbulence="severe", duration_s=2.0, seed=3, feedback="mmae",
                        failures=(make_failure("LF", 1.0),))
    options = {"turbulence_banks": True, "adaptive_dither": True}
    commands = []
    remote_run, _ = _lockstep_equals_in_process(turbulence_bank, scenario, "AD_", options, commands=commands)
    assert remote_run.estimator_settings["adaptive_dither"] is True
    fixed = _commands(scenario, turbulence_bank, {"turbulence_banks": True, "fixed_dither": True})
    adaptive = commands[0]
    lf = 2  # ACTUATORS: LS RS LF RF RUD (THR)
    assert np.abs(fixed[:, lf] - adaptive[:, lf]).max() > np.radians(1.0)


def test_lockstep_with_the_sensor_loss_dither_reproduces_the_in_process_run(bank):
    """--sensor-loss-dither over the link: the truth side sets the dither's gains from the status's
    declared hypothesis (loop/flight.py), so the commands and probabilities are the in-process
    flight's exactly; after PIT is declared the stabilators' line is larger than the fixed dither's."""
    scenario = Scenario(mach=0.4, alt_ft=20000.0, turbulence="none", noise=False, duration_s=3.0, seed=1,
                        feedback="mmae", failures=(make_failure("PIT", 1.0),))
    commands = []
    remote_run, _ = _lockstep_equals_in_process(bank, scenario, "SL_", {"sensor_loss_dither": True},
                                                commands=commands)
    assert remote_run.declarations and remote_run.declarations[0]["hypothesis"] == "PIT"
    assert remote_run.estimator_settings["sensor_loss_dither"] is True
    fixed = _commands(scenario, bank, {})
    k = int(round(remote_run.declarations[0]["time_s"] * 64))
    np.testing.assert_array_equal(fixed[:k], commands[0][:k])
    assert np.abs(fixed[k:, 0] - commands[0][k:, 0]).max() > 0.0


def test_lockstep_with_one_adapted_banks_adaptive_dither_reproduces_the_in_process_run(tmp_path):
    """The scheduled default's adaptive dither over the link: the status carries the adaptation's
    measured rho-bar (member -1), the truth side sets the gains from it and the air data it sent,
    so the commands and probabilities are the in-process flight's exactly; in severe air the
    flaperons' turbulence line comes in and the rudder's line grows (its calm-air line with
    --fixed-rudder-dither)."""
    schedule = one_node_schedule(tmp_path)
    options = bank_defaults({"adapt_turbulence": True}, schedule)   # as f16mmae hil gives them
    assert options["adaptive_dither"] is True
    scenario = Scenario(mach=0.4, alt_ft=20000.0, turbulence="severe", duration_s=2.0, seed=3, feedback="mmae",
                        failures=(make_failure("LF", 1.0),))
    commands = []
    remote_run, _ = _lockstep_equals_in_process(schedule, scenario, "ADA_", options, commands=commands)
    assert remote_run.estimator_settings["adaptive_dither"] is True
    fixed = _commands(scenario, schedule, {**options, "adaptive_dither": False, "fixed_dither": True})
    lf = 2  # ACTUATORS: LS RS LF RF RUD
    assert np.abs(fixed[:, lf] - commands[0][:, lf]).max() > np.radians(1.0)
    rud = 4
    calm_rudder = _commands(scenario, schedule, {**options, "fixed_rudder_dither": True})
    assert np.abs(calm_rudder[:, rud] - commands[0][:, rud]).max() > np.radians(0.1)
    executive = InProcessExecutive(schedule, **options)
    status = executive.on_sensor(0, schedule.z_trim)
    assert status.turbulence_member == -1 and np.isfinite(status.turbulence_power_ratio)


def test_the_adaptive_dither_over_lcm_needs_the_sets_member_in_the_status(bank, turbulence_bank):
    """An executive running one bank without the adaptation sends member -1 and rho NaN: the
    truth side refuses the adaptive dither, saying what to start."""
    lc = lcm.LCM("memq://")
    chans = channels("ADX_")
    InProcessExecutive(bank).serve(lc, chans)
    scenario = Scenario(mach=0.4, alt_ft=20000.0, turbulence="severe", duration_s=0.1, seed=3, feedback="mmae")
    remote = RemoteEstimator(lc, chans, lockstep=True, timeout_s=2.0,
                             initial_hypotheses=level0_hypotheses(turbulence_bank))
    with pytest.raises(ValueError, match="--turbulence-banks"):
        fly_hil(scenario, turbulence_bank, lc, chans, remote=remote,
                estimator_options={"turbulence_banks": True, "adaptive_dither": True})
    status = InProcessExecutive(bank).on_sensor(0, bank.z_trim)
    assert status.turbulence_member == -1 and np.isnan(status.turbulence_power_ratio)
