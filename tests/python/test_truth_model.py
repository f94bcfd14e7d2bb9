"""TruthModel: trim holds for 10 s, frames are 2 JSBSim steps, seeds reproduce, the record
carries the failure truth while measure() returns only z."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.names import FRAME_RATE_HZ, SIM_RATE_HZ
from f16mmae.truth import FlightControlSystem, Scenario, TrimError, TruthModel, fly_raw
from f16mmae.truth.dither import DitherSpec

#: Documented trim-hold bounds over 10 s (no failure, turbulence, dither or noise; FCS closed).
HOLD = {"alt_ft": 2.0, "vt_fps": 0.2, "theta_deg": 0.05, "phi_deg": 0.01, "psi_deg": 0.01,
        "alpha_deg": 0.05, "beta_deg": 0.01}


def _wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


@pytest.mark.parametrize("mach,alt_ft", [(0.4, 20_000.0), (0.8, 5_000.0)])
def test_trim_holds_for_ten_seconds(mach, alt_ft):
    sc = Scenario(mach=mach, alt_ft=alt_ft, duration_s=10.0, dither=DitherSpec(enabled=False),
                  noise=False, feedback="raw")
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    st = dict(zip(log["state_names"], log["state"].T))
    dev = {
        "alt_ft": np.abs(st["alt_ft"] - alt_ft).max(),
        "vt_fps": np.abs(st["vt_fps"] - truth.trim.vt_fps).max(),
        "theta_deg": np.degrees(np.abs(st["theta_rad"] - truth.trim.theta_rad).max()),
        "phi_deg": np.degrees(np.abs(st["phi_rad"]).max()),
        "psi_deg": np.degrees(np.abs(_wrap(st["psi_rad"] - st["psi_rad"][0])).max()),
        "alpha_deg": np.degrees(np.abs(st["alpha_rad"] - truth.trim.alpha_rad).max()),
        "beta_deg": np.degrees(np.abs(st["beta_rad"]).max()),
    }
    for k, bound in HOLD.items():
        assert dev[k] < bound, (k, dev[k])
    # the FCS commanded the trim all along (nothing to correct)
    assert np.abs(log["u_cmd_rad"] - truth.trim.u_rad).max() < 2e-4


def test_a_frame_is_two_jsbsim_steps_and_time_counts_frames():
    truth = TruthModel(Scenario(duration_s=1.0))
    assert SIM_RATE_HZ // FRAME_RATE_HZ == 2
    assert truth.fdm.get_delta_t() == pytest.approx(1.0 / SIM_RATE_HZ)
    t0 = truth.fdm["simulation/sim-time-sec"]
    for _ in range(10):
        truth.measure()
        truth.advance(truth.trim.u_rad)
    assert truth.time_s == pytest.approx(10 / FRAME_RATE_HZ)
    assert truth.fdm["simulation/sim-time-sec"] - t0 == pytest.approx(10 / FRAME_RATE_HZ)
    with pytest.raises(ValueError, match="5 surface commands"):
        truth.advance([0.0] * 4)


def _run(seed, turbulence="light"):
    sc = Scenario(duration_s=3.0, seed=seed, turbulence=turbulence, feedback="raw",
                  failures=(), noise=True)
    truth, _ = fly_raw(sc)
    return truth.truth_log


def test_same_seed_same_run_other_seed_other_run():
    a, b, c = _run(5), _run(5), _run(6)
    for k in ("z", "z_ideal", "u_cmd_rad", "state"):
        assert np.array_equal(a[k], b[k]), k
    assert not np.array_equal(a["z"], c["z"])
    # the gusts themselves differ with the seed (not only the sensor noise)
    assert not np.allclose(a["z_ideal"], c["z_ideal"])


def test_turbulence_levels_shake_the_aircraft_in_order():
    spread = []
    for level in ("none", "light", "moderate", "severe"):
        log = _run(1, level)
        spread.append(np.std(np.diff(log["z_ideal"][:, 4])))   # roll-rate activity
    assert spread[0] < spread[1] < spread[2] < spread[3]


def test_record_holds_the_failure_truth_measure_returns_only_z():
    sc = Scenario(duration_s=2.0, failures=(), seed=3).with_failures(["LS@0.5", "AOA@1:bias"])
    truth = TruthModel(sc)
    fcs = FlightControlSystem(truth.trim, sc)
    for i in range(int(2.0 * FRAME_RATE_HZ)):
        z = truth.measure()
        assert isinstance(z, np.ndarray) and z.shape == (7,)
        truth.advance(fcs.command(z, truth.time_s))
    log = truth.truth_log
    assert [f["name"] for f in log["failures"]] == ["LS", "AOA"]
    assert [(o["name"], o["onset_s"]) for o in log["onsets"]] == [("LS", 0.5), ("AOA", 1.0)]
    assert log["scenario"]["seed"] == 3 and Scenario.from_dict(log["scenario"]) == sc
    assert log["z"].shape == (128, 7) and log["u_cmd_rad"].shape == (128, 5)


def test_run_longer_than_planned_keeps_recording():
    truth = TruthModel(Scenario(duration_s=0.1))
    for _ in range(20):
        truth.measure()
        truth.advance(truth.trim.u_rad)
    assert len(truth.truth_log["z"]) == 20


def test_impossible_flight_condition_names_it():
    with pytest.raises(TrimError, match="Mach 0.3, 35000 ft"):
        TruthModel(Scenario(mach=0.3, alt_ft=35_000.0))


def test_benchmark_runs_and_reports_both_sides():
    from f16mmae.bench import truth as bench

    r = bench.benchmark(duration_s=0.25, repeat=1)
    for k in ("bare_loop", "bare_total", "derived_loop", "contacts_loop", "cpp_flight", "python_flight",
              "cpp_first_flight"):
        assert r[f"{k}_s"] > 0 and r[f"{k}_rtf"] == pytest.approx(0.25 / r[f"{k}_s"])
    assert r["cpp_over_bare"] == pytest.approx(r["cpp_flight_s"] / r["bare_loop_s"])
    assert r["python_over_cpp"] == pytest.approx(r["python_flight_s"] / r["cpp_flight_s"])
    assert r["derived_over_contacts"] == pytest.approx(r["derived_loop_s"] / r["contacts_loop_s"])
