"""Replay of recorded executive traffic (f16mmae replay) through the daemon's own executive
(core.Executive).

* the frame rules through the binding: fates, shapes refused, a wild frame counter
  re-synchronising in constant time (the C++ tests hold the rules themselves);
* a log of a flight recorded over memq:// replays with every status matching exactly;
* a log with wire faults (duplicate, late, lost, non-finite, invalid frames) replays, and
  the stale flags and counters are those the rules prescribe;
* a tampered status is found and named by frame; the command exits 1;
* unreadable or foreign logs are refused with a clear message.
"""
from __future__ import annotations


import lcm
import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.cli.main import main
from f16mmae.lcm.channels import channels
from f16mmae.lcm.hil import fly_hil
from f16mmae.loop.flight import fly
from f16mmae.lcmt_mmae_status import lcmt_mmae_status
from f16mmae import core
from f16mmae.lcm.replay import (COMMAND_FRAME_FINGERPRINT_WITHOUT_THROTTLE, SENSOR_FRAME_FINGERPRINT_WITHOUT_AIR_DATA,
                                STATUS_FINGERPRINT_WITHOUT_TURBULENCE_MEMBER,
                                InProcessExecutive, ReplayError, replay_log)
from f16mmae.lcmt_sensor_frame import lcmt_sensor_frame
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure
from wire_faults import STALE, STATUS_FRAMES, WIRE, publish_step


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


# -- the frame rules, through the binding ---------------------------------------------------------
def test_the_bound_executive_gives_every_frame_its_fate(bank):
    ex = core.Executive(bank)
    z, u = np.array(bank.z_trim), np.array(bank.u_trim)
    assert ex.encoded_status == b""
    assert ex.on_command(5, u) == "out-of-order"          # before the first sensor frame
    assert ex.on_sensor(0, z) == "used"
    assert ex.on_sensor(0, z) == "duplicate"
    assert ex.on_command(0, u) == "used"
    assert ex.on_sensor(3, z) == "used"                    # frames 1, 2 lost: caught up, stale
    assert lcmt_mmae_status.decode(ex.encoded_status).frames_without_update == 2
    assert ex.on_sensor(2, z) == "out-of-order"
    assert ex.on_sensor(4, z, valid=[True] * 6 + [False]) == "rejected"
    assert ex.on_sensor(4, np.full(7, np.nan)) == "rejected"
    # air data: the two used frames came without any (NaN): counted, the frames still used
    assert ex.counters == dict(frames_updated=2, commands_applied=1, frames_rejected=2, dropped_duplicate=1,
                               dropped_out_of_order=2, frames_resynchronised=0, frames_stale=2,
                               commands_missed=2, air_data_rejected=2)
    assert ex.on_sensor(4, z, air_data=(0.41, 20300.0)) == "used"
    assert ex.on_sensor(5, z, air_data=(0.41, np.inf)) == "used"
    status = lcmt_mmae_status.decode(ex.encoded_status)
    assert status.air_data_rejected == ex.counters["air_data_rejected"] == 3
    with pytest.raises(ValueError, match=r"air_data must be \(mach, pressure_altitude_ft\), got 3"):
        ex.on_sensor(6, z, air_data=(0.4, 2e4, 1.0))
    with pytest.raises(ValueError, match=r"z must have shape \(7,\), got \(6,\)"):
        ex.on_sensor(5, z[:6])
    with pytest.raises(ValueError, match="valid must hold 7 flags, got 2"):
        ex.on_sensor(5, z, valid=[True, True])
    with pytest.raises(ValueError, match=r"u must have shape \(5,\)"):
        ex.on_command(5, z)


def test_a_wild_frame_counter_resynchronises_at_once(bank):
    """Issue 16: a frame 2^62 ahead made the executive propagate once per skipped frame."""
    ex = InProcessExecutive(bank)
    assert ex.executive.max_gap_frames == 64
    z, u = np.array(bank.z_trim), np.array(bank.u_trim)
    for i in range(10):
        ex.on_sensor(i, z)
        ex.on_command(i, u)
    status = ex.on_sensor(2**62, z)          # returns at once
    assert status.resynchronised and status.frame == 2**62 and status.frames_resynchronised == 1
    assert ex.on_command(10, u) == "resynchronised"   # the real traffic, far behind it
    assert not ex.on_sensor(11, z).resynchronised
    assert ex.executive.counters["frames_resynchronised"] == 2


# -- logs ------------------------------------------------------------------------------------------
class Recorder:
    """Every message on an LCM instance, written to an event log as lcm-logger would."""

    def __init__(self, lc, path):
        self.log = lcm.EventLog(str(path), "w", overwrite=True)
        self.n = 0
        lc.subscribe(".*", self._on)

    def _on(self, channel, data):
        self.log.write_event(self.n, channel, data)
        self.n += 1

    def close(self):
        self.log.close()


def _record_flight(bank, path, prefix="REC_", turbulence="light", failure="AOA", **estimator_options):
    lc = lcm.LCM("memq://")
    chans = channels(prefix)
    rec = Recorder(lc, path)
    InProcessExecutive(bank, **estimator_options).serve(lc, chans)
    result = fly_hil(_recorded_scenario(turbulence, failure), bank, lc, chans, lockstep=True, timeout_s=2.0,
                     estimator_options=estimator_options)
    lc.handle_timeout(10)  # the last command reaches the recorder
    rec.close()
    return result


def _recorded_scenario(turbulence="light", failure="AOA"):
    return Scenario(mach=0.4, alt_ft=20000.0, turbulence=turbulence, duration_s=3.0, seed=4,
                    feedback="mmae", failures=(make_failure(failure, 0.5),))


def test_a_recorded_flight_replays_exactly(bank, tmp_path):
    log = tmp_path / "flight.lcmlog"
    result = _record_flight(bank, log)
    assert result.declarations[0]["hypothesis"] == "AOA"
    report = replay_log(log, bank, channel_prefix="REC_")
    assert report.ok, [str(m) for m in report.mismatches]
    assert report.statuses_compared == report.sensor_frames == report.command_frames == 192
    assert report.max_probability_diff == 0.0
    assert main(["replay", str(log), "--channel-prefix", "REC_"]) == 0  # --bank auto finds "tuned"
    # the air data crossed the link with every frame, and the executive scheduled on every one
    sensors = [lcmt_sensor_frame.decode(e.data) for e in lcm.EventLog(str(log), "r") if e.channel == "REC_F16_SENSORS"]
    statuses = [lcmt_mmae_status.decode(e.data) for e in lcm.EventLog(str(log), "r") if e.channel == "REC_MMAE_STATUS"]
    assert all(abs(f.mach - 0.4) < 0.02 and abs(f.pressure_altitude_ft - 20000.0) < 100.0 for f in sensors)
    assert len({f.mach for f in sensors}) == len(sensors)   # measured per frame (noise), not a constant
    assert max(s.air_data_rejected for s in statuses) == 0


def test_a_flight_with_on_line_options_replays_with_the_daemons_flags(bank, tmp_path, capsys):
    """The executive takes every option of the estimator's table (core.Executive has
    core.HierarchicalBank's keyword arguments): a flight served with the turbulence adaptation,
    trim tracking and the actuator limits equals the in-process estimator with the same
    options, and its log replays exactly with the daemon's flags, and not without them."""
    options = dict(adapt_turbulence=True, adapt_reference=1.0, trim_time_constant_s=30.0, actuator_limits=True)
    log = tmp_path / "adapted.lcmlog"
    remote = _record_flight(bank, log, turbulence="moderate", failure="LS", **options)
    local = fly(_recorded_scenario("moderate", "LS"), bank, estimator_options=options)
    plain = fly(_recorded_scenario("moderate", "LS"), bank)
    assert remote.declarations == local.declarations
    assert np.nanmax(np.abs(remote.probabilities - local.probabilities)) <= 1e-12
    assert (plain.hypotheses != local.hypotheses   # the options matter here
            or np.nanmax(np.abs(plain.probabilities - local.probabilities)) > 1e-3)
    flags = ["--adapt-turbulence", "--adapt-reference", "1.0", "--trim-tracking", "30", "--actuator-limits"]
    assert main(["replay", str(log), "--channel-prefix", "REC_", *flags]) == 0
    out = capsys.readouterr().out
    assert "replay matches the log" in out and "estimator options: " + " ".join(flags[:4]) in out
    assert main(["replay", str(log), "--channel-prefix", "REC_"]) == 1   # the bank as designed differs
    assert "replay DIFFERS from the log" in capsys.readouterr().out


def test_a_flight_with_steady_trim_tracking_replays_with_its_flag(bank, tmp_path, capsys):
    """Steady trim tracking (--trim-tracking-steady, the daemon's flag too) is part of the
    executive's options: a flight served with it replays exactly with the daemon's flags, and
    differs from the same flight replayed with plain trim tracking."""
    options = dict(trim_time_constant_s=2.0, trim_steady_g=0.1)
    log = tmp_path / "steady.lcmlog"
    remote = _record_flight(bank, log, failure="LS", **options)
    plain = fly(_recorded_scenario("light", "LS"), bank, estimator_options=dict(trim_time_constant_s=2.0))
    assert np.nanmax(np.abs(plain.probabilities - remote.probabilities)) > 0.0   # the gate matters here
    flags = ["--trim-tracking", "2", "--trim-tracking-steady", "0.1"]
    assert main(["replay", str(log), "--channel-prefix", "REC_", *flags]) == 0
    out = capsys.readouterr().out
    assert "replay matches the log" in out and "estimator options: --trim-tracking 2.0 --trim-tracking-steady 0.1" in out
    assert main(["replay", str(log), "--channel-prefix", "REC_", *flags[:2]]) == 1   # plain tracking differs
    assert "replay DIFFERS from the log" in capsys.readouterr().out


def test_wire_faults_replay_with_the_prescribed_stale_flags(bank, tmp_path):
    lc = lcm.LCM("memq://")
    chans = channels("WIRE_")
    log = tmp_path / "wire.lcmlog"
    rec = Recorder(lc, log)
    statuses = []
    lc.subscribe(chans.status, lambda ch, data: statuses.append(lcmt_mmae_status.decode(data)))
    InProcessExecutive(bank).serve(lc, chans)
    rng = np.random.default_rng(5)
    for step in WIRE:
        publish_step(lc, chans, step, bank, rng, z_sigma=0.01, u_sigma=0.001, nan_index=3)
        while lc.handle_timeout(0) > 0:
            pass
    rec.close()
    by_frame = {s.frame: s for s in statuses}
    assert sorted(by_frame) == STATUS_FRAMES
    stale = {i: s.frames_without_update for i, s in by_frame.items() if s.stale}
    assert stale == STALE  # frames 4+5, 8, 10 propagated without update
    last = statuses[-1]
    assert (last.frames_dropped, last.frames_rejected, last.frames_stale) == (2, 2, 4)
    assert last.commands_missed == 3  # frames 4, 5 and 10 flown on the held command
    report = replay_log(log, bank, channel_prefix="WIRE_")
    assert report.ok and report.statuses_compared == 8


def test_a_tampered_status_is_found_by_frame(bank, tmp_path):
    log = tmp_path / "flight.lcmlog"
    _record_flight(bank, log, prefix="")
    src = lcm.EventLog(str(log), "r")
    bad = tmp_path / "tampered.lcmlog"
    dst = lcm.EventLog(str(bad), "w", overwrite=True)
    for e in src:
        data = e.data
        if e.channel == "MMAE_STATUS":
            s = lcmt_mmae_status.decode(data)
            if s.frame == 100:
                p = list(s.probabilities)
                p[0] += 1e-9
                s.probabilities = p
                data = s.encode()
        dst.write_event(e.timestamp, e.channel, data)
    src.close()
    dst.close()
    report = replay_log(bad, bank)
    assert not report.ok and report.mismatch_count == 1
    assert str(report.mismatches[0]).startswith("frame 100: probabilities differ by 1e-09")
    assert main(["replay", str(bad), "--bank", "tuned"]) == 1


def test_statuses_logged_ahead_of_their_frames_still_match(bank, tmp_path):
    """Over udpm the logger may receive the daemon's status before the harness's sensor
    frame that caused it (separate processes, several cores): the replay pairs them by
    frame; a status whose frame never comes is still reported."""
    log = tmp_path / "flight.lcmlog"
    _record_flight(bank, log, prefix="")
    events = [(e.channel, e.data) for e in lcm.EventLog(str(log), "r")]
    swapped = list(events)
    for i in range(len(swapped) - 1):  # every 7th status moves ahead of its sensor frame
        if swapped[i][0] == "F16_SENSORS" and swapped[i + 1][0] == "MMAE_STATUS":
            if lcmt_mmae_status.decode(swapped[i + 1][1]).frame % 7 == 3:
                swapped[i], swapped[i + 1] = swapped[i + 1], swapped[i]
    orphan = lcmt_mmae_status.decode(next(d for c, d in events if c == "MMAE_STATUS"))
    orphan.frame = 10_000
    for name, extra in (("reordered", []), ("orphan", [("MMAE_STATUS", orphan.encode())])):
        out = lcm.EventLog(str(tmp_path / f"{name}.lcmlog"), "w", overwrite=True)
        for n, (ch, data) in enumerate(swapped + extra):
            out.write_event(n, ch, data)
        out.close()
    report = replay_log(tmp_path / "reordered.lcmlog", bank)
    assert report.ok, [str(m) for m in report.mismatches]
    assert report.statuses_compared == 192 and report.max_probability_diff == 0.0
    report = replay_log(tmp_path / "orphan.lcmlog", bank)
    assert [str(m) for m in report.mismatches] == [
        "frame 10000: a status was logged for a frame the replay did not update"]


def test_unreadable_or_foreign_logs_are_refused(bank, tmp_path, capsys):
    with pytest.raises(ReplayError, match="does not exist"):
        replay_log(tmp_path / "nope.lcmlog", bank)
    junk = tmp_path / "junk.lcmlog"
    junk.write_bytes(b"not an event log at all" * 10)
    with pytest.raises(ReplayError):
        replay_log(junk, bank)
    other = tmp_path / "other.lcmlog"
    log = lcm.EventLog(str(other), "w", overwrite=True)
    log.write_event(0, "SOMETHING_ELSE", b"\x00" * 8)
    log.close()
    with pytest.raises(ReplayError, match="holds no 'MMAE_STATUS' messages"):
        replay_log(other, bank)
    for channel, data, said in (  # logs of older message versions, known by their fingerprints
            ("F16_SENSORS", SENSOR_FRAME_FINGERPRINT_WITHOUT_AIR_DATA + b"\x00" * 120,
             "recorded before lcmt_sensor_frame carried air data"),
            ("F16_COMMANDS", COMMAND_FRAME_FINGERPRINT_WITHOUT_THROTTLE + b"\x00" * 96,
             "recorded before lcmt_command_frame carried the throttle"),
            ("MMAE_STATUS", STATUS_FINGERPRINT_WITHOUT_TURBULENCE_MEMBER + b"\x00" * 200,
             "recorded before lcmt_mmae_status carried the turbulence set's member")):
        old = tmp_path / f"old_{channel}.lcmlog"
        log = lcm.EventLog(str(old), "w", overwrite=True)
        log.write_event(0, channel, data)
        log.close()
        with pytest.raises(ReplayError, match=said):
            replay_log(old, bank)
    assert main(["replay", str(tmp_path / "nope.lcmlog"), "--bank", "tuned"]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["replay", str(other), "--bank", "tuned", "--tolerance", "-1"]) == 2


def test_a_recorded_flight_of_a_gust_state_bank_replays_exactly(tmp_path):
    """The daemon's executive runs a 19-state bank (nx selects it); its log replays exactly."""
    path = tmp_path / "gust.f16bank"
    assert main(["design", "--tuning", "tuned_gust", "--out", str(path)]) == 0
    gust = core.load_bank(str(path))
    assert gust.nx == 19
    log = tmp_path / "gust.lcmlog"
    result = _record_flight(gust, log, prefix="GUST_")
    assert result.declarations[0]["hypothesis"] == "AOA"
    report = replay_log(log, gust, channel_prefix="GUST_")
    assert report.ok, [str(m) for m in report.mismatches]
    assert report.statuses_compared == 192 and report.max_probability_diff == 0.0
    assert main(["replay", str(log), "--channel-prefix", "GUST_", "--bank", str(path)]) == 0
