"""mmae-daemon in its own process, over UDP multicast (udpm): the scenarios test_udpm.py runs,
each inside a private network namespace whose only interface is the loopback (f16mmae.lcm.netns).
Collected on their own (outside such a namespace) they refuse to run, so that no test of
ours ever multicasts on a real interface.

* lockstep flight against the daemon = the in-process run (to 1e-12), including a level-1
  switch; the stock lcm-logger's record of it replays exactly (f16mmae replay), and
  lcm-logplayer against a fresh daemon reproduces every logged status;
* wire faults sent to the daemon give the stale flags and counters the frame rules
  prescribe, and the replay of that traffic agrees with the daemon frame by frame;
* hostile messages (a junk flood, messages of the wrong type, truncated ones, frame
  counters of 2^62 and 10^7) hang nothing: the daemon answers the next frame at once, stops
  on SIGINT, and counts every message by fate in its statistics line;
* SIGTERM ends the daemon cleanly with its summary and statistics lines;
* the latency benchmark's bare echo returns every message byte for byte and times each from
  its callback to its echo published, as the daemon times a sensor frame to its status;
  with --work-us it spends that work first.
"""
from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time

import lcm
import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.design.turbulence_banks import START, TRIM_TIME_CONSTANT_S
from latency_driver import find_tool
from f16mmae.cli.main import main
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.lcm.channels import channels
from f16mmae.lcm.codec import command_frame_bytes, sensor_frame_bytes
from f16mmae.lcm.daemon import DaemonProcess, daemon_flags, find_executable, statistics_line
from f16mmae.lcm.hil import fly_hil
from f16mmae.lcmt_command_frame import lcmt_command_frame
from f16mmae.lcmt_mmae_status import lcmt_mmae_status
from f16mmae.lcm.replay import replay_log
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure
from f16mmae.truth.maneuvers import parse_maneuver
from f16mmae.lcm.netns import only_loopback
from wire_faults import STALE, STATUS_FRAMES, WIRE, publish_step

if not only_loopback():
    raise RuntimeError("udpm_scenarios.py runs only inside a private network namespace whose only interface is "
                       "lo: run tests/python/test_udpm.py, which makes one for each scenario")

PORT = 7700
# A 2-MiB socket receive buffer (the host's default is ~200 KiB): a lockstep flight runs at
# about 1 ms a frame, and lcm-logger, which nothing waits for, must not drop a burst while
# the scheduler of a loaded 2-core host keeps it off the CPU (a dropped frame shows as a
# replay mismatch). The kernel caps it at net.core.rmem_max.
RECV_BUF = "recv_buf_size=2097152"
URL = f"udpm://239.255.76.67:{PORT}?ttl=0&{RECV_BUF}"
URL2 = f"udpm://239.255.76.67:{PORT + 1}?ttl=0&{RECV_BUF}"


@pytest.fixture(scope="module")
def banked():
    return load_bank("tuned")


def _tool(name):
    """The stock LCM tool itself (the wheel's binary, not its Python wrapper, so that a
    signal reaches it)."""
    return os.path.join(lcm.LCM_BIN_DIR, name)


def _wait_until_logged(log, lc, channel, frame, timeout_s=10.0):
    """Until the logger has written ``frame`` on ``channel``: it may lag the flight when the
    machine is busy, and it flushes its file only when a later message arrives, so a small
    message on another channel of the prefix (which the replay ignores) is sent meanwhile."""
    poke = channel.rsplit("F16_COMMANDS", 1)[0] + "TEST_FLUSH"
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        lc.publish(poke, b"")
        time.sleep(0.15)
        if log.exists():
            ev = lcm.EventLog(str(log), "r")
            try:
                if any(e.channel == channel and lcmt_command_frame.decode(e.data).frame == frame for e in ev):
                    return
            finally:
                ev.close()
    raise AssertionError(f"lcm-logger did not write {channel} frame {frame} within {timeout_s} s")


@contextlib.contextmanager
def sending_from_one_cpu():
    """Keep this process on one CPU while it publishes. Multicast loopback hands each
    datagram to the backlog queue of the CPU that sent it, and a loaded host may leave that
    queue to ksoftirqd: a sender that migrates between two publishes (command i, then sensor
    i+1) can have the second delivered first, to the logger or the daemon. The executive then
    sees frame i+1 before command i -- a real reordering on the wire, which it handles (catch
    up, stale status) but which makes the logged order differ from the order the daemon saw.
    One CPU, one queue, the order sent."""
    allowed = os.sched_getaffinity(0)
    os.sched_setaffinity(0, {min(allowed)})
    try:
        yield min(allowed)
    finally:
        os.sched_setaffinity(0, allowed)


def _fly_logged(path, bank, scenario, prefix, log, pause_s=0.0, options=None):
    """A lockstep flight of ``scenario`` against mmae-daemon running bank file ``path``, the stock
    lcm-logger recording the channels of ``prefix`` into ``log``; returns (daemon, result).
    ``pause_s`` after each frame: a calm-air flight runs its frames faster than lcm-logger,
    which nothing waits for, drains its socket on a loaded 2-core host. ``options``: estimator
    options given to the daemon (its flags) and to the harness alike."""
    chans = channels(prefix)
    last = int(round(scenario.duration_s * 64)) - 1
    logger = subprocess.Popen([_tool("lcm-logger"), "-q", "-f", "-l", URL, "-c", f"{prefix}.*", str(log)])
    try:
        with DaemonProcess(path, lcm_url=URL, channel_prefix=prefix,
                           extra_args=daemon_flags(options or {}, bank.nu)) as daemon:
            time.sleep(0.5)  # the logger subscribes
            lc = lcm.LCM(URL)
            with sending_from_one_cpu():
                remote = fly_hil(scenario, bank, lc, chans, lockstep=True, timeout_s=5.0, estimator_options=options,
                                 on_frame=(lambda *frame: time.sleep(pause_s)) if pause_s else None)
        _wait_until_logged(log, lc, chans.commands, frame=last)
    finally:
        logger.send_signal(signal.SIGINT)
        logger.wait(timeout=10)
    assert daemon.returncode == 0
    return daemon, remote


def test_lockstep_flight_matches_in_process_and_its_log_replays(banked, tmp_path):
    label, path, bank = banked
    prefix = f"T{os.getpid()}A_"
    chans = channels(prefix)
    scenario = Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=4.0, seed=2,
                        feedback="mmae", failures=(make_failure("LS", 0.5),))
    log = tmp_path / "hil.lcmlog"
    # paced as the calm-air flights below: on a loaded host lcm-logger, which nothing waits for,
    # may drop a frame the daemon received, and the replay of its log then differs
    daemon, remote = _fly_logged(path, bank, scenario, prefix, log, pause_s=0.002)
    assert "256 updated, 256 commands applied, 0 rejected, 0 dropped" in daemon.summary
    # the air data crossed with every frame (a frame without it would be counted here)
    assert "0 air data rejected" in daemon.summary and remote.timing["link"]["air_data_rejected"] == 0
    assert daemon.statistics["messages"]["used"] == 256 + 256 + 1  # frames and the flight's reset
    assert daemon.statistics["messages"]["undecodable"] == 0
    local = fly(scenario, bank)
    assert remote.hypotheses == local.hypotheses
    assert any("+" in h for h in remote.hypotheses)
    assert np.nanmax(np.abs(remote.probabilities - local.probabilities)) <= 1e-12
    assert remote.declarations == local.declarations

    report = replay_log(log, bank, channel_prefix=prefix)
    assert report.ok, [str(m) for m in report.mismatches]
    assert report.statuses_compared == 256
    assert main(["replay", str(log), "--channel-prefix", prefix]) == 0

    # lcm-logplayer feeds the logged frames to a fresh daemon: every status reproduced
    logged = {}
    for e in lcm.EventLog(str(log), "r"):
        if e.channel == chans.status:
            s = lcmt_mmae_status.decode(e.data)
            logged[s.frame] = s
    lc2 = lcm.LCM(URL2)
    replayed = {}
    lc2.subscribe(chans.status, lambda ch, data: replayed.__setitem__(
        lcmt_mmae_status.decode(data).frame, lcmt_mmae_status.decode(data)))
    with DaemonProcess(path, lcm_url=URL2, channel_prefix=prefix):
        # at a quarter of the recorded pace: the lockstep flight ran ~1 ms per frame, and
        # UDP on a loaded 2-core host may drop a burst that fast
        player = subprocess.Popen([_tool("lcm-logplayer"), "-s", "0.25", "-l", URL2, "-e",
                                   f"^{prefix}(F16_SENSORS|F16_COMMANDS|MMAE_RESET)$", str(log)],
                                  preexec_fn=lambda: os.sched_setaffinity(0, {min(os.sched_getaffinity(0))}))
        while player.poll() is None:
            lc2.handle_timeout(50)
        end = time.time() + 2.0
        while len(replayed) < len(logged) and time.time() < end:
            lc2.handle_timeout(50)
    assert sorted(replayed) == sorted(logged)
    worst = max(max(abs(a - b) for a, b in zip(replayed[i].probabilities, logged[i].probabilities))
                for i in logged)
    assert worst <= 1e-12
    assert all(replayed[i].declared == logged[i].declared for i in logged)


def test_wire_faults_against_the_daemon_agree_with_the_replay(banked, tmp_path):
    label, path, bank = banked
    prefix = f"T{os.getpid()}B_"
    chans = channels(prefix)
    log = tmp_path / "wire.lcmlog"
    rng = np.random.default_rng(9)
    lc = lcm.LCM(URL)
    statuses = []
    lc.subscribe(chans.status, lambda ch, data: statuses.append(lcmt_mmae_status.decode(data)))
    writer = lcm.EventLog(str(log), "w", overwrite=True)
    lc.subscribe(f"{prefix}.*", lambda ch, data: writer.write_event(len(statuses), ch, data))
    with DaemonProcess(path, lcm_url=URL, channel_prefix=prefix) as daemon, sending_from_one_cpu():
        for step in WIRE:
            kind, i = publish_step(lc, chans, step, bank, rng, z_sigma=0.05, u_sigma=0.002), step[1]
            end = time.time() + 0.2  # settle: the daemon answers sensor frames within this
            while time.time() < end and lc.handle_timeout(20) >= 0:
                if kind == "s" and statuses and statuses[-1].frame == i:
                    break
        while lc.handle_timeout(100) > 0:
            pass
    writer.close()
    assert [s.frame for s in statuses] == STATUS_FRAMES
    assert {s.frame: s.frames_without_update for s in statuses if s.stale} == STALE
    last = statuses[-1]
    assert (last.frames_dropped, last.frames_rejected, last.frames_stale, last.commands_missed) == (2, 2, 4, 3)
    assert "8 updated, 9 commands applied, 2 rejected, 2 dropped (1 duplicate, 1 out-of-order), " \
        "0 resynchronised, 4 stale" in daemon.summary
    inside = daemon.statistics["sensor_to_publish_us"]  # 8 statuses timed
    assert 0 < inside["p50"] <= inside["p99"] <= inside["max"], daemon.summary
    report = replay_log(log, bank, channel_prefix=prefix)
    assert report.ok, [str(m) for m in report.mismatches]
    assert report.statuses_compared == 8


def _wild(frame_bytes: bytes, counter: int) -> bytes:
    """A sensor or command frame with its counter replaced (bytes 16..24: after the
    fingerprint and utime)."""
    return frame_bytes[:16] + counter.to_bytes(8, "big") + frame_bytes[24:]


def test_hostile_messages_hang_nothing_and_are_counted_by_fate(banked):
    """Issue 16: one frame numbered 2^62 made the daemon propagate once per skipped frame
    (statuses stopped, SIGINT ignored); junk and malformed messages appeared in no counter."""
    label, path, bank = banked
    prefix = "HOSTILE_"
    chans = channels(prefix)
    lc = lcm.LCM(URL)
    statuses = []
    lc.subscribe(chans.status, lambda ch, data: statuses.append(lcmt_mmae_status.decode(data)))
    z, u = np.array(bank.z_trim), np.array(bank.u_trim)

    def send(channel, data, wait_status_of=None):
        lc.publish(channel, data)
        end = time.monotonic() + 5.0
        while wait_status_of is not None and not any(s.frame == wait_status_of for s in statuses):
            assert time.monotonic() < end, f"no status for frame {wait_status_of} within 5 s"
            lc.handle_timeout(20)

    rng = np.random.default_rng(3)
    junk = 1500
    with DaemonProcess(path, lcm_url=URL, channel_prefix=prefix) as daemon:
        for i in range(junk):  # random bytes on the three channels the daemon reads
            channel = (chans.sensors, chans.commands, chans.reset)[i % 3]
            lc.publish(channel, rng.integers(0, 256, size=int(rng.integers(0, 120)), dtype=np.uint8).tobytes())
            if i % 15 == 14:
                # paced below what LCM queues per subscription (30 messages; beyond that LCM
                # drops a message before the daemon sees it), so every one is counted
                time.sleep(0.01)
        time.sleep(0.3)
        send(chans.sensors, command_frame_bytes(0, u))       # the wrong type
        send(chans.sensors, sensor_frame_bytes(0, z)[:-3])   # truncated
        for i in range(3):
            send(chans.sensors, sensor_frame_bytes(i, z), wait_status_of=i)
            send(chans.commands, command_frame_bytes(i, u))
        t0 = time.monotonic()
        send(chans.sensors, _wild(sensor_frame_bytes(0, z), 2**62), wait_status_of=2**62)
        send(chans.commands, _wild(command_frame_bytes(0, u), 10**7))   # far from 2^62 as well
        send(chans.sensors, sensor_frame_bytes(3, z), wait_status_of=3)
        assert time.monotonic() - t0 < 2.0
        time.sleep(0.2)
        t_stop = time.monotonic()
    assert daemon.returncode == 0 and time.monotonic() - t_stop < 5.0
    assert [s.resynchronised for s in statuses[-2:]] == [True, False]
    m = daemon.statistics["messages"]
    assert m["undecodable"] == junk + 2
    assert (m["used"], m["resynchronised"], m["rejected"]) == (7, 2, 0)
    assert m["received"] == junk + 2 + 7 + 2
    assert daemon.statistics["frames"]["resynchronised"] == 2


def test_with_a_key_the_daemon_obeys_only_signed_fresh_messages(banked, tmp_path, capsys):
    label, path, bank = banked
    key = tmp_path / "link.key"
    key.write_bytes(os.urandom(32))
    prefix = "AUTH_"
    assert main(["hil", "--start-daemon", "--lockstep", "--duration", "0.5", "--lcm-url", URL,
                 "--channel-prefix", prefix, "--auth-key", str(key)]) == 0
    out = capsys.readouterr().out
    assert "frames authenticated" in out and "32 updated" in out and "0 unauthenticated" in out

    chans = channels(prefix)
    lc = lcm.LCM(URL)
    raw = []
    lc.subscribe(chans.status, lambda ch, data: raw.append(data))
    z = np.array(bank.z_trim)
    auth, checker = core.FrameAuth.from_key_file(str(key)), core.FrameAuth.from_key_file(str(key))

    def settle(s=0.3):
        end = time.monotonic() + s
        while time.monotonic() < end:
            lc.handle_timeout(20)

    with DaemonProcess(path, lcm_url=URL, channel_prefix=prefix, auth_key=key) as daemon:
        assert "frames authenticated" in daemon.ready_line
        lc.publish(chans.sensors, sensor_frame_bytes(0, z))                       # unsigned
        lc.publish(chans.reset, core.FrameAuth(os.urandom(32)).sign(chans.reset, sensor_frame_bytes(0, z)))
        settle()
        assert raw == []
        signed = auth.sign(chans.sensors, sensor_frame_bytes(0, z))
        lc.publish(chans.sensors, signed)
        settle()
        lc.publish(chans.sensors, signed)                                          # replayed
        settle()
    assert len(raw) == 1 and checker.check(chans.status, raw[0]) == "ok"
    m = daemon.statistics["messages"]
    assert (m["unauthenticated"], m["replayed"], m["used"], m["received"]) == (2, 1, 1, 4)
    assert daemon.statistics["authenticated"] is True


def test_sigterm_ends_the_daemon_cleanly_with_a_summary(banked):
    exe = str(find_executable("mmae-daemon"))
    p = subprocess.Popen([exe, "--bank", str(banked[1]), "--lcm-url", URL, "--channel-prefix", "IDLE_"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert "ready" in p.stdout.readline()
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate(timeout=5)
    assert p.returncode == 0, err
    assert "no --auth-key: frames, commands and resets are accepted from any sender" in err
    lines = out.strip().splitlines()
    assert len(lines) == 2 and lines[0].startswith("mmae-daemon: stopped by signal: frames 0 updated")
    assert "step p50" in lines[0] and "p99" in lines[0] and "max" in lines[0]
    assert statistics_line(out, "mmae-daemon")["messages"]["received"] == 0


@pytest.mark.parametrize("work_us", [0, 200])
def test_the_bare_echo_returns_each_message_and_times_it(work_us):
    exe = str(find_tool("lcm-echo-f16"))
    p = subprocess.Popen([exe, "--lcm-url", URL2, "--in", "T_PING", "--out", "T_PONG", "--work-us", str(work_us)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert "ready" in p.stdout.readline()
        lc = lcm.LCM(URL2)
        pongs = []
        lc.subscribe("T_PONG", lambda ch, data: pongs.append(data))
        pings = [bytes([i]) * (10 + i) for i in range(5)]
        for ping in pings:
            lc.publish("T_PING", ping)
            end = time.monotonic() + 2.0
            while len(pongs) < pings.index(ping) + 1 and time.monotonic() < end:
                lc.handle_timeout(100)
    finally:
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=5)
    assert pongs == pings
    assert p.returncode == 0, err
    assert "5 messages echoed" in out
    inside = statistics_line(out, "lcm-echo-f16")["message_to_publish_us"]
    assert 0 < inside["p50"] <= inside["p99"] <= inside["max"], out
    assert inside["p50"] >= 0.5 * work_us, out  # --work-us is spent before each echo


def test_hil_command_starts_its_own_daemon(capsys):
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "1", "--fail", "AOA@0.2",
               "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}C_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "mmae-daemon: ready" in out and "64 updated" in out
    assert "p_min 1e-09, threshold" in out and "no start-up" in out  # the bank's recommended settings, as in process
    assert "in-process run: max |probability difference| = 0" in out


def test_hil_lockstep_with_a_scheduled_bank_equals_in_process(tmp_path, capsys):
    """mmae-daemon runs a scheduled bank (a small real grid) over LCM, scheduling on the
    sensor frames' air data, and the lockstep flight between its nodes equals the in-process
    run exactly; so does a flight with the on-line options (turbulence adaptation, trim
    tracking, nearest-node schedule, the maneuver model) given to both, and with steady trim
    tracking; the air data's low-pass (--air-data-time-constant, which the interpolated trims
    follow) reaches the daemon."""
    sched = tmp_path / "small.f16sched"
    assert main(["design", "--schedule", "mach=0.4/0.5,alt=20000", "--workers", "2", "--out", str(sched)]) == 0
    capsys.readouterr()
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "2", "--bank", str(sched),
               "--mach", "0.45", "--alt-ft", "20000", "--fail", "LF@0.5", "--air-data-time-constant", "0.5",
               "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}S_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "mmae-daemon: ready" in out and "128 updated" in out and "0 air data rejected" in out
    assert "schedule interpolate on air data low-passed 0.5 s" in out  # the trims follow it
    # the floors are the nodes' own (their range), the start-up the file's (its design flew it)
    floors = sorted({n["bank"].p_min for n in core.load_bank(sched).schedule["nodes"]})
    assert (f"p_min per node {floors[0]:g} to {floors[-1]:g}" if len(floors) > 1
            else f"p_min {floors[0]:g} at every node") in out
    assert "start-up 1 s" in out and core.load_bank(sched).schedule["start_up_s"] == 1.0
    assert "in-process run: max |probability difference| = 0 (identical declarations)" in out
    capsys.readouterr()
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "2", "--bank", str(sched),
               "--mach", "0.45", "--alt-ft", "20000", "--fail", "LF@0.5", "--adapt-turbulence",
               "--trim-tracking", "2", "--trim-freeze-probability", "0.5", "--schedule-mode", "nearest",
               "--maneuver-kinematics", "--maneuver-tempering", "0.1", "--actuator-limits", "--maneuver-setting", "off",
               "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}O_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert ("turbulence adaptation (reference per node, own channels, vel counted, level scale, vel level scaled from 8, "
            f"lull floor over {names.SCHEDULE_ADAPT_FLOOR_S:g} s, "   # the scheduled default's lull floor
            f"bound rising from rho {names.SCHEDULE_ADAPT_SCALE_MAX_FROM:g}, "   # and the bound's knee
            "complete in calm air VEL 1 by either "  # the scheduled defaults:
            "(whiteness below 0.78)), "
            "set tempering 0.25 from rho 0 full 734 "  # LS RS LF RF VEL AOA AZ kept at s (names.ADAPT_SET_TEMPERING_FULL)
            f"rough 4128 from rho {names.SCHEDULE_SET_TEMPERING_ROUGH:g} "   # RUD's and AY's share in severe air
            f"weight {names.SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT:g}, "
            "trim tracking 2 s (freeze above 0.5), complete failures on the trim averaged over "
            f"{names.SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S:g} s held while declared, "   # the scheduled default too
            "schedule nearest on air data low-passed 2 s, maneuver kinematics, "  # the core's default low-pass
            "tempering 0.1 g, actuator limits, "
            f"alpha tempering 1 deg beyond {names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG:g} deg sqrt(s), "
            "its reference shrinking above a trim alpha of "
            f"{names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG:g} deg)" in out), out   # the scheduled default's
    assert "in-process run: max |probability difference| = 0 (identical declarations)" in out
    capsys.readouterr()
    # steady trim tracking (--trim-tracking-steady) and the adaptation's climb reference: their
    # gates read the air data's rates (and z_hat)
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "2", "--bank", str(sched),
               "--mach", "0.45", "--alt-ft", "20000", "--fail", "LF@1", "--trim-tracking", "2",
               "--trim-tracking-steady", "0.1", "--air-data-time-constant", "0.5", "--adapt-turbulence",
               "--adapt-all-channels", "--adapt-reference", "0.65", "--adapt-reference-climb", "0.6", "--adapt-reference-climb-hold", "30",
               "--maneuver-setting", "off", "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}Y_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert ("turbulence adaptation (reference 0.65, level scale, vel level scaled from 8, "
            f"lull floor over {names.SCHEDULE_ADAPT_FLOOR_S:g} s, bound rising from rho "
            f"{names.SCHEDULE_ADAPT_SCALE_MAX_FROM:g}, complete in calm air VEL 1 by "
            "either (whiteness "
            "below 0.78)), set tempering 0.25 from rho 0 full 734 "
            f"rough 4128 from rho {names.SCHEDULE_SET_TEMPERING_ROUGH:g} weight {names.SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT:g}, "
            "climbing 0.6 held 30 s, "
            "trim tracking 2 s (freeze above 0.05, steady 0.1 g)") in out, out
    assert ("no maneuver kinematics, tempering 1 g, alpha tempering 1 deg beyond "
            f"{names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG:g} deg sqrt(s), its reference shrinking "
            f"above a trim alpha of {names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG:g} deg)"   # the scheduled
            in out), out                                                                      # default's temperings
    assert "in-process run: max |probability difference| = 0 (identical declarations)" in out
    capsys.readouterr()
    # the scheduled default's maneuvering-flight setting (names.SCHEDULE_MANEUVER_SETTING), as flags
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "2", "--bank", str(sched),
               "--mach", "0.45", "--alt-ft", "20000", "--fail", "LF@1", "--adapt-turbulence",
               "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}M_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    for said in ("climbing 0.6 held 30 s", "steady 0.1 g on AOA,VEL,AZ,AY, air-data rates off)", "maneuver kinematics",
                 "maneuver dwell 0.4 s held 30 s", "gates x sqrt(s_c)", "actuator limits"):
        assert said in out, (said, out)
    assert "in-process run: max |probability difference| = 0 (identical declarations)" in out



def test_hil_lockstep_with_the_climb_dwell_and_own_channels_equals_in_process(tmp_path, capsys):
    """The climb reference's dwell and the adaptation's power per channel each filter reads reach
    mmae-daemon (their flags, named in its ready line) and its lockstep flight equals the
    in-process run exactly, on a bank whose failed VEL's channel is uninformative (the
    `constant` model) flying a steep climb with a stabilator failing in it: in process each
    option changes the flight (the declarations with the climb's dwell, the probabilities with
    the channels)."""
    path = tmp_path / "constant_vel.f16bank"
    assert main(["design", "--failure-model", "constant=VEL", "--out", str(path)]) == 0
    capsys.readouterr()
    # the bank's evidence dwell (its N_k) is off while the climb's longer dwell is in force (declarer.h)
    flags = ["--adapt-turbulence", "--adapt-own-channels", "--adapt-reference-climb", "0.6",
             "--adapt-reference-climb-dwell", "1"]
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "3", "--bank", str(path),
               "--maneuver", "climb@0.5:to=22000ft:rate=6000fpm", "--fail", "LS@1", *flags,
               "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}D_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "turbulence adaptation (reference 0.6, own channels), climbing 0.6 held 0 s with dwell 1 s" in out, out
    assert "in-process run: max |probability difference| = 0 (identical declarations)" in out
    bank = core.load_bank(str(path))
    scenario = Scenario(duration_s=3.0, turbulence="light", failures=(make_failure("LS", 1.0),),
                        maneuvers=(parse_maneuver("climb@0.5:to=22000ft:rate=6000fpm"),))
    options = {"adapt_turbulence": True, "adapt_own_channels": True, "adapt_reference_climb": 0.6,
               "adapt_reference_climb_dwell_s": 1.0}
    both = fly(scenario, bank, estimator_options=options)
    no_dwell = fly(scenario, bank, estimator_options={**options, "adapt_reference_climb_dwell_s": 0.0})
    all_channels = fly(scenario, bank, estimator_options={k: v for k, v in options.items() if k != "adapt_own_channels"})
    assert both.declarations != no_dwell.declarations
    assert np.nanmax(np.abs(both.probabilities - all_channels.probabilities)) > 0


def test_hil_lockstep_with_a_gust_state_bank_equals_in_process(tmp_path, capsys):
    """mmae-daemon runs a 19-state bank (the Dryden gust states; the bank file's nx selects
    it) and the lockstep flight over udpm equals the in-process run exactly: as designed, and
    with the turbulence adaptation and the reconfigured feedback given to both."""
    gust = tmp_path / "gust.f16bank"
    assert main(["design", "--tuning", "tuned_gust", "--out", str(gust)]) == 0
    capsys.readouterr()
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "2", "--bank", str(gust), "--fail", "LF@0.5",
               "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}G_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "hierarchical bank of 19 states (gust)" in out and "128 updated" in out
    assert "in-process run: max |probability difference| = 0 (identical declarations)" in out
    rc = main(["hil", "--start-daemon", "--lockstep", "--duration", "3", "--bank", str(gust), "--fail", "AZ@0.5",
               "--turbulence", "moderate", "--adapt-turbulence", "--feedback", "reconfigure",
               "--lcm-url", URL, "--channel-prefix", f"T{os.getpid()}H_", "--compare"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "19 states (gust)" in out and "turbulence adaptation" in out and "declared AZ" in out
    assert "in-process run: max |probability difference| = 0 (identical declarations)" in out


def test_lockstep_flight_with_a_throttle_bank_equals_in_process_and_its_log_replays(tmp_path):
    """mmae-daemon runs a 6-input bank (the throttle command, `f16mmae design --throttle-input`;
    the bank file's nu selects it) on the command frames' throttle: a calm-air VEL failure flown
    in lockstep over udpm equals the in-process run exactly, and lcm-logger's record of it
    replays to the same statuses and declarations."""
    path = tmp_path / "calm_throttle.f16bank"
    assert main(["design", "--throttle-input", "--gust-level", "none", "--out", str(path)]) == 0
    bank = core.load_bank(str(path))
    assert bank.nu == 6
    prefix = f"T{os.getpid()}T_"
    scenario = Scenario(mach=0.4, alt_ft=20000.0, turbulence="none", duration_s=3.0, seed=3,
                        failures=(make_failure("VEL", 0.5),))
    log = tmp_path / "throttle.lcmlog"
    daemon, remote = _fly_logged(path, bank, scenario, prefix, log, pause_s=0.003)
    assert "13 states, 6 inputs (throttle)" in daemon.ready_line, daemon.ready_line
    assert "192 updated, 192 commands applied, 0 rejected, 0 dropped" in daemon.summary
    local = fly(scenario, bank)
    assert remote.hypotheses == local.hypotheses
    assert np.nanmax(np.abs(remote.probabilities - local.probabilities)) == 0.0
    assert remote.declarations == local.declarations
    assert [d["hypothesis"] for d in remote.declarations][:1] == ["VEL"]
    throttles = [lcmt_command_frame.decode(e.data).throttle for e in lcm.EventLog(str(log), "r")
                 if e.channel == channels(prefix).commands]
    assert len(throttles) == 192 and np.std(throttles) > 1e-3  # the dithered throttle, logged
    report = replay_log(log, bank, channel_prefix=prefix)
    assert report.ok, [str(m) for m in report.mismatches]
    assert report.statuses_compared == 192
    assert main(["replay", str(log), "--bank", str(path), "--channel-prefix", prefix]) == 0


def test_lockstep_flight_with_the_turbulence_bank_set_equals_in_process_and_its_log_replays(tmp_path, capsys):
    """mmae-daemon --bank SET --turbulence-banks runs the turbulence bank set of the set file
    (19-state, 6-input members, one in force, each with its trim tracking and the file's load-factor
    tempering): a calm-air flight in which the set hands
    over from its light start member to the calm one and then declares a stuck left
    stabilator, flown in lockstep over udpm, equals the in-process set exactly (probabilities,
    declarations); the status carries the set's hash; lcm-logger's record of it replays to the
    same statuses, by the API and by `f16mmae replay` finding the set by that hash."""
    label, path, bank = load_bank("turbulence")
    bank_set = Estimator(bank, turbulence_banks=True)
    assert path.suffix == ".f16set" and bank.nu == 6
    options = {"turbulence_banks": True}
    prefix = f"T{os.getpid()}B_"
    scenario = Scenario(mach=0.4, alt_ft=20000.0, turbulence="none", duration_s=5.0, seed=3,
                        failures=(make_failure("LS", 3.0),))
    log = tmp_path / "set.lcmlog"
    daemon, remote = _fly_logged(path, bank, scenario, prefix, log, pause_s=0.003, options=options)
    assert "turbulence bank set of 2 members of 19 states, 6 inputs" in daemon.ready_line, daemon.ready_line
    # the ready line reads the member in force: the set file's load-factor tempering and trim tracking
    assert "tempering 1 g" in daemon.ready_line, daemon.ready_line
    assert f"trim tracking {TRIM_TIME_CONSTANT_S[START]:g} s" in daemon.ready_line, daemon.ready_line
    assert "320 updated, 320 commands applied, 0 rejected, 0 dropped" in daemon.summary
    assert remote.bank_hash == bank_set.bank_hash != str(bank.content_hash)   # the set's hash
    local = fly(scenario, bank, estimator=bank_set)
    assert bank_set.core_bank.switches >= 1 and bank_set.core_bank.active == 0   # handed over to the calm member
    assert remote.hypotheses == local.hypotheses
    assert np.nanmax(np.abs(remote.probabilities - local.probabilities)) == 0.0
    assert remote.declarations == local.declarations
    assert [d["hypothesis"] for d in remote.declarations][:1] == ["LS"]
    # the set's default dither, the adaptive one, flown over the link: the truth side read the
    # member in force and its rho off each status, which are the in-process set's
    assert remote.estimator_settings["adaptive_dither"] is True and local.estimator_settings["adaptive_dither"] is True
    statuses = [lcmt_mmae_status.decode(e.data) for e in lcm.EventLog(str(log), "r")
                if e.channel == channels(prefix).status]
    assert statuses[0].turbulence_member == START and statuses[-1].turbulence_member == bank_set.turbulence_member == 0
    assert statuses[-1].turbulence_power_ratio == bank_set.turbulence_power_ratio
    report = replay_log(log, bank, channel_prefix=prefix, turbulence_banks=True)
    assert report.ok, [str(m) for m in report.mismatches]
    assert report.statuses_compared == 320
    assert main(["replay", str(log), "--channel-prefix", prefix]) == 0   # --bank auto: the set, by its hash
    assert "--turbulence-banks" in capsys.readouterr().out
