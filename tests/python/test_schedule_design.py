"""The scheduled design (``f16mmae design --schedule``) on a small real grid, and a flight
between its nodes: each node is the ordinary design at its point with the tuning calibrated
there (same content hash as ``design_bank`` with ``calibrate_node``'s tuning; with
``--node-tuning fixed``, with the tuning as given), the CLI shows progress and refuses bad grids, and an off-grid flight
flown through the Python loop and through the C++ closed loop gives identical declarations
and probabilities (both loops feed it the truth's measured air data every frame)."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.cli.main import main
from f16mmae.design.bank import design_bank, to_model_bank
from f16mmae.design.calibrate import (CALIBRATION_START_UP_S, NODE_FLIGHT_S, START_UP_S, adaptation_reference,
                                      bounded_settings, calibrate_node, failure_log_odds_peak, log_odds_bound,
                                      node_flights)
from f16mmae.design.hypotheses import TRIM_SIGMA, check_failure_model
from f16mmae.design.model import linearize_truth
from f16mmae.design.gust_states import GUST_STATES, pad_bank
from f16mmae.design.schedule import (ScheduleSpecError, format_spec, gust_neighbourhoods, gust_node_tuning, neighbourhood_minimum,
                                     neighbourhood_settings, parse_grid, schedule_failed_sensor_noise,
                                     schedule_failure_model, x_trim)
from f16mmae.design.tuning import TUNINGS_DIR, load_tuning
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import make_failure
from f16mmae.truth.scenario import Scenario
from f16mmae.truth.sensors import NOISE_SIGMA

GRID = "mach=0.4/0.5,alt=20000"


@pytest.fixture(scope="module")
def scheduled(tmp_path_factory):
    """Plain nodes (no gust states: the default would give these 20,000-ft nodes Dryden gust
    states, whose design the gust tests below check; five inputs: the default's throttle input
    has tests of its own, test_throttle_input.py): each is the ordinary design at its point."""
    out = tmp_path_factory.mktemp("sched") / "small.f16sched"
    assert main(["design", "--schedule", GRID, "--gust-states-below-ft", "none", "--no-throttle-input", "--workers", "2",
                 "--out", str(out)]) == 0
    return core.load_bank(out)


def _tuned():
    """The tuned tuning as the schedule's nodes take it: without the nominal bank's evidence
    dwell table (design/schedule.py: the nodes keep the frame dwell alone), its failed sensors at
    the scheduled design's noise (names.SCHEDULE_FAILED_SENSOR_NOISE)."""
    t = load_tuning("tuned")
    return dataclasses.replace(t, estimator={k: v for k, v in t.estimator.items() if k != "dwell_nats_per_hypothesis"},
                               failed_sensor_noise=names.SCHEDULE_FAILED_SENSOR_NOISE)


def _hash(design, p_min=None) -> str:
    """The content hash of ``design`` as a node of the schedule (the frame dwell alone: no
    evidence dwell table) with ``p_min`` if given."""
    bank = to_model_bank(design).with_settings(p_min=p_min, dwell_nats_per_hypothesis={})
    return core.ModelBank.from_bytes(bank.to_bytes()).content_hash


def _constant_vel(tuning):
    """The tuning with the scheduled design's failure model (names.SCHEDULE_FAILURE_MODEL)."""
    return dataclasses.replace(tuning, failure_model=check_failure_model(names.SCHEDULE_FAILURE_MODEL))


def test_each_node_is_the_ordinary_design_at_its_point_with_its_calibrated_tuning(scheduled):
    """Own nodes first (Mach 0.4 trims alpha 8.1 deg: flap 15 deg, layer 1; Mach 0.5 4.7 deg:
    flap 0, layer 0), then the cell's corners in the other flap position (the flap held, the
    node's tuning and reference), and the flap law on alpha at 5 and 15 deg.  The nodes'
    hypotheses take the scheduled design's failure model (a failed VEL or roll gyro at an unknown constant),
    their floors and references are bounded on the node's `complete` design."""
    s = scheduled.schedule
    assert s["mach"] == (0.4, 0.5) and s["alt_ft"] == (20000.0,)
    assert [(n["mach"], n["alt_ft"], n["layer"]) for n in s["nodes"]] == [
        (0.4, 20000.0, 1), (0.5, 20000.0, 0), (0.4, 20000.0, 0), (0.5, 20000.0, 1)]
    assert s["switch_state"] == 1 and s["switch_thresholds"] == (0.0873, 0.2618)
    assert scheduled.mach == 0.4  # the primary: nearest the nominal point
    tuning, _, _ = calibrate_node(0.5, 20000.0, _tuned())
    design = design_bank(0.5, 20000.0, tuning)   # complete: what the floor and reference are bounded on
    node_design = design_bank(0.5, 20000.0, _constant_vel(tuning))
    node = s["nodes"][1]
    flights = node_flights(0.5, 20000.0, "light")
    chosen = bounded_settings(to_model_bank(design), flights, start_up_s=CALIBRATION_START_UP_S)
    reference, p_min = chosen["adapt_reference"], chosen["p_min"]
    peak = failure_log_odds_peak(to_model_bank(design).with_settings(p_min=p_min), flights, reference,
                                 start_up_s=CALIBRATION_START_UP_S)
    assert round(peak, 2) == chosen["failure_log_odds_peak"] and peak <= log_odds_bound(p_min, 0.9)
    # the file carries the smaller of the two nodes' floors (neighbours on the grid, both within
    # their bound), as the node bank's recommended p_min, and the smaller of their bounded
    # references at that floor
    s0 = bounded_settings(to_model_bank(design_bank(0.4, 20000.0, calibrate_node(0.4, 20000.0, _tuned())[0])),
                          node_flights(0.4, 20000.0, "light"), start_up_s=CALIBRATION_START_UP_S)
    assert chosen["bound_met"] and s0["bound_met"]
    p_min_in_file = min(p_min, s0["p_min"])
    reference_in_file = min(row[1] for row in chosen["candidates"] + s0["candidates"] if row[0] == p_min_in_file)
    assert node["adapt_reference"] == reference_in_file == s["nodes"][0]["adapt_reference"]
    assert node["bank"].p_min == p_min_in_file == s["nodes"][0]["bank"].p_min
    assert node["bank"].content_hash == _hash(node_design, p_min_in_file) != _hash(design, p_min_in_file)
    vel = [h for h in node["bank"].hypotheses if h.name == "VEL"][0]
    assert vel.uninformative_width[0] == pytest.approx(6 * TRIM_SIGMA["VEL"]) and np.asarray(vel.uninformative_width)[1:].max() == 0
    flap_held = design_bank(0.5, 20000.0, _constant_vel(tuning), linearized=linearize_truth(0.5, 20000.0, lef_rad=0.262))
    assert s["nodes"][3]["bank"].content_hash == _hash(flap_held, p_min_in_file) != node["bank"].content_hash
    assert s["nodes"][3]["adapt_reference"] == reference_in_file
    assert node["bank"].content_hash != _hash(design_bank(0.5, 20000.0, "tuned"))
    np.testing.assert_array_equal(node["x_trim"], x_trim(node_design))
    assert node["x_trim"][0] == pytest.approx(design.z_trim[0]) and node["x_trim"][8] == design.u_trim[0]
    meta = json.loads(scheduled.schedule["metadata"])
    assert meta["start_up_s"] == START_UP_S == 1.0 and meta["calibration_start_up_s"] == CALIBRATION_START_UP_S == 0.25
    assert "--start-up-s 1 --calibration-start-up-s 0.25 --failure-model constant=VEL+ROL" in meta["command"]
    assert meta["failure_model"] == {"default": "complete", "constant": ["VEL", "ROL"]}
    assert meta["failed_sensor_noise"] == "sensor"
    assert np.asarray(vel.a)[0, 0] == NOISE_SIGMA[0] ** 2   # the failed airspeed sensor's own noise
    assert s["start_up_s"] == 1.0
    assert meta["node_tuning"] == "calibrated" and [(n["mach"], n["alt_ft"]) for n in meta["nodes"]] == [
        (0.4, 20000.0), (0.5, 20000.0)]
    assert meta["nodes"][1]["power_ratio_mean"] == adaptation_reference(design, flights)
    assert meta["nodes"][1]["adapt_reference_node"] == reference and meta["nodes"][1]["bound_met"]
    assert meta["nodes"][1]["adapt_reference"] == reference_in_file
    assert meta["nodes"][1]["p_min_node"] == p_min and meta["nodes"][1]["p_min"] == p_min_in_file
    assert meta["nodes"][1]["knobs"] == {k: v for f in ("qd_longitudinal", "r_pseudonoise", "qd_lateral")
                                         for k, v in getattr(tuning, f).items()}


def test_calibration_at_the_nominal_point_keeps_the_shipped_tuning():
    """The shipped tuning was calibrated there: stage 1 from it is at its fixed point."""
    tuned = _tuned()
    tuning, before, after = calibrate_node(0.4, 20000.0, tuned)
    for field in ("qd_longitudinal", "r_pseudonoise", "qd_lateral", "actuator_q", "estimator"):
        assert getattr(tuning, field) == getattr(tuned, field), field
    np.testing.assert_allclose(after.var_over_a, before.var_over_a)


def test_calibration_at_a_high_dynamic_pressure_node_matches_its_residuals():
    """At Mach 0.7, 10,000 ft (q 5x the design point's) the nominal tuning under-predicts the
    residuals (a channel's var/A well above 1); calibrated there, every channel it under-predicted
    is within 15 % and none is above 1.15.  The calibration adds noise, it never takes the design's
    away: AZ, which the design over-predicts there (the pitch gust takes back much of the vertical
    gust's normal acceleration, truth/turbulence.py), stays below 1."""
    tuning, before, after = calibrate_node(0.7, 10000.0, _tuned())
    assert before.var_over_a.max() > 2.0
    under = before.var_over_a > 1.0
    assert under.sum() >= 5 and np.all(np.abs(after.var_over_a[under] - 1.0) < 0.15), after.var_over_a
    assert np.all(after.var_over_a < 1.15), after.var_over_a
    assert tuning.name == "tuned@node" and tuning.estimator == _tuned().estimator


def test_a_node_whose_alpha_state_noise_misfits_jointly_puts_aoa_on_its_measurement():
    """At Mach 0.35, 10,000 ft the per-channel calibration on the alpha state leaves var/A about 1
    on every channel but the NONE filter's mean NIS per channel above JOINT_NIS_LIMIT (A's AOA-AZ
    correlation is not the residuals'); calibrate_node then puts AOA's excess on R AOA and keeps
    the alpha-state noise of the tuning it starts from, and the NONE filter designed with its
    result, run over the node's flights here, fits within the limit."""
    from f16mmae.design.calibrate import JOINT_NIS_LIMIT, KNOBS, calibrate
    from f16mmae.design.residuals import filter_residuals, residual_stats

    tuned = _tuned()
    lin = linearize_truth(0.35, 10000.0)
    flights = node_flights(0.35, 10000.0, tuned.turbulence)
    plain, hist = calibrate(tuned, flights, lin, knobs=KNOBS)
    assert hist[-1].nis_mean / names.NZ > JOINT_NIS_LIMIT and "AOA" not in plain.r_pseudonoise
    tuning, _, after = calibrate_node(0.35, 10000.0, tuned, linearized=lin, flights=flights)
    assert tuning.r_pseudonoise["AOA"] > 0.0
    assert tuning.qd_longitudinal["alpha_rad"] == tuned.qd_longitudinal["alpha_rad"]
    f = design_bank(tuning=tuning, linearized=lin, hypotheses=(names.NONE,)).filters[0]
    res = [filter_residuals(f.model.phi, f.model.bd, f.model.h, f.gains.k, fl.u, fl.z)[names.FRAME_RATE_HZ:]
           for fl in flights]
    r = np.vstack(res)
    nis = float(np.mean(np.einsum("ij,ij->i", r, np.linalg.solve(f.gains.a, r.T).T)))
    assert nis / names.NZ <= JOINT_NIS_LIMIT
    assert abs(nis - after.nis_mean) < 1e-9 * nis
    assert residual_stats(res, f.gains.a).var_over_a.max() < 1.1


def test_the_cli_shows_progress_and_the_size(tmp_path, capsys):
    out = tmp_path / "one.f16sched"
    assert main(["design", "--schedule", "mach=0.5,alt=20000", "--node-tuning", "fixed", "--no-throttle-input", "--workers", "1",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "[1/1] Mach 0.50, 20000 ft: designed" in text and "tuning at every point: tuned" in text
    assert f"scheduled bank {out}: 1 banks (0 of them in the other flap position), 0 left out" in text
    assert "content hash" in text
    node = core.load_bank(out).schedule["nodes"][0]
    assert node["bank"].content_hash == _hash(design_bank(0.5, 20000.0, _constant_vel(_tuned())))
    assert "start_up_s" not in json.loads(core.load_bank(out).schedule["metadata"])  # no calibration flights


def test_a_constant_roll_gyro_level_comes_from_the_command(tmp_path):
    """``--failure-model constant=VEL+ROL``: every node's ROL-failed hypotheses read an unknown
    level within 6 noise sigmas of the gyro (0.6 deg/s) with a level random walk of 1e-6 of its
    noise variance, the filters and the other hypotheses those of constant=VEL; the
    file names the model in its metadata and command."""
    out, ref = tmp_path / "rol.f16sched", tmp_path / "vel.f16sched"
    common = ["design", "--schedule", "mach=0.5,alt=20000", "--node-tuning", "fixed", "--no-throttle-input", "--workers", "1"]
    assert main(common + ["--failure-model", "constant=VEL+ROL", "--out", str(out)]) == 0
    assert main(common + ["--failure-model", "constant=VEL", "--out", str(ref)]) == 0
    node, plain = core.load_bank(out).schedule["nodes"][0]["bank"], core.load_bank(ref).schedule["nodes"][0]["bank"]
    j = names.SENSORS.index("ROL")
    rol = 0
    for h, g in zip(node.hypotheses, plain.hypotheses):
        assert h.name == g.name
        np.testing.assert_array_equal(h.k, g.k)
        w, q = np.array(h.uninformative_width), np.array(h.uninformative_level_q)
        if "ROL" in h.name.split("+"):
            rol += 1
            assert w[j] == pytest.approx(6 * np.radians(0.1), rel=1e-12)
            assert q[j] == pytest.approx(1e-6 * np.radians(0.1) ** 2, rel=1e-12)
            w[j], q[j] = 0.0, 0.0
        np.testing.assert_array_equal(w, g.uninformative_width)
        np.testing.assert_array_equal(q, g.uninformative_level_q)
    assert rol == 12  # ROL and its eleven duals
    meta = json.loads(core.load_bank(out).schedule["metadata"])
    assert meta["failure_model"] == {"default": "complete", "constant": ["VEL", "ROL"]}
    assert node.content_hash == _hash(design_bank(0.5, 20000.0, dataclasses.replace(
        _tuned(), failure_model=check_failure_model("constant=VEL+ROL"))))


@pytest.mark.parametrize("args, message", [
    (["--schedule", "mach=0.5,alt=20000", "--node-tuning", "per-point"], "--node-tuning 'per-point': valid: "
                                                                         "calibrated, fixed"),
    (["--node-tuning", "fixed"], "--node-tuning, --flap-layers, --node-p-min, --start-up-s, --calibration-start-up-s, "
                                 "--calibration-flight-s, --calibration-bank, --scale-model and --adapt-running-start "
                                 "apply to a scheduled design; give --schedule"),
    (["--scale-model", "complete"], "apply to a scheduled design; give --schedule"),
    (["--schedule", "mach=0.5,alt=20000", "--scale-model", "complete"],
     "--scale-model gives the reference scale's model: it needs --calibration-bank scaled"),
    (["--schedule", "mach=0.5,alt=20000", "--calibration-bank", "scaled", "--scale-model", "sticky=VEL"],
     "--scale-model: "),
    (["--calibration-flight-s", "60"], "apply to a scheduled design; give --schedule"),
    (["--schedule", "mach=0.5,alt=20000", "--calibration-flight-s", "4"], "--calibration-flight-s '4' must be >= 8.0"),
    (["--schedule", "mach=0.5,alt=20000", "--calibration-flight-s", "nan"], "--calibration-flight-s 'nan'"),
    (["--schedule", "mach=0.5,alt=20000", "--calibration-flight-s", "601"], "--calibration-flight-s '601' must be <= 600.0"),
    (["--schedule", "mach=0.5,alt=20000", "--calibration-bank", "paper"], "--calibration-bank 'paper': valid: complete, own, scaled"),
    (["--schedule", "mach=0.5,alt=20000", "--node-tuning", "fixed", "--calibration-bank", "own"],
     "--calibration-flight-s and --calibration-bank go with the calibration flights: they need --node-tuning calibrated"),
    (["--adapt-running-start"], "apply to a scheduled design; give --schedule"),
    (["--schedule", "mach=0.5,alt=20000", "--node-tuning", "fixed", "--adapt-running-start"],
     "--adapt-running-start goes with the calibration flights: it needs --node-tuning calibrated"),
    (["--calibration-start-up-s", "1"], "apply to a scheduled design; give --schedule"),
    (["--schedule", "mach=0.5,alt=20000", "--start-up-s", "-1"], "--start-up-s '-1' must be >= 0.0"),
    (["--schedule", "mach=0.5,alt=20000", "--calibration-start-up-s", "x"], "--calibration-start-up-s 'x'"),
    (["--schedule", "mach=0.5,alt=20000", "--node-tuning", "fixed", "--start-up-s", "0.25"],
     "--start-up-s goes with the calibration flights: it needs --node-tuning calibrated"),
    (["--schedule", "mach=0.5,alt=20000", "--node-tuning", "fixed", "--calibration-start-up-s", "0.25"],
     "--calibration-start-up-s goes with the calibration flights: it needs --node-tuning calibrated"),
    (["--schedule", "mach=0.5,alt=20000", "--node-p-min", "1e-9/0.5"], "--node-p-min '0.5' must be < 0.012658"),
    (["--schedule", "mach=0.5,alt=20000", "--flap-layers", "maybe"], "--flap-layers 'maybe': valid: on, off"),
])
def test_a_bad_node_tuning_is_refused_before_any_work(args, message, tmp_path, capsys):
    out = tmp_path / "x.f16sched"
    assert main(["design", *args, "--out", str(out)]) != 0
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_a_tuning_s_level_widths_go_to_the_models_that_cover_them(tmp_path, capsys):
    """A tuning whose failed_sensor_level_width names AOA: the complete bank a node is bounded on
    and the scale model's bank take it without that width (schedule.in_model: a width applies to
    a cover sensor only); a failure model that does not cover AOA is refused by name before any
    work (the CLI with no traceback)."""
    from f16mmae.design.schedule import in_model
    tuned = dataclasses.replace(_tuned(), failure_model=check_failure_model("cover=AOA+PIT,constant=VEL"),
                                failed_sensor_level_width={"AOA": "reading", "PIT": "reading"})
    assert in_model(tuned, "complete").failed_sensor_level_width == {}
    assert in_model(tuned, "complete").failure_model == "complete"
    assert in_model(tuned, check_failure_model("cover=PIT")).failed_sensor_level_width == {"PIT": "reading"}
    text = (TUNINGS_DIR / "tuned.toml").read_text()
    toml = tmp_path / "widths.toml"
    toml.write_text(text.replace('gust_model = "gust_rate"\n', 'gust_model = "gust_rate"\n'
                                 'failure_model = "cover=AOA"\nfailed_sensor_level_width = {AOA = "reading"}\n', 1))
    out = tmp_path / "x.f16sched"
    assert main(["design", "--schedule", "mach=0.5,alt=20000", "--tuning", str(toml), "--failure-model",
                 "constant=VEL+ROL", "--out", str(out)]) != 0
    err = capsys.readouterr().err
    assert ("--schedule: the tuning tuned's failed_sensor_level_width names AOA, whose failure model under "
            "constant=VEL+ROL is not cover: a level width applies to a cover sensor") in err
    assert "Traceback" not in err and not out.exists()


@pytest.mark.parametrize("spec, message", [
    ("mach=0.2:0.5:0.1,alt=20000", "every point must lie in the design envelope 0.3-0.8"),
    ("mach=0.5/0.4,alt=20000", "strictly ascending"),
    ("mach=0.4:0.5:0,alt=20000", "the step must be > 0"),
    ("alt=20000", "give mach=START:STOP:STEP,alt=START:STOP:STEP"),
    ("mach=x,alt=20000", "is not start:stop:step or a list"),
])
def test_bad_grids_are_refused_naming_the_rule(spec, message, tmp_path, capsys):
    with pytest.raises(ScheduleSpecError, match=message):
        parse_grid(spec)
    assert main(["design", "--schedule", spec, "--out", str(tmp_path / "x.f16sched")]) != 0
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x.f16sched").exists()


def test_the_default_grid_covers_the_envelope():
    g = parse_grid()
    assert g.mach == (0.3, 0.35, 0.4, 0.5, 0.6, 0.7, 0.8)
    assert g.alt_ft == (5000.0, 10000.0, 15000.0, 20000.0, 25000.0, 30000.0, 35000.0)


@pytest.mark.parametrize("mode", ["interpolate", "nearest"])
def test_an_off_grid_flight_is_the_same_in_the_python_loop_and_in_cpp(scheduled, mode):
    scenario = Scenario(mach=0.46, alt_ft=20000.0, turbulence="light", failures=(make_failure("PIT", 3.0),),
                        duration_s=6.0, seed=11)
    results = {}
    for engine in ("python", "cpp"):
        est = Estimator(scheduled, schedule_mode=mode)
        results[engine] = (fly(scenario, scheduled, estimator=est, engine=engine), est.core_bank.schedule_state)
    (py, py_state), (cpp, cpp_state) = results["python"], results["cpp"]
    assert py.declarations == cpp.declarations and py.declarations
    np.testing.assert_array_equal(py.probability_of("PIT"), cpp.probability_of("PIT"))
    expected = [(0.5, 20000.0)] if mode == "nearest" else [(0.4, 20000.0), (0.5, 20000.0)]
    assert py_state["nodes"] == cpp_state["nodes"] == expected


def test_a_node_s_reference_is_the_smallest_of_its_neighbours_that_met_the_bound():
    """Hand-made 3 x 2 grid: (0, 0) met its bound at 0.6, (1, 0) at 1.0, (2, 0) did not meet it
    (0.3, the range's floor), (0, 1) and (2, 1) at 0.8, (1, 1) not covered."""
    bounded = {(0, 0): (0.6, True), (1, 0): (1.0, True), (2, 0): (0.3, False),
               (0, 1): (0.8, True), (2, 1): (0.8, True)}
    assert neighbourhood_minimum(bounded) == {
        (0, 0): 0.6,   # its own is the smallest
        (1, 0): 0.6,   # (0, 0) beside it; (2, 0) did not meet the bound and does not count
        (2, 0): 0.3,   # keeps its own
        (0, 1): 0.6,   # (0, 0) below it; (1, 1) is not covered
        (2, 1): 0.8}   # (1, 0) at 1.0 and (2, 0) unbounded: its own


def test_the_scheduled_designs_failure_model_given_then_the_tunings_then_constant_vel_rol():
    """``schedule_failure_model``: an explicit model wins; a tuning naming one keeps it; a tuning
    naming none (the shipped ones) gets names.SCHEDULE_FAILURE_MODEL; a bad one is refused."""
    tuned = _tuned()
    cover = dataclasses.replace(tuned, failure_model="cover=VEL+AOA")
    assert schedule_failure_model(tuned) == "constant=VEL+ROL" == check_failure_model(names.SCHEDULE_FAILURE_MODEL)
    assert schedule_failure_model(cover) == "cover=VEL+AOA"
    assert schedule_failure_model(cover, "complete") == schedule_failure_model(tuned, "complete") == "complete"
    assert schedule_failure_model(tuned, {"default": "complete", "constant": ["AOA", "VEL"]}) == "constant=VEL+AOA"
    with pytest.raises(ValueError, match="component PIT has no trim uncertainty"):
        schedule_failure_model(tuned, "constant=PIT")


def test_the_scheduled_designs_failed_sensor_noise_given_then_the_tunings_then_the_sensors():
    """``schedule_failed_sensor_noise``: an explicit choice wins; a tuning naming ``sensor`` keeps
    it; a tuning naming none (``design``, the shipped ones) gets names.SCHEDULE_FAILED_SENSOR_NOISE;
    ``--failed-sensor-noise design`` reaches the design; a bad one is refused naming the choices."""
    tuned = load_tuning("tuned")
    own = dataclasses.replace(tuned, failed_sensor_noise="sensor")
    assert schedule_failed_sensor_noise(tuned) == names.SCHEDULE_FAILED_SENSOR_NOISE == "sensor"
    assert schedule_failed_sensor_noise(own) == "sensor"
    assert schedule_failed_sensor_noise(own, "design") == schedule_failed_sensor_noise(tuned, "design") == "design"
    with pytest.raises(ValueError, match="'loud' is not one of design, sensor"):
        schedule_failed_sensor_noise(tuned, "loud")


def test_the_failed_sensor_noise_flag_reaches_the_scheduled_design(monkeypatch, tmp_path, capsys):
    """``design --schedule --failed-sensor-noise design`` hands the paper's R to the design; a bad
    value is refused before any work, naming the flag and the choices."""
    import f16mmae.cli.design as cli_design

    seen = {}

    def record(grid, tuning, out, **kw):
        seen.update(kw)
        raise OSError("recorded")

    monkeypatch.setattr(cli_design, "design_schedule", record)
    out = str(tmp_path / "x.f16sched")
    assert main(["design", "--schedule", "--failed-sensor-noise", "design", "--out", out]) != 0
    assert seen["failed_sensor_noise"] == "design"
    seen.clear()
    assert main(["design", "--schedule", "--failed-sensor-noise", "loud", "--out", out]) == 2
    assert not seen and "--failed-sensor-noise: 'loud' is not one of design, sensor" in capsys.readouterr().err


GUST_GRID = "mach=0.5,alt=10000/20000"
SHIPPED = "constant=VEL+ROL"  # check_failure_model(names.SCHEDULE_FAILURE_MODEL), written out


@pytest.fixture(scope="module")
def gust_scheduled(tmp_path_factory):
    """Two nodes, the tuning as given at both (fixed: no calibration flights), gust states at
    the 10,000-ft node only; and the same grid without gust states."""
    d = tmp_path_factory.mktemp("gust_sched")
    common = ["design", "--schedule", GUST_GRID, "--node-tuning", "fixed", "--no-throttle-input", "--workers", "1"]
    assert main(common + ["--gust-states-below-ft", "12000", "--out", str(d / "gust.f16sched")]) == 0
    assert main(common + ["--out", str(d / "plain.f16sched")]) == 0
    return core.load_bank(d / "gust.f16sched"), core.load_bank(d / "plain.f16sched")


def test_gust_states_below_ft_designs_gust_nodes_and_pads_the_others(gust_scheduled, capsys):
    """The node at or below FT is the ordinary 19-state design with the gust counterpart of the
    tuning (gust_node_tuning); the node above it is its 13-state design padded with inert gust
    states; one state count in the file; the metadata says which nodes carry gust states."""
    gust, plain = gust_scheduled
    s = gust.schedule
    assert gust.nx == 19 and tuple(gust.state_names) == names.STATES + GUST_STATES
    by_alt = {n["alt_ft"]: n for n in s["nodes"]}
    tuning = _constant_vel(_tuned())
    low = design_bank(0.5, 10000.0, gust_node_tuning(tuning))
    assert low.continuous.gust_model == "dryden_states"
    assert by_alt[10000.0]["bank"].content_hash == _hash(low)
    high = pad_bank(to_model_bank(design_bank(0.5, 20000.0, tuning)).with_settings(dwell_nats_per_hypothesis={}))
    assert by_alt[20000.0]["bank"].content_hash == core.ModelBank.from_bytes(high.to_bytes()).content_hash
    assert len(by_alt[20000.0]["x_trim"]) == 19 and not np.asarray(by_alt[20000.0]["x_trim"])[names.NX:].any()
    meta = json.loads(s["metadata"])
    assert meta["gust_states"]["below_ft"] == 12000.0
    assert meta["gust_states"]["nodes"] == [{"mach": 0.5, "alt_ft": 10000.0}]
    assert meta["command"].endswith("--gust-states-below-ft 12000 --gust-node-choice all")   # re-runs as designed
    # the plain schedule's file has no gust key (the default's bytes are unchanged by the option)
    assert "gust_states" not in json.loads(plain.schedule["metadata"]) and plain.nx == names.NX
    # the gust tuning keeps the tuning's name (one per schedule) and takes the gust-state knobs
    g = gust_node_tuning(tuning)
    assert g.name == tuning.name and g.failure_model == tuning.failure_model
    assert g.qd_longitudinal == load_tuning("tuned_gust").qd_longitudinal
    assert gust_node_tuning(g) is g


def test_a_padded_node_flies_as_its_13_state_node(gust_scheduled):
    """At the padded node (nearest: that node alone) the estimator's probabilities are those of
    the schedule without gust states, frame for frame; between the nodes (interpolate: a gust
    and a padded node blended) the Python loop and the C++ loop fly the same."""
    gust, plain = gust_scheduled
    at_node = Scenario(mach=0.5, alt_ft=20000.0, turbulence="light", failures=(make_failure("LF", 3.0),),
                       duration_s=6.0, seed=11)
    runs = [fly(at_node, b, estimator=Estimator(b, schedule_mode="nearest"), engine="cpp") for b in (gust, plain)]
    assert runs[0].declarations == runs[1].declarations
    np.testing.assert_allclose(runs[0].probability_of("LF"), runs[1].probability_of("LF"), rtol=1e-7, atol=1e-12)
    between = Scenario(mach=0.5, alt_ft=15000.0, turbulence="light", failures=(make_failure("PIT", 3.0),),
                       duration_s=6.0, seed=12)
    py, cpp = (fly(between, gust, estimator=Estimator(gust, schedule_mode="interpolate"), engine=e)
               for e in ("python", "cpp"))
    assert py.declarations == cpp.declarations and py.declarations
    np.testing.assert_array_equal(py.probability_of("PIT"), cpp.probability_of("PIT"))


@pytest.mark.parametrize("args, message", [
    (["--schedule", GUST_GRID, "--gust-states-below-ft", "x"], "--gust-states-below-ft: gust states below 'x' ft: "
                                                               "not a number of feet"),
    (["--schedule", GUST_GRID, "--gust-states-below-ft", "nan"], "not a finite number of feet"),
    (["--schedule", GUST_GRID, "--gust-states-below-ft", "4000"], "gust states below 4000 ft: no node of the grid "
                                                                  "(altitudes 10000, 20000 ft) lies at or below it"),
    (["--schedule", GUST_GRID, "--gust-states-below-ft", "15000", "--tuning", "tuned_gust"],
     "the tuning tuned_gust already models gust states (dryden_states) at every node"),
    (["--gust-states-below-ft", "15000"], "--gust-states-below-ft applies to a scheduled design; give --schedule"),
])
def test_a_bad_gust_altitude_is_refused_before_any_work(args, message, tmp_path, capsys):
    out = tmp_path / "x.f16sched"
    assert main(["design", *args, "--out", str(out)]) != 0
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_gust_nodes_keep_their_own_settings_only_inside_the_gust_region():
    """3 x 3 grid, gust states on the two lower rows (j = 0, 1): the nodes of row 0 have only
    gust neighbours and keep their own floor and reference; row 1 borders row 2 (no gust
    states) and takes the neighbourhood rule as every plain node does."""
    covered = {(i, j) for i in range(3) for j in range(3)}
    gust = {(i, j) for i in range(3) for j in (0, 1)}
    keep = gust_neighbourhoods(covered, gust)
    assert keep == {(0, 0), (1, 0), (2, 0)}
    assert gust_neighbourhoods(covered - {(0, 1)}, gust - {(0, 1)}) == {(0, 0), (1, 0), (2, 0)}

    def record(p_min, ref):   # bounded_settings' record: one candidate floor, met
        return {"p_min": p_min, "bound_met": True, "adapt_reference": ref, "candidates": [[1e-9, ref, 0.0, 0.0, True]]}

    records = {k: record(1e-9, 0.9 if k[1] == 0 else 0.5) for k in covered}
    floors, refs = neighbourhood_settings(records, keep_own=keep)
    assert all(refs[(i, 0)] == 0.9 for i in range(3))        # own, though row 1 is lower
    assert all(refs[(i, j)] == 0.5 for i in range(3) for j in (1, 2))
    _, refs_rule = neighbourhood_settings(records)
    assert all(v == 0.5 for v in refs_rule.values())          # without keep_own: the neighbourhood's

    # a kept node's own floor above the rule's does not raise its neighbours' floor, nor
    # lower their reference to the one bounded at that floor: they keep the rule's pair
    def two(p_min, ref, low, high):   # candidates at floors 1e-9 and 1e-5, both met
        return {"p_min": p_min, "bound_met": True, "adapt_reference": ref,
                "candidates": [[1e-9, low, 0.0, 0.0, True], [1e-5, high, 0.0, 0.0, True]]}

    records = {k: two(1e-5, 0.7, 0.9, 0.7) if k[1] == 0 else two(1e-9, 0.8, 0.8, 0.4) for k in covered}
    floors, refs = neighbourhood_settings(records, keep_own=keep)
    assert all(refs[(i, 0)] == 0.7 for i in range(3))         # the kept node's own reference
    assert all(refs[(i, j)] == 0.8 for i in range(3) for j in (1, 2))
    assert all(floors[(i, 0)] == 1e-5 for i in range(3))      # the kept node's own floor ...
    assert all(floors[(i, j)] == 1e-9 for i in range(3) for j in (1, 2))   # ... not its neighbours'


def test_the_floors_are_the_chosen_ones_and_the_references_bounded_at_the_neighbourhoods_floor():
    """3 x 3 grid: the nodes of rows 0 and 1 chose the floor 1e-5 (reference 0.6 there), row 2 1e-9
    (reference 0.9); steps 1-2 give row 0 the floor 1e-5 (its neighbours' least that met the bound),
    rows 1 and 2 1e-9, so the neighbourhood's floor P is 1e-5 for rows 0 and 1 and their reference
    the one bounded there, 0.6, row 2's 0.9; the floors in the file are those of step 1 (the
    estimator lowers the floor in force in rough air itself)."""
    def two(p_min):   # candidates at floors 1e-9 and 1e-5, both met; the reference is lower at 1e-5
        return {"p_min": p_min, "bound_met": True, "adapt_reference": 0.6 if p_min > 1e-9 else 0.9,
                "candidates": [[1e-9, 0.9, 0.0, 0.0, True], [1e-5, 0.6, 0.0, 0.0, True]]}

    records = {(i, j): two(1e-5 if j <= 1 else 1e-9) for i in range(3) for j in range(3)}
    floors, refs = neighbourhood_settings(records)
    assert all(floors[(i, j)] == (1e-5 if j == 0 else 1e-9) for i in range(3) for j in range(3))
    assert all(refs[(i, j)] == (0.6 if j <= 1 else 0.9) for i in range(3) for j in range(3))


def test_each_cell_bounds_its_corners_references_at_its_own_floor():
    """3 x 4 grid: rows 0-2 chose the floor 1e-5 (reference 1.0 at both floors), row 3 1e-9 with
    0.8 there and 0.5 at 1e-5.  Step 1 gives row 2 the floor 1e-9 (row 3 beside it), rows 0-1 1e-5.
    A node of row 2 touches cells below that blend 1e-5 (1.0 there) and cells above that blend
    1e-9 (0.8 at row 3): its reference is 0.8, not row 3's 0.5 at the floor of the cells below.
    And on random grids every cell's blend is bounded: each corner's reference is at most every
    met corner's bounded reference at the largest floor of step 1 among the cell's corners."""
    def rec(p_min, at_low, at_high):
        return {"p_min": p_min, "bound_met": True, "adapt_reference": at_low,
                "candidates": [[1e-9, at_low, 0.0, 0.0, True], [1e-5, at_high, 0.0, 0.0, True]]}

    records = {(i, j): rec(1e-9, 0.8, 0.5) if j == 3 else rec(1e-5, 1.0, 1.0) for i in range(3) for j in range(4)}
    floors, refs = neighbourhood_settings(records)
    assert [floors[(1, j)] for j in range(4)] == [1e-5, 1e-5, 1e-9, 1e-9]
    assert [refs[(1, j)] for j in range(4)] == [1.0, 1.0, 0.8, 0.8]

    rng = np.random.default_rng(3)
    floors_ = (1e-9, 1e-7, 1e-5, 1e-3)
    for _ in range(20):
        recs = {}
        for i in range(4):
            for j in range(4):
                if rng.random() < 0.1:
                    continue   # an untrimmable point
                refs_at = np.sort(rng.choice(np.arange(0.4, 1.01, 0.02), size=4))[::-1]   # falls with the floor
                met = rng.random(4) < 0.9
                recs[(i, j)] = {"p_min": floors_[rng.integers(4)], "bound_met": True, "adapt_reference": 1.0,
                                "candidates": [[f, float(r), 0.0, 0.0, bool(m)] for f, r, m in zip(floors_, refs_at, met)]}
        step1 = neighbourhood_minimum({k: (r["p_min"], r["bound_met"]) for k, r in recs.items()})
        _, refs = neighbourhood_settings(recs)
        at = {k: {row[0]: (row[1], row[4]) for row in r["candidates"]} for k, r in recs.items()}
        for ci in range(3):
            for cj in range(3):
                corners = [(ci + a, cj + b) for a in (0, 1) for b in (0, 1) if (ci + a, cj + b) in recs]
                if len(corners) < 2:
                    continue
                top = max(step1[k] for k in corners)
                for k in corners:
                    assert refs[k] <= min([at[k][top][0]] + [at[n][top][0] for n in corners if at[n][top][1]]) + 1e-12


def test_a_node_beside_an_untrimmable_point_takes_its_smallest_floor_and_keeps_its_reference():
    """3 x 3 grid with (0, 2) left out (untrimmable): its neighbours (0, 1), (1, 1), (1, 2) take
    their smallest candidate floor, 1e-9, and keep the reference bounded at the neighbourhood's
    floor (1e-5); every other node is as without the edge (the neighbourhood rule)."""
    def two(p_min):   # candidates at floors 1e-9 and 1e-5, both met; the reference is lower at 1e-5
        return {"p_min": p_min, "bound_met": True, "adapt_reference": 0.6,
                "candidates": [[1e-9, 0.9, 0.0, 0.0, True], [1e-5, 0.6, 0.0, 0.0, True]]}

    records = {(i, j): two(1e-5) for i in range(3) for j in range(3) if (i, j) != (0, 2)}
    plain_floors, plain_refs = neighbourhood_settings(records)
    floors, refs = neighbourhood_settings(records, untrimmable={(0, 2)})
    beside = {(0, 1), (1, 1), (1, 2)}
    assert refs == plain_refs and set(plain_refs.values()) == {0.6}   # bounded at 1e-5, as without the edge
    assert all(floors[k] == 1e-9 for k in beside)
    assert all(floors[k] == plain_floors[k] == 1e-5 for k in records if k not in beside)


def test_a_low_node_keeps_gust_states_only_where_its_calibration_gains():
    """gust_gains on bounded_settings records: strictly less declaration effort with the gust
    states at the smallest candidate floor, s (ln(thr/(1-thr)) - floor's log-odds), keeps them,
    whatever the efforts at the larger floors; a tie or more does not; a design that met its
    bound there wins over one that did not; records without candidates, or of different
    floors, are refused."""
    from f16mmae.design.calibrate import declaration_effort
    from f16mmae.design.schedule import floor_effort, gust_gains

    def rec(s_low, s_high=1.0, met=True):   # floors 1e-9 and 1e-5: [p_min, reference, peak, s, met]
        return {"candidates": [[1e-5, 0.5, -3.0, s_high, True], [1e-9, 0.7, -7.0, s_low, met]]}

    assert floor_effort(rec(1.3)) == (1e-9, round(float(declaration_effort(1e-9, 0.9, 1.3)), 2), True)
    assert floor_effort(rec(1.0))[1] == 22.92                            # ln 9 + the climb from 1e-9
    assert not gust_gains(rec(1.295), rec(1.621))        # Mach 0.8, 10,000 ft of the default grid
    assert gust_gains(rec(3.06), rec(1.0))                # Mach 0.8, 5,000 ft
    assert not gust_gains(rec(1.0, s_high=5.0), rec(1.0, s_high=1.0))   # a tie at 1e-9: plain
    assert gust_gains(rec(1.0, met=False), rec(4.0))
    assert not gust_gains(rec(4.0), rec(1.0, met=False))
    with pytest.raises(ValueError, match="no calibration candidates"):
        gust_gains(rec(1.0), {"p_min": 1e-9})
    with pytest.raises(ValueError, match="smallest floors differ"):
        gust_gains(rec(1.0), {"candidates": [[1e-7, 0.7, -7.0, 1.0, True]]})


@pytest.mark.parametrize("args, message", [
    (["--schedule", GUST_GRID, "--gust-states-below-ft", "none", "--gust-node-choice", "effort"],
     "--gust-node-choice chooses among the nodes at or below --gust-states-below-ft, and this design has none"),
    (["--schedule", GUST_GRID, "--node-tuning", "fixed", "--gust-node-choice", "all"],
     "--gust-node-choice chooses among the nodes at or below --gust-states-below-ft, and this design has none"),
    (["--schedule", GUST_GRID, "--gust-states-below-ft", "12000", "--gust-node-choice", "some"],
     "--gust-node-choice 'some': valid: all, effort"),
    (["--schedule", GUST_GRID, "--gust-states-below-ft", "12000", "--gust-node-choice", "effort",
      "--node-tuning", "fixed"], "--gust-node-choice effort compares each node's calibration"),
    (["--gust-node-choice", "effort"], "--gust-node-choice applies to a scheduled design"),
])
def test_a_bad_gust_node_choice_is_refused_before_any_work(args, message, tmp_path, capsys):
    out = tmp_path / "x.f16sched"
    assert main(["design", *args, "--out", str(out)]) != 0
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_design_schedule_refuses_the_effort_choice_without_calibration(tmp_path):
    from f16mmae.design.schedule import design_schedule

    with pytest.raises(ScheduleSpecError, match="needs the node tuning calibrated"):
        design_schedule(parse_grid(GUST_GRID), "tuned", tmp_path / "x.f16sched", node_tuning="fixed",
                        gust_states_below_ft=12000, gust_node_choice="effort")
    with pytest.raises(ScheduleSpecError, match="gust node choice 'x' is not one of all, effort"):
        design_schedule(parse_grid(GUST_GRID), "tuned", tmp_path / "x.f16sched",
                        gust_states_below_ft=12000, gust_node_choice="x")
    assert not (tmp_path / "x.f16sched").exists()


def test_the_effort_choice_keeps_each_low_node_s_better_design(tmp_path, monkeypatch):
    """Two low nodes designed with and without gust states; the calibration (flights, knobs,
    bounded pair) replaced by records whose scale s at the floor says the gust design gains at
    Mach 0.5 and loses at Mach 0.6 (the workers fork with the replacement): the file keeps the 19-state
    design at 0.5 and the 13-state design, padded, at 0.6, whose filters are design_bank's at
    the point; the metadata lists both efforts of each node and the nodes with gust states."""
    import types

    from f16mmae.design import schedule as sched

    def bounded(model_bank, flights, candidates, start_up_s=0.0, running_start=False):
        gusty = len(model_bank.state_names) > names.NX
        scale = {(0.5, True): 1.0, (0.5, False): 2.0, (0.6, True): 3.0, (0.6, False): 2.0}[
            (round(model_bank.mach, 6), gusty)]
        return {"p_min": 1e-9, "adapt_reference": 0.6, "failure_log_odds_peak": -7.0, "bound_met": True,
                "scale": scale, "effort": 0.0, "candidates": [[1e-9, 0.6, -7.0, scale, True]]}

    ratios = types.SimpleNamespace(var_over_a=[1.0] * len(names.SENSORS))
    monkeypatch.setattr(sched, "node_flights", lambda mach, alt_ft, turbulence: ())
    monkeypatch.setattr(sched, "calm_reference", lambda bank, calm, light: (0.55, 0.5, 0.6))
    monkeypatch.setattr(sched, "calibrate_node", lambda mach, alt_ft, tun, linearized, flights: (tun, ratios, ratios))
    monkeypatch.setattr(sched, "bounded_settings", bounded)
    monkeypatch.setattr(sched, "adaptation_reference", lambda design, flights: 1.0)
    out = tmp_path / "choice.f16sched"
    s = sched.design_schedule(parse_grid("mach=0.5/0.6,alt=10000"), "tuned", out, workers=2, flap_layers=False,
                              gust_states_below_ft=12000, gust_node_choice="effort")
    f = core.load_bank(out).schedule
    meta = json.loads(f["metadata"])
    assert meta["command"].endswith("--gust-states-below-ft 12000 --gust-node-choice effort")
    assert meta["gust_states"]["nodes"] == [{"mach": 0.5, "alt_ft": 10000.0}]
    assert meta["gust_states"]["efforts"] == [
        {"mach": 0.5, "alt_ft": 10000.0, "gust": True, "effort_plain": 45.84, "effort_gust": 22.92},
        {"mach": 0.6, "alt_ft": 10000.0, "gust": False, "effort_plain": 45.84, "effort_gust": 68.76}]
    assert s["covered"] == 2
    # each node's calm-air reference (format 4) and its two means in the node records
    assert [n["calm_reference"] for n in f["nodes"]] == [0.55, 0.55]
    assert [(r["calm_reference"], r["power_ratio_calm"], r["power_ratio_light"]) for r in meta["nodes"]] == [
        (0.55, 0.5, 0.6)] * 2
    assert "midway between its no-failure flights" in meta["calm_reference"]
    nodes = {n["mach"]: n["bank"] for n in f["nodes"]}
    ng = len(GUST_STATES)
    gust_phi = np.asarray(nodes[0.5].hypotheses[0].phi)
    assert np.abs(gust_phi[names.NX:, names.NX:]).max() > 0           # live gust states
    tuned = _constant_vel(_tuned())
    plain = pad_bank(to_model_bank(design_bank(0.6, 10000.0, tuned)))
    for h, want in zip(nodes[0.6].hypotheses, plain.hypotheses):   # the plain design, padded
        np.testing.assert_array_equal(np.asarray(h.phi), np.asarray(want.phi))
        np.testing.assert_array_equal(np.asarray(h.k), np.asarray(want.k))
        assert not np.asarray(h.phi)[names.NX:, :].any() and np.asarray(h.k)[-ng:].sum() == 0


def test_the_bound_s_flights_and_bank_come_from_the_command(tmp_path, monkeypatch):
    """--calibration-flight-s and --calibration-bank: the knobs are calibrated on the
    NODE_FLIGHT_S-second flights as before, the floor and reference bounded on flights of the
    given length (the same seeds) and on the node's own bank (its constant VEL) or its complete
    one; the command and the note say which. The calibration is replaced by recorders (the
    workers fork with them): the bounded reference names the flights' length and the bank."""
    import types

    from f16mmae.design import schedule as sched

    def flights(mach, alt_ft, turbulence, duration_s=NODE_FLIGHT_S):
        return (types.SimpleNamespace(duration_s=duration_s),)

    def bounded(model_bank, flights, candidates, start_up_s=0.0, running_start=False):
        own = bool(np.asarray(model_bank.hypotheses[names.ALL_HYPOTHESES.index("VEL")].uninformative_level_q).any())
        reference = round(0.3 + flights[0].duration_s / 100 + (0.05 if own else 0.0), 6)
        return {"p_min": 1e-9, "adapt_reference": reference, "failure_log_odds_peak": -7.0, "bound_met": True,
                "scale": 1.0, "effort": 0.0, "candidates": [[1e-9, reference, -7.0, 1.0, True]]}

    ratios = types.SimpleNamespace(var_over_a=[1.0] * len(names.SENSORS))
    monkeypatch.setattr(sched, "node_flights", flights)
    monkeypatch.setattr(sched, "calm_reference", lambda bank, calm, light: (0.55, 0.5, 0.6))
    monkeypatch.setattr(sched, "calibrate_node", lambda mach, alt_ft, tun, linearized, flights: (
        (tun, ratios, ratios) if flights[0].duration_s == NODE_FLIGHT_S else None))
    monkeypatch.setattr(sched, "bounded_settings", bounded)
    monkeypatch.setattr(sched, "adaptation_reference", lambda design, flights: 1.0)
    for kw, reference, tail in (({}, 0.38, "--failure-model constant=VEL+ROL --gust-states-below-ft none"),
                                ({"calibration_flight_s": 60.0, "calibration_bank": "own"}, 0.95,
                                 "--calibration-flight-s 60 --calibration-bank own --failure-model constant=VEL+ROL"),
                                ({"calibration_bank": "own"}, 0.43, "--calibration-bank own --failure-model")):
        out = tmp_path / "bound.f16sched"
        sched.design_schedule(parse_grid("mach=0.5/0.6,alt=25000"), "tuned", out, workers=1, flap_layers=False, **kw)
        f = core.load_bank(out).schedule
        meta = json.loads(f["metadata"])
        assert [n["adapt_reference"] for n in f["nodes"]] == [reference, reference]
        assert tail in meta["command"]
        own = kw.get("calibration_bank") == "own"
        assert ("bounded on the node's own bank" in meta["tuning_note"]) == own
        assert ("over 60-s flights of the same seeds" in meta["tuning_note"]) == ("calibration_flight_s" in kw)
    with pytest.raises(ScheduleSpecError, match="calibration bank 'x' is not one of complete, own"):
        sched.design_schedule(parse_grid("mach=0.5,alt=25000"), "tuned", out, calibration_bank="x")


def test_a_scaled_calibration_carries_each_node_s_power_ratio_over_its_complete_bank_s(tmp_path, monkeypatch):
    """--calibration-bank scaled: the floor and reference bounded on the node's complete bank, and
    each node carries sigma = rho-bar(own) / rho-bar(scale model) on the same flights (schedule
    format 5), recorded with both means; the estimator on the file holds the node's reference and
    sigma (before air data the primary node's). The calibration and the measured power ratios are
    replaced by recorders (the workers fork with them): the own bank (the cover AOA) reads 0.8 at
    Mach 0.5 and 0.9 at 0.6 of the scale model's (constant VEL) 0.5, and the complete bank 0.625."""
    import types

    from f16mmae.design import schedule as sched

    def free(model_bank, sensor):
        return bool(np.asarray(model_bank.hypotheses[names.ALL_HYPOTHESES.index(sensor)].uninformative_level_q).any())

    def bounded(model_bank, flights, candidates, start_up_s=0.0, running_start=False):
        reference = 0.7 if free(model_bank, "AOA") else 0.6
        return {"p_min": 1e-9, "adapt_reference": reference, "failure_log_odds_peak": -7.0, "bound_met": True,
                "scale": 1.0, "effort": 0.0, "candidates": [[1e-9, reference, -7.0, 1.0, True]]}

    def measured(model_bank, flights):
        if free(model_bank, "AOA"):
            return {0.5: 0.4, 0.6: 0.45}[round(model_bank.mach, 6)]
        return 0.5 if free(model_bank, "VEL") else 0.625

    ratios = types.SimpleNamespace(var_over_a=[1.0] * len(names.SENSORS))
    monkeypatch.setattr(sched, "node_flights", lambda mach, alt_ft, turbulence, duration_s=NODE_FLIGHT_S: ())
    monkeypatch.setattr(sched, "calm_reference", lambda bank, calm, light: (0.55, 0.5, 0.6))
    monkeypatch.setattr(sched, "calibrate_node", lambda mach, alt_ft, tun, linearized, flights: (tun, ratios, ratios))
    monkeypatch.setattr(sched, "bounded_settings", bounded)
    monkeypatch.setattr(sched, "adaptation_reference", lambda design, flights: 1.0)
    monkeypatch.setattr(sched, "measured_power_ratio", measured)
    out = tmp_path / "scaled.f16sched"
    cover = "cover=AOA,constant=VEL+ROL"
    for scale_model, sigma in ((names.SCHEDULE_SCALE_MODEL, (0.8, 0.9)), ("complete", (0.64, 0.72))):
        sched.design_schedule(parse_grid("mach=0.5/0.6,alt=25000"), "tuned", out, workers=1, flap_layers=False,
                              failure_model=cover, calibration_bank="scaled", scale_model=scale_model)
        bank = core.load_bank(out)
        f = bank.schedule
        meta = json.loads(f["metadata"])
        assert f"--calibration-bank scaled --scale-model {scale_model} --failure-model" in meta["command"]
        assert f"of the failure model {scale_model} on the same flights" in meta["tuning_note"]
        assert [n["adapt_reference"] for n in f["nodes"]] == [0.6, 0.6]   # bounded on the complete bank
        assert tuple(n["reference_scale"] for n in f["nodes"]) == sigma
        assert [(r["power_ratio_own"], r["power_ratio_scale_model"], r["reference_scale"]) for r in meta["nodes"]] == [
            (0.4, round(0.4 / sigma[0], 3), sigma[0]), (0.45, round(0.45 / sigma[1], 3), sigma[1])]
    primary = f["nodes"][f["primary"]]
    hb = core.HierarchicalBank(bank, adapt_turbulence=True)
    assert hb.reference_scale == primary["reference_scale"]
    assert hb.adapt_reference == 0.6 and hb.turbulence_scale == 1.0
    sched.design_schedule(parse_grid("mach=0.5,alt=25000"), "tuned", out, workers=1, flap_layers=False)
    plain = core.load_bank(out)
    assert plain.schedule["nodes"][0]["reference_scale"] is None   # complete: no scale, format 4
    assert core.HierarchicalBank(plain, adapt_turbulence=True).reference_scale == 1.0


@pytest.mark.parametrize("argv, shape", [
    ([], (SHIPPED, 20000.0, "all", "calibrated")),        # the shipped default (names.SCHEDULE_*)
    (["--gust-states-below-ft", "none"], (SHIPPED, None, "all", "calibrated")),
    (["--failure-model", "constant=VEL", "--gust-states-below-ft", "none"], ("constant=VEL", None, "all", "calibrated")),
    (["--gust-states-below-ft", "10000"], (SHIPPED, 10000.0, "all", "calibrated")),
    (["--gust-node-choice", "effort"], (SHIPPED, 20000.0, "effort", "calibrated")),
    (["--no-throttle-input"], (SHIPPED, 20000.0, "all", "calibrated")),   # revision 14's five inputs
    (["--node-tuning", "fixed"], (SHIPPED, None, "all", "fixed")),
    (["--node-tuning", "fixed", "--gust-states-below-ft", "15000"], (SHIPPED, 15000.0, "all", "fixed")),
    (["--tuning", "tuned_gust"], (SHIPPED, None, "all", "calibrated")),   # gust states at every node already
    (["mach=0.4/0.5,alt=25000"], (SHIPPED, None, "all", "calibrated")),   # no node at or below 20,000 ft
])
def test_design_schedule_without_flags_designs_the_shipped_default(argv, shape, monkeypatch, tmp_path):
    """``f16mmae design --schedule`` without flags hands the design the shipped default's
    failure model, gust-state altitude, node choice and throttle input (names.SCHEDULE_*, the
    values the cached ``scheduled`` bank is generated with); ``--gust-states-below-ft none``,
    ``--failure-model`` and ``--no-throttle-input`` give the former shapes; the defaults step
    aside where they cannot apply.
    The design itself is replaced by a recorder: nothing is designed."""
    import f16mmae.cli.design as cli_design

    seen = {}

    def record(grid, tuning, out, **kw):
        seen.update(kw, grid=grid)
        raise OSError("recorded")    # the CLI's own refusal path: nothing written

    monkeypatch.setattr(cli_design, "design_schedule", record)
    grid = [a for a in argv if a.startswith("mach=")]
    flags = [a for a in argv if not a.startswith("mach=")]
    assert main(["design", "--schedule", *grid, *flags, "--out", str(tmp_path / "x.f16sched")]) != 0
    got = (seen["failure_model"], seen["gust_states_below_ft"], seen["gust_node_choice"], seen["node_tuning"])
    assert got == shape
    assert seen["throttle_input"] is ("--no-throttle-input" not in argv)   # the default's sixth input
    if not argv:   # one source: the generator of the cached default takes the same names
        assert got == (check_failure_model(names.SCHEDULE_FAILURE_MODEL), names.SCHEDULE_GUST_STATES_BELOW_FT,
                       names.SCHEDULE_GUST_NODE_CHOICE, names.SCHEDULE_NODE_TUNING)
        assert seen["throttle_input"] is names.SCHEDULE_THROTTLE_INPUT
        assert format_spec(seen["grid"]) == format_spec(parse_grid(names.SCHEDULE_GRID))
    assert seen["failed_sensor_noise"] == names.SCHEDULE_FAILED_SENSOR_NOISE == "sensor"   # no flag above names one
