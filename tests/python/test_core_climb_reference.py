"""The turbulence adaptation's climb reference (cpp/f16mmae/climb_reference.h) in
core.HierarchicalBank, on the synthetic bank of test_core_hierarchical:

* given but never climbing, the bank is the one without it, bit for bit;
* while the air data climb (or change Mach) and for the hold after, the reference in force is
  the climb reference: the scale s follows clamp(1 + gain (rho - rho_0), s_min, s_max) with the
  rho_0 that an independent recomputation of the air-data rate gate (two first-order
  low-passes, 1 s and 5 s) gives, frame by frame;
* with a dwell of its own, a level-0 declaration while the gate is open needs that many
  consecutive frames above the threshold, elsewhere the declarer's (an independent count over
  the bank's own probabilities);
* reset() returns to the reference without it; bad options are refused by name.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae import core
from test_core_hierarchical import ACT, RATE_HZ, SEN, fly, small  # noqa: F401  (fixture)

GAIN = 20.0           # the adaptation's default gain, passed explicitly below
BASE, CLIMB = 0.0, 100.0   # s = 1 + 20 rho away from a climb, exactly 1 in one (rho < 100)


def _gate(air: np.ndarray, hold_s: float, climb_ft_s: float = 5.0, mach_per_s: float = 0.001) -> np.ndarray:
    """The climbing flag of every frame, recomputed from the header's rule."""
    g1, g5 = 1 - math.exp(-1 / (RATE_HZ * 1.0)), 1 - math.exp(-1 / (RATE_HZ * 5.0))
    hold = round(hold_s * RATE_HZ)
    out, held = [], 0
    h1 = h5 = m1 = m5 = None
    for mach, alt in air:
        if h1 is None:
            h1 = h5 = alt
            m1 = m5 = mach
        else:
            h1 += g1 * (alt - h1)
            h5 += g5 * (alt - h5)
            m1 += g1 * (mach - m1)
            m5 += g5 * (mach - m5)
        climbing = abs((h1 - h5) / 4.0) > climb_ft_s or abs((m1 - m5) / 4.0) > mach_per_s
        held = hold + 1 if climbing else max(0, held - 1)
        out.append(held > 0)
    return np.array(out)


def _air(n: int) -> np.ndarray:
    """Level at 20,000 ft for 5 s, a 2,000-ft/min climb for 5 s, level again (Mach 0.4)."""
    t = np.arange(n) / RATE_HZ
    alt = 20000.0 + np.clip(t - 5.0, 0.0, 5.0) * 2000.0 / 60.0
    return np.column_stack([np.full(n, 0.4), alt])


def _run(bank, zs, us, air):
    out = []
    for z, u, a in zip(zs, us, air):
        bank.schedule(*a)
        bank.step(z, u)
        out.append((bank.turbulence_scale, bank.turbulence_power_ratio, np.array(bank.probabilities)))
    return out


def test_never_climbing_is_the_bank_without_it_bit_for_bit(small):
    pl, mb = small
    zs, us = fly(pl, ACT, SEN, mb, [("Z2", 300, 10**9)], 600, seed=3)
    level = np.column_stack([np.full(600, 0.4), np.full(600, 20000.0)])
    opts = dict(adapt_turbulence=True, adapt_reference=0.5, adapt_gain=GAIN)
    ref = _run(core.HierarchicalBank(mb, **opts), zs, us, level)
    got = _run(core.HierarchicalBank(mb, adapt_reference_climb=0.1, adapt_reference_climb_hold_s=3.0, **opts),
               zs, us, level)
    for (s0, r0, p0), (s1, r1, p1) in zip(ref, got):
        assert s0 == s1 and r0 == r1 and np.array_equal(p0, p1)


@pytest.mark.parametrize("hold_s", [0.0, 3.0])
def test_the_climb_reference_is_in_force_while_the_air_data_climb_and_its_hold(small, hold_s):
    pl, mb = small
    n = 1800   # the gate closes about 9 s after a 2,000-ft/min climb ends (the 5-s low-pass)
    zs, us = fly(pl, ACT, SEN, mb, [], n, seed=5)
    air = _air(n)
    gate = _gate(air, hold_s)
    assert gate[:320].sum() == 0 and gate.sum() > 200   # level, then a climb the gate sees
    if hold_s:
        assert gate[int(11 * RATE_HZ)]                   # 1 s after the climb: still held
    bank = core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference=BASE, adapt_gain=GAIN,
                                 adapt_reference_climb=CLIMB, adapt_reference_climb_hold_s=hold_s)
    got = _run(bank, zs, us, air)
    for i, (s, rho, _) in enumerate(got):
        rho0 = CLIMB if gate[i] else BASE
        assert s == pytest.approx(min(100.0, max(1.0, 1.0 + GAIN * (rho - rho0))), rel=1e-12), i
    assert not gate[-1]
    plain = _run(core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference=BASE, adapt_gain=GAIN), zs, us, air)
    assert sum(a[0] != b[0] for a, b in zip(plain, got)) >= 200   # the climb's frames are tempered otherwise
    bank.reset()
    assert bank.turbulence_scale == 1.0   # rho = rho_0 = BASE: s = clamp(1)


def _first_declaration(probabilities, threshold: float, need) -> tuple[int, int]:
    """(frame, hypothesis) of the first declaration of a hypothesis other than NONE by the rule
    of declarer.h with need(i) consecutive frames above the threshold on frame i."""
    candidate, count = -1, 0
    for i, p in enumerate(probabilities):
        above = next((k for k, pk in enumerate(p) if pk > threshold), -1)
        if above < 0:
            candidate, count = -1, 0
            continue
        if above != candidate:
            candidate, count = above, 0
        if count < need(i):
            count += 1
        if count >= need(i) and candidate != 0:
            return i, candidate
    return -1, -1


@pytest.mark.parametrize("climb_dwell_s", [0.0, 2.0])
def test_the_climb_dwell_is_in_force_while_the_gate_is_open(small, climb_dwell_s):
    pl, mb = small
    n = 1800
    fail = 480   # inside the climb (5-10 s) and the gate
    zs, us = fly(pl, ACT, SEN, mb, [("Z2", fail, 10**9)], n, seed=5)
    air = _air(n)
    gate = _gate(air, 3.0)
    assert gate[fail:fail + 200].all()
    opts = dict(adapt_turbulence=True, adapt_reference=BASE, adapt_gain=GAIN, adapt_reference_climb=BASE,
                adapt_reference_climb_hold_s=3.0, adapt_reference_climb_dwell_s=climb_dwell_s)
    bank = core.HierarchicalBank(mb, **opts)
    # the level-0 probabilities up to the declaration: a bank that declares nothing (the
    # declarer does not touch them before its first switch)
    watcher = core.HierarchicalBank(mb, threshold=1 - 1e-15, **opts)
    probabilities = []
    for z, u, a in zip(zs, us, air):
        for b in (bank, watcher):
            b.schedule(*a)
            b.step(z, u)
        probabilities.append(np.array(watcher.probabilities))
    assert watcher.declarations == []
    base = round(0.25 * RATE_HZ)
    climb = round(climb_dwell_s * RATE_HZ) if climb_dwell_s else base
    frame, k = _first_declaration(probabilities, 0.9, lambda i: climb if gate[i] else base)
    first = bank.declarations[0]
    assert ("NONE", "U1", "U2", "Z1", "Z2", "Z3")[k] == "Z2"   # the level-0 order
    assert (first["frame"], first["hypothesis"], first["level"]) == (frame, "Z2", 0)
    if climb_dwell_s:
        assert frame >= fail + climb - 1   # climb frames above the threshold, the failure's first
        plain = core.HierarchicalBank(mb, **{**opts, "adapt_reference_climb_dwell_s": 0.0})
        for z, u, a in zip(zs, us, air):
            plain.schedule(*a)
            plain.step(z, u)
        assert plain.declarations[0]["frame"] < frame   # the declarer's dwell alone declares sooner


def test_bad_climb_reference_options_are_refused_by_name(small):
    _, mb = small
    with pytest.raises(ValueError, match=r"adapt_reference_climb must be a power ratio in \[0, 100\], got -1"):
        core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference_climb=-1.0)
    with pytest.raises(ValueError, match=r"adapt_reference_climb_hold_s must be in \[0, 3600\] s"):
        core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference_climb=0.6, adapt_reference_climb_hold_s=-2.0)
    with pytest.raises(ValueError, match=r"adapt_reference_climb_dwell_s must be in \[0, 60"):
        core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference_climb=0.6, adapt_reference_climb_dwell_s=61.0)
