"""The per-hypothesis tempering (``--set-tempering W``; cpp/f16mmae/turbulence_adaptation.h): the
option reaches the core as the weight and the fully tempered hypotheses' bits, bad values are
refused by name, and on each frame at most one hypothesis' likelihood differs from the shipped
tempering's: the best-fitting failure hypothesis, never NONE or a fully tempered one. Its gate on
the measured rho (``--set-tempering-rho``) leaves every likelihood the shipped one below it, its
margin (``--set-tempering-margin``) forms the spared likelihood over the best of NONE and the fully
tempered hypotheses (with ``--set-tempering-margin-stabilators`` over NONE and the stabilators only),
and the options reach ``mmae-daemon`` as flags that its ready line names."""
from __future__ import annotations

import subprocess

import numpy as np
import pytest

import f16mmae.design.turbulence_banks  # noqa: F401  (registers the turbulence bank set with banks.py)
from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.design.turbulence_banks import set_path
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.loop.estimator import core_arguments
from f16mmae.loop.estimator_options import check, check_requirements
from f16mmae.names import ADAPT_SET_TEMPERING_FULL, ADAPT_SET_TEMPERING_ROUGH, SET_TEMPERING_FULL, SINGLE_HYPOTHESES

from daemon_support import ready_line


def test_the_option_becomes_the_weight_and_the_fully_tempered_hypotheses_bits():
    args = core_arguments({"set_tempering": 0.25, "turbulence_banks": True})
    assert args["adapt_hypothesis_weight"] == 0.25
    bits = args["adapt_full_tempering"]
    assert [h for i, h in enumerate(SINGLE_HYPOTHESES) if bits >> i & 1] == list(SET_TEMPERING_FULL)
    assert bits & 0b110 == 0b110   # the stabilators (LS, RS: level-0 slots 1 and 2) among them
    assert "set_tempering" not in args
    assert "adapt_hypothesis_weight" not in core_arguments({})
    # a bank's own adaptation keeps the gust-mimicked sensors at s too: AZ, AOA and VEL
    own = core_arguments({"set_tempering": 0.25, "adapt_turbulence": True})["adapt_full_tempering"]
    assert [h for i, h in enumerate(SINGLE_HYPOTHESES) if own >> i & 1] == ["LS", "RS", "LF", "RF", "VEL", "AOA", "AZ"]
    assert sorted(ADAPT_SET_TEMPERING_FULL) == sorted(["LS", "RS", "LF", "RF", "VEL", "AOA", "AZ"])
    check({"set_tempering": 0.25, "adapt_turbulence": True})


def test_with_a_bank_s_own_adaptation_the_daemon_takes_it_and_names_it():
    bank = load_bank("tuned")[2]
    options = {"adapt_turbulence": True, "set_tempering": 0.25}
    flags = daemon_flags(options)
    assert flags[flags.index("--set-tempering-full") + 1] == "LS,RS,LF,RF,VEL,AOA,AZ"
    ready = ready_line("--bank", load_bank("tuned")[1], *flags)
    bits = core_arguments(options)["adapt_full_tempering"]
    assert f"set tempering 0.25 from rho 0 full {bits}" in ready, ready
    # in process the same bits reach the core
    core.HierarchicalBank(bank, **core_arguments(options))


def test_bad_values_are_refused_by_name():
    with pytest.raises(ValueError, match="--set-tempering"):
        check({"set_tempering": 0.0, "turbulence_banks": True})
    with pytest.raises(ValueError, match="--set-tempering"):
        check({"set_tempering": 1.5, "turbulence_banks": True})
    with pytest.raises(ValueError, match="--set-tempering applies with --adapt-turbulence or --turbulence-banks only"):
        check({"set_tempering": 0.5})
    check({"set_tempering": 0.5, "turbulence_banks": True})
    bank = load_bank("turbulence")[2]
    with pytest.raises(ValueError, match="adapt_hypothesis_weight"):
        core.HierarchicalBank(bank, adapt_turbulence=True, adapt_hypothesis_weight=0.0)
    with pytest.raises(ValueError, match="adapt_hypothesis_weight below 1 needs the common scale"):
        core.HierarchicalBank(bank, adapt_turbulence=True, adapt_hypothesis_weight=0.5, adapt_channel_weight=0.5)


def test_only_the_best_fitting_failure_hypothesis_is_spared():
    bank = load_bank("turbulence")[2]
    full = core_arguments({"set_tempering": 0.25, "turbulence_banks": True})["adapt_full_tempering"]
    kw = dict(adapt_turbulence=True, adapt_reference=0.6, adapt_time_constant_s=1.0, p_min=1e-9)
    plain = core.HierarchicalBank(bank, **kw)
    spared = core.HierarchicalBank(bank, adapt_hypothesis_weight=0.25, adapt_full_tempering=full, **kw)
    rng = np.random.default_rng(7)
    z_trim, u_trim = np.asarray(bank.z_trim), np.asarray(bank.u_trim)
    sigma = np.sqrt(np.diag(np.asarray(bank.hypotheses[0].a)))
    differing, first = 0, None
    for i in range(192):   # 3 s of residuals 3 times the design's: s rises above 1
        z = z_trim + 3.0 * sigma * rng.standard_normal(len(z_trim))
        for b in (plain, spared):
            b.update(z)
            b.propagate(u_trim)
        if plain.level != 0 or spared.level != 0:
            break
        assert plain.turbulence_scale == spared.turbulence_scale   # the raw forms drive s
        diff = np.nonzero(np.asarray(plain.log_likelihoods) != np.asarray(spared.log_likelihoods))[0]
        assert len(diff) <= 1
        if len(diff):
            k = int(diff[0])
            assert k != 0 and not (full >> k & 1)
            assert plain.turbulence_scale > 1.0
            differing += 1
            first = i if first is None else first
    assert differing > 50
    assert first > 8   # not before the scale has caught up with the air (rho >= rho-bar / 2)


def test_the_gate_reaches_the_core_and_the_daemon():
    options = {"turbulence_banks": True, "set_tempering": 0.25, "set_tempering_rho": 2.68}
    check(options)
    args = core_arguments(options)
    assert args["adapt_spare_rho"] == 2.68
    assert "set_tempering_rho" not in args
    assert "adapt_spare_rho" not in core_arguments({"set_tempering": 0.25})
    with pytest.raises(ValueError, match="--set-tempering"):
        check({"turbulence_banks": True, "set_tempering_rho": 2.68})
    with pytest.raises(ValueError, match="--set-tempering-rho"):
        check({"turbulence_banks": True, "set_tempering": 0.25, "set_tempering_rho": -1.0})
    flags = daemon_flags(options)
    assert flags[flags.index("--set-tempering") + 1] == "0.25"
    assert flags[flags.index("--set-tempering-full") + 1] == ",".join(SET_TEMPERING_FULL)
    assert flags[flags.index("--set-tempering-rho") + 1] == "2.68"
    daemon = str(find_executable("mmae-daemon"))
    ready = ready_line("--bank", set_path(), *flags)
    bits = args["adapt_full_tempering"]
    assert f"set tempering 0.25 from rho 2.68 full {bits}" in ready, ready
    for bad, message in ((["--turbulence-banks", "--set-tempering-rho", "2"], "--set-tempering-rho applies with --set-tempering only"),
                         (["--turbulence-banks", "--set-tempering", "0"],
                          "--set-tempering must be a weight in (0, 1], got '0'"),
                         (["--set-tempering", "0.5"], "--set-tempering applies with --adapt-turbulence or --turbulence-banks only")):
        r = subprocess.run([daemon, "--bank", str(set_path()), *bad], capture_output=True, text=True, timeout=20)
        assert r.returncode == 2 and message in r.stdout + r.stderr, (bad, r.stdout + r.stderr)
    r = subprocess.run([daemon, "--bank", str(set_path()), "--turbulence-banks", "--set-tempering", "0.5",
                        "--set-tempering-full", "LS,XYZ", "--lcm-url", "memq://"], capture_output=True, text=True,
                       timeout=20)
    assert r.returncode == 1 and "the bank has no failure hypothesis XYZ" in r.stderr, r.stderr


def _rough_flight(banks, seconds=3.0):
    """The banks fed the same rough residuals (3 times the design's) at level 0; per frame, the
    log-likelihoods of each."""
    bank = load_bank("turbulence")[2]
    rng = np.random.default_rng(7)
    z_trim, u_trim = np.asarray(bank.z_trim), np.asarray(bank.u_trim)
    sigma = np.sqrt(np.diag(np.asarray(bank.hypotheses[0].a)))
    out = []
    for _ in range(int(64 * seconds)):
        z = z_trim + 3.0 * sigma * rng.standard_normal(len(z_trim))
        for b in banks:
            b.update(z)
            b.propagate(u_trim)
        if any(b.level != 0 for b in banks):
            break
        out.append([np.asarray(b.log_likelihoods).copy() for b in banks])
    return out


def test_below_the_gate_every_likelihood_is_the_shipped_one():
    bank = load_bank("turbulence")[2]
    full = core_arguments({"set_tempering": 0.25, "turbulence_banks": True})["adapt_full_tempering"]
    kw = dict(adapt_turbulence=True, adapt_reference=0.6, adapt_time_constant_s=1.0, p_min=1e-9,
              adapt_own_channels=True)
    spare = dict(adapt_hypothesis_weight=0.25, adapt_full_tempering=full)
    plain = core.HierarchicalBank(bank, **kw)
    gated = core.HierarchicalBank(bank, adapt_spare_rho=100.0, **spare, **kw)   # rho-bar never reaches 100
    open_ = core.HierarchicalBank(bank, adapt_spare_rho=0.5, **spare, **kw)      # rho-bar above 0.5 throughout
    raw = core.HierarchicalBank(bank, **spare, **kw)
    frames = _rough_flight([plain, gated, open_, raw])
    assert len(frames) > 150
    spared = 0
    for l_plain, l_gated, l_open, l_raw in frames:
        assert np.array_equal(l_plain, l_gated)
        assert np.array_equal(l_open, l_raw)
        diff = np.nonzero(l_raw != l_plain)[0]
        assert len(diff) <= 1
        if len(diff):
            assert diff[0] != 0 and not (full >> int(diff[0]) & 1)
            spared += 1
    assert spared > 50


def _severe_stabilator_flight(banks):
    """The banks fed the z and u of a 6-s severe flight with LS stuck at 3 s (a tuning seed), at level 0;
    per frame, the log-likelihoods of each."""
    from f16mmae.loop.flight import fly
    from f16mmae.names import FAILURE_TIME_S
    from f16mmae.seeds import derived_seed, tuning_seeds
    from f16mmae.truth import Scenario
    from f16mmae.truth.failures import make_failure
    seed = derived_seed("single", 1, "LS", 1)
    assert seed in tuning_seeds()
    frames = []
    scenario = Scenario(turbulence="severe", duration_s=6.0, seed=seed, feedback="raw",
                        failures=(make_failure("LS", FAILURE_TIME_S, "complete", None),))
    fly(scenario, load_bank("turbulence")[2], estimator_options={"turbulence_banks": True},
        on_frame=lambda t, u, z, air: frames.append((z, u)))
    out = []
    for z, u in frames:
        for b in banks:
            b.update(z)
            b.propagate(u)
        if any(b.level != 0 for b in banks):
            break
        out.append([np.asarray(b.log_likelihoods).copy() for b in banks])
    return out


def test_the_margin_spares_the_same_hypothesis_over_the_best_of_none_and_the_fully_tempered():
    """``--set-tempering-margin``: on the same frames the margin spares the hypothesis the raw
    rule spares, its likelihood formed over q_r = min(q_0, q_f: f fully tempered) in place of q_0
    (turbulence_adaptation.h); recomputed here from the shipped bank's l_k = -q_k / (2 s) and the
    raw rule's s / s_b."""
    options = {"turbulence_banks": True, "set_tempering": 0.25, "set_tempering_margin": True}
    check(options)
    assert core_arguments(options)["adapt_spare_margin"] is True
    assert "adapt_spare_margin" not in core_arguments({"set_tempering": 0.25})
    with pytest.raises(ValueError, match="--set-tempering"):
        check({"turbulence_banks": True, "set_tempering_margin": True})
    assert "--set-tempering-margin" in daemon_flags(options)
    bank = load_bank("turbulence")[2]
    full = core_arguments({"set_tempering": 0.25, "turbulence_banks": True})["adapt_full_tempering"]
    kw = dict(adapt_turbulence=True, adapt_reference=0.6, adapt_time_constant_s=1.0, p_min=1e-9,
              adapt_own_channels=True, adapt_hypothesis_weight=0.25, adapt_full_tempering=full)
    plain = core.HierarchicalBank(bank, **{k: v for k, v in kw.items() if k not in ("adapt_hypothesis_weight",
                                                                                    "adapt_full_tempering")})
    stabilators = core_arguments({**options, "set_tempering_margin_stabilators": True})["adapt_spare_margin_over"]
    assert stabilators == sum(1 << SINGLE_HYPOTHESES.index(h) for h in ("LS", "RS"))
    raw = core.HierarchicalBank(bank, **kw)
    margin = core.HierarchicalBank(bank, adapt_spare_margin=True, **kw)
    over = core.HierarchicalBank(bank, adapt_spare_margin=True, adapt_spare_margin_over=stabilators, **kw)
    full_slots = [k for k in range(len(SINGLE_HYPOTHESES)) if full >> k & 1]
    stabilator_slots = [k for k in range(len(SINGLE_HYPOTHESES)) if stabilators >> k & 1]
    spared = lowered = 0
    for l_plain, l_raw, l_margin, l_over in _severe_stabilator_flight([plain, raw, margin, over]):
        d_raw, d_margin = np.nonzero(l_raw != l_plain)[0], np.nonzero(l_margin != l_plain)[0]
        assert len(d_raw) <= 1 and len(d_margin) <= len(d_raw)
        assert len(np.nonzero(l_over != l_plain)[0]) <= len(d_raw)
        if not len(d_raw):
            continue
        b = int(d_raw[0])
        q = -2.0 * l_plain                                   # q_k / s
        ratio = (-2.0 * l_raw[b] - q[0]) / (q[b] - q[0])     # s / s_b
        q_r = min(q[0], *q[full_slots])
        assert l_margin[b] == pytest.approx(-0.5 * (q_r + (q[b] - q_r) * ratio), rel=1e-9, abs=1e-9)
        q_s = min(q[0], *q[stabilator_slots])                # the margin over NONE and the stabilators only
        assert l_over[b] == pytest.approx(-0.5 * (q_s + (q[b] - q_s) * ratio), rel=1e-9, abs=1e-9)
        spared += 1
        lowered += q_r < q[0]
    assert spared > 50 and lowered > 20   # the failed stabilator (or a flaperon) fits better than NONE at times


def test_the_daemon_flies_the_margin_and_names_it():
    options = {"turbulence_banks": True, "set_tempering": 0.15, "set_tempering_rho": 2.68,
               "set_tempering_margin": True}
    flags = daemon_flags(options)
    daemon = str(find_executable("mmae-daemon"))
    ready = ready_line("--bank", set_path(), *flags)
    bits = core_arguments(options)["adapt_full_tempering"]
    assert f"set tempering 0.15 from rho 2.68 margin full {bits}" in ready, ready
    flags = daemon_flags({**options, "set_tempering_margin_stabilators": True})
    assert flags[flags.index("--set-tempering-margin-over") + 1] == "LS,RS"
    ready = ready_line("--bank", set_path(), *flags)
    over = core_arguments({**options, "set_tempering_margin_stabilators": True})["adapt_spare_margin_over"]
    assert f"set tempering 0.15 from rho 2.68 margin over {over} full {bits}" in ready, ready
    r = subprocess.run([daemon, "--bank", str(set_path()), "--turbulence-banks", "--set-tempering", "0.15",
                        "--set-tempering-margin-over", "LS,RS"], capture_output=True, text=True, timeout=20)
    assert r.returncode == 2 and "--set-tempering-margin-over applies with --set-tempering-margin only" in r.stdout + r.stderr
    r = subprocess.run([daemon, "--bank", str(set_path()), "--turbulence-banks", "--set-tempering-margin"],
                       capture_output=True, text=True, timeout=20)
    assert r.returncode == 2 and "--set-tempering-margin applies with --set-tempering only" in r.stdout + r.stderr


def test_the_spare_dwell_reaches_the_core_and_the_daemon():
    """``--set-tempering-dwell S`` (hierarchical_bank.h spare_dwell_s): a keyword of the core, refused
    there outside [a frame, the longest dwell] and without the per-hypothesis tempering; a flag of
    ``mmae-daemon`` that its ready line names (the dwell's rule itself: test_hierarchical_bank.cpp)."""
    options = {"turbulence_banks": True, "set_tempering": 0.15, "set_tempering_rho": 2.68,
               "spare_dwell_s": 0.0625}
    check(options)
    assert core_arguments(options)["spare_dwell_s"] == 0.0625
    with pytest.raises(ValueError, match="--set-tempering"):
        check({"turbulence_banks": True, "spare_dwell_s": 0.0625})
    with pytest.raises(ValueError, match="--set-tempering-dwell"):
        check({**options, "spare_dwell_s": -1.0})
    bank = load_bank("turbulence")[2]
    full = core_arguments({"set_tempering": 0.15, "turbulence_banks": True})["adapt_full_tempering"]
    kw = dict(adapt_turbulence=True, adapt_hypothesis_weight=0.15, adapt_full_tempering=full)
    assert core.HierarchicalBank(bank, spare_dwell_s=0.0625, **kw).level == 0
    with pytest.raises(ValueError, match=r"spare_dwell_s must be 0 \(off\) or in \[0.015625, 60\] s"):
        core.HierarchicalBank(bank, spare_dwell_s=0.01, **kw)
    with pytest.raises(ValueError, match="spare_dwell_s 0.0625 applies while the per-hypothesis tempering spares"):
        core.HierarchicalBank(bank, spare_dwell_s=0.0625, adapt_turbulence=True)
    flags = daemon_flags(options)
    assert flags[flags.index("--set-tempering-dwell") + 1] == "0.0625"
    daemon = str(find_executable("mmae-daemon"))
    ready = ready_line("--bank", set_path(), *flags)
    assert f"set tempering 0.15 from rho 2.68 full {full} dwell 0.0625 s" in ready, ready
    r = subprocess.run([daemon, "--bank", str(set_path()), "--turbulence-banks", "--set-tempering-dwell", "0.0625"],
                       capture_output=True, text=True, timeout=20)
    assert r.returncode == 2 and "--set-tempering-dwell applies with --set-tempering only" in r.stdout + r.stderr


def test_the_rough_air_set_reaches_the_core_and_the_daemon():
    options = {"adapt_turbulence": True, "set_tempering": 0.25, "set_tempering_rough": 9.0}
    check(options)
    args = core_arguments(options)
    assert args["adapt_rough_rho"] == 9.0
    bits = args["adapt_rough_tempering"]
    assert [h for i, h in enumerate(SINGLE_HYPOTHESES) if bits >> i & 1] == list(ADAPT_SET_TEMPERING_ROUGH) == ["RUD", "AY"]
    assert not bits & args["adapt_full_tempering"]   # spared in calmer air: not among the always fully tempered
    assert "set_tempering_rough" not in args
    assert "adapt_rough_tempering" not in core_arguments({**options, "set_tempering_rough": 0.0})   # 0: off
    with pytest.raises(ValueError, match="--set-tempering-rough applies with --set-tempering"):
        check({"turbulence_banks": True, "set_tempering_rough": 9.0})
    with pytest.raises(ValueError, match="--set-tempering-rough applies with --set-tempering only .the bank is not sch"):
        check_requirements({"adapt_turbulence": True, "set_tempering_rough": 9.0}, scheduled=False)
    with pytest.raises(ValueError, match="--set-tempering-rough"):
        check({**options, "set_tempering_rough": -1.0})
    flags = daemon_flags(options)
    assert flags[flags.index("--set-tempering-rough") + 1] == "9.0"
    assert flags[flags.index("--set-tempering-rough-full") + 1] == "RUD,AY"
    assert "--set-tempering-rough-weight" not in flags and "adapt_rough_weight" not in args   # the core's 1: the full s
    ready = ready_line("--bank", load_bank("tuned")[1], *flags)
    assert f"full {args['adapt_full_tempering']} rough {bits} from rho 9 weight 1" in ready, ready
    shared = {**options, "set_tempering_rough_weight": 0.5}   # the scheduled default's share
    check(shared)
    assert core_arguments(shared)["adapt_rough_weight"] == 0.5
    flags = daemon_flags(shared)
    assert flags[flags.index("--set-tempering-rough-weight") + 1] == "0.5"
    assert f"rough {bits} from rho 9 weight 0.5" in ready_line("--bank", load_bank("tuned")[1], *flags)
    with pytest.raises(ValueError, match="--set-tempering-rough-weight"):
        check({**shared, "set_tempering_rough_weight": 0.0})
    daemon = str(find_executable("mmae-daemon"))
    for bad, message in ((["--adapt-turbulence", "--set-tempering", "0.25", "--set-tempering-rough-full", "RUD"],
                          "--set-tempering-rough-full applies with --set-tempering-rough only"),
                         (["--adapt-turbulence", "--set-tempering", "0.25", "--set-tempering-rough", "-1"],
                          "--set-tempering-rough must be a power ratio in [0, 100], got '-1'")):
        r = subprocess.run([daemon, "--bank", str(load_bank("tuned")[1]), *bad], capture_output=True, text=True,
                           timeout=20)
        assert r.returncode == 2 and message in r.stdout + r.stderr, (bad, r.stdout + r.stderr)


def test_in_rough_air_its_hypotheses_are_tempered_fully_and_below_it_spared_as_before():
    bank = load_bank("turbulence")[2]
    full = core_arguments({"set_tempering": 0.25, "turbulence_banks": True})["adapt_full_tempering"]
    spared_ones = sum(1 << k for k in range(1, len(SINGLE_HYPOTHESES)) if not full >> k & 1)
    kw = dict(adapt_turbulence=True, adapt_reference=0.6, adapt_time_constant_s=1.0, p_min=1e-9,
              adapt_own_channels=True, adapt_hypothesis_weight=0.25, adapt_full_tempering=full)
    raw = core.HierarchicalBank(bank, **kw)
    calm = core.HierarchicalBank(bank, adapt_rough_rho=100.0, adapt_rough_tempering=spared_ones, **kw)
    rough = core.HierarchicalBank(bank, adapt_rough_rho=0.5, adapt_rough_tempering=spared_ones, **kw)
    plain = core.HierarchicalBank(bank, **{**kw, "adapt_hypothesis_weight": 1.0})
    assert rough.fully_tempered == full   # before the first update the air's rho is 0
    assert rough.power_scale == 1.0       # a bank without a schedule: rho in its own units
    frames = _rough_flight([raw, calm, rough, plain])
    assert len(frames) > 150
    assert rough.air_power_ratio >= 0.5 and rough.fully_tempered == full | spared_ones
    assert calm.fully_tempered == full
    spared = 0
    for l_raw, l_calm, l_rough, l_plain in frames:
        assert np.array_equal(l_calm, l_raw)     # never rough: every frame as without the rough-air set
        assert np.array_equal(l_rough, l_plain)  # rough throughout, every hypothesis fully tempered: none spared
        spared += int(not np.array_equal(l_raw, l_plain))
    assert spared > 50
