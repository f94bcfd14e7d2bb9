"""Dither: subliminal by the stated criterion (measured and printed), one spectral line per
surface, and each surface's line vanishes from the measurements when that surface fails."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.names import ACTUATORS, FRAME_RATE_HZ, SENSORS
from f16mmae.truth import Scenario, fly_raw
from f16mmae.truth.dither import CRITERION, DEFAULT_FREQUENCY_HZ, Dither, DitherSpec
from f16mmae.truth.failures import FailureSpec

DURATION_S = 8.0


def _line_amplitudes(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Amplitude (5 lines x channels) of each dither frequency in x (n, channels), by
    least-squares fit of sin/cos at the 5 frequencies plus a mean and a ramp."""
    cols = [np.ones_like(t), t]
    for f in DEFAULT_FREQUENCY_HZ:
        cols += [np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)]
    a = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(a, x, rcond=None)
    return np.hypot(coef[2::2], coef[3::2])


def _fly(failures=(), mach=0.4, alt_ft=20_000.0):
    sc = Scenario(mach=mach, alt_ft=alt_ft, duration_s=DURATION_S, noise=False, feedback="raw",
                  failures=failures)
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    return log["time_s"], log["z_ideal"] - truth.trim.z


@pytest.mark.parametrize("mach,alt_ft", [(0.4, 20_000.0), (0.8, 5_000.0), (0.45, 35_000.0)])
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


def test_each_surface_failure_removes_its_own_line():
    t, dz = _fly()
    healthy = _line_amplitudes(dz, t)
    print("\ndither line amplitude / noise sigma, rows LS RS LF RF RUD, columns", SENSORS)
    from f16mmae.truth.sensors import NOISE_SIGMA
    print((healthy / NOISE_SIGMA).round(2))
    for j, name in enumerate(ACTUATORS):
        tf, failed = _fly((FailureSpec(name, 0.0, "complete"),))
        lines = _line_amplitudes(failed, tf)
        k = int(np.argmax(healthy[j] / NOISE_SIGMA))          # the sensor that sees it best
        assert lines[j, k] < 0.15 * healthy[j, k], (name, SENSORS[k])
        others = [i for i in range(5) if i != j]
        kept = lines[others, k] / healthy[others, k]
        assert np.all(kept > 0.3), (name, kept)


def test_lines_are_distinct_and_every_surface_reaches_several_sensors():
    assert len(set(DEFAULT_FREQUENCY_HZ)) == 5
    t, dz = _fly()
    from f16mmae.truth.sensors import NOISE_SIGMA
    snr = _line_amplitudes(dz, t) / NOISE_SIGMA
    # every surface shows in at least one sensor above noise; every sensor except VEL sees a
    # line of at least 0.15 sigma per sample, i.e. >= 0.15 sqrt(N/2) ~ 2.4 sigma over the
    # N = 512 frames of an 8-s run
    assert np.all(snr.max(axis=1) > 1.0)
    assert np.all(snr[:, 1:].max(axis=0) > 0.15)
    assert snr[:, 0].max() > 0.0


def test_dither_values_and_switch():
    d = Dither(DitherSpec(amplitude_deg=(1, 0, 0, 0, 2), frequency_hz=(1, 1, 1, 1, 0.5)))
    v = d.value(0.25)
    assert v[0] == pytest.approx(math.radians(1.0)) and v[4] == pytest.approx(math.radians(2) * math.sin(math.pi / 4))
    assert Dither(DitherSpec(enabled=False)).value(0.3) == [0.0] * 5
    assert Dither(DitherSpec(), scale=2.0).value(0.1)[0] == pytest.approx(2 * Dither().value(0.1)[0])
    with pytest.raises(ValueError, match=r"\[0, 16\] Hz"):
        DitherSpec(frequency_hz=(1, 1, 1, 1, 40))
    assert FRAME_RATE_HZ / 2 > max(DEFAULT_FREQUENCY_HZ) * 4
