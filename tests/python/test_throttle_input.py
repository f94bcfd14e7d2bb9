"""The throttle as the estimator's sixth modelled input (``f16mmae design --throttle-input``):
the design against SciPy (the zero-order hold of the throttle column, the DARE gains), the
fixed-size 6-input core bank against covariance-propagating Kalman filters with a hand Bayes
update (test_core_filter_bank's reference), the bank file and the recorded command."""
from __future__ import annotations

import dataclasses
import json
from itertools import combinations

import numpy as np
import pytest
from scipy.linalg import expm, solve_discrete_are

from f16mmae import core, names
from f16mmae.cli import main as cli
from f16mmae.design import bank
from f16mmae.design.linearize import throttle_column
from f16mmae.design.model import linearize_truth
from f16mmae.design.schedule import schedule_failed_sensor_noise, schedule_failure_model
from f16mmae.design.tuning import load_tuning
from f16mmae.truth import aircraft
from f16mmae.truth.sensors import NOISE_SIGMA
from test_core_filter_bank import CovarianceKalmanBank

SINGLES = names.SINGLE_HYPOTHESES


@pytest.fixture(scope="module")
def linearized():
    return linearize_truth(bank.NOMINAL_MACH, bank.NOMINAL_ALT_FT, throttle=True)


@pytest.fixture(scope="module")
def designs(linearized):
    calm = dataclasses.replace(load_tuning("tuned"), turbulence="none")
    return (bank.design_bank(tuning=calm, hypotheses=SINGLES, linearized=linearized),
            bank.design_bank(tuning=calm, hypotheses=SINGLES, linearized=linearized, throttle_input=True))


def test_throttle_column_is_jsbsims_own_linearization(linearized):
    fdm, _ = aircraft.trimmed_fdm(mach=bank.NOMINAL_MACH, alt_ft=bank.NOMINAL_ALT_FT)
    np.testing.assert_array_equal(linearized.throttle_column, throttle_column(fdm))
    assert linearized.throttle_column[0] == pytest.approx(26.9, abs=0.1)  # ft/s^2 of u' per unit command


def test_sixth_column_is_the_zero_order_hold_and_the_rest_is_unchanged(designs, linearized):
    five, six = designs
    assert six.throttle_input and not five.throttle_input
    assert six.input_names == names.INPUTS_WITH_THROTTLE
    assert six.u_trim[-1] == linearized.trim.throttle and np.array_equal(six.u_trim[:5], five.u_trim)
    dt = 1.0 / six.frame_rate_hz
    f = six.continuous.f
    n = f.shape[0]
    aug = np.zeros((n + 1, n + 1))  # [[F, b], [0, 0]] dt: exp gives [[Phi, Bd], [0, 1]]
    aug[:n, :n] = f
    aug[:8, n] = linearized.throttle_column
    bd_th = expm(aug * dt)[:n, n]
    for f5, f6 in zip(five.filters, six.filters):
        assert f6.model.bd.shape == (n, 6)
        # the surfaces' columns as before, to rounding: a wider exponential may scale differently
        np.testing.assert_allclose(f6.model.bd[:, :5], f5.model.bd, rtol=1e-12, atol=1e-14 * np.abs(f5.model.bd).max())
        np.testing.assert_allclose(f6.model.bd[:, 5], bd_th, rtol=1e-9, atol=1e-12)  # never a failure
        for g6, g5 in ((f6.gains.k, f5.gains.k), (f6.gains.a, f5.gains.a)):  # the gain does not depend on B
            np.testing.assert_allclose(g6, g5, rtol=0.0, atol=1e-10 * np.abs(g5).max())


def test_gains_are_scipys_dare_on_the_six_input_model(designs):
    six = designs[1]
    for name in ("NONE", "LS", "VEL"):
        m = six.filter(name)
        p = solve_discrete_are(m.model.phi.T, m.model.h.T, m.model.qd, six.r)
        a = m.model.h @ p @ m.model.h.T + six.r
        k = p @ m.model.h.T @ np.linalg.inv(a)  # compared on each matrix's scale: SciPy's Schur solver
        np.testing.assert_allclose(m.gains.a, a, rtol=0.0, atol=1e-7 * np.abs(a).max())  # is the less exact
        np.testing.assert_allclose(m.gains.k, k, rtol=0.0, atol=1e-7 * np.abs(k).max())


def _plant(seed):
    rng = np.random.default_rng(seed)
    phi = rng.standard_normal((names.NX, names.NX))
    phi *= 0.95 / max(abs(np.linalg.eigvals(phi)))
    return (phi, rng.standard_normal((names.NX, 6)), rng.standard_normal((names.NZ, names.NX)),
            1e-3 * np.eye(names.NX), 1e-3 * np.eye(names.NZ))


def _hypothesis(phi, bd, h, q, r, failed):
    bd, h = bd.copy(), h.copy()
    for c in failed:
        if c in names.ACTUATORS:
            bd[:, names.ACTUATORS.index(c)] = 0.0  # the throttle's column (index 5) is never removed
        else:
            h[names.SENSORS.index(c), :] = 0.0
    p_prior = solve_discrete_are(phi.T, h.T, q, r)
    a = h @ p_prior @ h.T + r
    a = 0.5 * (a + a.T)
    return dict(phi=phi, bd=bd, h=h, k=p_prior @ h.T @ np.linalg.inv(a), a=a, p_prior=p_prior)


def test_fixed_size_six_input_bank_equals_covariance_kalman_filters():
    phi, bd, h, q, r = _plant(7)
    comps = names.ACTUATORS + names.SENSORS
    hyp = {"NONE": _hypothesis(phi, bd, h, q, r, [])}
    hyp.update({c: _hypothesis(phi, bd, h, q, r, [c]) for c in comps})
    hyp.update({f"{a}+{b}": _hypothesis(phi, bd, h, q, r, [a, b]) for a, b in combinations(comps, 2)})
    u_trim = np.array([-0.03, -0.03, 0.0, 0.0, 0.0, 0.25])
    z_trim = np.array([414.8, 0.14, 0.0, 1.0, 0.0, 0.0, 0.0])
    mb = core.ModelBank([(n, {k: v for k, v in hyp[n].items() if k != "p_prior"}) for n in names.ALL_HYPOTHESES],
                        state_names=[f"x{i}" for i in range(names.NX)], input_names=list(names.INPUTS_WITH_THROTTLE),
                        measurement_names=list(names.SENSORS), frame_rate_hz=64.0, u_trim=u_trim, z_trim=z_trim,
                        h_output=h)
    hb = core.HierarchicalBank(mb, p_min=0.001)
    assert hb.fixed_size and mb.nu == 6
    singles = [hyp[n] for n in SINGLES]
    ref = CovarianceKalmanBank(singles, q, r, p_min=0.001, strip=True)
    blind = CovarianceKalmanBank([dict(s, bd=np.hstack([s["bd"][:, :5], np.zeros((names.NX, 1))]))
                                  for s in singles], q, r, p_min=0.001, strip=True)  # the throttle unmodelled
    rng = np.random.default_rng(3)
    x, worst_blind = np.zeros(names.NX), 0.0
    for i in range(96):
        z = h @ x + rng.multivariate_normal(np.zeros(names.NZ), r)
        u = 0.05 * np.sin(2 * np.pi * np.array([0.7, 1.1, 1.3, 1.7, 2.3, 0.4]) * i / 64.0)
        u[5] = 0.5 * np.sin(2 * np.pi * 0.4 * i / 64.0)  # the throttle dither
        hb.step(z + z_trim, u + u_trim)
        p_ref, _ = ref.step(z, u)
        p_blind, _ = blind.step(z, u)
        np.testing.assert_allclose(hb.probabilities, p_ref, rtol=0, atol=1e-8)
        worst_blind = max(worst_blind, float(np.abs(p_blind - p_ref).max()))
        x = phi @ x + bd @ u + rng.multivariate_normal(np.zeros(names.NX), q)
    assert hb.level == 0 and hb.declarations == []
    assert worst_blind > 1e-3  # the test sees the sixth input: without it the probabilities differ
    with pytest.raises(ValueError, match="u"):
        hb.step(z_trim, u_trim[:5])


def test_design_throttle_input_writes_a_six_input_bank_its_command_reproduces(tmp_path):
    out = tmp_path / "calm_throttle.f16bank"
    assert cli.main(["design", "--throttle-input", "--gust-level", "none", "--out", str(out)]) == 0
    mb = core.load_bank(str(out))
    assert mb.nu == 6 and tuple(mb.input_names) == names.INPUTS_WITH_THROTTLE
    meta = json.loads(mb.metadata)
    assert meta["command"].endswith("--tuning tuned --gust-level none --throttle-input")
    assert meta["model"]["throttle_column_per_unit"][0] == pytest.approx(26.9, abs=0.1)
    again = tmp_path / "again.f16bank"
    assert cli.main(meta["command"].split()[1:] + ["--out", str(again)]) == 0
    assert again.read_bytes() == out.read_bytes()
    hb = core.HierarchicalBank(mb)
    assert hb.fixed_size
    for _ in range(64):  # at the trim (throttle included) nothing is declared
        hb.step(mb.z_trim, mb.u_trim)
    assert hb.declarations == [] and hb.probabilities[0] > 0.9


def test_one_bank_models_the_throttle_only_when_asked_and_the_turbulence_set_refuses_the_choice(tmp_path, capsys):
    """`design` without the flag (or with --no-throttle-input) is the five-input bank; the
    scheduled design's default is names.SCHEDULE_THROTTLE_INPUT (test_schedule_design.py), and
    --turbulence-banks, whose members are designed as it chooses, refuses either form."""
    plain, off = tmp_path / "plain.f16bank", tmp_path / "off.f16bank"
    assert cli.main(["design", "--out", str(plain)]) == 0
    assert cli.main(["design", "--no-throttle-input", "--out", str(off)]) == 0
    assert core.load_bank(str(plain)).nu == 5 and plain.read_bytes() == off.read_bytes()
    capsys.readouterr()
    for flag in ("--throttle-input", "--no-throttle-input"):
        assert cli.main(["design", "--turbulence-banks", flag, "--out", str(tmp_path / "s.f16set")]) == 2
        assert "--turbulence-banks designs its own members" in capsys.readouterr().err


@pytest.mark.slow
def test_a_scheduled_throttle_bank_runs_six_inputs_at_every_node(tmp_path, capsys):
    """`design --schedule ... --throttle-input`: every node is the point's 6-input design (its
    throttle column JSBSim's at that point), the file reproduces from its command, and the core
    schedules it as a throttle bank."""
    out = tmp_path / "s.f16sched"
    args = ["design", "--schedule", "mach=0.4/0.5,alt=20000", "--node-tuning", "fixed", "--flap-layers", "off",
            "--throttle-input", "--workers", "2", "--out", str(out)]
    assert cli.main(args) == 0
    mb = core.load_bank(str(out))
    meta = json.loads(mb.schedule["metadata"])
    assert meta["throttle_input"] is True and " --throttle-input" in meta["command"]
    assert mb.nu == 6 and tuple(mb.input_names) == names.INPUTS_WITH_THROTTLE
    nodes = {n["mach"]: n["bank"] for n in mb.schedule["nodes"]}
    assert sorted(nodes) == [0.4, 0.5]
    tuned = load_tuning("tuned")   # with the scheduled design's failure model and failed sensors' noise
    tuned = dataclasses.replace(tuned, failure_model=schedule_failure_model(tuned),   # and the frame dwell alone
                                failed_sensor_noise=schedule_failed_sensor_noise(tuned),
                                estimator={k: v for k, v in tuned.estimator.items() if k != "dwell_nats_per_hypothesis"})
    for m, node in nodes.items():  # each node is that point's own throttle design
        single = bank.to_model_bank(bank.design_bank(m, 20000.0, tuned, throttle_input=True))
        assert node.content_hash == core.ModelBank.from_bytes(single.to_bytes()).content_hash
        assert node.nu == 6
    again = tmp_path / "again.f16sched"
    assert cli.main(args[:-1] + [str(again)]) == 0
    assert again.read_bytes() == out.read_bytes()
    hb = core.HierarchicalBank(mb)
    assert hb.fixed_size
    # at the trim with the sensors' noise nothing is declared (a reading exactly at its trim,
    # frame after frame, is what the constant-level hypotheses of VEL and ROL expect of a failure)
    rng = np.random.default_rng(3)
    for _ in range(64):
        hb.schedule(0.45, 20000.0)
        hb.step(mb.z_trim + NOISE_SIGMA * rng.standard_normal(names.NZ), mb.u_trim)
    assert hb.declarations == []


@pytest.fixture(scope="module")
def throttle_bank(tmp_path_factory, linearized):
    calm = dataclasses.replace(load_tuning("tuned"), turbulence="none")
    path = tmp_path_factory.mktemp("throttle") / "calm_throttle.f16bank"
    return bank.write_bank(bank.design_bank(tuning=calm, linearized=linearized, throttle_input=True), path)


@pytest.mark.slow
def test_closed_loop_flies_the_scheduled_throttle_dither_and_hands_its_command_to_the_bank(throttle_bank):
    from f16mmae.loop.flight import fly
    from f16mmae.truth import Scenario
    from f16mmae.truth.dither import scheduled_throttle_amplitude
    from f16mmae.truth.failures import make_failure

    sc = Scenario(turbulence="none", duration_s=4.0, seed=3, failures=(make_failure("VEL", 1.0),))
    assert not sc.dither.throttle_on
    in_cpp = fly(sc, throttle_bank)  # the whole flight in C++
    frames = []
    in_py = fly(sc, throttle_bank, on_frame=lambda t, u, z, a: frames.append((u, a)))  # frame by frame
    assert in_cpp.scenario["dither"]["throttle_schedule"] is True  # the record says what the truth flew
    assert in_cpp.declarations == in_py.declarations
    np.testing.assert_array_equal(in_cpp.probabilities, in_py.probabilities)
    u = np.array([f[0] for f in frames])
    air = np.array([f[1] for f in frames])
    assert u.shape == (len(frames), 6)
    t = np.arange(len(frames)) / names.FRAME_RATE_HZ
    a = np.array([scheduled_throttle_amplitude(m, h) for m, h in air])  # on the measured air data
    np.testing.assert_allclose(u[:, 5], throttle_bank.u_trim[5] + a * np.sin(2 * np.pi * 0.1 * t), atol=1e-4)
    assert a.mean() == pytest.approx(0.9 * 0.0239, rel=0.01)
    assert [d["hypothesis"] for d in in_cpp.declarations][:1] == ["VEL"]


@pytest.mark.slow
def test_lockstep_over_memq_with_a_throttle_bank_equals_the_in_process_run_and_its_frames_replay(throttle_bank):
    """The command frame carries the throttle: the LCM executive (core.Executive, served on
    memq://) runs the 6-input bank on it exactly as the in-process closed loop does, and the
    frames it received, fed to a fresh executive, give the same statuses; a command frame
    without its throttle is rejected by this bank."""
    import lcm

    from f16mmae.lcm.channels import channels
    from f16mmae.lcm.codec import command_of
    from f16mmae.lcm.hil import fly_hil
    from f16mmae.lcm.replay import InProcessExecutive
    from f16mmae.lcmt_command_frame import lcmt_command_frame
    from f16mmae.lcmt_mmae_status import lcmt_mmae_status
    from f16mmae.lcmt_sensor_frame import lcmt_sensor_frame
    from f16mmae.loop.flight import fly
    from f16mmae.truth import Scenario
    from f16mmae.truth.failures import make_failure

    sc = Scenario(turbulence="none", duration_s=3.0, seed=3, failures=(make_failure("VEL", 0.5),))
    lc = lcm.LCM("memq://")
    chans = channels("THR_")
    served = InProcessExecutive(throttle_bank)
    assert served.executive.nu == 6
    served.serve(lc, chans)
    wire = []  # every frame the executive received, in order
    for ch in (chans.sensors, chans.commands):
        lc.subscribe(ch, lambda channel, data: wire.append((channel, data)))
    remote = fly_hil(sc, throttle_bank, lc, chans, lockstep=True, timeout_s=2.0)
    lc.handle_timeout(100)  # the last command frame, which no status follows
    local = fly(sc, throttle_bank)
    assert remote.hypotheses == local.hypotheses
    assert np.nanmax(np.abs(remote.probabilities - local.probabilities)) == 0.0
    assert remote.declarations == local.declarations
    assert [d["hypothesis"] for d in remote.declarations][:1] == ["VEL"]
    assert served.executive.counters["commands_applied"] == 192 and served.executive.counters["frames_rejected"] == 0
    commands = [lcmt_command_frame.decode(d) for c, d in wire if c == chans.commands]
    throttles = np.array([f.throttle for f in commands])
    assert np.all(np.isfinite(throttles)) and throttles.std() > 1e-3  # the dithered throttle crossed
    # the same frames into a fresh executive: the same statuses
    again = InProcessExecutive(throttle_bank)
    last = None
    for ch, data in wire:
        if ch == chans.sensors:
            f = lcmt_sensor_frame.decode(data)
            last = again.on_sensor(f.frame, f.z, list(f.valid), f.utime, (f.mach, f.pressure_altitude_ft))
        else:
            f = lcmt_command_frame.decode(data)
            assert again.on_command(f.frame, command_of(f), f.utime) == "used"
    assert last.declared == remote.final_hypothesis == "VEL"
    served_last = lcmt_mmae_status.decode(served.executive.encoded_status)
    assert last.frame == served_last.frame == 191
    assert list(last.probabilities) == list(served_last.probabilities)
    # five values (no throttle) to this bank: refused by the binding, NaN on the wire rejected
    with pytest.raises(ValueError, match="throttle"):
        again.executive.on_command(192, np.asarray(throttle_bank.u_trim)[:5])
    nan_throttle = np.asarray(throttle_bank.u_trim).copy()
    nan_throttle[5] = np.nan
    assert again.on_command(192, nan_throttle) == "rejected"


def _maneuvering_throttles(engine, sc):
    """Per frame: the outer loop's throttle (python engine: the lever the pilot set before
    advance; NaN on cpp, where it flies inside the frames) and the command advance wrote."""
    from f16mmae.truth import FlightControlSystem, TruthModel
    from f16mmae.truth.outer_loop import THROTTLE_PROPERTY

    truth = TruthModel(sc, engine=engine)
    fcs = FlightControlSystem(truth.trim, sc, pilot=truth.pilot())
    truth.attach(fcs)
    z, outer, sent = truth.measure(), [], []
    for _ in range(int(round(sc.duration_s * names.FRAME_RATE_HZ))):
        if engine == "python":
            u = fcs.command(z, truth.time_s)
            outer.append(truth.fdm[THROTTLE_PROPERTY])
            truth.advance(u)
            z = truth.measure()
        else:
            outer.append(np.nan)
            _, z = truth.step(fcs, z)
        sent.append(truth.last_throttle_command)
    truth.detach(fcs)
    truth.close()
    return np.array(outer), np.array(sent)


def test_in_maneuvers_the_throttle_dither_rides_on_the_outer_loops_throttle_in_both_engines():
    """th_i = sat(outer loop's throttle_i + a sin(2 pi f t_i), 0, 1) (hand-computed here from
    the lever the pilot set), and the C++ frames write the same commands bit for bit."""
    from f16mmae.truth import Scenario
    from f16mmae.truth.dither import DitherSpec

    sc = Scenario(turbulence="none", duration_s=5.0, seed=5, feedback="raw",
                  dither=DitherSpec(throttle_amplitude=0.03, throttle_frequency_hz=0.7),
                  maneuvers=("decel@0.2:to=0.3mach:rate=0.05mach/s",))
    outer, sent = _maneuvering_throttles("python", sc)
    t = np.arange(len(sent)) / names.FRAME_RATE_HZ
    expected = np.clip(outer + 0.03 * np.sin(2 * np.pi * 0.7 * t), 0.0, 1.0)
    np.testing.assert_allclose(sent, expected, rtol=0, atol=1e-15)
    assert np.ptp(outer) > 0.2                                # the pilot moved the lever
    assert (sent == 0.0).any() and (sent > 0.0).any()         # the slow-down idles it: clamped
    _, sent_cpp = _maneuvering_throttles("cpp", sc)
    np.testing.assert_array_equal(sent_cpp, sent)


@pytest.mark.slow
def test_a_throttle_bank_flies_maneuvers_with_the_dither_on_the_outer_loop_alike_in_cpp_and_python(throttle_bank):
    """The closed loop with a throttle bank and maneuvers (the scheduled dither on the outer
    loop's throttle): the whole flight in C++, frame by frame and on the Python engine give the
    same declarations and probabilities, and u carries the throttle command the truth wrote."""
    from f16mmae.loop.flight import fly
    from f16mmae.truth import Scenario

    sc = Scenario(turbulence="none", duration_s=4.0, seed=7, maneuvers=("climb@0.5:to=20400ft:rate=3000fpm",
                                                                         "turn@1:bank=30"))
    one_call = fly(sc, throttle_bank)
    assert one_call.scenario["dither"]["throttle_schedule"] is True
    frames = []
    per_frame = fly(sc, throttle_bank, on_frame=lambda t, u, z, a: frames.append(u))
    python = fly(sc, throttle_bank, engine="python")
    for other in (per_frame, python):
        assert other.declarations == one_call.declarations
        np.testing.assert_array_equal(other.probabilities, one_call.probabilities)
    th = np.array(frames)[:, 5]
    assert np.all((th >= 0) & (th <= 1)) and np.ptp(th) > 0.01  # the pilot's lever moved, dither on it


def test_actuator_limits_pass_the_throttle_through_and_limit_the_surfaces(throttle_bank):
    """--actuator-limits with 6 inputs: the throttle (no actuator: +inf limits) reaches the
    filters unchanged; the surfaces are limited as in a 5-input bank. A finite limit on the
    throttle is refused by name (it drives no lag state), and the daemon gets 'inf'."""
    from f16mmae.lcm.daemon import daemon_flags
    from f16mmae.loop.estimator import Estimator, core_arguments
    from f16mmae.truth.actuators import POSITION_LIMIT_RAD, RATE_LIMIT_RAD_S

    args = core_arguments({"actuator_limits": True}, 6)
    assert args["actuator_rate_limits_rad_s"] == [*RATE_LIMIT_RAD_S, float("inf")]
    flags = daemon_flags({"actuator_limits": True}, 6)
    assert flags[flags.index("--actuator-rate-limits") + 1].endswith(",inf")
    limited, free = Estimator(throttle_bank, actuator_limits=True), Estimator(throttle_bank)
    u_trim, z_trim = np.asarray(throttle_bank.u_trim), np.asarray(throttle_bank.z_trim)
    for i in range(64):  # inside every limit: the same probabilities (u_eff = u to rounding)
        u = u_trim + 0.002 * np.sin(0.3 * i + np.arange(6))
        u[5] = u_trim[5] + 0.02 * np.sin(0.1 * i)
        for e in (limited, free):
            e.update(z_trim)
            e.propagate(u)
    np.testing.assert_allclose(limited.probabilities, free.probabilities, rtol=0, atol=1e-9)
    finite = dict(core_arguments({"actuator_limits": True}, 6))
    finite["actuator_rate_limits_rad_s"] = [*RATE_LIMIT_RAD_S, 1.0]
    finite["actuator_position_limits_rad"] = [*POSITION_LIMIT_RAD, 1.0]
    with pytest.raises(ValueError, match="input 5 drives no first-order lag state"):
        core.HierarchicalBank(throttle_bank, **finite)


def test_paced_hil_with_a_throttle_bank_sends_the_throttle_with_every_command(throttle_bank):
    """Free-running (paced, 64 Hz wall clock) over memq://: every command frame carries the
    frame's throttle command, so the throttle bank applies each (none rejected)."""
    import lcm

    from f16mmae.lcm.channels import channels
    from f16mmae.lcm.hil import fly_hil
    from f16mmae.lcm.replay import InProcessExecutive
    from f16mmae.truth import Scenario

    lc = lcm.LCM("memq://")
    chans = channels("THRP_")
    served = InProcessExecutive(throttle_bank)
    served.serve(lc, chans)
    result = fly_hil(Scenario(turbulence="none", duration_s=0.5, seed=4), throttle_bank, lc, chans, lockstep=False)
    while lc.handle_timeout(100) > 0:   # the commands a loaded host left queued (memq:// loses none)
        pass
    link = result.timing["link"]
    assert link["statuses"] + link["deadline_misses"] == 32  # a loaded host may make a status late
    assert served.executive.counters["commands_applied"] == 32 and served.executive.counters["frames_rejected"] == 0


@pytest.mark.slow
def test_the_loop_cost_of_a_throttle_bank_is_measured_with_the_throttle_dither_on_both_sides(throttle_bank):
    """`bench truth` with a bank that models the throttle: the closed loop (``fly`` adds the
    scheduled throttle dither for such a bank) and the truth alone fly the same dither."""
    from f16mmae.loop.overhead import measure_overhead
    from f16mmae.truth import Scenario

    sc = Scenario(turbulence="none", duration_s=1.0, seed=3)
    assert not sc.dither.throttle_on
    cost = measure_overhead(sc, throttle_bank, repeats=1, pieces=True)
    assert cost["ratio"] > 0.0 and np.isfinite(cost["ratio"])
    assert cost["truth_frames_s"] > 0.0 and cost["closed_loop_frames_s"] > 0.0
