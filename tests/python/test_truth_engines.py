"""The C++ truth path (engine ``cpp``) flies exactly the flights of the Python reference
(engine ``python``): every failure mode, turbulence, noise and dither, off-nominal flight
conditions, per-frame calls, and a single-failure campaign on its evaluation seeds with the
estimator in the loop."""
from __future__ import annotations

import json

import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.campaign.engine.executor import InlineExecutor
from f16mmae.campaign.engine.failure_runs import plan
from f16mmae.campaign.engine.runner import planned_bank
from f16mmae.campaign.engine.store import ResultsStore
from f16mmae.campaign.single import SingleCampaign, run_campaign
from f16mmae.loop.flight import fly
from f16mmae.names import FRAME_RATE_HZ
from f16mmae.truth import FlightControlSystem, Scenario, TruthModel, fly_raw, parse_fail
from f16mmae.truth.dither import DitherSpec
from f16mmae.truth.engine import ENGINE_ENV, check_engine

ARRAYS = ("time_s", "z", "z_ideal", "air_data", "air_data_ideal", "state", "u_cmd_rad", "surface_rad")


def _fails(*texts):
    return tuple(parse_fail(t) for t in texts)


SCENARIOS = {
    "nominal": Scenario(duration_s=3.0, seed=11, feedback="raw"),
    "actuator modes": Scenario(duration_s=3.0, seed=12, turbulence="light", feedback="raw",
                               failures=_fails("LS@0.5", "RS@0.9:stuck", "LF@1.2:hardover=-1",
                                               "RF@1.01:loss=0.3", "RUD@2.0:hardover")),
    "sensor modes": Scenario(duration_s=3.0, seed=13, turbulence="moderate", feedback="raw",
                             failures=_fails("VEL@0.5", "AOA@0.7:null", "PIT@1.0:stuck", "AZ@1.3:hardover=-1",
                                             "ROL@1.5:bias", "YAW@1.7:drift=0.01", "AY@2.0:bias=0.02")),
    "severe, high and fast": Scenario(mach=0.8, alt_ft=5_000.0, duration_s=2.0, seed=14, turbulence="severe",
                                      feedback="raw", failures=_fails("LS@1.0:hardover")),
    "throttle dither": Scenario(duration_s=3.0, seed=16, turbulence="light", feedback="raw",
                                dither=DitherSpec(throttle_amplitude=0.03, throttle_frequency_hz=0.7),
                                failures=_fails("VEL@1.0")),
    "scheduled throttle dither, fast and low": Scenario(
        mach=0.8, alt_ft=5_000.0, duration_s=2.0, seed=17, feedback="raw",
        dither=DitherSpec(throttle_schedule=True, throttle_frequency_hz=0.7)),
    "throttle dither on the outer loop's throttle": Scenario(
        duration_s=4.0, seed=18, turbulence="light", feedback="raw",
        dither=DitherSpec(throttle_amplitude=0.03, throttle_frequency_hz=0.7),
        maneuvers=("accel@0.5:to=0.45mach", "turn@1:bank=30"), failures=_fails("VEL@2.0")),
    "no noise, no dither": Scenario(mach=0.45, alt_ft=35_000.0, duration_s=2.0, seed=15, noise=False,
                                    dither=DitherSpec(enabled=False), ari=False, feedback="raw",
                                    failures=_fails("RUD@1.0:stuck")),
}


def _same_logs(a: dict, b: dict) -> None:
    for k in ARRAYS:
        assert a[k].shape == b[k].shape, k
        assert np.array_equal(a[k], b[k]), f"{k}: max difference {np.abs(a[k] - b[k]).max()}"
    assert a["onsets"] == b["onsets"]
    assert a["trim"] == b["trim"]


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_both_engines_fly_the_same_flight_bit_for_bit(name):
    sc = SCENARIOS[name]
    ref, ref_fcs = fly_raw(sc, engine="python")
    cpp, cpp_fcs = fly_raw(sc, engine="cpp")
    _same_logs(ref.truth_log, cpp.truth_log)
    assert (ref_fcs.x_int, ref_fcs.x_wash, ref_fcs.x_vel) == (cpp_fcs.x_int, cpp_fcs.x_wash, cpp_fcs.x_vel)
    assert len(ref.truth_log["onsets"]) == len(sc.failures)


def _fly_frames(engine: str, sc: Scenario, extra_frames: int) -> dict:
    """Frame by frame: arbitrary commands through measure/advance, then the FCS through step on a
    perturbed feedback, past the scenario's duration (the noise is drawn on)."""
    truth = TruthModel(sc, engine=engine)
    fcs = FlightControlSystem(truth.trim, dither=sc.dither, ari=sc.ari)
    truth.attach(fcs)
    n = int(round(sc.duration_s * FRAME_RATE_HZ))
    for i in range(n // 2):
        truth.measure()
        truth.advance(truth.trim.u_rad + 0.01 * np.sin(0.3 * i + np.arange(5)))
    z = truth.measure()
    for i in range(n // 2, n + extra_frames):
        _, z = truth.step(fcs, z + 0.001, measure_next=True)
    truth.detach(fcs)
    truth.close()
    return {**truth.truth_log, "fcs": (fcs.x_int, fcs.x_wash, fcs.x_vel)}


def test_per_frame_calls_are_the_same_on_both_engines_past_the_duration():
    sc = Scenario(duration_s=1.0, seed=21, turbulence="light", failures=_fails("PIT@0.6:drift"))
    ref, cpp = _fly_frames("python", sc, 70), _fly_frames("cpp", sc, 70)
    assert len(cpp["time_s"]) == int(round(sc.duration_s * FRAME_RATE_HZ)) + 71
    _same_logs(ref, cpp)
    assert ref["fcs"] == cpp["fcs"]


def test_a_pilot_flies_on_the_python_law_on_either_engine():
    sc = Scenario(duration_s=1.5, seed=22, feedback="raw")

    def pilot(t):
        return (0.2 if t > 0.5 else 0.0, 0.05 if t > 1.0 else 0.0)

    ref, _ = fly_raw(sc, pilot=pilot, engine="python")
    cpp, _ = fly_raw(sc, pilot=pilot, engine="cpp")
    _same_logs(ref.truth_log, cpp.truth_log)
    assert abs(cpp.truth_log["z_ideal"][-1, 3] - cpp.trim.z[3]) > 0.05  # the pilot's pull-up flew
    with pytest.raises(ValueError, match="pilot"):
        FlightControlSystem(cpp.trim, pilot=pilot).coefficients()


def test_engine_names_are_checked(monkeypatch):
    with pytest.raises(ValueError, match="valid: cpp, python"):
        check_engine("fortran")
    monkeypatch.setenv(ENGINE_ENV, "python")
    assert TruthModel(Scenario(duration_s=0.5)).engine == "python"
    monkeypatch.setenv(ENGINE_ENV, "rust")
    with pytest.raises(ValueError, match="unknown truth engine 'rust'"):
        TruthModel(Scenario(duration_s=0.5))


def test_a_closed_flight_refuses_more_frames():
    for engine in ("python", "cpp"):
        truth = TruthModel(Scenario(duration_s=0.5), engine=engine)
        truth.measure()
        truth.close()
        with pytest.raises(RuntimeError, match="closed"):
            truth.measure()
        assert len(truth.truth_log["time_s"]) == 1


def _records(out) -> list[dict]:
    rows = [{k: v for k, v in r.items() if k != "timing"} for r in ResultsStore(out).records()]
    return sorted(json.loads(json.dumps(rows)), key=lambda r: r["run_key"])


@pytest.mark.slow
def test_single_failure_campaign_is_the_same_on_both_engines(tmp_path, monkeypatch):
    """The thirteen cases of the single-failure campaign on its evaluation seeds (light
    turbulence), estimator in the loop: the same declarations, the probabilities and what the
    estimator saw (u, z) equal to 1e-9 (in fact bit for bit)."""
    cfg = SingleCampaign(runs=1, baseline=None, turbulence="light")
    records = {}
    for engine in ("python", "cpp"):
        monkeypatch.setenv(ENGINE_ENV, engine)
        run_campaign(cfg, tmp_path / engine, InlineExecutor(), show_progress=False, measure_cost=False)
        records[engine] = _records(tmp_path / engine)
    assert len(records["cpp"]) == 13
    for a, b in zip(records["python"], records["cpp"]):
        assert a["declarations"] == b["declarations"]
        assert np.allclose(a["p_injected"], b["p_injected"], rtol=0, atol=1e-9)
        assert {k: v for k, v in a.items() if k != "p_injected"} == {k: v for k, v in b.items() if k != "p_injected"}
    label, _, bank = load_bank(cfg.tuning)
    spec = next(s for s in plan(cfg, {label: (cfg.tuning, bank)}) if s["case"] == "LS")
    seen = {}
    for engine in ("python", "cpp"):
        frames = []
        result = fly(Scenario.from_dict(spec["scenario"]), planned_bank(spec), engine=engine,
                     estimator_options=spec["estimator"],
                     on_frame=lambda t, u, z, a: frames.append(np.concatenate([u, z, a])))
        seen[engine] = (np.array(frames), result)
    (fa, ra), (fb, rb) = seen["python"], seen["cpp"]
    assert np.abs(fa - fb).max() <= 1e-9
    assert ra.declarations == rb.declarations
    assert np.nanmax(np.abs(ra.probabilities - rb.probabilities)) <= 1e-9


@pytest.mark.parametrize("feedback", ["mmae", "raw"])
def test_a_closed_loop_flown_whole_in_cpp_is_the_per_frame_one(feedback):
    """The C++ whole-flight loop (cpp engine, no on_frame) against the per-frame Python loop
    (forced by on_frame) on both engines: the same declarations and probabilities, bit for bit,
    through a declaration and the switch to the level-1 bank."""
    _, _, bank = load_bank("tuned")
    sc = Scenario(mach=float(bank.mach), alt_ft=float(bank.alt_ft), duration_s=6.0, seed=31,
                  turbulence="light", failures=_fails("LF@2.0"), feedback=feedback)
    whole = fly(sc, bank, engine="cpp")
    assert whole.declarations, "the failure is declared (the level changes mid-flight)"
    for engine in ("cpp", "python"):
        frames = fly(sc, bank, engine=engine, on_frame=lambda t, u, z, a: None)
        assert frames.declarations == whole.declarations
        assert frames.hypotheses == whole.hypotheses
        assert np.array_equal(frames.probabilities, whole.probabilities, equal_nan=True)
        assert frames.final_hypothesis == whole.final_hypothesis


def test_frames_without_a_log_fly_the_same_flight_and_refuse_the_log():
    """record_log=False (a closed-loop flight nobody reads the log of): the same frames, bit for
    bit, through a sensor and an actuator failure, the same onsets; truth_log refused by name."""
    sc = Scenario(duration_s=2.0, seed=7, turbulence="light", failures=_fails("LF@0.5", "AOA@1.0"))
    seen = []
    for record_log in (True, False):
        truth = TruthModel(sc, engine="cpp", record_log=record_log)
        fcs = FlightControlSystem(truth.trim, dither=sc.dither, ari=sc.ari)
        truth.attach(fcs)
        z, frames = truth.measure(), []
        for i in range(int(sc.duration_s * FRAME_RATE_HZ)):
            u, z = truth.step(fcs, z)
            frames.append(np.concatenate([u, z]))
        truth.detach(fcs)
        truth.close()
        seen.append((np.array(frames), truth._onsets_so_far(), fcs.x_int))
        if not record_log:
            with pytest.raises(RuntimeError, match=r"keeps no truth log \(built with record_log=False\)"):
                truth.truth_log
    (fa, oa, xa), (fb, ob, xb) = seen
    assert np.array_equal(fa, fb) and oa == ob and xa == xb
    assert [o["name"] for o in oa] == ["LF", "AOA"]


def test_a_core_built_for_another_jsbsim_is_refused_by_name(monkeypatch):
    from f16mmae import core
    from f16mmae.truth import aircraft

    monkeypatch.setattr(core, "JSBSIM_VERSION", "0.0.1")
    with pytest.raises(RuntimeError, match=r"built against jsbsim 0\.0\.1 but .*\(make build\)"):
        aircraft.load_fdm(cxx=True)


def test_the_cpp_frames_refuse_bad_input_by_name():
    truth = TruthModel(Scenario(duration_s=0.5), engine="cpp")
    with pytest.raises(ValueError, match=r"noise must be an \(n, 7\) array"):
        truth._frames.set_noise(np.zeros((3, 6)))
    with pytest.raises(ValueError, match=r"air_data_noise must be an \(n, 2\) array"):
        truth._frames.set_air_data_noise(np.zeros((3, 7)))
    with pytest.raises(ValueError, match="u needs 5 values"):
        truth._frames.advance(np.zeros(4))
    with pytest.raises(ValueError, match="no flight control law"):
        truth._frames.command(truth.trim.z)
    with pytest.raises(ValueError, match="field 'kq'"):
        truth._frames.set_fcs({"u_trim": [0.0] * 5, "limit_rad": [1.0] * 5, "z_trim": [0.0] * 7})
    truth.close()
