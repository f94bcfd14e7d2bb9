"""Closed-loop flights with the REAL truth model and the REAL estimator (C++ core).

* a failure-free flight declares nothing;
* an injected pitch-rate sensor failure is declared as PIT (fixed seed);
* the estimator sees only u, z and air data, copied: structurally (its constructor takes the
  model bank only, the loop hands it nothing but z, u and the truth model's measured air data)
  and behaviourally (replaying the recorded (u, z, air data) through a fresh estimator
  reproduces every probability and declaration);
* the air data it is scheduled on are the air-data sensor's, not the truth: they differ from
  the truth Mach and pressure altitude by exactly the sensor model (lag, then noise drawn from
  its own stream), and the whole-flight C++ loop schedules the same values as the Python one.
"""
from __future__ import annotations

import ast
import inspect
import json

import numpy as np
import pytest

from f16mmae import banks
from f16mmae.loop import flight
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import failed_components
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure
from schedule_support import floors_in_force

pytestmark = pytest.mark.slow


def _scenario(failures=(), seed=1, duration_s=6.0, turbulence="light"):
    return Scenario(mach=0.4, alt_ft=20000.0, turbulence=turbulence, duration_s=duration_s, seed=seed,
                    feedback="mmae", failures=tuple(make_failure(n, t) for n, t in failures))


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


@pytest.mark.parametrize("turbulence", ["none", "light"])
def test_failure_free_flight_declares_nothing(bank, turbulence):
    # light turbulence: the shipped tuned bank false-alarmed in 1 of 30 8-s no-failure
    # flights of the campaign (README); this seed is not that one
    r = fly(_scenario(turbulence=turbulence), bank)
    assert r.declarations == [] and r.final_hypothesis == "NONE"
    assert r.failures == []
    on = ~np.isnan(r.probabilities)
    np.testing.assert_allclose(np.nansum(r.probabilities, axis=1), 1.0, atol=1e-9)
    assert on[:, r.hypotheses.index("NONE")].all()


def test_pitch_rate_sensor_failure_is_declared_as_pit(bank):
    r = fly(_scenario([("PIT", 2.0)]), bank)
    assert r.declarations, "nothing declared"
    assert r.declarations[0]["hypothesis"] == "PIT"
    assert r.declarations[0]["time_s"] >= 2.0
    # at level 1 a dual with PIT may follow (a weakly excited flaperon; see the README)
    assert "PIT" in failed_components(r.final_hypothesis)
    assert r.failures == [{"name": "PIT", "time_s": 2.0, "mode": "complete"}]


def test_estimator_uses_the_bank_recommended_settings_unless_overridden(bank):
    recommended = {"p_min": 1e-9, "threshold": 0.9, "dwell_s": 0.25,   # tunings/tuned.toml [estimator]
                   "dwell_nats_per_hypothesis": {"LS": 32.0, "RS": 32.0, "LF": 178.8, "RF": 232.0, "VEL": 290.7,
                                                 "AOA": 308.4, "PIT": 275.8, "AZ": 277.5, "ROL": 32.0,
                                                 "YAW": 32.0, "AY": 32.0}}
    assert banks.bank_estimator_settings(bank) == recommended == bank.estimator_settings
    est = Estimator(bank)
    assert est.settings == recommended
    assert est._bank.p_min == 1e-9 and est._bank.threshold == 0.9
    over = Estimator(bank, p_min=1e-3, dwell_s=0.5)
    assert over._bank.p_min == 1e-3 and over._bank.dwell_s == 0.5
    assert over._bank.threshold == 0.9
    untuned = load_bank("untuned")[2]                    # recommends the core defaults
    assert banks.bank_estimator_settings(untuned) == {"p_min": 0.001, "threshold": 0.9, "dwell_s": 0.25}
    assert Estimator(untuned)._bank.p_min == 0.001
    r = fly(_scenario(duration_s=1.0), bank)
    assert r.estimator_settings == recommended and r.run_json()["estimator_settings"] == recommended


def test_the_estimator_sees_only_u_z_and_air_data_copied():
    params = list(inspect.signature(Estimator.__init__).parameters)
    assert params == ["self", "model_bank", "options"]
    assert list(inspect.signature(Estimator.update).parameters) == ["self", "z"]
    assert list(inspect.signature(Estimator.propagate).parameters) == ["self", "u"]
    assert list(inspect.signature(Estimator.schedule).parameters) == ["self", "mach", "pressure_altitude_ft"]
    # copied: the boundary converts to fresh floats / float arrays before the core sees them
    for method, copy in ((Estimator.update, "np.array(z, dtype=float)"), (Estimator.propagate, "np.array(u, dtype=float)"),
                         (Estimator.schedule, "float(mach)")):
        assert copy in inspect.getsource(method)
    # In fly(), the estimator is built from the bank alone and called with z, u and air data only.
    tree = ast.parse(inspect.getsource(flight.fly))
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call)]
    ctor = [c for c in calls if ast.unparse(c.func) == "Estimator.fresh"]
    assert len(ctor) == 1 and [ast.unparse(a) for a in ctor[0].args] == ["model_bank"]
    assert [k.arg for k in ctor[0].keywords] == [None]  # **estimator_options only
    assert list(inspect.signature(Estimator.fresh).parameters) == ["model_bank", "options"]
    est_calls = [c for c in calls if isinstance(c.func, ast.Attribute)
                 and isinstance(c.func.value, ast.Name) and c.func.value.id == "estimator"]
    assert {(c.func.attr, tuple(ast.unparse(a) for a in c.args)) for c in est_calls} == {
        ("schedule", ("air[0]", "air[1]")), ("update", ("z",)), ("propagate", ("u",))}
    assert all(not c.keywords for c in est_calls)
    # ... and the air data come from the truth model's air-data sensor and nowhere else
    sources = {ast.unparse(n.value) for n in ast.walk(tree) if isinstance(n, ast.Assign)
               and any(isinstance(t, (ast.Name, ast.Tuple)) and {"air", "air_next"} & {
                   x.id for x in ast.walk(t) if isinstance(x, ast.Name)} for t in n.targets)}
    assert sources == {"truth.air_data if n_frames_python else None", "truth.air_data", "(z_next, air_next)"}


def test_the_air_data_scheduled_on_are_the_sensor_model_not_the_truth(bank):
    from f16mmae.truth.air_data import AIR_DATA_SIGMA, air_data_rng, lag_decay

    sc = _scenario(seed=9, duration_s=4.0)
    r = fly(sc, bank, record_series=True)
    air, log = r.series["air_data"], r.series["truth_log"]
    ideal = log["air_data_ideal"][: len(air)]
    assert np.array_equal(air, log["air_data"][: len(air)])   # what the sensor measured, frame by frame
    assert not np.any(air == ideal)                            # never the truth Mach / pressure altitude
    # the sensor model, recomputed independently: lag from the truth, then the air-data stream's noise
    lag = np.empty_like(ideal)
    lag[0] = ideal[0]
    for i in range(1, len(ideal)):
        lag[i] = ideal[i] + (lag[i - 1] - ideal[i]) * lag_decay()
    noise = air_data_rng(sc.seed).standard_normal((len(air), 2)) * AIR_DATA_SIGMA
    np.testing.assert_allclose(air - lag, noise, rtol=0, atol=1e-9)
    assert abs(np.std(air[:, 0] - ideal[:, 0]) - AIR_DATA_SIGMA[0]) < 0.3 * AIR_DATA_SIGMA[0]
    # pressure altitude, not geometric: at 20,000 ft the two differ by the day's atmosphere only
    # (standard day here), so check the definition on the property JSBSim reports
    assert abs(ideal[0, 1] - 20000.0) < 50.0
    # the whole-flight C++ loop and the per-frame loop schedule the same last value
    for on_frame in (None, lambda t, u, z, a: None):
        est = Estimator(bank)
        fly(sc, bank, estimator=est, on_frame=on_frame)
        assert est.air_data == tuple(air[-1]) and est.air_data_rejected == 0


def test_replaying_u_and_z_alone_reproduces_the_estimator(bank):
    fly(_scenario([("AZ", 1.0)], seed=2, duration_s=4.0), bank)  # leaves a used estimator to reuse
    frames = []
    r = fly(_scenario([("LS", 2.0)], seed=5, duration_s=5.0), bank,
            on_frame=lambda t, u, z, a: frames.append((t, u, z, a)))
    est = Estimator(bank)
    probs, decl = [], []
    for t, u, z, a in frames:
        est.schedule(*a)
        est.update(z)
        est.propagate(u)
        if est.last_declaration is not None:
            decl.append({"hypothesis": est.last_declaration, "time_s": round(t, 9)})
        probs.append(dict(zip(est.hypotheses, est.probabilities)))
    assert decl == r.declarations
    for i, p in enumerate(probs):
        for name, value in p.items():
            assert r.probabilities[i, r.hypotheses.index(name)] == value


def test_run_command_writes_run_json_csv_and_png(tmp_path, capsys):
    from f16mmae.cli.main import main

    assert main(["run", "--fail", "PIT@2.0", "--duration", "6", "--seed", "1", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "declared PIT" in out
    run = json.loads((tmp_path / "run.json").read_text())
    for key in ("seed", "scenario", "bank_hash", "version", "failures", "declarations", "final_hypothesis"):
        assert key in run
    assert run["failures"] == [{"name": "PIT", "time_s": 2.0, "mode": "complete"}]
    assert run["declarations"][0]["hypothesis"] == "PIT" and run["declarations"][0]["time_s"] >= 2.0
    header = (tmp_path / "probabilities.csv").read_text().splitlines()[0].split(",")
    assert header[:14] == ["time_s", "NONE", "LS", "RS", "LF", "RF", "RUD", "VEL", "AOA",
                           "PIT", "AZ", "ROL", "YAW", "AY"]
    assert (tmp_path / "probabilities.png").stat().st_size > 1000


def test_the_start_up_weighs_no_hypothesis_for_its_frames(bank):
    """``start_up_s``: the first round(start_up_s x 64) frames leave the probabilities where the
    estimator started (its filters run); the next frame weighs again."""
    n = round(0.25 * 64)
    start = np.array(Estimator(bank).probabilities)
    held = fly(_scenario(seed=3, duration_s=1.0), bank, estimator_options={"start_up_s": 0.25})
    plain = fly(_scenario(seed=3, duration_s=1.0), bank)
    cols = [held.hypotheses.index(h) for h in Estimator(bank).hypotheses]
    p = held.probabilities[:, cols]
    assert np.array_equal(p[:n], np.tile(start, (n, 1)))
    assert not np.array_equal(p[n], start)
    assert not np.array_equal(plain.probabilities[0, cols], start)


def test_a_records_estimator_settings_fly_the_same_estimator_again(tmp_path):
    """A scheduled bank's floor is each node's (core ``node_p_min``): the settings in force, which
    every run record carries, name no p_min then, so a record flown again with its
    ``estimator_settings`` is the flight it records. A two-node schedule whose node at Mach 0.5
    recommends the floor 1e-5 and whose primary node (at 0.4, the bank's one p_min) 1e-9, flown at
    Mach 0.5: giving that one p_min would fly another estimator."""
    from f16mmae import core, names
    from f16mmae.design.bank import design_bank, to_model_bank
    from f16mmae.design.tuning import load_tuning
    tuning = load_tuning("tuned")
    nodes = [(i, 0, to_model_bank(design_bank(m, 20_000.0, tuning)).with_settings(p_min=p), np.zeros(names.NX))
             for i, (m, p) in enumerate(((0.4, 1e-9), (0.5, 1e-5)))]
    core.save_schedule([0.4, 0.5], [20000.0], nodes, primary=0, path=str(tmp_path / "two.f16sched"))
    bank = core.load_bank(str(tmp_path / "two.f16sched"))
    given = Estimator(bank)
    assert "p_min" not in given.settings and "threshold" in given.settings
    assert bank.estimator_settings["p_min"] == 1e-9
    scenario = Scenario(mach=0.5, alt_ft=20000.0, turbulence="light", duration_s=2.0, seed=537703878)
    floors = {}
    for name, options in (("given", {}), ("settings", given.settings),
                          ("one p_min", {**given.settings, "p_min": bank.estimator_settings["p_min"]})):
        est = Estimator(bank, **options)
        result, seen = floors_in_force(scenario, bank, est)
        floors[name] = (seen, np.nan_to_num(result.probabilities), est.settings)
    assert np.array_equal(floors["settings"][0], floors["given"][0])
    assert np.array_equal(floors["settings"][1], floors["given"][1])
    assert floors["settings"][2] == floors["given"][2]
    # the test can tell them apart: with the bank's one p_min the floor and the flight differ
    assert set(floors["given"][0]) != set(floors["one p_min"][0])
    assert not np.array_equal(floors["one p_min"][1], floors["given"][1])
