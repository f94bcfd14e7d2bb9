"""The scheduled estimator's evidence dwell per hypothesis (``names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS``,
kept through the flight phases' dwells, ``--evidence-dwell-in-phases``): the defaults and how
they are turned off or replaced, the table inline (``--dwell-nats-per-hypothesis NAME=N,...``) at
every door (core, option table, command line, daemon flags and ready line), and a flight declared
on the frame its recorded log-odds excess reaches the default's N."""
from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.loop.estimator import core_arguments
from f16mmae.loop.estimator_options import check, load_dwell_nats_table, scheduled_defaults
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure

from daemon_support import ready_line

LN9 = math.log(9.0)   # the threshold 0.9's log-odds
DEFAULT = load_dwell_nats_table(names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS)


def test_the_default_names_every_failure_hypothesis_once():
    assert set(DEFAULT) == set(names.SINGLE_HYPOTHESES) - {names.NONE}
    assert all(32.0 <= n <= 1.0e6 for n in DEFAULT.values())   # the tool's floor, the core's bound


def test_the_scheduled_defaults_give_the_table_through_the_phases_unless_replaced():
    on = scheduled_defaults({"adapt_turbulence": True}, True)
    assert on["dwell_nats_per_hypothesis"] == names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS
    assert on["evidence_dwell_in_phases"] is True
    assert core_arguments(on)["dwell_nats_per_hypothesis"] == DEFAULT   # the inline text, read as the core reads it
    off = scheduled_defaults({"adapt_turbulence": True, "dwell_nats": 0.0}, True)   # --dwell-nats 0: the frame dwell
    assert "dwell_nats_per_hypothesis" not in off and "evidence_dwell_in_phases" not in off
    mine = scheduled_defaults({"adapt_turbulence": True, "dwell_nats_per_hypothesis": "LS=20"}, True)
    assert mine["dwell_nats_per_hypothesis"] == "LS=20" and "evidence_dwell_in_phases" not in mine
    for unscheduled in (scheduled_defaults({"adapt_turbulence": True}, False), scheduled_defaults({}, True)):
        assert "dwell_nats_per_hypothesis" not in unscheduled


def test_the_table_inline_at_every_door():
    assert load_dwell_nats_table("LS=32,AY=99.1") == {"LS": 32.0, "AY": 99.1}
    check({"dwell_nats_per_hypothesis": "LS=32,AY=99.1"})
    assert daemon_flags({"dwell_nats_per_hypothesis": "LS=32", "evidence_dwell_in_phases": True}) == (
        "--dwell-nats-per-hypothesis", "LS=32", "--evidence-dwell-in-phases")
    with pytest.raises(ValueError, match=r"^--dwell-nats-per-hypothesis: expected NAME=N .* got 'AY=x'"):
        check({"dwell_nats_per_hypothesis": "LS=32,AY=x"})
    with pytest.raises(ValueError, match=r"AY's N must lie in \[0, 1e\+06\] nats, got -1"):
        load_dwell_nats_table("AY=-1")
    with pytest.raises(ValueError, match="not a hypothesis of the bank"):
        core.HierarchicalBank(load_bank("tuned")[2], **core_arguments({"dwell_nats_per_hypothesis": "QQ=4"}))


def test_the_command_line_keeps_an_inline_table_and_refuses_a_bad_one(tmp_path, capsys):
    import json
    from f16mmae.cli.main import main
    bad = tmp_path / "bad"
    assert main(["run", "--bank", "scheduled", "--adapt-turbulence", "--dwell-nats-per-hypothesis", "LS=32,RS=x",
                 "--duration", "1", "--out", str(bad)]) == 2
    assert "--dwell-nats-per-hypothesis: expected NAME=N" in capsys.readouterr().err
    assert not bad.exists()   # refused before anything flew
    good = tmp_path / "good"
    assert main(["run", "--bank", "scheduled", "--adapt-turbulence", "--dwell-nats-per-hypothesis", "LS=32",
                 "--duration", "1", "--out", str(good)]) == 0
    settings = json.loads((good / "run.json").read_text())["estimator_settings"]
    assert settings["dwell_nats_per_hypothesis"] == "LS=32"   # as given, not a path
    assert "evidence_dwell_in_phases" not in settings   # a table given: the phases' rule as configured


def test_the_daemon_keeps_the_table_through_the_phases_only_when_told():
    """mmae-daemon with a maneuver dwell: the inline table is in force (its ready line names it)
    with --evidence-dwell-in-phases, and off without it."""
    bank = str(load_bank("scheduled")[1])
    args = ("--bank", bank, "--adapt-turbulence", "--maneuver-dwell", "0.4", "--dwell-nats-per-hypothesis", "LS=32")
    assert "or per hypothesis (LS 32) nats" in ready_line(*args, "--evidence-dwell-in-phases")
    assert "per hypothesis" not in ready_line(*args)
    r = subprocess.run([str(find_executable("mmae-daemon")), "--bank", bank, "--dwell-nats-per-hypothesis",
                        "LS=32,LS=4", "--lcm-url", "memq://"], capture_output=True, text=True, timeout=20)
    assert r.returncode != 0 and "LS" in r.stderr, r.stderr


@pytest.mark.slow
def test_a_flight_declares_when_the_log_odds_excess_reaches_the_defaults_n():
    """AY fails at 3 s in light air: the scheduled default declares it before the frame dwell
    alone (--dwell-nats 0) does, on the first frame whose log-odds excess over the threshold's,
    summed over AY's consecutive frames above 0.9 (from the recorded probabilities), reaches the
    default's N for AY (level flight: no phase's dwell in force)."""
    bank = load_bank("scheduled")[2]
    sc = Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=5.0, seed=5, feedback="mmae",
                  failures=(make_failure("AY", 3.0),))
    table = fly(sc, bank, estimator_options={"adapt_turbulence": True})
    frames = fly(sc, bank, estimator_options={"adapt_turbulence": True, "dwell_nats": 0.0})
    assert table.declarations[0]["hypothesis"] == "AY" == frames.declarations[0]["hypothesis"]
    assert 3.0 < table.declarations[0]["time_s"] < frames.declarations[0]["time_s"]
    p = table.probability_of("AY")
    i = int(np.argmin(np.abs(table.time_s - table.declarations[0]["time_s"])))
    run = []
    for j in range(i, -1, -1):   # the consecutive frames above the threshold, back from the declaration
        if not p[j] > 0.9:
            break
        run.append(j)
    excess = [math.log(min(p[j], 1.0 - 1e-16)) - math.log1p(-min(p[j], 1.0 - 1e-16)) - LN9 for j in reversed(run)]
    assert len(run) < 16
    assert sum(excess) >= DEFAULT["AY"] > sum(excess[:-1])
