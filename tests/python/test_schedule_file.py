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


def image(payload: bytes, version: int = 2) -> bytes:
    return HEADER.pack(b"F16MMAES", version, len(payload), hashlib.sha256(payload).digest()) + payload


def payload(mach, alt, nodes, primary=0, metadata=b"{}", version=2, references=None, layers=None,
            switch=(-1, ())) -> bytes:
    """The documented payload: axes, primary, metadata string, (version 2: switch_state and
    thresholds), nodes (version 2: each with its layer, 0 unless ``layers`` gives them, and its
    adapt_reference after x_trim, NaN unless ``references`` gives them)."""
    out = struct.pack(">i", len(mach)) + b"".join(struct.pack(">d", m) for m in mach)
    out += struct.pack(">i", len(alt)) + b"".join(struct.pack(">d", a) for a in alt)
    out += struct.pack(">i", primary) + struct.pack(">i", len(metadata) + 1) + metadata + b"\0"
    if version >= 2:
        out += struct.pack(">ii", switch[0], len(switch[1])) + b"".join(struct.pack(">d", t) for t in switch[1])
    out += struct.pack(">i", len(nodes))
    for n, (i, j, x_trim, bank_bytes) in enumerate(nodes):
        out += struct.pack(">ii", i, j)
        if version >= 2:
            out += struct.pack(">i", layers[n] if layers else 0)
        out += struct.pack(">i", len(x_trim)) + b"".join(struct.pack(">d", x) for x in x_trim)
        if version >= 2:
            out += struct.pack(">d", references[n] if references else float("nan"))
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


def test_a_version_1_file_still_loads_its_nodes_carrying_no_reference(tmp_path):
    b0 = synthetic_bank(names.ALL_HYPOTHESES, 1)
    data = payload([0.4], [20000.0], [(0, 0, [1.0] * 13, b0.to_bytes())], version=1)
    loaded = core.ModelBank.from_bytes(image(data, version=1), "v1")
    assert loaded.schedule["nodes"][0]["adapt_reference"] is None
    np.testing.assert_array_equal(loaded.schedule["nodes"][0]["x_trim"], np.ones(13))


def test_per_node_references_round_trip_and_are_checked(tmp_path):
    b0, b1 = synthetic_bank(names.ALL_HYPOTHESES, 1), synthetic_bank(names.ALL_HYPOTHESES, 2)
    data = payload([0.4, 0.6], [20000.0], [(0, 0, [0.0] * 13, b0.to_bytes()), (1, 0, [0.0] * 13, b1.to_bytes())],
                   references=[0.7, 1.25])
    path = tmp_path / "ref.f16sched"
    path.write_bytes(image(data))
    loaded = core.load_bank(path)
    assert [n["adapt_reference"] for n in loaded.schedule["nodes"]] == [0.7, 1.25]
    again = tmp_path / "again.f16sched"
    core.save_schedule([0.4, 0.6], [20000.0], [(0, 0, b0, np.zeros(13), 0.7), (1, 0, b1, np.zeros(13), 1.25)],
                       primary=0, metadata="{}", path=again)
    assert again.read_bytes() == path.read_bytes()
    with pytest.raises(ValueError, match=r"nodes\[1\]\.adapt_reference is missing but nodes\[0\]'s is given"):
        core.save_schedule([0.4, 0.6], [20000.0], [(0, 0, b0, np.zeros(13), 0.7), (1, 0, b1, np.zeros(13))],
                           primary=0, path=tmp_path / "mixed.f16sched")
    with pytest.raises(ValueError, match=r"nodes\[0\]\.adapt_reference must be in \[0, 100\], got -1"):
        core.ModelBank.from_bytes(image(payload([0.4], [20000.0], [(0, 0, [0.0] * 13, b0.to_bytes())],
                                                references=[-1.0])), "negative")
    assert not (tmp_path / "mixed.f16sched").exists()


def test_the_node_references_set_the_adaptation_blended_with_the_filters(tmp_path):
    """References 1.0, 0.5, 0.8, 0.3 at the corners of the 2 x 2 schedule.  Before the first
    update rho starts at the reference in force (s = 1): at node (0.6, 10000 ft) rho_0 = 0.5, at
    the centre rho_0 = (1.0 + 0.5 + 0.8 + 0.3) / 4 = 0.65.  After an update rho is kept and
    s = 1 + 20 (rho - rho_0) shows the reference in force."""
    refs = (1.0, 0.5, 0.8, 0.3)
    nodes = []
    for n, (i, j) in enumerate(((0, 0), (1, 0), (0, 1), (1, 1))):
        nodes.append((i, j, synthetic_bank(names.ALL_HYPOTHESES, seed=1 + n), np.zeros(names.NX), refs[n]))
    path = tmp_path / "refs.f16sched"
    core.save_schedule([0.4, 0.6], [10000.0, 20000.0], nodes, primary=0, path=path)
    bank = core.load_bank(path)
    hb = core.HierarchicalBank(bank, adapt_turbulence=True, air_data_time_constant_s=0.0)
    assert hb.schedule_state["nodes"] == [(0.4, 10000.0)]
    assert hb.turbulence_power_ratio == 1.0 and hb.turbulence_scale == 1.0
    hb.schedule(0.6, 10000.0)   # the first air data, before any residual: rho starts at its rho_0
    assert hb.turbulence_power_ratio == 0.5 and hb.turbulence_scale == 1.0
    hb.schedule(0.5, 15000.0)
    assert hb.schedule_state["weights"] == [0.25] * 4
    assert hb.turbulence_power_ratio == pytest.approx(0.65, rel=1e-12) and hb.turbulence_scale == 1.0
    hb.update(np.asarray(hb.z_trim) + 0.05)   # one update averaged: from here on rho is the residuals'
    rho = hb.turbulence_power_ratio
    assert rho != pytest.approx(0.65)
    hb.schedule(0.6, 10000.0)
    assert hb.turbulence_power_ratio == rho
    assert hb.turbulence_scale == pytest.approx(min(100.0, max(1.0, 1.0 + 20.0 * (rho - 0.5))), rel=1e-12)
    hb.reset()   # back to the start: rho = the reference in force, and the next air data's again
    assert hb.turbulence_scale == 1.0
    hb.schedule(0.4, 20000.0)
    assert hb.turbulence_power_ratio == 0.8 and hb.turbulence_scale == 1.0
    # one reference given: it applies everywhere, the nodes' are not used
    fixed = core.HierarchicalBank(bank, adapt_turbulence=True, adapt_reference=0.6, air_data_time_constant_s=0.0)
    fixed.schedule(0.6, 10000.0)
    assert fixed.turbulence_power_ratio == 0.6 and fixed.turbulence_scale == 1.0


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
        at = 4 + 8 * len(mach) + 4 + 8 + 4 + 4 + 3 + 8
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
    with pytest.raises(banks.BankError, match=r"f16mmae design --schedule --failure-model constant=VEL\+ROL "
                                              r"--failed-sensor-noise sensor --gust-states-below-ft 20000 --gust-node-choice all --throttle-input --out "
                                              r".*scheduled_tuned_"):
        banks.load_bank("scheduled")
    built = []
    monkeypatch.setattr(banks, "_schedule_generator", built.append)
    with pytest.raises(banks.BankError):
        banks.load_bank("scheduled")  # the generator was called but wrote nothing
    assert built == [banks.scheduled_bank_path()]


def test_configuration_layers_follow_the_law_on_the_trims_and_switch_at_once(tmp_path):
    """Two nodes on a Mach axis, alpha (x_trim[1]) 0 and 1 rad with a switch at 0.5: own layers
    0 and 1, each also covered in the other layer (x_trim[0] marks the layer: 0 or 100). The
    law on the interpolated alpha a (the Mach fraction here) gives layer 0 for a <= 0.5, else
    1, whatever the blend step; nodes of the layer in force only."""
    nodes = []
    for i in (0, 1):
        for layer in (0, 1):
            x = np.zeros(names.NX)
            x[0], x[1] = 100.0 * layer, float(i)
            nodes.append((i, 0, synthetic_bank(names.ALL_HYPOTHESES, seed=1 + 2 * i + layer), x, None, layer))
    path = tmp_path / "layers.f16sched"
    core.save_schedule([0.4, 0.6], [20000.0], nodes, primary=0, path=path, switch_state=1, switch_thresholds=[0.5])
    bank = core.load_bank(path)
    assert bank.schedule["switch_state"] == 1 and bank.schedule["switch_thresholds"] == (0.5,)
    assert [n["layer"] for n in bank.schedule["nodes"]] == [0, 1, 0, 1]
    hb = core.HierarchicalBank(bank, air_data_time_constant_s=0.0, blend_step_cells=0.9)
    hb.schedule(0.46, 20000.0)   # a = 0.3: layer 0
    st = hb.schedule_state
    assert st["layer"] == 0 and st["x_trim"][0] == 0.0
    np.testing.assert_allclose(st["x_trim"][1], 0.3, rtol=1e-12)
    blends = st["blends"]
    hb.schedule(0.54, 20000.0)   # a = 0.7, moved 0.4 < blend step: layer 1, re-blended at once
    st = hb.schedule_state
    assert st["layer"] == 1 and st["blends"] == blends + 1
    np.testing.assert_allclose(st["x_trim"][0], 100.0, rtol=1e-12)
    near = core.HierarchicalBank(bank, air_data_time_constant_s=0.0, schedule_mode="nearest")
    near.schedule(0.46, 20000.0)
    assert near.schedule_state["layer"] == 0 and near.schedule_state["nodes"] == [(0.4, 20000.0)]
    near.schedule(0.52, 20000.0)   # a = 0.6: layer 1, the node at Mach 0.6 in it
    assert near.schedule_state["layer"] == 1 and near.schedule_state["nodes"] == [(0.6, 20000.0)]
    with pytest.raises(ValueError, match=r"nodes\[1\] covers grid index \(0, 0\) in layer 0 a second time"):
        core.save_schedule([0.4, 0.6], [20000.0], [nodes[0], nodes[0]], primary=0, path=tmp_path / "x",
                           switch_state=1, switch_thresholds=[0.5])
    with pytest.raises(ValueError, match=r"nodes\[1\]\.layer = 1 is outside \[0, 0\]"):
        core.save_schedule([0.4, 0.6], [20000.0], nodes[:2], primary=0, path=tmp_path / "x")
    with pytest.raises(ValueError, match=r"switch_state = 1 with 0 switch_thresholds"):
        core.save_schedule([0.4, 0.6], [20000.0], nodes[:1], primary=0, path=tmp_path / "x", switch_state=1)


def test_the_node_floors_set_p_min_blended_geometrically_with_the_filters(tmp_path):
    """Each node's bank recommends its own floor p_min: 1e-9, 1e-3, 1e-5, 1e-7 at the corners
    of the 2 x 2 schedule. At a node the floor in force is that node's exactly; at the centre
    (weights 1/4) it is the geometric mean 10^((-9 - 3 - 5 - 7) / 4) = 1e-6; NONE starts
    presumed with the start node's floor (p_k = 1e-9 for the 12 others, not the options'
    0.001); node_p_min=False, or the Estimator given a p_min, puts one floor everywhere."""
    from f16mmae.loop.estimator import Estimator

    floors = (1e-9, 1e-3, 1e-5, 1e-7)
    nodes = [(i, j, synthetic_bank(names.ALL_HYPOTHESES, seed=1 + n).with_settings(p_min=floors[n]), np.zeros(names.NX))
             for n, (i, j) in enumerate(((0, 0), (1, 0), (0, 1), (1, 1)))]
    path = tmp_path / "floors.f16sched"
    core.save_schedule([0.4, 0.6], [10000.0, 20000.0], nodes, primary=0, path=path)
    bank = core.load_bank(path)
    assert [n["bank"].p_min for n in bank.schedule["nodes"]] == list(floors)
    with pytest.raises(ValueError, match="a scheduled bank's settings are its nodes' banks' own"):
        bank.with_settings(p_min=1e-3)
    hb = core.HierarchicalBank(bank, air_data_time_constant_s=0.0)
    assert hb.p_min == 0.001 and hb.p_min_in_force == 1e-9
    np.testing.assert_array_equal(hb.probabilities[1:], np.full(12, 1e-9))
    hb.schedule(0.6, 10000.0)
    assert hb.p_min_in_force == 1e-3
    hb.update(np.asarray(bank.z_trim) + 5.0)   # a frame far from every hypothesis: the floor shows
    assert hb.probabilities.min() >= 1e-3 * (1 - 1e-12)
    hb.schedule(0.5, 15000.0)
    assert hb.schedule_state["weights"] == [0.25] * 4
    assert hb.p_min_in_force == pytest.approx(1e-6, rel=1e-12)
    hb.reset()
    assert hb.p_min_in_force == 1e-9
    np.testing.assert_array_equal(hb.probabilities[1:], np.full(12, 1e-9))
    one = core.HierarchicalBank(bank, p_min=1e-4, node_p_min=False, air_data_time_constant_s=0.0)
    one.schedule(0.6, 10000.0)
    assert one.p_min_in_force == 1e-4
    assert Estimator(bank, p_min=1e-4).core_bank.p_min_in_force == 1e-4
    assert Estimator(bank).core_bank.p_min_in_force == 1e-9


def test_with_settings_copies_a_bank_with_other_recommended_settings():
    b = synthetic_bank(names.ALL_HYPOTHESES, 1)
    c = b.with_settings(p_min=1e-5)
    assert b.p_min == 1e-3 and c.p_min == 1e-5 and (c.threshold, c.dwell_s) == (b.threshold, b.dwell_s)
    assert c.content_hash != b.content_hash
    assert core.ModelBank.from_bytes(c.to_bytes()).content_hash == c.content_hash
    assert b.with_settings().content_hash == b.content_hash
    with pytest.raises(ValueError, match=r"p_min must be in \[0, 1/K\) with K = 79 hypotheses, got 0.02"):
        b.with_settings(p_min=0.02)


def test_a_version_3_file_recommends_its_start_up_to_the_estimator_and_replay(tmp_path):
    """The schedule's start_up_s (format 3: a double after the switch law) is the loaded bank's
    recommended start_up_s: the in-process estimator and the daemon's executive (replay) fly
    it unless told otherwise, so the first round(0.25 x 64) = 16 frames weigh nothing; a
    version-2 file recommends none; core.save_schedule writes 3 only with a start-up."""
    from f16mmae.lcm.replay import InProcessExecutive
    from f16mmae.loop.estimator import Estimator

    b0, b1 = synthetic_bank(names.ALL_HYPOTHESES, 1), synthetic_bank(names.ALL_HYPOTHESES, 2)
    nodes = [(0, 0, [1.0] * 13, b0.to_bytes()), (1, 0, [2.0] * 13, b1.to_bytes())]
    v2 = payload([0.4, 0.6], [20000.0], nodes)
    split = 4 + 2 * 8 + 4 + 8 + 4 + 4 + 3 + 8   # axes, primary, metadata "{}", switch law (-1, none)
    v3 = v2[:split] + struct.pack(">d", 0.25) + v2[split:]
    (tmp_path / "v3.f16sched").write_bytes(image(v3, version=3))
    (tmp_path / "v2.f16sched").write_bytes(image(v2, version=2))
    with_start = core.load_bank(tmp_path / "v3.f16sched")
    without = core.load_bank(tmp_path / "v2.f16sched")
    assert with_start.estimator_settings["start_up_s"] == 0.25 and with_start.schedule["start_up_s"] == 0.25
    assert "start_up_s" not in without.estimator_settings and without.schedule["start_up_s"] == 0.0
    assert banks.bank_estimator_settings(with_start)["start_up_s"] == 0.25
    rng = np.random.default_rng(5)
    z = with_start.z_trim + 0.05 * rng.standard_normal((20, 7))
    u = np.tile(with_start.u_trim, (20, 1))
    assert Estimator(with_start).settings["start_up_s"] == 0.25
    assert "start_up_s" not in Estimator(without).settings
    weighed = []
    for est in (Estimator(with_start), Estimator(with_start, start_up_s=0.0)):
        p = []
        for k in range(20):
            est.schedule(0.4, 20000.0)
            est.update(z[k])
            est.propagate(u[k])
            p.append(np.array(est.probabilities))
        weighed.append(p)
    assert all(np.array_equal(weighed[0][k], weighed[0][0]) for k in range(16))     # the start-up
    assert not np.array_equal(weighed[0][16], weighed[0][15])
    assert not np.array_equal(weighed[1][1], weighed[1][0])                          # the override: none
    replay = InProcessExecutive(with_start)   # the daemon's executive: the same start-up
    for k in range(20):
        status = replay.on_sensor(k, z[k], air_data=(0.4, 20000.0))
        assert replay.on_command(k, u[k]) == "used"
        assert np.array_equal(np.array(status.probabilities), weighed[0][k]), k
    # written by the binding: 3 with the start-up, byte for byte the crafted file; 2 without
    for start, version in ((0.25, 3), (0.0, 2)):
        out = tmp_path / f"saved{version}.f16sched"
        core.save_schedule([0.4, 0.6], [20000.0], [(0, 0, b0, [1.0] * 13), (1, 0, b1, [2.0] * 13)], primary=0,
                           metadata="{}", path=str(out), start_up_s=start)
        assert struct.unpack(">I", out.read_bytes()[8:12])[0] == version
        assert out.read_bytes() == (tmp_path / f"v{version}.f16sched").read_bytes()
    with pytest.raises(ValueError, match=r"start_up_s = -1 must be in \[0, 3600\] s"):
        core.save_schedule([0.4, 0.6], [20000.0], [(0, 0, b0, [1.0] * 13)], primary=0, path=str(tmp_path / "x"),
                           start_up_s=-1.0)
