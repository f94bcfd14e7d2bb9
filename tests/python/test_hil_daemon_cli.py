"""mmae-daemon's and `f16mmae hil`'s refusals: each bad input exits non-zero with a message
naming it (no multicast needed: the daemon refuses before it listens, hil over memq://)."""
from __future__ import annotations

import argparse
import re
import subprocess

import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.cli.main import main
from f16mmae.cli.options import add_estimator_arguments, estimator_options_from_args
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.loop.estimator_options import CORE_ONLY, ESTIMATOR_OPTIONS, HARNESS_ONLY
from f16mmae.truth.actuators import POSITION_LIMIT_RAD, RATE_LIMIT_RAD_S

from daemon_support import ready_line

DAEMON = str(find_executable("mmae-daemon"))  # part of every build: a missing daemon fails here


def _daemon(*args):
    p = subprocess.run([DAEMON, *args], capture_output=True, text=True, timeout=20)
    return p.returncode, p.stdout + p.stderr


def test_daemon_refuses_bad_arguments_banks_and_urls(tmp_path):
    bank = str(load_bank("tuned")[1])
    rc, out = _daemon()
    assert rc == 2 and "--bank FILE is required" in out
    rc, out = _daemon("--bank", bank, "--rate-hz", "fast")
    assert rc == 2 and "'fast'" in out
    rc, out = _daemon("--bank", bank, "--start-up-s", "nan")
    assert rc == 2 and "--start-up-s must be a time in seconds in [0, 3600], got 'nan'" in out
    rc, out = _daemon("--bank", bank, "--air-data-time-constant", "-0.5")
    assert rc == 2 and ("--air-data-time-constant must be a time constant in seconds in [0, 60] (0: no low-pass), "
                        "got '-0.5'") in out
    rc, out = _daemon("--bank", bank, "--air-data-time-constant", "61")
    assert rc == 2 and "got '61'" in out
    rc, out = _daemon("--bank", bank, "--frobnicate")
    assert rc == 2 and "unknown argument '--frobnicate'" in out and "valid options" in out
    rc, out = _daemon("--bank", bank, "--warm-lead-us", "16000")
    assert rc == 2 and "shorter than a frame period (15625 us at --rate-hz 64)" in out
    rc, out = _daemon("--bank", str(tmp_path / "missing.f16bank"))
    assert rc == 1 and "missing.f16bank" in out and "no such file" in out
    junk = tmp_path / "junk.f16bank"
    junk.write_bytes(b"not a bank")
    rc, out = _daemon("--bank", str(junk))
    assert rc == 1 and "junk.f16bank" in out and "magic" in out
    rc, out = _daemon("--bank", bank, "--rate-hz", "50")
    assert rc == 1 and "--rate-hz 50 does not match the bank's design rate 64 Hz" in out
    rc, out = _daemon("--bank", bank, "--lcm-url", "nosuch://here")
    assert rc == 1 and "cannot open LCM URL 'nosuch://here'" in out
    rc, out = _daemon("--bank", bank, "--turbulence-banks")
    assert rc == 1 and "--turbulence-banks needs a turbulence bank set file as --bank" in out
    rc, out = _daemon("--help")
    assert rc == 0 and "usage: mmae-daemon" in out


def test_daemon_on_memq_stops_cleanly_on_sigterm():
    bank = str(load_bank("tuned")[1])
    p = subprocess.Popen([DAEMON, "--bank", bank, "--lcm-url", "memq://"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert "ready" in p.stdout.readline()
    p.terminate()
    out, err = p.communicate(timeout=5)
    assert p.returncode == 0, err
    assert out.startswith("mmae-daemon: stopped by signal: frames 0 updated")


def test_hil_command_errors_name_the_problem(capsys):
    assert main(["hil", "--timeout", "soon"]) == 2
    assert "--timeout 'soon' is not a number" in capsys.readouterr().err
    assert main(["hil", "--lcm-url", "nosuch://x"]) == 2
    assert "cannot be opened" in capsys.readouterr().err
    assert main(["hil", "--lockstep", "--lcm-url", "memq://", "--timeout", "0.05", "--duration", "0.1"]) == 2
    assert "no MMAE_STATUS for frame 0" in capsys.readouterr().err
    assert main(["hil", "--lockstep", "--lcm-url", "memq://", "--timeout", "0.05", "--duration", "0.1",
                 "--adapt-turbulence"]) == 2  # a daemon of one's own: the options it must run with are named
    assert "the record assumes the daemon on memq:// runs with --adapt-turbulence" in capsys.readouterr().out
    assert main(["hil", "--start-daemon", "--lcm-url", "memq://"]) == 2
    assert "memq:// is a queue inside one process" in capsys.readouterr().err
    assert main(["hil", "--fail", "XYZ@1"]) == 2
    assert "XYZ" in capsys.readouterr().err


def test_every_estimator_option_of_the_cli_has_a_daemon_flag():
    p = argparse.ArgumentParser()
    add_estimator_arguments(p)
    args = p.parse_args(["--threshold", "0.95", "--dwell-s", "0.5", "--p-min", "1e-6", "--adapt-turbulence",
                         "--adapt-reference", "0.76", "--trim-tracking", "30", "--trim-freeze-probability", "0.2",
                         "--trim-tracking-steady", "0.1", "--schedule-mode", "nearest", "--maneuver-kinematics", "--actuator-limits",
                         "--maneuver-tempering", "0.1"])
    flags = daemon_flags(estimator_options_from_args(args))
    assert flags[:21] == ("--threshold", "0.95", "--dwell-s", "0.5", "--p-min", "1e-06", "--adapt-turbulence",
                          "--adapt-reference", "0.76", "--trim-tracking", "30.0", "--trim-freeze-probability", "0.2",
                          "--trim-tracking-steady", "0.1", "--schedule-mode", "nearest", "--maneuver-kinematics", "--maneuver-tempering", "0.1",
                          "--actuator-rate-limits")
    rates = [float(x) for x in flags[21].split(",")]
    assert flags[22] == "--actuator-position-limits" and len(flags) == 24
    assert rates == list(RATE_LIMIT_RAD_S) and [float(x) for x in flags[23].split(",")] == list(POSITION_LIMIT_RAD)
    assert daemon_flags({"adapt_turbulence": False}) == ()
    assert daemon_flags({"start_up_s": 0.25}) == ("--start-up-s", "0.25")
    assert daemon_flags({"air_data_time_constant_s": 0.5}) == ("--air-data-time-constant", "0.5")
    with pytest.raises(ValueError, match="no flag for the estimator option 'gust_states'"):
        daemon_flags({"gust_states": True})
    assert daemon_flags({"turbulence_banks": True}) == ("--turbulence-banks",)   # with --bank SET
    assert daemon_flags({"turbulence_banks": False}) == ()
    # the closed loop's dither (the truth side's, read off the status): no flag for the executive
    assert daemon_flags({"turbulence_banks": True, "adaptive_dither": True}) == ("--turbulence-banks",)
    assert daemon_flags({"turbulence_banks": True, "fixed_dither": True}) == ("--turbulence-banks",)


def test_the_climb_dwell_and_own_channels_reach_the_daemon():
    """The climb reference's dwell and the adaptation's own channels (rows of the table with a
    daemon flag): passed on by daemon_flags, and in force in the daemon, which names them in its
    ready line; each refused without the option it applies with."""
    assert daemon_flags({"adapt_turbulence": True, "adapt_own_channels": True, "adapt_reference_climb": 0.6,
                         "adapt_reference_climb_dwell_s": 1.5}) == (
        "--adapt-turbulence", "--adapt-own-channels", "--adapt-reference-climb", "0.6",
        "--adapt-reference-climb-dwell", "1.5")
    bank = str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, "--adapt-turbulence", "--adapt-own-channels",
                        "--adapt-reference-climb", "0.6", "--adapt-reference-climb-dwell", "1.5")
    assert "turbulence adaptation (reference 0.6, own channels), climbing 0.6 held 0 s with dwell 1.5 s" in ready, ready
    rc, out = _daemon("--bank", bank, "--adapt-own-channels")
    assert rc == 2 and "--adapt-own-channels applies with --adapt-turbulence only" in out
    rc, out = _daemon("--bank", bank, "--adapt-turbulence", "--adapt-reference-climb-dwell", "1.5")
    assert rc == 2 and "--adapt-reference-climb-dwell applies with --adapt-reference-climb only" in out
    rc, out = _daemon("--bank", bank, "--adapt-turbulence", "--adapt-reference-climb", "0.6",
                      "--adapt-reference-climb-dwell", "61")
    assert rc == 2 and "--adapt-reference-climb-dwell must be a time in seconds in [0, 60] (0: the dwell), got '61'" in out


def _keywords(cls) -> dict[str, str]:
    """The estimator's keyword arguments of a pybind11 class's constructor, from its docstring
    (bindings/estimator_init.h writes one a line: ``  p_min: a number = 0.001``), with their
    defaults as written."""
    doc = cls.__init__.__doc__
    assert "model_bank: " in doc and "**kwargs" in doc, doc
    return dict(re.findall(r"^  (\w+): .+ = (.+)$", doc, flags=re.M))


def test_the_estimator_options_are_one_list():
    """Every keyword of the estimator's bindings (core.HierarchicalBank; core.Executive, the
    daemon's executive in process, replay's; core.TurbulenceBankSet from a set file) is a row of the option table or named with its
    reason in CORE_ONLY, and every row a keyword or the harness's own (HARNESS_ONLY): a
    setting added to bindings/estimator_init.h without that decision fails here."""
    rows = {o.key for o in ESTIMATOR_OPTIONS}
    assert not rows & set(CORE_ONLY) and set(HARNESS_ONLY) <= rows
    for cls in (core.HierarchicalBank, core.Executive, core.TurbulenceBankSet):
        keywords = set(_keywords(cls))
        assert len(keywords) > 30, cls
        assert keywords - rows - set(CORE_ONLY) == set(), cls
        assert rows - set(HARNESS_ONLY) - keywords == set(), cls
        assert set(CORE_ONLY) - keywords == set(), cls


def test_the_daemon_takes_every_flag_of_the_table():
    """Every estimator option the harness can pass (loop.estimator_options) is a flag that
    mmae-daemon's own usage names and accepts."""
    usage = subprocess.run([DAEMON, "--help"], capture_output=True, text=True, check=True).stdout
    for option in ESTIMATOR_OPTIONS:
        if option.flag != "--actuator-limits" and option.in_daemon:  # the limits: passed as the limits themselves
            assert f"[{option.flag}" in usage or f"  {option.flag}" in usage, option.flag


def test_the_maneuver_trim_reaches_the_daemon():
    """--maneuver-trim and its time constant: passed on by daemon_flags, in force in the daemon
    (its ready line names it), the time constant refused without it, naming the flag."""
    options = {"maneuver_trim": True, "maneuver_trim_time_constant_s": 0.25}
    flags = daemon_flags(options)
    assert "--maneuver-trim" in flags
    i = flags.index("--maneuver-trim-time-constant")
    assert float(flags[i + 1]) == 0.25
    bank = str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, *flags)
    assert "maneuver trim 0.25 s" in ready, ready
    rc, out = _daemon("--bank", bank, "--maneuver-trim-time-constant", "0.5")
    assert rc == 2 and "--maneuver-trim-time-constant applies with --maneuver-trim only" in out


def test_the_maneuver_trim_inertial_rates_reach_the_daemon():
    """--maneuver-trim-rates inertial and --maneuver-trim-blend: passed on by daemon_flags, in
    force in the daemon (its ready line names them), refused without --maneuver-trim."""
    options = {"maneuver_trim": True, "maneuver_trim_rates": "inertial", "maneuver_trim_blend_s": 3.0}
    flags = daemon_flags(options)
    assert flags[flags.index("--maneuver-trim-rates") + 1] == "inertial"
    assert float(flags[flags.index("--maneuver-trim-blend") + 1]) == 3.0
    bank = str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, *flags)
    assert "inertial rates 3 s" in ready, ready
    rc, out = _daemon("--bank", bank, "--maneuver-trim-rates", "inertial")
    assert rc == 2 and "--maneuver-trim-rates applies with --maneuver-trim only" in out


def test_the_maneuver_dwell_and_the_level1_options_reach_the_daemon():
    """The maneuver dwell and reference, the tempering's dead band, the angle-of-attack tempering
    with its trim knee and the load factor's added term with their dead bands, the level-1 floor and dwell,
    the departure hold and the channel weight: passed on by daemon_flags, in force in the
    daemon (its ready line names the maneuver ones), each refused without the option it
    applies with or out of range, naming the flag."""
    options = {"adapt_turbulence": True, "maneuver_dwell_s": 1.5, "maneuver_dwell_hold_s": 30.0,
               "maneuver_reference": 0.65, "maneuver_tempering_g": 0.1, "maneuver_tempering_deadband_g": 0.05,
               "level1_p_min": 1e-4, "level1_dwell_s": 0.5, "level1_allowance": 0.1, "departure_hold": "off",
               "adapt_channel_weight": 0.5, "maneuver_tempering_alpha_deg": 1.0,
               "maneuver_tempering_alpha_deadband_deg": 0.75, "maneuver_tempering_alpha_trim_deg": 9.0,
               "maneuver_tempering_added_g": 0.1,
               "maneuver_tempering_added_deadband_g": 0.02}
    flags = daemon_flags(options)
    for key, value in options.items():
        option = next(o for o in ESTIMATOR_OPTIONS if o.key == key)
        assert option.in_daemon, key
        i = flags.index(option.flag)
        if option.kind == "number":
            assert float(flags[i + 1]) == value, key
        elif option.kind == "choice":
            assert flags[i + 1] == value, key
    bank = str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, *flags)
    assert ("tempering 0.1 g, tempering dead band 0.05 g, alpha tempering 1 deg beyond 0.75 deg sqrt(s), "
            "its reference shrinking above a trim alpha of 9 deg, added tempering 0.1 g beyond 0.02 g sqrt(s), "
            "maneuver dwell 1.5 s held 30 s, maneuver reference 0.65" in ready), ready
    rc, out = _daemon("--bank", bank, "--maneuver-dwell-hold", "30")
    assert rc == 2 and "--maneuver-dwell-hold applies with --maneuver-dwell S > 0 only" in out
    rc, out = _daemon("--bank", bank, "--maneuver-reference", "0.65")
    assert rc == 2 and "--maneuver-reference applies with --adapt-turbulence only" in out
    rc, out = _daemon("--bank", bank, "--departure-hold", "maybe")
    assert rc == 2 and "--departure-hold must be 'on' or 'off', got 'maybe'" in out
    # the level-1 floor's bound depends on the threshold: the flag's range is the default
    # threshold's, (1 - 0.9)/12; the core refuses 0.005 at 0.95, (1 - 0.95)/12, naming it
    rc, out = _daemon("--bank", bank, "--lcm-url", "memq://", "--level1-p-min", "0.05")
    assert rc == 2 and "--level1-p-min must be a probability in [0, (1 - 0.9)/12)" in out, out
    rc, out = _daemon("--bank", bank, "--lcm-url", "memq://", "--threshold", "0.95", "--level1-p-min", "0.005")
    assert rc == 1 and "level1_p_min must lie in [0, (1 - threshold)/(K - 1))" in out, out
    # the partial hypotheses' floor reaches the core, which refuses it for a bank without them
    flags = daemon_flags({"partial_p_min": 0.002})
    assert flags == ("--partial-p-min", "0.002")
    rc, out = _daemon("--bank", bank, "--lcm-url", "memq://", *flags)
    assert rc == 1 and "partial" in out, out


def test_the_calm_air_complete_model_reaches_the_daemon():
    """``--calm-complete`` (a table) is passed on as given and in force in the daemon, which names
    its bounds in the ready line; refused without the adaptation, and for a bound out of range."""
    assert daemon_flags({"adapt_turbulence": True, "calm_complete": "VEL=0.6"}) == (
        "--adapt-turbulence", "--calm-complete", "VEL=0.6")
    bank = str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, "--adapt-turbulence", "--calm-complete", "VEL=0.6,AZ=0")
    assert "turbulence adaptation (reference 0.6, complete in calm air VEL 0.6)" in ready, ready
    rc, out = _daemon("--bank", bank, "--calm-complete", "VEL=0.6")
    assert rc == 2 and "--calm-complete applies with --adapt-turbulence only" in out
    rc, out = _daemon("--bank", bank, "--adapt-turbulence", "--calm-complete", "VEL=-1")
    assert rc == 2 and "VEL's bound must lie in [0, 100] (0: off), got -1" in out, out


def test_the_calm_air_measure_reaches_the_daemon():
    """``--calm-measure`` and ``--calm-whiteness-bound`` are passed on and named in the ready line;
    the daemon refuses a measure it does not know and the whiteness' bound without a measure that
    reads it."""
    settings = {"adapt_turbulence": True, "calm_complete": "VEL=1", "calm_measure": "either",
                "calm_whiteness_bound": 0.7}
    flags = daemon_flags(settings)
    assert flags[flags.index("--calm-measure") + 1] == "either"
    assert flags[flags.index("--calm-whiteness-bound") + 1] == "0.7"
    bank = str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, *flags)
    assert "complete in calm air VEL 1 by either (whiteness below 0.7))" in ready, ready
    rc, out = _daemon("--bank", bank, "--adapt-turbulence", "--calm-complete", "VEL=1", "--calm-measure", "white")
    assert rc == 2 and "--calm-measure must be 'power', 'whiteness' or 'either', got 'white'" in out, out
    rc, out = _daemon("--bank", bank, "--adapt-turbulence", "--calm-complete", "VEL=1", "--calm-whiteness-bound", "0.7")
    assert rc == 2 and "--calm-whiteness-bound applies with --calm-measure only" in out, out
