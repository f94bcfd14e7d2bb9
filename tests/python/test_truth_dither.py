"""Dither: subliminal by the stated criterion (measured and printed) at nine flight points,
symmetric pairs (nearly in phase) on one line each, and each surface's failure visible at its line."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.names import ACTUATORS, FRAME_RATE_HZ, SENSORS
from f16mmae.truth import Scenario, fly_raw
from f16mmae.truth.dither import (CRITERION, DEFAULT_FREQUENCY_HZ, DEFAULT_PHASE_RAD, Dither,
                                  DitherSpec)
from f16mmae.truth.failures import FailureSpec

DURATION_S = 8.0


FREQS = sorted(set(DEFAULT_FREQUENCY_HZ))
ROL = SENSORS.index("ROL")


def _lines(x: np.ndarray, t: np.ndarray) -> dict[float, np.ndarray]:
    """Complex line (sin + i cos coefficient, per channel) at each dither frequency in x
    (n, channels), by least-squares fit of sin/cos at the frequencies plus a mean and a ramp."""
    cols = [np.ones_like(t), t]
    for f in FREQS:
        cols += [np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), x, rcond=None)
    return {f: coef[2 + 2 * i] + 1j * coef[3 + 2 * i] for i, f in enumerate(FREQS)}


def _fly(failures=(), mach=0.4, alt_ft=20_000.0):
    sc = Scenario(mach=mach, alt_ft=alt_ft, duration_s=DURATION_S, noise=False, feedback="raw",
                  failures=failures)
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    return log["time_s"], log["z_ideal"] - truth.trim.z


# (0.42, 20,000 ft), (0.44, 20,000 ft), (0.46, 20,000 ft): q̄ 1.10, 1.21, 1.32 Q0, the start
# of the pairs' high-q̄ blend (its largest shares, n_z 0.87 and p 0.87); (0.5, 10,000 ft),
# (0.45, 5,000 ft): q̄ 2.3 Q0, the rule in full with its rate cap; (0.8, 15,000 ft): q̄ 535, the
# flaperons' boost nearly in full, the largest share measured with it (p 0.87)
@pytest.mark.parametrize("mach,alt_ft", [(0.4, 20_000.0), (0.8, 5_000.0), (0.45, 35_000.0), (0.42, 20_000.0),
                                         (0.44, 20_000.0), (0.46, 20_000.0), (0.5, 10_000.0),
                                         (0.45, 5_000.0), (0.8, 15_000.0)])
def test_default_dither_is_subliminal(mach, alt_ft):
    t, dz = _fly(mach=mach, alt_ft=alt_ft)
    peak = np.abs(dz).max(axis=0)
    rates = np.degrees(peak[[2, 4, 5]])
    print(f"\ndither peaks at M {mach}, {alt_ft:.0f} ft: n_z {peak[3]:.4f} g, n_y {peak[6]:.4f} g, "
          f"q/p/r {rates.round(3).tolist()} deg/s, alpha {np.degrees(peak[1]):.3f} deg, "
          f"u {peak[0]:.3f} ft/s  (criterion: {CRITERION})")
    assert peak[3] < CRITERION["nz_g"]
    assert peak[6] < CRITERION["ny_g"]
    assert np.all(rates < CRITERION["rate_deg_s"])
    assert peak[3] > 0.005 and np.all(rates > 0.1)   # and it is not nothing


def test_each_surface_failure_removes_its_own_share():
    """A surface's failure changes the measurements at its own frequency by its signature
    (>= 1 noise sigma per sample in some sensor), keeps the other frequencies' lines, and
    the two surfaces of a pair (same frequency, in phase) have signatures >= 1 sigma apart;
    the unpaired rudder's line vanishes with it."""
    from f16mmae.truth.sensors import NOISE_SIGMA

    t, dz = _fly()
    healthy = _lines(dz, t)
    signature = {}
    print("\nfailure signature |healthy - failed| / noise sigma at the surface's frequency, columns",
          SENSORS)
    for j, name in enumerate(ACTUATORS):
        f_j = DEFAULT_FREQUENCY_HZ[j]
        tf, failed_z = _fly((FailureSpec(name, 0.0, "complete"),))
        failed = _lines(failed_z, tf)
        signature[name] = (healthy[f_j] - failed[f_j]) / NOISE_SIGMA
        print(f"  {name:4s} {f_j} Hz", np.abs(signature[name]).round(2))
        assert np.abs(signature[name]).max() > 1.0, name
        for f in FREQS:
            if f != f_j:
                k = int(np.argmax(np.abs(healthy[f]) / NOISE_SIGMA))
                assert np.abs(failed[f][k]) > 0.3 * np.abs(healthy[f][k]), (name, f, SENSORS[k])
        if DEFAULT_FREQUENCY_HZ.count(f_j) == 1:   # unpaired: its line vanishes
            k = int(np.argmax(np.abs(healthy[f_j]) / NOISE_SIGMA))
            assert np.abs(failed[f_j][k]) < 0.15 * np.abs(healthy[f_j][k]), (name, SENSORS[k])
        else:  # paired, phases +-phi: the pair's roll moments add to 2 |sin phi| of one's
            share = 2.0 * abs(math.sin(DEFAULT_PHASE_RAD[j]))
            assert np.abs(healthy[f_j][ROL]) < (share + 0.2) * np.abs(failed[f_j][ROL]), name
    for a, b in (("LS", "RS"), ("LF", "RF")):
        assert np.abs(signature[a] - signature[b]).max() > 1.0, (a, b)


def test_pairs_share_a_frequency_with_symmetric_phases_and_every_line_reaches_sensors():
    """LS/RS and LF/RF: same frequency, phases +-phi with |phi| < 45 deg (mostly in phase: their
    roll largely cancels in healthy flight, so the roll-rate criterion leaves room for larger
    amplitudes); the three frequencies are distinct; every line shows above noise and every
    sensor but VEL sees one."""
    from f16mmae.truth.sensors import NOISE_SIGMA

    f, ph = DEFAULT_FREQUENCY_HZ, DEFAULT_PHASE_RAD
    assert f[0] == f[1] and f[2] == f[3] and ph[0] == -ph[1] and ph[2] == -ph[3]
    assert abs(ph[0]) < math.pi / 4 and abs(ph[2]) < math.pi / 4
    assert len({f[0], f[2], f[4]}) == 3
    t, dz = _fly()
    snr = np.array([np.abs(line) for line in _lines(dz, t).values()]) / NOISE_SIGMA
    # every line shows in at least one sensor above noise; every sensor except VEL sees a line
    # of at least 0.15 sigma per sample, i.e. >= 0.15 sqrt(N/2) ~ 2.4 sigma over the N = 512
    # frames of an 8-s run
    assert np.all(snr.max(axis=1) > 1.0)
    assert np.all(snr[:, 1:].max(axis=0) > 0.15)
    assert snr[:, 0].max() > 0.0


def test_dither_values_and_switch():
    d = Dither(DitherSpec(amplitude_deg=(1, 0, 0, 0, 2), frequency_hz=(1, 1, 1, 1, 0.5)))
    v = d.value(0.25)
    assert v[0] == pytest.approx(math.radians(1.0)) and v[4] == pytest.approx(math.radians(2) * math.sin(math.pi / 4))
    assert Dither(DitherSpec(enabled=False)).value(0.3) == [0.0] * 5
    assert Dither(DitherSpec(), scale=2.0).value(0.1)[0] == pytest.approx(2 * Dither().value(0.1)[0])
    # above the design dynamic pressure (scale < 1) the amplitudes shrink as scale^1.5 (the
    # rudder, which the pairs' high-q̄ rule leaves alone, shows it at 4 Q0)
    assert Dither(DitherSpec(), scale=0.25).value(0.1)[4] == pytest.approx(0.125 * Dither().value(0.1)[4])
    assert Dither(DitherSpec(), scale=0.95).value(0.1) == pytest.approx([0.95 ** 1.5 * v for v in Dither().value(0.1)])
    with pytest.raises(ValueError, match="scale"):
        Dither(DitherSpec(), scale=-1.0)
    with pytest.raises(ValueError, match=r"\[0, 16\] Hz"):
        DitherSpec(frequency_hz=(1, 1, 1, 1, 40))
    assert FRAME_RATE_HZ / 2 > max(DEFAULT_FREQUENCY_HZ) * 4


def test_throttle_dither_settings_are_checked_and_kept_out_of_records_when_off():
    from f16mmae.truth.scenario import Scenario as Sc

    assert "throttle_amplitude" not in DitherSpec().to_dict()   # records without it keep their form
    on = DitherSpec(throttle_amplitude=0.02, throttle_frequency_hz=0.1)
    assert on.throttle_on and not DitherSpec(enabled=False, throttle_amplitude=0.02).throttle_on
    back = Sc.from_dict(Sc(dither=on).to_dict())
    assert back.dither == on
    for bad in (-0.01, 0.5, float("nan"), True, "0.02"):
        with pytest.raises(ValueError, match="throttle_amplitude"):
            DitherSpec(throttle_amplitude=bad)
    with pytest.raises(ValueError, match="throttle_frequency_hz"):
        DitherSpec(throttle_amplitude=0.02, throttle_frequency_hz=20.0)
    # with maneuvers the dither rides on the outer loop's throttle (test_throttle_input.py)
    maneuvering = Sc(dither=on, duration_s=10.0, maneuvers=("turn@1:bank=20",))
    assert Sc.from_dict(maneuvering.to_dict()) == maneuvering


def test_scheduled_throttle_amplitude_meets_the_criterion_on_jsbsims_column():
    from f16mmae.design.linearize import throttle_column
    from f16mmae.truth import aircraft
    from f16mmae.truth.dither import G_FPS2, scheduled_throttle_amplitude, thrust_accel_fps2

    # the table at its nodes is JSBSim's thrust acceleration per unit command (3 decimals)
    for mach, alt in ((0.4, 20000.0), (0.8, 5000.0), (0.5, 35000.0)):
        fdm, _ = aircraft.trimmed_fdm(mach=mach, alt_ft=alt)
        b_x = throttle_column(fdm)[0]
        assert thrust_accel_fps2(mach, alt) == pytest.approx(b_x, abs=6e-4)
        assert scheduled_throttle_amplitude(mach, alt) * b_x / G_FPS2 == pytest.approx(0.018, rel=1e-4)
    # bilinear: the centre of a cell is the mean of its corners; outside the grid it is clamped
    corners = [thrust_accel_fps2(m, h) for m in (0.4, 0.5) for h in (20000.0, 25000.0)]
    assert thrust_accel_fps2(0.45, 22500.0) == pytest.approx(sum(corners) / 4, rel=1e-14)
    assert thrust_accel_fps2(0.95, 1000.0) == thrust_accel_fps2(0.8, 5000.0)
    assert scheduled_throttle_amplitude(float("nan"), 1.0) == scheduled_throttle_amplitude(0.4, 20000.0)


def test_scheduled_throttle_settings_and_the_bank_default():
    from f16mmae.truth.dither import SCHEDULED_THROTTLE_FREQUENCY_HZ
    from f16mmae.truth.scenario import Scenario as Sc

    on = DitherSpec().with_scheduled_throttle()
    assert on.throttle_on and on.throttle_schedule and on.throttle_frequency_hz == SCHEDULED_THROTTLE_FREQUENCY_HZ
    assert Sc.from_dict(Sc(dither=on).to_dict()).dither == on
    given = DitherSpec(throttle_amplitude=0.01, throttle_frequency_hz=0.3)
    assert given.with_scheduled_throttle() == given  # a throttle dither of the scenario's own stays
    assert DitherSpec(enabled=False).with_scheduled_throttle() == DitherSpec(enabled=False)
    with pytest.raises(ValueError, match="throttle_schedule"):
        DitherSpec(throttle_schedule=True, throttle_amplitude=0.02)
    with pytest.raises(ValueError, match="throttle_schedule"):
        DitherSpec(throttle_schedule="yes")


def test_high_qbar_rule_turns_the_flaperons_antisymmetric_and_grows_the_pairs():
    """The pairs' rule (Dither docstring): nothing up to 1.1 Q0 (the design point), phases and
    frequencies linear in q̄/Q0 to 1.5 Q0 and the amplitude factors with its square, then
    flaperons at +-pi/2 and 4.2 Hz with 2.5 x 4.2/2.9 and stabilators at 3.5 Hz with 1.6 x 3.5/1.7
    the scheduled amplitude, each pair's rate amplitude capped at 0.6 of its rate limit, the
    flaperons 1.8 x that from 5 Q0 (linear from 4 Q0); the terms computed by hand from the
    defaults."""
    from f16mmae.truth.dither import high_qbar_blend

    assert high_qbar_blend(1.0) == 0.0 and high_qbar_blend(1 / 1.09) == 0.0 and high_qbar_blend(1 / 1.5) == 1.0
    assert high_qbar_blend(0.1) == 1.0 and high_qbar_blend(0.0) == 1.0 and high_qbar_blend(1.5) == 0.0
    assert high_qbar_blend(1 / 1.3) == pytest.approx(0.5)
    base = [math.radians(a) for a in (1.8, 1.8, 2.2, 2.2, 5.5)]
    a, w, ph = Dither(DitherSpec(), scale=1 / 1.05).terms()     # 1.05 Q0: unchanged but for s^1.5
    assert a == pytest.approx([1.05 ** -1.5 * x for x in base]) and ph == list(DEFAULT_PHASE_RAD)
    assert w == [2 * math.pi * f for f in DEFAULT_FREQUENCY_HZ]
    g = 0.25 ** 1.5
    a, w, ph = Dither(DitherSpec(), scale=0.25).terms()         # 4 Q0: in full, below the cap
    gs, gf = 1.6 * 3.5 / 1.7, 2.5 * 4.2 / 2.9
    assert a == pytest.approx([g * gs * base[0], g * gs * base[1], g * gf * base[2], g * gf * base[3], g * base[4]])
    assert ph == pytest.approx([0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0])
    assert w == pytest.approx([2 * math.pi * f for f in (3.5, 3.5, 4.2, 4.2, 2.3)])
    cap_s = 0.6 * math.radians(60) / (2 * math.pi * 3.5)
    cap_f = 0.6 * math.radians(80) / (2 * math.pi * 4.2)
    a, _, _ = Dither(DitherSpec(), scale=0.5).terms()           # 2 Q0: in full, at the rate cap
    assert 0.5 ** 1.5 * gs * base[0] > cap_s and 0.5 ** 1.5 * gf * base[2] > cap_f
    assert a == pytest.approx([cap_s, cap_s, cap_f, cap_f, 0.5 ** 1.5 * base[4]])
    a, w, ph = Dither(DitherSpec(), scale=1 / 1.3).terms()      # 1.3 Q0: half way, factors at 1/4
    g = 1.3 ** -1.5
    assert a[0] == pytest.approx(g * 1.15 * (1 + 0.25 * (2.6 / 1.7 - 1)) * base[0])
    uncapped = g * 1.375 * (1 + 0.25 * (3.55 / 2.9 - 1)) * base[2]      # the flaperons at their cap
    assert uncapped > 0.6 * math.radians(80) / (2 * math.pi * 3.55)
    assert a[2] == pytest.approx(0.6 * math.radians(80) / (2 * math.pi * 3.55))
    assert ph[2] == pytest.approx(0.55 + 0.5 * (math.pi / 2 - 0.55)) and ph[3] == pytest.approx(-ph[2])
    assert w == pytest.approx([2 * math.pi * f for f in (2.6, 2.6, 3.55, 3.55, 2.3)])
    # the flaperons' boost: 1 up to 4 Q0 (above), linear to 1.8 at 5 Q0, 1.8 beyond; the
    # other surfaces as the rule gives them
    from f16mmae.truth.dither import high_qbar_flaperon_boost
    assert high_qbar_flaperon_boost(0.25) == 1.0 and high_qbar_flaperon_boost(1 / 4.5) == pytest.approx(1.4)
    assert high_qbar_flaperon_boost(0.2) == pytest.approx(1.8) and high_qbar_flaperon_boost(0.1) == pytest.approx(1.8)
    for scale, boost in ((1 / 4.5, 1.4), (0.15, 1.8)):
        g = scale ** 1.5
        a, w, ph = Dither(DitherSpec(), scale=scale).terms()
        assert a == pytest.approx([g * gs * base[0], g * gs * base[1], g * gf * boost * base[2],
                                   g * gf * boost * base[3], g * base[4]])
    # antisymmetric flaperons: their lift cancels in healthy flight (n_z from the stabilators only)
    d = Dither(DitherSpec(), scale=0.25)
    assert sum(d.value(t)[2] + d.value(t)[3] for t in (0.01, 0.13, 0.27)) == pytest.approx(0.0, abs=1e-15)
