"""The scheduled-bank file (cpp/bankfile/schedule_file.h) and the scheduled bank through the
binding: files crafted here from the documented layout (52-byte header, then the payload,
SHA-256 recomputed so only the targeted check refuses them), round trips through the loader
and pickle, and the schedule's trims at a node and at a cell midpoint computed by hand."""
from __future__ import annotations

import hashlib
import pickle
import struct

import numpy as np
import pytest

from f16mmae import banks, core, names
from f16mmae.bench.scheduled import synthetic_schedule
from f16mmae.bench.estimator import synthetic_bank

HEADER = struct.Struct(">8sIQ32s")


def image(payload: bytes, version: int = 1) -> bytes:
    return HEADER.pack(b"F16MMAES", version, len(payload), hashlib.sha256(payload).digest()) + payload


def payload(mach, alt, nodes, primary=0, metadata=b"{}") -> bytes:
    """The documented payload: axes, primary, metadata string, nodes."""
    out = struct.pack(">i", len(mach)) + b"".join(struct.pack(">d", m) for m in mach)
    out += struct.pack(">i", len(alt)) + b"".join(struct.pack(">d", a) for a in alt)
    out += struct.pack(">i", primary) + struct.pack(">i", len(metadata) + 1) + metadata + b"\0"
    out += struct.pack(">i", len(nodes))
    for i, j, x_trim, bank_bytes in nodes:
        out += struct.pack(">iii", i, j, len(x_trim)) + b"".join(struct.pack(">d", x) for x in x_trim)
        out += struct.pack(">q", len(bank_bytes)) + bank_bytes
    return out


@pytest.fixture(scope="module")
def schedule(tmp_path_factory):
    return synthetic_schedule(1, tmp_path_factory.mktemp("sched"))


def test_a_crafted_file_loads_as_the_primary_node_with_the_schedule(tmp_path):
    b0, b1 = synthetic_bank(names.ALL_HYPOTHESES, 1), synthetic_bank(names.ALL_HYPOTHESES, 2)
    data = payload([0.4, 0.6], [20000.0], [(0, 0, [1.0] * 13, b0.to_bytes()), (1, 0, [2.0] * 13, b1.to_bytes())],
                   primary=1)
    path = tmp_path / "crafted.f16sched"
    path.write_bytes(image(data))
    loaded = core.load_bank(path)
    assert loaded.content_hash == hashlib.sha256(data).hexdigest()
    s = loaded.schedule
    assert s["mach"] == (0.4, 0.6) and s["alt_ft"] == (20000.0,) and s["primary"] == 1
    assert [n["bank"].content_hash for n in s["nodes"]] == [b0.content_hash, b1.content_hash]
    assert list(loaded.hypothesis_names) == list(b1.hypothesis_names)
    np.testing.assert_array_equal(s["nodes"][1]["x_trim"], np.full(13, 2.0))
    # the writer gives the same bytes
    again = tmp_path / "again.f16sched"
    h = core.save_schedule([0.4, 0.6], [20000.0], [(0, 0, b0, np.ones(13)), (1, 0, b1, np.full(13, 2.0))],
                           primary=1, metadata="{}", path=again)
    assert h == loaded.content_hash and again.read_bytes() == path.read_bytes()


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d[:-1], "truncated"),
    (lambda d: d[:30], "truncated"),
    (lambda d: d[:60] + bytes([d[60] ^ 1]) + d[61:], "content hash mismatch"),
    (lambda d: b"F16MMAEX" + d[8:], "wrong magic bytes"),
    (lambda d: d[:8] + struct.pack(">I", 7) + d[12:], "unsupported format version 7"),
])
def test_corruption_is_refused_naming_the_problem(tmp_path, schedule, mutate, message):
    good = tmp_path / "good.f16sched"
    s = schedule.schedule
    core.save_schedule(list(s["mach"]), list(s["alt_ft"]),
                       [(n["i_mach"], n["i_alt"], n["bank"], n["x_trim"]) for n in s["nodes"]], primary=0, path=good)
    bad = tmp_path / "bad.f16sched"
    bad.write_bytes(mutate(good.read_bytes()))
    with pytest.raises(ValueError, match=message):
        core.load_bank(bad)


@pytest.mark.parametrize("fields, message", [
    (dict(mach=[0.4] * 65), r"mach size \(byte 0\) = 65 exceeds the limit of 64"),
    (dict(nodes_count=2**30), r"nodes size .* exceeds the limit of 1024"),
    (dict(x_trim=[0.0] * 3), r"nodes\[0\]\.x_trim must hold 13 finite values, it has 3"),
    (dict(i=5), r"nodes\[0\] at grid index \(5, 0\) is outside the 1 x 1 grid"),
    (dict(primary=4), r"primary = 4 is not one of its 1 nodes"),
    (dict(bank_bytes=b"F16MMAEB"), r"nodes\[0\]: truncated"),
    (dict(bank_len=2**62), r"nodes\[0\]\.bank size = 4611686018427387904 is outside"),
    (dict(mach=[float("nan")]), r"mach\[0\] = nan must be finite"),
])
def test_hostile_fields_are_refused_naming_the_field(tmp_path, fields, message):
    bank = synthetic_bank(names.ALL_HYPOTHESES, 1).to_bytes()
    mach = fields.get("mach", [0.4])
    data = payload(mach, [20000.0], [(fields.get("i", 0), 0, fields.get("x_trim", [0.0] * 13),
                                      fields.get("bank_bytes", bank))], primary=fields.get("primary", 0))
    if "nodes_count" in fields:
        at = 4 + 8 * len(mach) + 4 + 8 + 4 + 4 + 3
        data = data[:at] + struct.pack(">i", fields["nodes_count"]) + data[at + 4:]
    if "bank_len" in fields:
        at = len(data) - len(bank) - 8
        data = data[:at] + struct.pack(">q", fields["bank_len"]) + data[at + 8:]
    with pytest.raises(ValueError, match=message):
        core.ModelBank.from_bytes(image(data), "hostile")


def test_pickle_keeps_the_schedule(schedule):
    again = pickle.loads(pickle.dumps(schedule))
    assert again.content_hash == schedule.content_hash
    assert len(again.schedule["nodes"]) == 4


def test_the_schedule_brings_a_nodes_trim_and_the_hand_blend_at_a_midpoint(schedule):
    nodes = schedule.schedule["nodes"]
    hb = core.HierarchicalBank(schedule, air_data_time_constant_s=0.0)  # each value as given
    assert hb.schedule_state["nodes"] == [(0.4, 10000.0)]
    hb.schedule(0.6, 20000.0)
    st = hb.schedule_state
    assert st["nodes"] == [(0.6, 20000.0)] and st["weights"] == [1.0]
    np.testing.assert_array_equal(st["x_trim"], nodes[3]["x_trim"])
    hb.schedule(0.5, 15000.0)
    st = hb.schedule_state
    assert st["weights"] == [0.25] * 4
    np.testing.assert_allclose(st["x_trim"][0], (0.0 + 10.0 + 20.0 + 30.0) / 4, rtol=1e-15)
    hb.schedule(0.45, 30000.0)  # above the grid: clamped to 20,000 ft and counted
    st = hb.schedule_state
    assert st["outside_frames"] == 1 and st["weights"] == [0.75, 0.25]
    hb.schedule(float("nan"), 1.0)
    assert hb.air_data_rejected == 1 and hb.air_data == (0.45, 30000.0)
    with pytest.raises(ValueError, match="schedule_mode must be 'interpolate' or 'nearest', got 'cubic'"):
        core.HierarchicalBank(schedule, schedule_mode="cubic")


def test_an_unscheduled_bank_has_no_schedule_and_takes_a_trim_offset():
    bank = synthetic_bank(names.ALL_HYPOTHESES, 1)
    assert bank.schedule is None
    hb = core.HierarchicalBank(bank)
    assert hb.schedule_state is None
    hb.set_trim_offset(np.full(5, 0.1), np.arange(7.0))
    np.testing.assert_array_equal(hb.z_trim, np.asarray(bank.z_trim))
    np.testing.assert_array_equal(hb.trim_offset[0], np.full(5, 0.1))
    np.testing.assert_array_equal(hb.trim_offset[1], np.arange(7.0))
    np.testing.assert_allclose(hb.z_hat, hb.z_hat_perturbation + np.asarray(bank.z_trim) + np.arange(7.0))
    with pytest.raises(ValueError):
        hb.set_trim_offset(np.zeros(4), np.zeros(7))


def test_the_scheduled_bank_name_says_how_to_build_it_when_missing(tmp_path, monkeypatch):
    monkeypatch.setenv("F16MMAE_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(banks, "_schedule_generator", None)
    with pytest.raises(banks.BankError, match=r"f16mmae design --schedule --out .*scheduled_tuned_"):
        banks.load_bank("scheduled")
    built = []
    monkeypatch.setattr(banks, "_schedule_generator", built.append)
    with pytest.raises(banks.BankError):
        banks.load_bank("scheduled")  # the generator was called but wrote nothing
    assert built == [banks.scheduled_bank_path()]
