"""Authenticated frames on the Python side of the link (core.FrameAuth, the daemon's own code):
the tag is HMAC-SHA256 over the channel name, a NUL and the message up to the tag (checked
against Python's hmac module), sequences rise, tampering and replays are refused, bad key files
are named, and a logged flight replays with only its authentic messages."""
from __future__ import annotations

import hashlib
import hmac

import lcm
import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.cli.main import main
from f16mmae.lcm.channels import channels
from f16mmae.lcm.codec import sensor_frame_bytes
from f16mmae.lcm.replay import replay_log
from f16mmae.lcmt_sensor_frame import lcmt_sensor_frame

KEY = bytes(range(40, 72))


def test_the_tag_is_hmac_sha256_over_channel_and_message():
    auth = core.FrameAuth(KEY)
    data = sensor_frame_bytes(7, np.arange(7.0))
    signed = auth.sign("SIM_F16_SENSORS", data)
    assert len(signed) == len(data) and signed[:-40] == data[:-40]
    expected = hmac.new(KEY, b"SIM_F16_SENSORS\0" + signed[:-32], hashlib.sha256).digest()
    assert signed[-32:] == expected
    msg = lcmt_sensor_frame.decode(signed)
    words = [int.from_bytes(expected[k:k + 8], "big", signed=True) for k in range(0, 32, 8)]
    assert msg.frame == 7 and msg.auth_sequence > 0 and list(msg.auth_tag) == words
    later = auth.sign("SIM_F16_SENSORS", data)
    assert lcmt_sensor_frame.decode(later).auth_sequence == msg.auth_sequence + 1


def test_tampered_replayed_foreign_and_unsigned_messages_are_refused():
    sender, receiver = core.FrameAuth(KEY), core.FrameAuth(KEY)
    data = sensor_frame_bytes(0, np.zeros(7))
    signed = sender.sign("F16_SENSORS", data)
    tampered = bytearray(signed)
    tampered[30] ^= 0x40  # inside z
    assert receiver.check("F16_SENSORS", bytes(tampered)) == "unauthenticated"
    assert receiver.check("F16_SENSORS", data) == "unauthenticated"
    assert receiver.check("F16_COMMANDS", signed) == "unauthenticated"
    assert receiver.check("F16_SENSORS", core.FrameAuth(bytes(32)).sign("F16_SENSORS", data)) == "unauthenticated"
    assert receiver.check("F16_SENSORS", signed) == "ok"
    assert receiver.check("F16_SENSORS", signed) == "replayed"
    with pytest.raises(ValueError, match="16 to 64 bytes, got 8"):
        core.FrameAuth(b"12345678")
    with pytest.raises(ValueError, match="at least 48 bytes"):
        sender.sign("F16_SENSORS", b"short")


def test_key_files_are_checked_by_name(tmp_path, capsys):
    short = tmp_path / "short.key"
    short.write_bytes(b"abc")
    with pytest.raises(ValueError, match=r"short.key' holds 3 bytes; a key is 16 to 64 bytes"):
        core.FrameAuth.from_key_file(str(short))
    with pytest.raises(ValueError, match="is not a regular file"):
        core.FrameAuth.from_key_file(str(tmp_path))
    assert main(["replay", str(tmp_path / "x.lcmlog"), "--bank", "tuned", "--auth-key", str(short)]) == 2
    assert "--auth-key: auth key file" in capsys.readouterr().err
    assert main(["hil", "--lcm-url", "memq://", "--auth-key", str(tmp_path / "none.key")]) == 2
    assert "none.key' cannot be read" in capsys.readouterr().err


def test_a_log_replays_with_only_its_authentic_messages(tmp_path):
    """The signed frames of a flight (signed as `f16mmae hil --auth-key` signs them), a forged
    frame and a replayed one in between: with the key the replay skips and counts those two
    and matches every status; the forged frame would otherwise change the flight."""
    bank = load_bank("tuned")[2]
    chans = channels()
    auth = core.FrameAuth(KEY)
    from f16mmae.lcm.replay import InProcessExecutive
    executive = InProcessExecutive(bank)
    log_path = tmp_path / "signed.lcmlog"
    log = lcm.EventLog(str(log_path), "w", overwrite=True)
    z, u = np.array(bank.z_trim), np.array(bank.u_trim)
    from f16mmae.lcm.codec import command_frame_bytes
    n = 0
    for i in range(40):
        zi = z + 0.01 * np.sin(i + np.arange(7))
        s = auth.sign(chans.sensors, sensor_frame_bytes(i, zi))
        log.write_event(n, chans.sensors, s)
        n += 1
        status = executive.on_sensor(i, zi)
        log.write_event(n, chans.status, auth.sign(chans.status, status.encode()))
        n += 1
        if i == 20:
            log.write_event(n, chans.sensors, sensor_frame_bytes(21, z + 5.0))  # forged: no key
            log.write_event(n + 1, chans.sensors, s)                            # replayed
            n += 2
        log.write_event(n, chans.commands, auth.sign(chans.commands, command_frame_bytes(i, u)))
        executive.on_command(i, u)
        n += 1
    log.close()
    report = replay_log(log_path, bank, auth=core.FrameAuth(KEY))
    assert report.ok, [str(m) for m in report.mismatches]
    assert (report.unauthenticated, report.replayed, report.statuses_compared) == (1, 1, 40)
    unkeyed = replay_log(log_path, bank)
    assert not unkeyed.ok  # without the key the forged frame is flown and the statuses differ
