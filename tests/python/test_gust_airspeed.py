"""The schedule on the speed through the mean air (cpp/f16mmae/hierarchical_bank.h,
``gust_airspeed``), on the shipped scheduled bank in closed loop against the truth model flown
through JSBSim's own Python interface, whose wind is read each frame:

* the filters' blended along-track gust estimate û_g (state ``u_g_fps``) is the truth's wind
  along the body x axis, u - u_aero (JSBSim's velocities/u-fps less velocities/u-aero-fps), with
  that sign: correlated and within a fraction of its spread;
* so the Mach number the schedule follows (its low-passed M + û_g / c) is nearer the truth's Mach
  of the speed through the mean air, (V_air + u_w) / a, than the low-passed measured Mach the
  schedule follows without the option.
"""
from __future__ import annotations

import numpy as np
import pytest

import f16mmae.loop.flight as flight
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import bank_defaults
from f16mmae.truth.scenario import Scenario

FRAME_HZ = 64


@pytest.fixture(scope="module")
def scheduled():
    _, _, bank = load_bank("scheduled")
    return bank


def _fly(bank, monkeypatch, gust_airspeed: bool, seed: int):
    """Per frame after the first second: (truth along-track wind ft/s, truth Mach of the
    speed through the mean air, û_g, the schedule's Mach, the measured Mach)."""
    truth = {}

    class Recorded(flight.TruthModel):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            truth["model"] = self

    monkeypatch.setattr(flight, "TruthModel", Recorded)
    settings = bank_defaults({"adapt_turbulence": True}, bank)
    est = Estimator(bank, **settings, gust_airspeed=gust_airspeed)
    rows = []

    def on_frame(t, u, z, air):
        fdm = truth["model"].fdm
        wind = fdm["velocities/u-fps"] - fdm["velocities/u-aero-fps"]
        mean_air = (fdm["velocities/vt-fps"] + wind) / fdm["atmosphere/a-fps"]
        rows.append((wind, mean_air, float(est.core_bank.blended_state[13]),
                     est.core_bank.schedule_state["air_data"][0], air[0]))

    flight.fly(Scenario(turbulence="moderate", duration_s=30.0, seed=seed), bank, estimator=est,
               on_frame=on_frame, engine="python")
    return np.array(rows)[FRAME_HZ:]


@pytest.mark.parametrize("seed", [3, 4])
def test_the_gust_estimate_is_the_truths_along_track_wind(scheduled, monkeypatch, seed):
    r = _fly(scheduled, monkeypatch, True, seed)
    wind, estimate = r[:, 0], r[:, 2]
    assert np.corrcoef(wind, estimate)[0, 1] > 0.75
    assert np.sqrt(np.mean((estimate - wind) ** 2)) < 0.7 * np.std(wind)
    # the opposite sign would be as far off as the wind and its estimate together
    assert np.sqrt(np.mean((estimate + wind) ** 2)) > 1.2 * np.std(wind)


@pytest.mark.parametrize("seed", [3, 4])
def test_the_schedule_follows_the_speed_through_the_mean_air(scheduled, monkeypatch, seed):
    on, off = _fly(scheduled, monkeypatch, True, seed), _fly(scheduled, monkeypatch, False, seed)
    # the schedule's 2-s low-pass, applied to the truth's Mach too
    alpha = 1.0 - np.exp(-1.0 / (FRAME_HZ * 2.0))

    def low_pass(x):
        y = np.empty_like(x)
        y[0] = x[0]
        for i in range(1, len(x)):
            y[i] = y[i - 1] + alpha * (x[i] - y[i - 1])
        return y

    tail = slice(2 * FRAME_HZ, None)   # past the low-pass's start
    err_on = np.sqrt(np.mean((on[tail, 3] - low_pass(on[:, 1])[tail]) ** 2))
    err_off = np.sqrt(np.mean((off[tail, 3] - low_pass(off[:, 1])[tail]) ** 2))
    assert err_on < 0.75 * err_off, (err_on, err_off)   # the gust counted twice: above 1
