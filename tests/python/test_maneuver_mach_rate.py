"""``maneuver_mach_per_s`` (``--maneuver-mach-rate``): the Mach rate above which the air-data
gates of the climb reference (cpp/f16mmae/climb_reference.h) and of the maneuver dwell
(cpp/f16mmae/maneuver_dwell.h) call the aircraft maneuvering, on the synthetic bank of
test_core_hierarchical:

* with the air data's Mach changing at 0.002 per s, the climb reference is in force frame by
  frame exactly where an independent recomputation of the gate (two first-order low-passes,
  1 s and 5 s; test_core_climb_reference) with the given rate says: open at the default 0.001,
  never at 0.003, where the bank is the one without the climb reference, bit for bit;
* the maneuver dwell's gate follows the same recomputation;
* a rate that is not positive is refused by name;
* mmae-daemon takes it as ``--maneuver-mach-rate`` (``daemon_flags`` passes it on): its ready
  line names the gate the core holds, out-of-range values are refused naming the flag; and a
  lockstep flight over memq:// against the executive with the option gives the in-process
  probabilities, which differ from the default gate's.
"""
from __future__ import annotations

import subprocess

import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.loop.flight import fly as fly_closed_loop

from daemon_support import ready_line
from test_core_climb_reference import BASE, CLIMB, GAIN, _gate, _run
from test_core_hierarchical import ACT, RATE_HZ, SEN, fly, small  # noqa: F401  (fixture)
from test_hil_memq import _lockstep_equals_in_process, _scenario


def _speed_change(n: int) -> np.ndarray:
    """Level at Mach 0.4, 20,000 ft for 5 s, then accelerating at 0.002 Mach/s."""
    t = np.arange(n) / RATE_HZ
    return np.column_stack([0.4 + np.clip(t - 5.0, 0.0, None) * 0.002, np.full(n, 20000.0)])


@pytest.mark.parametrize("rate", [None, 0.0015, 0.003])
def test_the_climb_reference_follows_the_given_mach_rate(small, rate):
    pl, mb = small
    n = 1200
    zs, us = fly(pl, ACT, SEN, mb, [], n, seed=5)
    air = _speed_change(n)
    gate = _gate(air, 0.0, mach_per_s=0.001 if rate is None else rate)
    assert (gate.sum() > 200) == (rate != 0.003)          # 0.002 per s: above 0.001 and 0.0015, below 0.003
    opts = dict(adapt_turbulence=True, adapt_reference=BASE, adapt_gain=GAIN)
    given = {} if rate is None else {"maneuver_mach_per_s": rate}
    got = _run(core.HierarchicalBank(mb, adapt_reference_climb=CLIMB, **given, **opts), zs, us, air)
    for i, (s, rho, _) in enumerate(got):
        rho0 = CLIMB if gate[i] else BASE
        assert s == pytest.approx(min(100.0, max(1.0, 1.0 + GAIN * (rho - rho0))), rel=1e-12), i
    if rate == 0.003:
        plain = _run(core.HierarchicalBank(mb, **opts), zs, us, air)
        for (s0, r0, p0), (s1, r1, p1) in zip(plain, got):
            assert s0 == s1 and r0 == r1 and np.array_equal(p0, p1)


@pytest.fixture(scope="module")
def nominal():
    """The shipped nominal bank (it measures AZ, which the maneuver dwell's load-factor gate reads)."""
    _, _, bank = load_bank("tuned")
    return bank


@pytest.mark.parametrize("rate", [0.0015, 0.003])
def test_the_maneuver_dwell_gate_follows_the_given_mach_rate(nominal, rate):
    n = 1200
    air = _speed_change(n)
    # the readings at the trim (no load factor off it) and a load-factor gate no flight reaches:
    # only the air data's rate can open the gate
    bank = core.HierarchicalBank(nominal, maneuver_dwell_s=1.0, maneuver_dwell_g=10.0, maneuver_mach_per_s=rate)
    gate = _gate(air, 0.0, mach_per_s=rate)
    assert (gate.sum() > 200) == (rate < 0.002)
    seen = []
    for a in air:
        bank.schedule(*a)
        bank.step(np.asarray(nominal.z_trim), np.asarray(nominal.u_trim))
        seen.append(bool(bank.maneuvering))
    np.testing.assert_array_equal(np.array(seen), gate)


@pytest.mark.parametrize("rate", [0.0, -0.001])
def test_a_mach_rate_that_is_not_positive_is_refused(nominal, rate):
    with pytest.raises(ValueError, match="mach_per_s must be > 0"):
        core.HierarchicalBank(nominal, maneuver_dwell_s=1.0, maneuver_mach_per_s=rate)


def test_the_daemon_takes_the_mach_rate_and_names_the_gate_in_force(nominal):
    options = {"adapt_turbulence": True, "adapt_reference_climb": 0.6, "maneuver_dwell_s": 1.25,
               "maneuver_mach_per_s": 0.003}
    flags = daemon_flags(options)
    i = flags.index("--maneuver-mach-rate")
    assert float(flags[i + 1]) == 0.003
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, *flags)
    assert "maneuver dwell 1.25 s held 0 s, Mach-rate gate 0.003/s" in ready, ready
    without = [f for f in flags if f not in ("--maneuver-mach-rate", flags[i + 1])]
    ready = ready_line("--bank", bank, *without)
    assert "maneuver dwell 1.25 s held 0 s" in ready and "Mach-rate" not in ready, ready
    for bad in ("0", "-0.001", "2", "nan"):
        r = subprocess.run([daemon, "--bank", bank, "--maneuver-mach-rate", bad], capture_output=True, text=True,
                           timeout=20)
        assert r.returncode == 2, bad
        assert f"--maneuver-mach-rate must be a Mach rate per second, > 0 and <= 1, got '{bad}'" in r.stderr + r.stdout


def test_lockstep_with_the_mach_rate_reproduces_the_in_process_run(nominal):
    # the load-factor gate out of reach and a Mach-rate gate light turbulence crosses: the
    # maneuver reference in force follows the air data's Mach rate alone, frame by frame
    options = dict(adapt_turbulence=True, maneuver_dwell_s=0.75, maneuver_dwell_g=10.0, maneuver_reference=0.3,
                   maneuver_mach_per_s=0.0001)
    scenario = _scenario([("LS", 0.5)], duration_s=3.0)
    _, local_run = _lockstep_equals_in_process(nominal, scenario, "MMR_", options)
    default_gate = fly_closed_loop(scenario, nominal,
                                   estimator_options={k: v for k, v in options.items() if k != "maneuver_mach_per_s"})
    # the option is in force: the flight is not the default gate's
    assert not np.array_equal(np.nan_to_num(local_run.probabilities), np.nan_to_num(default_gate.probabilities))
