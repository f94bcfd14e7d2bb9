"""``maneuver_mach_per_s`` (``--maneuver-mach-rate``) and ``maneuver_climb_ft_s``
(``--maneuver-climb-rate``): the Mach rate and the climb rate above which the air-data gates of
the climb reference (cpp/f16mmae/climb_reference.h) and of the maneuver dwell
(cpp/f16mmae/maneuver_dwell.h) call the aircraft maneuvering, on the synthetic bank of
test_core_hierarchical:

* with the air data's Mach changing at 0.002 per s, the climb reference is in force frame by
  frame exactly where an independent recomputation of the gate (two first-order low-passes,
  1 s and 5 s; test_core_climb_reference) with the given rate says: open at the default 0.001,
  never at 0.003, where the bank is the one without the climb reference, bit for bit;
* with the air data climbing at 2,000 ft/min (33 ft/s) the same holds of the climb rate: open
  at the default 5 ft/s and at 20, never at 40;
* the maneuver dwell's gate follows the same recomputation, for either rate;
* a rate that is not positive is refused by name;
* mmae-daemon takes them as ``--maneuver-mach-rate`` and ``--maneuver-climb-rate``
  (``daemon_flags`` passes them on): its ready line names the gates the core holds,
  out-of-range values are refused naming the flag; and a lockstep flight over memq:// against
  the executive with the Mach-rate option gives the in-process probabilities, which differ
  from the default gate's;
* ``maneuver_rate_gust_scaled``: the rate thresholds times sqrt(s_b) (the node's reference);
  ``maneuver_gates_calm_scaled``: all three thresholds, the load factor's too, times sqrt(s_c),
  s_c from the schedule's calm-air reference in force, each frame against a recomputation.
"""
from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.names import SENSORS
from f16mmae.truth.sensors import NOISE_SIGMA
from f16mmae.loop.flight import fly as fly_closed_loop

from daemon_support import ready_line
from test_core_climb_reference import BASE, CLIMB, GAIN, _gate, _run
from test_core_hierarchical import ACT, RATE_HZ, SEN, fly, small  # noqa: F401  (fixture)
from test_hil_memq import _lockstep_equals_in_process, _scenario


def _speed_change(n: int) -> np.ndarray:
    """Level at Mach 0.4, 20,000 ft for 5 s, then accelerating at 0.002 Mach/s."""
    t = np.arange(n) / RATE_HZ
    return np.column_stack([0.4 + np.clip(t - 5.0, 0.0, None) * 0.002, np.full(n, 20000.0)])


def _climb(n: int) -> np.ndarray:
    """Level at Mach 0.4, 20,000 ft for 5 s, then climbing at 2,000 ft/min."""
    t = np.arange(n) / RATE_HZ
    return np.column_stack([np.full(n, 0.4), 20000.0 + np.clip(t - 5.0, 0.0, None) * 2000.0 / 60.0])


# (keyword, the air data, the gate's keyword in _gate, its default, a rate it crosses, one it does not)
GATES = {"maneuver_mach_per_s": (_speed_change, "mach_per_s", 0.001, 0.0015, 0.003),   # 0.002 Mach/s
         "maneuver_climb_ft_s": (_climb, "climb_ft_s", 5.0, 20.0, 40.0)}              # 33 ft/s


@pytest.mark.parametrize("keyword", list(GATES))
@pytest.mark.parametrize("which", ["default", "crossed", "not crossed"])
def test_the_climb_reference_follows_the_given_rate(small, keyword, which):
    air_of, gate_keyword, default, crossed, above = GATES[keyword]
    rate = {"default": None, "crossed": crossed, "not crossed": above}[which]
    pl, mb = small
    n = 1200
    zs, us = fly(pl, ACT, SEN, mb, [], n, seed=5)
    air = air_of(n)
    gate = _gate(air, 0.0, **{gate_keyword: default if rate is None else rate})
    assert (gate.sum() > 200) == (rate != above)
    opts = dict(adapt_turbulence=True, adapt_reference=BASE, adapt_gain=GAIN)
    given = {} if rate is None else {keyword: rate}
    got = _run(core.HierarchicalBank(mb, adapt_reference_climb=CLIMB, **given, **opts), zs, us, air)
    for i, (s, rho, _) in enumerate(got):
        rho0 = CLIMB if gate[i] else BASE
        assert s == pytest.approx(min(100.0, max(1.0, 1.0 + GAIN * (rho - rho0))), rel=1e-12), i
    if rate == above:   # never open: the bank without the climb reference, bit for bit
        plain = _run(core.HierarchicalBank(mb, **opts), zs, us, air)
        for (s0, r0, p0), (s1, r1, p1) in zip(plain, got):
            assert s0 == s1 and r0 == r1 and np.array_equal(p0, p1)


@pytest.fixture(scope="module")
def nominal():
    """The shipped nominal bank (it measures AZ, which the maneuver dwell's load-factor gate reads)."""
    _, _, bank = load_bank("tuned")
    return bank


@pytest.mark.parametrize("keyword,rate", [("maneuver_mach_per_s", 0.0015), ("maneuver_mach_per_s", 0.003),
                                          ("maneuver_climb_ft_s", 20.0), ("maneuver_climb_ft_s", 40.0)])
def test_the_maneuver_dwell_gate_follows_the_given_rate(nominal, keyword, rate):
    n = 1200
    mach = keyword == "maneuver_mach_per_s"
    air = _speed_change(n) if mach else _climb(n)
    # the readings at the trim (no load factor off it) and a load-factor gate no flight reaches:
    # only the air data's rate can open the gate
    bank = core.HierarchicalBank(nominal, maneuver_dwell_s=1.0, maneuver_dwell_g=10.0, **{keyword: rate})
    gate = _gate(air, 0.0, mach_per_s=rate) if mach else _gate(air, 0.0, climb_ft_s=rate)
    assert (gate.sum() > 200) == (rate in (0.0015, 20.0))
    seen = []
    for a in air:
        bank.schedule(*a)
        bank.step(np.asarray(nominal.z_trim), np.asarray(nominal.u_trim))
        seen.append(bool(bank.maneuvering))
    np.testing.assert_array_equal(np.array(seen), gate)


@pytest.mark.parametrize("keyword", ["maneuver_mach_per_s", "maneuver_climb_ft_s"])
@pytest.mark.parametrize("rate", [0.0, -0.001])
def test_a_rate_that_is_not_positive_is_refused(nominal, keyword, rate):
    with pytest.raises(ValueError, match="climb_ft_s and mach_per_s must be > 0"):
        core.HierarchicalBank(nominal, maneuver_dwell_s=1.0, **{keyword: rate})


# flag, keyword, value, what the ready line says of it, out-of-range values, the refusal's range
DAEMON_GATES = {
    "--maneuver-mach-rate": ("maneuver_mach_per_s", 0.003, "Mach-rate gate 0.003/s", ("0", "-0.001", "2", "nan"),
                             "a Mach rate per second, > 0 and <= 1"),
    "--maneuver-climb-rate": ("maneuver_climb_ft_s", 20.0, "climb-rate gate 20 ft/s", ("0", "-5", "1001", "nan"),
                              "a climb rate in ft/s, > 0 and <= 1000"),
}


@pytest.mark.parametrize("flag", list(DAEMON_GATES))
def test_the_daemon_takes_the_rate_and_names_the_gate_in_force(nominal, flag):
    keyword, value, said, bad_values, valid = DAEMON_GATES[flag]
    options = {"adapt_turbulence": True, "adapt_reference_climb": 0.6, "maneuver_dwell_s": 1.25, keyword: value}
    flags = daemon_flags(options)
    i = flags.index(flag)
    assert float(flags[i + 1]) == value
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, *flags)
    assert f"maneuver dwell 1.25 s held 0 s, {said}" in ready, ready
    without = [f for f in flags if f not in (flag, flags[i + 1])]
    ready = ready_line("--bank", bank, *without)
    assert "maneuver dwell 1.25 s held 0 s" in ready and said.split(" gate")[0] not in ready, ready
    for bad in bad_values:
        r = subprocess.run([daemon, "--bank", bank, flag, bad], capture_output=True, text=True, timeout=20)
        assert r.returncode == 2, bad
        assert f"{flag} must be {valid}, got '{bad}'" in r.stderr + r.stdout


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


def _scaled_gate(air: np.ndarray, climb_ft_s: float, scale: np.ndarray) -> np.ndarray:
    """The gate of every frame with frame i's thresholds times scale[i] (no hold), recomputed
    from air_data_rates.h's rule: two first-order low-passes, 1 s and 5 s."""
    g1, g5 = 1 - math.exp(-1 / (RATE_HZ * 1.0)), 1 - math.exp(-1 / (RATE_HZ * 5.0))
    out, h1, h5, m1, m5 = [], None, None, None, None
    for (mach, alt), c in zip(air, scale):
        if h1 is None:
            h1, h5, m1, m5 = alt, alt, mach, mach
        else:
            h1 += g1 * (alt - h1)
            h5 += g5 * (alt - h5)
            m1 += g1 * (mach - m1)
            m5 += g5 * (mach - m5)
        out.append(abs((h1 - h5) / 4.0) > c * climb_ft_s or abs((m1 - m5) / 4.0) > c * 0.001)
    return np.array(out)


def _fast_climb(n: int) -> np.ndarray:
    """Level at Mach 0.4, 20,000 ft for 5 s, then climbing at 6,000 ft/min (100 ft/s)."""
    t = np.arange(n) / RATE_HZ
    return np.column_stack([np.full(n, 0.4), 20000.0 + np.clip(t - 5.0, 0.0, None) * 100.0])


def _s_b(rho: float) -> float:
    return min(100.0, max(1.0, 1.0 + GAIN * (rho - BASE)))


def test_gust_scaled_climb_reference_gate_multiplies_its_thresholds_by_sqrt_s_b(small):
    # s_b = clamp(1 + 20 rho) at the base reference whatever reference is in force: the climb
    # reference (100) sets s to 1 while the gate is open, s_b still reads the air
    pl, mb = small
    n = 1200
    zs, us = fly(pl, ACT, SEN, mb, [], n, seed=5)
    air = _fast_climb(n)
    opts = dict(adapt_turbulence=True, adapt_reference=BASE, adapt_gain=GAIN, adapt_reference_climb=CLIMB,
                maneuver_climb_ft_s=10.0)
    got = _run(core.HierarchicalBank(mb, maneuver_rate_gust_scaled=True, **opts), zs, us, air)
    rho = np.array([r for _, r, _ in got])
    # the gate reads the air data in schedule(), before the frame's update: the previous rho
    # (the base reference's at the start)
    scale = np.sqrt([_s_b(r) for r in np.concatenate([[BASE], rho[:-1]])])
    gate = _scaled_gate(air, 10.0, scale)
    plain_gate = _gate(air, 0.0, climb_ft_s=10.0)
    assert scale.max() > 2.0 and 0 < gate.sum() < plain_gate.sum() - 64   # the gusts' scale opens it later
    for i, (s, r, _) in enumerate(got):
        rho0 = CLIMB if gate[i] else BASE
        assert s == pytest.approx(min(100.0, max(1.0, 1.0 + GAIN * (r - rho0))), rel=1e-12), i
    # off, and on without the adaptation's gusts (s_b = 1), the gate is the given one
    plain = _run(core.HierarchicalBank(mb, **opts), zs, us, air)
    for i, (s, r, _) in enumerate(plain):
        rho0 = CLIMB if plain_gate[i] else BASE
        assert s == pytest.approx(min(100.0, max(1.0, 1.0 + GAIN * (r - rho0))), rel=1e-12), i


def test_gust_scaled_maneuver_dwell_gate_reads_the_latest_update(nominal):
    # readings noisier than the design's: rho well above the reference, s_b > 1; the load-factor
    # gate out of reach, so only the scaled rates open the maneuver gate
    n = 1200
    air = _fast_climb(n)
    rng = np.random.default_rng(11)
    z_trim, u_trim = np.asarray(nominal.z_trim), np.asarray(nominal.u_trim)
    zs = z_trim + rng.normal(size=(n, z_trim.size)) * 1.5 * NOISE_SIGMA   # noisier than the sensors
    bank = core.HierarchicalBank(nominal, adapt_turbulence=True, adapt_reference=BASE, adapt_gain=GAIN,
                                 maneuver_dwell_s=1.0, maneuver_dwell_g=10.0, maneuver_climb_ft_s=10.0,
                                 maneuver_rate_gust_scaled=True)
    seen, scale = [], []
    for a, z in zip(air, zs):
        bank.schedule(*a)
        bank.step(z, u_trim)
        seen.append(bool(bank.maneuvering))
        scale.append(math.sqrt(_s_b(bank.turbulence_power_ratio)))   # after the update, as the gate reads it
    scale = np.array(scale)
    assert scale[320:].min() > 2.0   # the gusts read before the climb begins
    np.testing.assert_array_equal(np.array(seen), _scaled_gate(air, 10.0, scale))
    assert 0 < np.array(seen).sum() < _gate(air, 0.0, climb_ft_s=10.0).sum() - 64   # open, a second later


def test_gust_scaled_gates_need_the_adaptation_in_mmae_daemon(nominal):
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    r = subprocess.run([daemon, "--bank", bank, "--maneuver-dwell", "1", "--maneuver-rate-gust-scaled"],
                       capture_output=True, text=True, timeout=20)
    assert r.returncode == 2 and "--maneuver-rate-gust-scaled" in r.stderr + r.stdout
    assert "--adapt-turbulence" in r.stderr + r.stdout
    flags = daemon_flags({"adapt_turbulence": True, "maneuver_dwell_s": 1.0, "maneuver_rate_gust_scaled": True})
    assert "--maneuver-rate-gust-scaled" in flags
    assert "rate gates x sqrt(s_b)" in ready_line("--bank", bank, *flags)


@pytest.fixture(scope="module")
def scheduled():
    """The shipped scheduled bank (its nodes carry the calm-air reference s_c reads)."""
    _, _, bank = load_bank("scheduled")
    return bank


def _gates_seen(bank, air: np.ndarray, zs: np.ndarray, u: np.ndarray) -> list[tuple]:
    """(maneuvering, the low-passed load factor, rho, the calm-air reference) after each frame."""
    seen = []
    for a, z in zip(air, zs):
        bank.schedule(*a)
        bank.step(z, u)
        seen.append((bool(bank.maneuvering), float(bank.maneuver_load_factor), float(bank.turbulence_power_ratio),
                     float(bank.calm_reference)))
    return seen


@pytest.mark.parametrize("calm_scaled", [False, True])
def test_calm_scaled_gates_multiply_the_load_factor_gate_by_sqrt_s_c(scheduled, calm_scaled):
    # level at the nominal point, readings noisier than the design's (rho above the calm-air
    # reference: s_c > 1) with AZ 0.1 g off the trim from 5 s: the low-passed load factor rises
    # through g = 0.05; calm-scaled, the gate opens only where it passes g sqrt(s_c), the air
    # data (level) never
    n = 960
    air = np.column_stack([np.full(n, 0.4), np.full(n, 20000.0)])
    bank = core.HierarchicalBank(scheduled, adapt_turbulence=True, adapt_gain=GAIN, maneuver_dwell_s=1.0,
                                 maneuver_dwell_g=0.05, maneuver_gates_calm_scaled=calm_scaled)
    bank.schedule(*air[0])
    z_trim, u_trim = np.asarray(bank.z_trim), np.asarray(bank.u_trim)
    rng = np.random.default_rng(3)
    zs = z_trim + rng.normal(size=(n, z_trim.size)) * 1.5 * NOISE_SIGMA
    zs[320:, SENSORS.index("AZ")] += 0.1
    seen = _gates_seen(bank, air, zs, u_trim)
    scale = np.array([math.sqrt(min(100.0, max(1.0, 1.0 + GAIN * (rho - rho_c)))) if calm_scaled else 1.0
                      for _, _, rho, rho_c in seen])
    n_lp = np.array([x for _, x, _, _ in seen])
    np.testing.assert_array_equal(np.array([m for m, _, _, _ in seen]), np.abs(n_lp) > 0.05 * scale)
    between = (np.abs(n_lp) > 0.05) & (np.abs(n_lp) <= 0.05 * scale)
    assert (between.sum() > 64) == calm_scaled   # the scale keeps the gate shut where the given g opens it


def test_calm_scaled_rate_gates_read_the_calm_air_reference(scheduled):
    # a fast climb from the nominal point, noisy readings: the climb-rate gate opens where the
    # recomputed rate passes 10 ft/s sqrt(s_c), s_c from the calm-air reference in force
    n = 1200
    air = _fast_climb(n)
    rng = np.random.default_rng(5)
    bank = core.HierarchicalBank(scheduled, adapt_turbulence=True, adapt_gain=GAIN, maneuver_dwell_s=1.0,
                                 maneuver_dwell_g=10.0, maneuver_climb_ft_s=10.0, maneuver_gates_calm_scaled=True)
    bank.schedule(*air[0])
    z_trim, u_trim = np.asarray(bank.z_trim), np.asarray(bank.u_trim)
    zs = z_trim + rng.normal(size=(n, z_trim.size)) * 1.5 * NOISE_SIGMA
    seen = _gates_seen(bank, air, zs, u_trim)
    scale = np.array([math.sqrt(min(100.0, max(1.0, 1.0 + GAIN * (rho - rho_c)))) for _, _, rho, rho_c in seen])
    assert scale[320:].min() > 1.5
    np.testing.assert_array_equal(np.array([m for m, _, _, _ in seen]), _scaled_gate(air, 10.0, scale))


def test_calm_scaled_gates_in_mmae_daemon(nominal):
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    r = subprocess.run([daemon, "--bank", bank, "--maneuver-dwell", "1", "--maneuver-gates-calm-scaled"],
                       capture_output=True, text=True, timeout=20)
    assert r.returncode == 2 and "--maneuver-gates-calm-scaled applies with --adapt-turbulence only" in r.stderr + r.stdout
    flags = daemon_flags({"adapt_turbulence": True, "maneuver_dwell_s": 1.0, "maneuver_gates_calm_scaled": True})
    assert "--maneuver-gates-calm-scaled" in flags
    assert "gates x sqrt(s_c)" in ready_line("--bank", bank, *flags)
