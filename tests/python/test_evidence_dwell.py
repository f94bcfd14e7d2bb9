"""The evidence dwell (cpp/f16mmae/declarer.h, ``--dwell-nats``): the declarer's rule against
hand-computed sums, the setting's refusals at every door (core, option table, daemon flags),
and a flight whose declaration comes on the frame the recorded probabilities' log-odds sum
reaches the dwell."""
from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.loop.estimator_options import check
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure
from f16mmae.truth.maneuvers import parse_maneuver

from daemon_support import ready_line

LN9 = math.log(9.0)   # the threshold 0.9's log-odds


def test_declarer_sums_the_log_odds_above_the_threshold():
    d = core.Declarer(dwell_nats=7.0)
    p = [0.005, 0.99, 0.005]   # ln 99 - ln 9 = 2.3979 a frame: 2.40, 4.80, 7.19
    assert d.update(p) is None and d.dwell_evidence_nats == pytest.approx(math.log(99.0) - LN9, abs=1e-12)
    assert d.update(p) is None
    assert d.update(p) == 1 and d.dwell_count == 3 and d.dwell_frames == 16
    off = core.Declarer()
    assert [off.update(p) for _ in range(16)] == [None] * 15 + [1]


def test_the_setting_is_refused_out_of_range_naming_it():
    with pytest.raises(ValueError, match=r"dwell_nats must be in \[0, 1e\+06\] nats, got -1"):
        core.Declarer(dwell_nats=-1.0)
    with pytest.raises(ValueError, match="dwell_nats"):
        core.HierarchicalBank(load_bank("tuned")[2], dwell_nats=float("nan"))
    with pytest.raises(ValueError, match="--dwell-nats -2.0 must lie in"):
        check({"dwell_nats": -2.0})
    assert daemon_flags({"dwell_nats": 48.0}) == ("--dwell-nats", "48.0")


def test_the_daemon_takes_the_flag_and_names_it():
    """mmae-daemon --dwell-nats: in force (its ready line names it), refused out of range."""
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, "--dwell-nats", "48")
    assert "threshold 0.9, dwell 0.25 s or 48 nats," in ready, ready
    r = subprocess.run([daemon, "--bank", bank, "--dwell-nats", "-1"], capture_output=True, text=True, timeout=20)
    assert r.returncode == 2
    assert "--dwell-nats must be a number of nats in [0, 1e+06] (0: the dwell alone), got '-1'" in r.stderr + r.stdout


@pytest.mark.slow
def test_a_flight_declares_when_the_recorded_log_odds_sum_reaches_the_dwell():
    """AZ fails at 2 s: with --dwell-nats 48 the first declaration is AZ, on the first frame on
    which the log-odds excess of AZ over the threshold's, summed over its consecutive frames
    above 0.9 (recomputed here from the recorded probabilities), reaches 48, before the
    16-frame dwell, and no later than without the option."""
    bank = load_bank("tuned")[2]
    sc = Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=4.0, seed=3, feedback="mmae",
                  failures=(make_failure("AZ", 2.0),))
    with_nats = fly(sc, bank, estimator_options={"dwell_nats": 48.0})
    without = fly(sc, bank)
    assert with_nats.declarations[0]["hypothesis"] == "AZ" == without.declarations[0]["hypothesis"]
    t_nats, t_plain = with_nats.declarations[0]["time_s"], without.declarations[0]["time_s"]
    assert 2.0 <= t_nats <= t_plain
    p = with_nats.probability_of("AZ")
    i = int(np.argmin(np.abs(with_nats.time_s - t_nats)))
    run, total, frames = [], 0.0, 0
    for j in range(i, -1, -1):   # the consecutive frames above the threshold, back from the declaration
        if not p[j] > 0.9:
            break
        frames += 1
        run.append(j)
    for j in reversed(run):
        x = min(p[j], 1.0 - 1e-16)
        total += math.log(x) - math.log1p(-x) - LN9
    assert frames < 16
    last = run[0]
    x = min(p[last], 1.0 - 1e-16)
    assert total >= 48.0 > total - (math.log(x) - math.log1p(-x) - LN9)


# -- the evidence dwell per hypothesis (--dwell-nats-per-hypothesis FILE) ------------------------
def test_the_table_file_is_read_and_refused_naming_the_line(tmp_path):
    from f16mmae.loop.estimator_options import load_dwell_nats_table
    f = tmp_path / "n.txt"
    f.write_text("# rule\nAZ 48   # E_max 20\nAOA 0\n")
    assert load_dwell_nats_table(str(f)) == {"AZ": 48.0, "AOA": 0.0}
    check({"dwell_nats_per_hypothesis": str(f)})
    assert daemon_flags({"dwell_nats_per_hypothesis": str(f)}) == ("--dwell-nats-per-hypothesis", str(f))
    f.write_text("AZ 48\nAOA -1\n")
    with pytest.raises(ValueError, match=r"line 2: AOA's N must lie in \[0, 1e\+06\] nats, got -1"):
        check({"dwell_nats_per_hypothesis": str(f)})
    f.write_text("AZ forty\n")
    with pytest.raises(ValueError, match="line 1: expected 'NAME N'"):
        load_dwell_nats_table(str(f))
    with pytest.raises(ValueError, match="not a hypothesis of the bank"):
        core.HierarchicalBank(load_bank("tuned")[2], dwell_nats_per_hypothesis={"XYZ": 4.0})


def test_the_daemon_reads_the_table_and_names_it(tmp_path):
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    f = tmp_path / "n.txt"
    f.write_text("AZ 48\nROL 32\n")
    ready = ready_line("--bank", bank, "--dwell-nats-per-hypothesis", f)
    assert "dwell 0.25 s or per hypothesis (AZ 48, ROL 32) nats," in ready, ready
    f.write_text("QQ 4\n")
    r = subprocess.run([daemon, "--bank", bank, "--dwell-nats-per-hypothesis", str(f)], capture_output=True,
                       text=True, timeout=20)
    assert r.returncode == 1 and "names 'QQ', not a hypothesis of the bank" in r.stderr, r.stderr


@pytest.mark.slow
def test_a_flight_takes_each_hypothesis_own_dwell(tmp_path):
    """AZ fails at 2 s (the flight above): a table giving AZ 48 nats declares on the frame
    --dwell-nats 48 does; one giving AZ 0 (and every other hypothesis 48) declares as the frame
    dwell alone does."""
    bank = load_bank("tuned")[2]
    sc = Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=4.0, seed=3, feedback="mmae",
                  failures=(make_failure("AZ", 2.0),))
    fast, slow = tmp_path / "fast.txt", tmp_path / "slow.txt"
    fast.write_text("AZ 48\n")
    slow.write_text("AZ 0\n")
    t = {name: fly(sc, bank, estimator_options=o).declarations[0]
         for name, o in (("nats", {"dwell_nats": 48.0}), ("plain", {}),
                         ("fast", {"dwell_nats_per_hypothesis": str(fast)}),
                         ("slow", {"dwell_nats": 48.0, "dwell_nats_per_hypothesis": str(slow)}))}
    assert {d["hypothesis"] for d in t.values()} == {"AZ"}
    assert t["fast"]["time_s"] == t["nats"]["time_s"] < t["plain"]["time_s"] == t["slow"]["time_s"]


def test_a_flight_phase_dwell_turns_the_bank_evidence_dwell_off():
    """A 30-degree turn with the maneuver model, a stabilator failing in it. Without a maneuver
    dwell the bank's evidence dwell (LS, ROL, YAW, AY 32 nats) declares the roll-in's few frames
    at the ceiling (AY, before the failure). With the maneuver dwell configured the declarers
    have no evidence dwell (hierarchical_bank.h): the flight equals the one flown with the frame
    dwell alone (--dwell-nats 0) declaration for declaration."""
    bank = load_bank("tuned")[2]
    assert bank.estimator_settings["dwell_nats_per_hypothesis"]["AY"] == 32.0
    sc = Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=6.0, seed=1, feedback="mmae",
                  failures=(make_failure("LS", 3.0),), maneuvers=(parse_maneuver("turn@0.5:bank=30"),))
    model = {"maneuver_kinematics": True, "maneuver_tempering_g": 0.1}
    dwell = {**model, "maneuver_dwell_s": 1.0, "maneuver_dwell_hold_s": 30.0}
    plain = fly(sc, bank, estimator_options=model)
    table = fly(sc, bank, estimator_options=dwell)
    frames = fly(sc, bank, estimator_options={**dwell, "dwell_nats": 0.0})
    assert plain.declarations[0]["hypothesis"] == "AY" and plain.declarations[0]["time_s"] < 1.0
    assert table.declarations == frames.declarations
    assert [d["hypothesis"] for d in table.declarations] == ["LS"]
