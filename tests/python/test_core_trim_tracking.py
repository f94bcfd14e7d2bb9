"""Trim in force and trim tracking in core.HierarchicalBank (cpp/f16mmae/trim_tracker.h), on the
synthetic banks of test_core_hierarchical and on the shipped F-16 bank:

* off (the default, and time constant 0) is the bank without a tracker, bit for bit;
* set_trim_offset(du, dz): the bank subtracts u_trim + du and z_trim + dz -- the same
  probabilities as a plain FilterBank fed the signals about the shifted trim;
* tracking is the first-order low-pass of the header, recomputed here independently;
* the freeze rule: a failure hypothesis above the freeze probability holds the estimate (and
  for hold_s after), a declared failure holds it, reset() returns to the design trim;
* bad options are refused by name.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from test_core_hierarchical import ACT, RATE_HZ, SEN, fly, small  # noqa: F401  (fixture)


def _frames(pl, mb, n, seed, failures=()):
    return fly(pl, ACT, SEN, mb, list(failures), n, seed=seed)


def test_off_is_the_bank_without_a_tracker_bit_for_bit(small):
    pl, mb = small
    zs, us = _frames(pl, mb, 400, seed=7, failures=[("Z2", 100, 10**9)])
    ref, off = core.HierarchicalBank(mb), core.HierarchicalBank(mb, trim_time_constant_s=0.0)
    for z, u in zip(zs, us):
        assert ref.step(z, u) == off.step(z, u)
        assert np.array_equal(ref.probabilities, off.probabilities)
        assert np.array_equal(ref.z_hat, off.z_hat)
    du, dz = off.trim_offset
    assert not du.any() and not dz.any() and off.trim_frozen_frames == 0


def test_the_trim_in_force_is_the_bank_trim_plus_the_offset(small):
    pl, mb = small
    du, dz = np.array([0.03, -0.01]), np.array([0.2, -0.05, 0.1])
    hb = core.HierarchicalBank(mb)
    hb.set_trim_offset(du, dz)
    level0 = [dict(zip(("phi", "bd", "h", "k", "a"), (m.phi, m.bd, m.h, m.k, m.a))) for m in mb.hypotheses[:6]]
    plain = core.FilterBank([core.FilterModel(**m) for m in level0], h_output=mb.h_output)
    zs, us = _frames(pl, mb, 100, seed=4)
    for z, u in zip(zs, us):
        hb.step(z + dz, u + du)   # the aircraft flies about the shifted trim
        plain.step(z - mb.z_trim, u - mb.u_trim)
        np.testing.assert_allclose(hb.probabilities, plain.probabilities, atol=1e-12)
        np.testing.assert_allclose(hb.z_hat, plain.z_hat + mb.z_trim + dz, atol=1e-12)
    np.testing.assert_array_equal(hb.trim_offset[0], du)
    np.testing.assert_array_equal(hb.trim_offset[1], dz)
    hb.reset()
    assert not hb.trim_offset[1].any()
    with pytest.raises(ValueError, match=r"dz must have shape \(3,\)"):
        hb.set_trim_offset(du, dz[:2])


def test_tracking_is_the_low_pass_of_the_header(small):
    pl, mb = small
    tau = 0.5
    hb = core.HierarchicalBank(mb, trim_time_constant_s=tau, trim_freeze_probability=1.0)
    offset_z, offset_u = np.array([0.02, -0.01, 0.015]), np.array([0.01, 0.005])
    zs, us = _frames(pl, mb, 300, seed=5)
    a = 1.0 - math.exp(-1.0 / (RATE_HZ * tau))
    dz, du = np.zeros(3), np.zeros(2)
    for z, u in zip(zs, us):
        z, u = z + offset_z, u + offset_u
        hb.update(z)
        assert hb.declared == "NONE"  # freeze_probability 1: only a declaration would freeze it
        dz = dz + a * ((z - mb.z_trim) - dz)
        np.testing.assert_allclose(hb.trim_offset[1], dz, rtol=0, atol=1e-12)
        hb.propagate(u)
        du = du + a * ((u - mb.u_trim) - du)
        np.testing.assert_allclose(hb.trim_offset[0], du, rtol=0, atol=1e-12)
    assert not hb.trim_frozen and hb.trim_frozen_frames == 0


def test_a_rising_failure_hypothesis_freezes_the_estimate_for_the_hold(small):
    pl, mb = small
    # every failure hypothesis sits at p_min = 0.001 at least: a freeze probability below that
    # freezes every frame
    hb = core.HierarchicalBank(mb, trim_time_constant_s=0.5, trim_freeze_probability=1e-4)
    for z, u in zip(*_frames(pl, mb, 50, seed=6)):
        hb.step(z + 0.5, u)
    assert hb.trim_frozen and hb.trim_frozen_frames == 50 and not hb.trim_offset[1].any()
    # a failure that is declared holds it from its declaration on
    hb = core.HierarchicalBank(mb, trim_time_constant_s=50.0)
    zs, us = _frames(pl, mb, 400, seed=3, failures=[("Z2", 64, 10**9)])
    frozen = []
    for z, u in zip(zs, us):
        hb.step(z, u)
        frozen.append(hb.trim_frozen)
    first_decl = hb.declarations[0]["frame"]
    assert hb.declared != "NONE" and all(frozen[first_decl:])
    before = hb.trim_offset[1].copy()
    # a frozen estimate does not move whatever the signals do
    hb.step(zs[-1] + 10.0, us[-1])
    np.testing.assert_array_equal(hb.trim_offset[1], before)
    hb.reset()
    assert not hb.trim_frozen and hb.trim_frozen_frames == 0 and not hb.trim_offset[1].any()


def test_the_hold_lasts_hold_s_after_the_last_freezing_frame(small):
    pl, mb = small
    rate = RATE_HZ
    hb = core.HierarchicalBank(mb, trim_time_constant_s=0.5, trim_freeze_probability=0.5, trim_hold_s=0.25)
    zs, us = _frames(pl, mb, 300, seed=8)
    freezing, frozen = [], []
    for z, u in zip(zs, us):
        hb.step(z, u)
        p = hb.probabilities
        freezing.append(bool(max(p[1:]) > 0.5) or hb.declared != "NONE" or hb.level != 0)
        frozen.append(hb.trim_frozen)
    hold = round(0.25 * rate)
    expected = [any(freezing[max(0, i - hold):i + 1]) for i in range(len(freezing))]
    assert frozen == expected


def test_bad_trim_options_are_refused_by_name(small):
    _, mb = small
    with pytest.raises(ValueError, match="time_constant_s must be >= 0"):
        core.HierarchicalBank(mb, trim_time_constant_s=-1.0)
    with pytest.raises(ValueError, match=r"freeze_probability must lie in \(0, 1\]"):
        core.HierarchicalBank(mb, trim_time_constant_s=30.0, trim_freeze_probability=0.0)
    with pytest.raises(ValueError, match="hold_s must be >= 0"):
        core.HierarchicalBank(mb, trim_time_constant_s=30.0, trim_hold_s=math.nan)


def test_the_f16_bank_tracks_a_constant_trim_error_away():
    """The fixed-size F-16 bank fed its own trim shifted by a constant AOA and stabilator error
    (a heavier aircraft): tracking moves the trim in force onto it."""
    bank = load_bank("tuned")[2]
    dz_true = np.zeros(7)
    dz_true[1] = math.radians(0.05)
    du_true = np.array([-0.001, -0.001, 0.0, 0.0, 0.0])
    hb = core.HierarchicalBank(bank, p_min=1e-9, trim_time_constant_s=2.0)
    assert hb.fixed_size
    z, u = np.array(bank.z_trim) + dz_true, np.array(bank.u_trim) + du_true
    for _ in range(64 * 20):
        hb.step(z, u)
    assert hb.declared == "NONE"
    np.testing.assert_allclose(hb.trim_offset[1], dz_true, atol=1e-4 * math.radians(1))
    np.testing.assert_allclose(hb.trim_offset[0], du_true, atol=1e-6)


def test_steady_tracking_moves_only_the_named_measurements_and_every_input():
    """Steady tracking (trim_steady_g > 0) on the F-16 bank fed its trim shifted by a constant
    AOA, yaw-rate and stabilator error in 1-g flight: the AOA and the input offsets are tracked
    (the low-pass of the header), the yaw rate's is not."""
    bank = load_bank("tuned")[2]
    names = list(bank.measurement_names)
    dz_true = np.zeros(7)
    dz_true[names.index("AOA")] = math.radians(0.05)
    dz_true[names.index("YAW")] = math.radians(0.02)
    du_true = np.array([-0.001, -0.001, 0.0, 0.0, 0.0])
    hb = core.HierarchicalBank(bank, p_min=1e-9, trim_time_constant_s=2.0, trim_steady_g=0.05,
                               trim_freeze_probability=1.0)
    z, u = np.array(bank.z_trim) + dz_true, np.array(bank.u_trim) + du_true
    for _ in range(64 * 20):
        hb.step(z, u)
    assert hb.declared == "NONE"
    expected = np.zeros(7)
    expected[names.index("AOA")] = dz_true[names.index("AOA")]
    np.testing.assert_allclose(hb.trim_offset[1], expected, atol=1e-4 * math.radians(1))
    assert hb.trim_offset[1][names.index("YAW")] == 0.0
    np.testing.assert_allclose(hb.trim_offset[0], du_true, atol=1e-6)
    with pytest.raises(ValueError, match="steady tracking needs the measurement 'ALPHA'; the bank's: VEL, AOA"):
        core.HierarchicalBank(bank, trim_time_constant_s=2.0, trim_steady_g=0.05, trim_steady_measurements=["ALPHA"])
    with pytest.raises(ValueError, match="steady_g must be >= 0"):
        core.HierarchicalBank(bank, trim_time_constant_s=2.0, trim_steady_g=-0.1)


def test_steady_tracking_freezes_while_the_estimated_load_factor_is_off_the_trim():
    """A slow 0.1-g load-factor swing (a gentle pull and push) on the F-16 bank's trim: the
    estimate is frozen on exactly the frames where the bank's estimated load factor (z_hat's AZ
    about the trim, read here after each update) was beyond trim_steady_g, or its roll rate
    beyond the default 5 deg/s, within the last trim_hold_s (no air data: the air-data gate stays
    open), or a failure was declared (the only other freezing frames with
    trim_freeze_probability 1); between them AOA's offset moves, and never while frozen."""
    bank = load_bank("tuned")[2]
    names = list(bank.measurement_names)
    az, aoa, rol = names.index("AZ"), names.index("AOA"), names.index("ROL")
    steady_g, hold_s = 0.03, 0.5
    hb = core.HierarchicalBank(bank, p_min=1e-9, trim_time_constant_s=5.0, trim_steady_g=steady_g,
                               trim_hold_s=hold_s, trim_freeze_probability=1.0)
    z0, u0 = np.array(bank.z_trim), np.array(bank.u_trim)
    n = 64 * 12
    freezing, frozen, moved = [], [], []
    for i in range(n):
        z = z0.copy()
        z[az] += 0.1 * math.sin(2 * math.pi * 0.1 * i / 64.0)
        z[aoa] += math.radians(0.05)
        before = hb.trim_offset[1][aoa]
        hb.update(z)
        dn = hb.z_hat[az] - z0[az]      # the AZ offset is never tracked: dz(AZ) = 0
        p_hat = hb.z_hat[rol] - z0[rol]
        freezing.append(abs(dn) > steady_g or abs(p_hat) > math.radians(5.0) or hb.declared != "NONE"
                        or hb.level != 0)
        frozen.append(hb.trim_frozen)
        moved.append(hb.trim_offset[1][aoa] != before)
        hb.propagate(u0)
    hold = round(hold_s * 64)
    expected = [any(freezing[max(0, i - hold):i + 1]) for i in range(n)]
    assert frozen == expected
    assert 0 < sum(frozen) < n                     # both kinds of frames occur
    assert all(m != f for m, f in zip(moved, frozen))


def test_steady_tracking_freezes_while_the_air_data_climb_or_accelerate():
    """The air-data gate: the F-16 bank at its trim handed air data that hold, then climb at
    50 ft/s, then hold, then speed up at 0.005 Mach/s. The climb and Mach rates are recomputed
    here from the header's two low-passes (1 s and 5 s, started at the first sample); the
    estimate is frozen on exactly the frames where one was beyond its limit within the last
    trim_hold_s (or a failure was declared), and moves on the others."""
    bank = load_bank("tuned")[2]
    aoa = list(bank.measurement_names).index("AOA")
    hold_s = 1.0
    hb = core.HierarchicalBank(bank, p_min=1e-9, trim_time_constant_s=5.0, trim_steady_g=0.5,
                               trim_hold_s=hold_s, trim_freeze_probability=1.0)
    z0, u0 = np.array(bank.z_trim), np.array(bank.u_trim)
    z0[aoa] += math.radians(0.05)
    rate = 64.0
    a1, a5 = 1.0 - math.exp(-1.0 / rate), 1.0 - math.exp(-1.0 / (5.0 * rate))
    n = int(40 * rate)
    h, m = 20000.0, 0.4
    freezing, frozen, moved = [], [], []
    lp = None
    for i in range(n):
        t = i / rate
        h += 50.0 / rate if 5.0 <= t < 15.0 else 0.0
        m += 0.005 / rate if 25.0 <= t < 30.0 else 0.0
        if lp is None:
            lp = [h, h, m, m]
        else:
            lp = [lp[0] + a1 * (h - lp[0]), lp[1] + a5 * (h - lp[1]), lp[2] + a1 * (m - lp[2]), lp[3] + a5 * (m - lp[3])]
        climb, mach_rate = (lp[0] - lp[1]) / 4.0, (lp[2] - lp[3]) / 4.0
        before = hb.trim_offset[1][aoa]
        hb.schedule(m, h)
        hb.update(z0)
        freezing.append(abs(climb) > 5.0 or abs(mach_rate) > 0.001 or hb.declared != "NONE" or hb.level != 0)
        frozen.append(hb.trim_frozen)
        moved.append(hb.trim_offset[1][aoa] != before)
        hb.propagate(u0)
    hold = round(hold_s * rate)
    expected = [any(freezing[max(0, i - hold):i + 1]) for i in range(n)]
    assert frozen == expected
    assert any(frozen[int(6 * rate):int(15 * rate)]) and any(frozen[int(26 * rate):int(30 * rate)])
    assert not any(frozen[:int(5 * rate)])
    assert all(mv != f for mv, f in zip(moved, frozen))
