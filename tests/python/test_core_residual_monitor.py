"""core.ResidualMonitor (paper Sec. VII voters): statistics against numpy on the same
window, and the votes on white noise of the design variance, a bias, and a dither tone."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae import core

RATE_HZ, DITHER_HZ, N = 64.0, 4.0, 128


def test_statistics_match_numpy_on_the_window():
    rng = np.random.default_rng(1)
    a = np.array([2.0, 0.5])
    mon = core.ResidualMonitor(a, window_frames=N, frame_rate_hz=RATE_HZ, dither_hz=DITHER_HZ)
    r = rng.standard_normal((300, 2)) * np.sqrt(a)
    for row in r:
        mon.update(row)
    w = r[-N:]
    np.testing.assert_allclose(mon.mean, w.mean(axis=0), atol=1e-14)
    np.testing.assert_allclose(mon.mean_z, w.mean(axis=0) / np.sqrt(a / N), atol=1e-12)
    c = (np.diff(np.signbit(w).astype(int), axis=0) != 0).sum(axis=0)
    np.testing.assert_allclose(mon.zero_crossing_rate, c / (N - 1), atol=1e-14)
    np.testing.assert_allclose(mon.zero_crossing_z, (c - (N - 1) / 2) / np.sqrt((N - 1) / 4), atol=1e-12)
    np.testing.assert_allclose(mon.variance_ratio, (w**2).mean(axis=0) / a, atol=1e-13)
    # DITHER_HZ is bin 8 of a 128-point DFT at 64 Hz
    x = np.fft.fft(w, axis=0)[int(DITHER_HZ * N / RATE_HZ)]
    np.testing.assert_allclose(mon.tone_ratio, np.abs(x) ** 2 / (N * a), rtol=1e-9)
    assert mon.ready and mon.samples == N and mon.frames == 300


@pytest.mark.parametrize(
    "signal, voter",
    [
        (lambda t, e: e, None),
        (lambda t, e: e + 1.5, "mean"),
        (lambda t, e: e + np.sin(2 * np.pi * DITHER_HZ * t + 0.3), "tone"),
        (lambda t, e: 3.0 * e, "variance"),
    ],
    ids=["white", "bias", "dither-tone", "variance"],
)
def test_votes(signal, voter):
    rng = np.random.default_rng(2)
    mon = core.ResidualMonitor([1.0], window_frames=N, frame_rate_hz=RATE_HZ, dither_hz=DITHER_HZ)
    counts = dict.fromkeys(("mean", "zero_crossing", "variance", "tone"), 0)
    frames = 0
    for i in range(1500):
        mon.update([signal(i / RATE_HZ, rng.standard_normal())])
        if mon.ready:
            frames += 1
            for k, v in mon.votes.items():
                counts[k] += bool(v[0])
    if voter is None:
        assert counts == dict.fromkeys(counts, 0)
    else:
        assert counts[voter] > 0.9 * frames
    if voter == "tone":
        assert counts["mean"] == 0  # a zero-mean tone does not look like a bias


def test_bad_input():
    with pytest.raises(ValueError, match="a_diag entries must be positive"):
        core.ResidualMonitor([1.0, -1.0])
    with pytest.raises(ValueError, match="dither_hz"):
        core.ResidualMonitor([1.0], dither_hz=40.0)
    mon = core.ResidualMonitor([1.0, 1.0])
    with pytest.raises(ValueError, match=r"r must have shape \(2,\), got \(3,\)"):
        mon.update([0.0, 0.0, 0.0])
    mon.update([np.nan, 0.0])
    assert mon.skipped_frames == 1 and mon.samples == 0
