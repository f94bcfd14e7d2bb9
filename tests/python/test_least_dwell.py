"""The least dwell per hypothesis (cpp/f16mmae/declarer.h, ``--dwell-s-per-hypothesis``): the
setting's refusals at every door (core, option table, command line, daemon), the daemon taking
it, and a flight whose declaration comes on the frame the recorded probability has held the
threshold for the hypothesis' own dwell."""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from f16mmae import core
from f16mmae.cli.main import main
from f16mmae.banks import load_bank
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.loop.estimator_options import check, command_line_flags
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure

from daemon_support import ready_line


def test_the_setting_is_refused_naming_the_entry():
    with pytest.raises(ValueError, match="expected NAME=S .*got 'AZ'"):
        check({"dwell_s_per_hypothesis": "VEL=1,AZ"})
    with pytest.raises(ValueError, match=r"--dwell-s-per-hypothesis: VEL's dwell must lie in \[0, 60\] s, got 90"):
        check({"dwell_s_per_hypothesis": "VEL=90"})
    with pytest.raises(ValueError, match="must be NAME=VALUE entries"):
        check({"dwell_s_per_hypothesis": 1.0})
    with pytest.raises(ValueError, match="dwell_s_per_hypothesis names 'XYZ', not a hypothesis of the bank"):
        core.HierarchicalBank(load_bank("tuned")[2], dwell_s_per_hypothesis={"XYZ": 1.0})
    check({"dwell_s_per_hypothesis": "VEL=1,AOA=0.5"})
    assert command_line_flags({"dwell_s_per_hypothesis": "VEL=1"}) == ["--dwell-s-per-hypothesis", "VEL=1"]
    assert daemon_flags({"dwell_s_per_hypothesis": "VEL=1"}) == ("--dwell-s-per-hypothesis", "VEL=1")


def test_the_command_line_refuses_a_bad_table_before_flying(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", "--dwell-s-per-hypothesis", "VEL=1s", "--out", str(out)]) != 0
    assert "--dwell-s-per-hypothesis: expected NAME=S" in capsys.readouterr().err
    assert not out.exists()


def test_the_daemon_takes_the_flag_and_names_it():
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, "--dwell-s-per-hypothesis", "VEL=1,AZ=0.5")
    assert " nats, at least AZ 0.5, VEL 1 s, " in ready, ready   # after the tuned bank's evidence dwells
    r = subprocess.run([daemon, "--bank", bank, "--dwell-s-per-hypothesis", "VEL=x"], capture_output=True, text=True,
                       timeout=20)
    assert r.returncode == 2
    assert "--dwell-s-per-hypothesis expected NAME=S" in r.stderr + r.stdout
    r = subprocess.run([daemon, "--bank", bank, "--dwell-s-per-hypothesis", "QQ=1"], capture_output=True, text=True,
                       timeout=20)
    assert r.returncode == 1 and "names 'QQ', not a hypothesis of the bank" in r.stderr, r.stderr


def test_a_flight_declares_once_the_hypothesis_held_its_own_dwell():
    """AZ fails at 2 s: with AZ=1 the first declaration is AZ, on the frame on which the recorded
    p_AZ has been above 0.9 for 64 frames in a row, later than the 16-frame dwell declares it;
    another hypothesis' least dwell leaves the flight as it is."""
    bank = load_bank("tuned")[2]
    sc = Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=5.0, seed=3, feedback="raw",
                  failures=(make_failure("AZ", 2.0),))
    held = fly(sc, bank, estimator_options={"dwell_s_per_hypothesis": "AZ=1"})
    plain = fly(sc, bank)
    other = fly(sc, bank, estimator_options={"dwell_s_per_hypothesis": "VEL=1"})
    assert held.declarations[0]["hypothesis"] == "AZ" == plain.declarations[0]["hypothesis"]
    assert other.declarations == plain.declarations
    t_held, t_plain = held.declarations[0]["time_s"], plain.declarations[0]["time_s"]
    assert t_held > t_plain
    p = held.probability_of("AZ")
    i = int(np.argmin(np.abs(held.time_s - t_held)))
    run = 0
    while i - run >= 0 and p[i - run] > 0.9:
        run += 1
    assert run == 64


def test_a_run_records_the_table_as_given(tmp_path):
    out = tmp_path / "run"
    assert main(["run", "--duration", "1", "--dwell-s-per-hypothesis", "VEL=1", "--out", str(out)]) == 0
    assert json.loads((out / "run.json").read_text())["estimator_settings"]["dwell_s_per_hypothesis"] == "VEL=1"
