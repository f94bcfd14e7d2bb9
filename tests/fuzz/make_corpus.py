"""Writes the seed and regression inputs of the fuzz corpora (tests/fuzz/corpus/<target>/).

Run from the repository root after a format change: ``.venv/bin/python tests/fuzz/make_corpus.py``.
Deterministic; files are named for what they hold. The regression inputs are the crash and
hang reproductions of issue 16: a bank declaring u_trim_size = 2^28 (and other huge sizes)
with its SHA-256 recomputed, a format-1 header, names with a NUL or invalid UTF-8, and a
sensor or command frame whose frame number jumps to 2^62."""
from __future__ import annotations

import hashlib
import importlib
import math
import struct
from pathlib import Path

import numpy as np
import scipy.linalg

from f16mmae import core

CORPUS = Path(__file__).resolve().parent / "corpus"
HEADER = struct.Struct(">8sIQ32s")


def lcm_type(name: str):
    return getattr(importlib.import_module(f"f16mmae.{name}"), name)


def image(payload: bytes, version: int = core.ModelBank.FORMAT_VERSION) -> bytes:
    return HEADER.pack(b"F16MMAEB", version, len(payload), hashlib.sha256(payload).digest()) + payload


def small_bank():
    """NONE plus one sensor failure of a 2-state, 1-input, 2-measurement system: the smallest
    bank that passes validation, so mutations reach every check quickly."""
    phi = np.array([[0.9, 0.1], [0.0, 0.8]])
    bd = np.array([[0.0], [0.1]])
    models = []
    for name, h in (("NONE", np.eye(2)), ("z1", np.array([[1.0, 0.0], [0.0, 0.0]]))):
        r = 0.01 * np.eye(2)
        p = scipy.linalg.solve_discrete_are(phi.T, h.T, 0.1 * np.eye(2), r)
        a = h @ p @ h.T + r
        a = 0.5 * (a + a.T)
        models.append((name, dict(phi=phi, bd=bd, h=h, k=p @ h.T @ np.linalg.inv(a), a=a)))
    return core.ModelBank(models, state_names=["x0", "x1"], input_names=["u0"], measurement_names=["z0", "z1"],
                          frame_rate_hz=64.0, mach=0.4, alt_ft=20000.0, tuning="fuzz", metadata="{}")


def bank_inputs() -> dict[str, bytes]:
    bank = small_bank()
    payload = bank.to_bytes()[HEADER.size:]
    # leading fields: fingerprint (8), num_states (4) + "x0" "x1" (7 each), num_inputs + "u0",
    # num_measurements + "z0" "z1", then u_trim_size
    at_states = 8
    at_name0 = at_states + 4
    at_u_trim_size = 8 + (4 + 7 + 7) + (4 + 7) + (4 + 7 + 7)
    at_h_rows = at_u_trim_size + 4 + 8 + 4 + 2 * 8

    def put(offset: int, value: int) -> bytes:
        data = bytearray(payload)
        struct.pack_into(">i", data, offset, value)
        return bytes(data)

    def name(offset: int, text: bytes) -> bytes:  # replaces the 2 bytes of a 2-letter name
        return payload[:offset + 4] + text + payload[offset + 6:]

    return {
        "valid_file": image(payload),
        "valid_payload": payload,
        "regress_u_trim_size_2p28_file": image(put(at_u_trim_size, 2**28)),
        "regress_u_trim_size_2p28_payload": put(at_u_trim_size, 2**28),
        "regress_num_states_2p30": image(put(at_states, 2**30)),
        "regress_name_length_int32_max": image(put(at_name0, 2**31 - 1)),
        "regress_h_output_rows_2p30": image(put(at_h_rows, 2**30)),
        "regress_negative_count": image(put(at_u_trim_size, -1)),
        "regress_format_version_1": image(payload, version=1),
        "regress_nul_in_name": image(name(at_name0, b"x\0")),
        "regress_invalid_utf8_name": image(name(at_name0, b"\xff\xfe")),
        **schedule_inputs(bank),
    }


def schedule_inputs(bank) -> dict[str, bytes]:
    """A scheduled-bank file of three nodes (two flap layers) of the small bank (cpp/bankfile/schedule_file.h), its
    payload alone, and one with a node count of 2^30 (hash recomputed)."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "s.f16sched"
        core.save_schedule([0.4, 0.5], [20000.0], [(0, 0, bank, [0.0, 0.0], 0.7, 0), (1, 0, bank, [1.0, 0.0], 0.8, 1),
                                                   (0, 0, bank, [0.1, 0.0], 0.7, 1)],
                           primary=0, metadata="{}", path=str(path), switch_state=0, switch_thresholds=[0.5])
        data = path.read_bytes()
    payload = data[HEADER.size:]
    at_nodes = 4 + 2 * 8 + 4 + 8 + 4 + 4 + 3 + 4 + 4 + 8  # axes, primary, metadata "{}", the flap law
    huge = payload[:at_nodes] + struct.pack(">i", 2**30) + payload[at_nodes + 4:]
    return {
        "schedule_valid_file": data,
        "schedule_valid_payload": payload,
        "regress_schedule_nodes_2p30": HEADER.pack(b"F16MMAES", 2, len(huge), hashlib.sha256(huge).digest()) + huge,
    }


def sensor(frame: int, z=None, valid=True, air_data=(0.4, 20000.0)) -> bytes:
    msg = lcm_type("lcmt_sensor_frame")()
    msg.utime, msg.frame = min(frame * 15625, 2**63 - 1), frame
    msg.z = list(z) if z is not None else [414.8, 0.14, 0.0, 1.0, 0.0, 0.0, 0.0]
    msg.valid = [valid] * 7
    msg.mach, msg.pressure_altitude_ft = air_data
    return msg.encode()


def command(frame: int) -> bytes:
    msg = lcm_type("lcmt_command_frame")()
    msg.utime, msg.frame, msg.u_rad = min(frame * 15625, 2**63 - 1), frame, [-0.036, -0.036, 0.0, 0.0, 0.0]
    return msg.encode()


def reset(reason: str) -> bytes:
    msg = lcm_type("lcmt_mmae_reset")()
    msg.utime, msg.reason = 0, reason
    return msg.encode()


def status_records(rows) -> bytes:
    """Records of fuzz_mmae_status: 7 doubles of z, a byte of valid flags, a byte of frame step."""
    return b"".join(struct.pack("<7dBB", *z, valid, step) for z, valid, step in rows)


def main() -> None:
    trim = [414.8, 0.14, 0.0, 1.0, 0.0, 0.0, 0.0]
    inputs = {
        "bank_file": bank_inputs(),
        "sensor_frame": {
            "valid_frame_1": sensor(1),
            "regress_frame_jump_2p62": sensor(2**62),
            "regress_frame_jump_1e7": sensor(10**7),
            "nan_z": sensor(1, [math.nan] * 7),
            "nan_air_data": sensor(1, air_data=(math.nan, math.inf)),
            "invalid_flags": sensor(1, valid=False),
            "truncated": sensor(1)[:-5],
        },
        "command_frame": {
            "valid_command_0": command(0),
            "regress_frame_jump_2p62": command(2**62),
            "truncated": command(0)[:-3],
        },
        "mmae_reset": {
            "valid_reset": reset("fuzz"),
            "empty_reason": reset(""),
            "regress_reason_length_int32_max": reset("x")[:8 + 8] + struct.pack(">i", 2**31 - 1) + b"x\0",
        },
        "mmae_status": {
            "trim_frames": status_records([(trim, 0x7F, 0)] * 8),
            "hostile_values": status_records([(trim, 0x7F, 0), ([math.nan] * 7, 0x7F, 0),
                                              ([math.inf, -math.inf, 1e308, -1e308, 0, 0, 0], 0x7F, 1),
                                              ([1e308] * 7, 0x00, 3), (trim, 0x7F, 0)]),
            "biased_pitch_rate": status_records([(trim[:2] + [0.2] + trim[3:], 0x7F, 0)] * 64),
        },
    }
    for target, files in inputs.items():
        folder = CORPUS / target
        folder.mkdir(parents=True, exist_ok=True)
        for name, data in files.items():
            (folder / name).write_bytes(data)
        print(f"{folder}: {len(files)} inputs")


if __name__ == "__main__":
    main()
