"""The bank loader against hostile and careless input (issue 16): crafted sizes that once
crashed or exhausted the loader, files that are not regular files, and validation gaps.
Every refusal is a ValueError/OSError whose sentence names the file, the field and the value.

Files are crafted here from the documented layout (bank_file.h: 52-byte header, then the
LCM payload), with the SHA-256 recomputed so only the targeted check can refuse them."""
from __future__ import annotations

import hashlib
import math
import os
import struct
import threading
import time

import numpy as np
import pytest

from f16mmae import core
from f16mmae.design import bank as design_bank

HEADER = struct.Struct(">8sIQ32s")


def image(payload: bytes, version: int = core.ModelBank.FORMAT_VERSION) -> bytes:
    return HEADER.pack(b"F16MMAEB", version, len(payload), hashlib.sha256(payload).digest()) + payload


@pytest.fixture(scope="module")
def shipped():
    return core.load_bank(design_bank.nominal_bank_path("tuned"))


@pytest.fixture(scope="module")
def payload(shipped):
    return shipped.to_bytes()[HEADER.size:]


def offsets(bank) -> dict[str, int]:
    """Byte offsets of the payload's leading fields, from the LCM layout of
    lcmt_model_bank.lcm: fingerprint, three (count, names) lists, then u_trim_size."""
    at = 8
    out = {}
    for field, names in (("num_states", bank.state_names), ("num_inputs", bank.input_names),
                         ("num_measurements", bank.measurement_names)):
        out[field] = at
        at += 4
        for i, n in enumerate(names):
            out[f"{field}[{i}]"] = at
            at += 4 + len(n.encode()) + 1
    out["u_trim_size"] = at
    at += 4 + 8 * bank.nu
    out["z_trim_size"] = at
    at += 4 + 8 * bank.nz
    out["h_output.rows"] = at
    return out


def patched(payload: bytes, at: int, fmt: str, value) -> bytes:
    data = bytearray(payload)
    struct.pack_into(fmt, data, at, value)
    return bytes(data)


def refused(tmp_path, data: bytes, pattern: str, error=ValueError):
    path = tmp_path / "hostile.f16bank"
    path.write_bytes(data)
    with pytest.raises(error, match=pattern) as info:
        core.load_bank(path)
    assert str(path) in str(info.value)
    return str(info.value)


@pytest.mark.parametrize("field, value, pattern", [
    # issue 16: u_trim_size = 2^28 with a recomputed SHA-256 segfaulted LCM's decoder
    ("u_trim_size", 2**28, r"payload field u_trim_size \(byte \d+\) = 268435456 exceeds the limit of 256"),
    ("u_trim_size", 2**31 - 1, r"u_trim_size \(byte \d+\) = 2147483647 exceeds the limit of 256"),
    ("u_trim_size", -1, r"u_trim_size \(byte \d+\) = -1 is negative"),
    ("z_trim_size", 257, r"z_trim_size \(byte \d+\) = 257 exceeds the limit of 256"),
    ("num_states", 2**30, r"num_states \(byte 8\) = 1073741824 exceeds the limit of 256"),
    ("num_states[0]", 2**31 - 1, r"state_names\[0\] length \(byte \d+\) = 2147483647 exceeds the limit of 257"),
    ("num_states[0]", 0, r"state_names\[0\] \(byte \d+\) has length 0"),
    ("h_output.rows", 2**28, r"h_output.rows \(byte \d+\) = 268435456 exceeds the limit of 256"),
    ("h_output.rows", -7, r"h_output.rows \(byte \d+\) = -7 is negative"),
])
def test_crafted_sizes_are_refused_before_allocation_naming_the_field(tmp_path, shipped, payload, field,
                                                                       value, pattern):
    refused(tmp_path, image(patched(payload, offsets(shipped)[field], ">i", value)), pattern)


def test_crafted_hypothesis_count_and_trailing_bytes(tmp_path, shipped, payload):
    at = len(payload) - len(shipped.to_bytes()) + HEADER.size  # 0: sanity of the fixture
    assert at == 0
    # num_hypotheses sits just before the first hypothesis name "NONE" (int32 5, "NONE\0")
    first = payload.index(struct.pack(">i", 5) + b"NONE\0")
    refused(tmp_path, image(patched(payload, first - 4, ">i", 2**31 - 1)),
            r"num_hypotheses \(byte \d+\) = 2147483647 exceeds the limit of 4096")
    refused(tmp_path, image(patched(payload, first - 4, ">i", 4000)),
            r"num_hypotheses \(byte \d+\) = 4000 needs at least 180000 bytes|hypotheses\[79\]")
    refused(tmp_path, image(payload + b"\0" * 3), "payload has 3 bytes after the f16mmae.lcmt_model_bank message")


def test_non_regular_files_are_refused_at_once_by_name(tmp_path):
    with pytest.raises(OSError, match="'/dev/zero': is a character device; it must be a regular file"):
        core.load_bank("/dev/zero")
    fifo = tmp_path / "bank.fifo"
    os.mkfifo(fifo)
    result = {}

    def load():
        try:
            core.load_bank(fifo)
        except OSError as e:
            result["error"] = str(e)

    t = threading.Thread(target=load, daemon=True)
    t0 = time.monotonic()
    t.start()
    t.join(timeout=10)
    assert not t.is_alive(), "loading a FIFO with no writer hung"
    assert time.monotonic() - t0 < 10
    assert result["error"] == f"bank file '{fifo}': is a FIFO; it must be a regular file"
    with pytest.raises(OSError, match="is a directory"):
        core.load_bank(tmp_path)


def test_a_file_over_the_size_limit_is_refused_without_reading_it(tmp_path):
    path = tmp_path / "huge.f16bank"
    with open(path, "wb") as f:  # sparse: 64 MiB + 1 byte of nothing
        f.truncate((64 << 20) + 1)
    with pytest.raises(ValueError, match=r"is 67108865 bytes, over the limit of 67108864 bytes"):
        core.load_bank(path)


def rebuilt(bank, **changes):
    """The bank with fields replaced, not validated (as a crafted file would hold it)."""
    fields = dict(state_names=bank.state_names, input_names=bank.input_names,
                  measurement_names=bank.measurement_names, frame_rate_hz=bank.frame_rate_hz,
                  u_trim=bank.u_trim, z_trim=bank.z_trim, h_output=bank.h_output, mach=bank.mach,
                  alt_ft=bank.alt_ft, tuning=bank.tuning, metadata=bank.metadata, **bank.estimator_settings)
    fields.update(changes)
    return core.ModelBank(bank.hypotheses, validate=False, **fields)


def swap(names, i, j):
    out = list(names)
    out[i], out[j] = out[j], out[i]
    return out


@pytest.mark.parametrize("changes, pattern", [
    (dict(mach=math.nan), r"mach must be finite, >= 0 and <= 10, got nan"),
    (dict(mach=math.inf), r"mach must be finite, >= 0 and <= 10, got inf"),
    (dict(mach=-0.4), r"mach must be finite, >= 0 and <= 10, got -0.4"),
    (dict(alt_ft=-20000.0), r"alt_ft must be finite, >= 0 and <= 1e\+06, got -20000"),
    (dict(alt_ft=math.nan), r"alt_ft must be finite, >= 0 and <= 1e\+06, got nan"),
    (dict(frame_rate_hz=1e9), r"frame_rate_hz must be finite, > 0 and <= 10000, got 1e\+09"),
    (dict(measurement_names=swap(("VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY"), 1, 2)),
     r"hypothesis 7 'AOA' fails measurement 'AOA' but its h row 2 \(measurement_names\[2\]\) is not zero: "
     "measurement_names do not match the matrices"),
    (dict(input_names=swap(("LS", "RS", "LF", "RF", "RUD"), 0, 4)),
     r"hypothesis 1 'LS' fails input 'LS' but its bd column 4 \(input_names\[4\]\) is not zero"),
    (dict(state_names=("u", "u") + tuple(f"s{i}" for i in range(11))),
     r"state_names\[1\] 'u' duplicates state_names\[0\]"),
    (dict(input_names=("LS", "", "LF", "RF", "RUD")), r"input_names\[1\] is empty"),
    (dict(p_min=0.5), r"estimator: p_min must be in \[0, 1/K\) with K = 79 hypotheses, got 0.5"),
    (dict(threshold=1.0), r"estimator: threshold must be in \(0.5, 1\), got 1"),
    (dict(dwell_s=3.4e7), r"estimator: dwell_s must be in \[0, 60\] s, got 3.4e\+07"),
    (dict(dwell_s=math.nan), r"estimator: dwell_s must be in \[0, 60\] s, got nan"),
])
def test_validation_gaps_are_refused_by_field_and_value(tmp_path, shipped, changes, pattern):
    bad = rebuilt(shipped, **changes)
    with pytest.raises(ValueError, match=pattern):
        bad.validate()
    message = refused(tmp_path, image(bad.__getstate__()), pattern)
    assert message.startswith(f"bank file '{tmp_path / 'hostile.f16bank'}': model bank: ")


def test_nul_and_invalid_utf8_in_names_are_refused_by_field(tmp_path, shipped, payload):
    at = offsets(shipped)["num_measurements[1]"] + 4  # the bytes of "AOA"
    assert payload[at:at + 4] == b"AOA\0"
    refused(tmp_path, image(payload[:at] + b"A\0A" + payload[at + 3:]),
            r"model bank: measurement_names\[1\] holds a NUL character at byte 1")
    refused(tmp_path, image(payload[:at] + b"A\xffA" + payload[at + 3:]),
            r"model bank: measurement_names\[1\] is not valid UTF-8 at byte 1")
    refused(tmp_path, image(payload[:at] + b"\xed\xa0\x80" + payload[at + 3:]),  # a UTF-16 surrogate
            r"measurement_names\[1\] is not valid UTF-8 at byte 0")
    refused(tmp_path, image(payload[:at] + b"A\xc3A" + payload[at + 3:]),  # no continuation byte
            r"measurement_names\[1\] is not valid UTF-8 at byte 1")
    refused(tmp_path, image(payload[:at] + b"AO\xc3" + payload[at + 3:]),  # a sequence cut by the end
            r"measurement_names\[1\] is not valid UTF-8 \(a truncated sequence\) at byte 2")
    at = payload.index(b"\0\0\0\x05NONE\0") + 4  # hypothesis 0's name
    refused(tmp_path, image(payload[:at] + b"N\xc0\x8eE" + payload[at + 4:]),  # an overlong form
            r"hypotheses\[0\]\.name is not valid UTF-8 at byte 1")
    ok = payload[:at] + "NÖE".encode()[:4] + payload[at + 4:]  # valid UTF-8: refused only as not NONE
    refused(tmp_path, image(ok), "hypothesis 0 must be NONE, got 'NÖE'")


def test_a_bank_round_trips_its_estimator_settings(tmp_path, shipped):
    bank = rebuilt(shipped, p_min=1e-6, threshold=0.95, dwell_s=0.5)
    bank.save(tmp_path / "s.f16bank")
    loaded = core.load_bank(tmp_path / "s.f16bank")
    assert loaded.estimator_settings == {"p_min": 1e-6, "threshold": 0.95, "dwell_s": 0.5,   # the N_k ride along
                                         "dwell_nats_per_hypothesis": shipped.estimator_settings[
                                             "dwell_nats_per_hypothesis"]}
    assert loaded.content_hash == bank.content_hash != shipped.content_hash
    np.testing.assert_array_equal(loaded["LS"].k, shipped["LS"].k)


def test_the_daemon_goes_through_the_same_loader(tmp_path):
    """mmae-daemon refuses /dev/zero, a FIFO and a crafted bank at once, by name (exit 1)."""
    import subprocess

    from f16mmae.lcm.daemon import find_executable

    fifo = tmp_path / "bank.fifo"
    os.mkfifo(fifo)
    crafted = tmp_path / "crafted.f16bank"
    shipped = core.load_bank(design_bank.nominal_bank_path("tuned"))
    payload = shipped.to_bytes()[HEADER.size:]
    crafted.write_bytes(image(patched(payload, offsets(shipped)["u_trim_size"], ">i", 2**28)))
    for path, message in (("/dev/zero", "is a character device; it must be a regular file"),
                          (str(fifo), "is a FIFO; it must be a regular file"),
                          (str(crafted), "payload field u_trim_size (byte 275) = 268435456 exceeds the limit of 256")):
        proc = subprocess.run([str(find_executable("mmae-daemon")), "--bank", path, "--lcm-url", "memq://",
                               "--quiet"], capture_output=True, text=True, timeout=30)
        assert proc.returncode == 1, proc.stderr
        assert f"cannot use bank file '{path}'" in proc.stderr and message in proc.stderr, proc.stderr
