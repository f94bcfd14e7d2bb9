"""The least dwell per hypothesis in rough air (cpp/f16mmae/declarer.h,
``--rough-dwell-s-per-hypothesis`` and ``--rough-scale``): the settings' refusals at every door
(option table, command line, core, daemon), the daemon naming them, and flights of the shipped
scheduled bank with its default (the rudder's 2 s while the adaptation's scale is at least 4):

* in severe air, where the scale runs far above 4, a failed rudder is declared (the frame dwells
  alone) on the frame the recorded p_RUD has held the threshold for 128 frames in a row, later
  than without the table, and the flight records the 128 frames in force on each of them (with
  the default's evidence dwell too);
* in light air, where the scale stays below 4 at the nominal point, the declarations are those
  of the bank without the table, frame for frame.
"""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.cli.main import main
from f16mmae.lcm.daemon import daemon_flags, find_executable
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import bank_defaults, check, command_line_flags
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure

from daemon_support import ready_line


def test_the_settings_are_refused_naming_the_entry():
    with pytest.raises(ValueError, match="--rough-dwell-s-per-hypothesis: expected NAME=S"):
        check({"adapt_turbulence": True, "rough_dwell_s_per_hypothesis": "RUD=1,AZ"})
    with pytest.raises(ValueError, match="--rough-dwell-s-per-hypothesis applies with --adapt-turbulence"):
        check({"rough_dwell_s_per_hypothesis": "RUD=1"})
    with pytest.raises(ValueError, match=r"--rough-scale 1.0 must lie in \(1, 1e\+06\]"):
        check({"adapt_turbulence": True, "rough_dwell_s_per_hypothesis": "RUD=1", "rough_scale": 1.0})
    with pytest.raises(ValueError, match="--rough-scale applies with --rough-dwell-s-per-hypothesis"):
        check({"rough_scale": 8.0})
    check({"adapt_turbulence": True, "rough_scale": 8.0})   # waits for a scheduled bank's default table
    bank = load_bank("tuned")[2]
    with pytest.raises(ValueError, match="rough_dwell_s_per_hypothesis names 'XYZ', not a hypothesis of the bank"):
        core.HierarchicalBank(bank, adapt_turbulence=True, rough_dwell_s_per_hypothesis={"XYZ": 1.0})
    with pytest.raises(ValueError, match="needs adapt_turbulence on"):
        core.HierarchicalBank(bank, rough_dwell_s_per_hypothesis={"RUD": 1.0})
    settings = {"adapt_turbulence": True, "rough_dwell_s_per_hypothesis": "RUD=1", "rough_scale": 6.0}
    check(settings)
    assert command_line_flags(settings) == ["--rough-dwell-s-per-hypothesis", "RUD=1", "--rough-scale", "6.0",
                                            "--adapt-turbulence"]
    assert daemon_flags(settings) == ("--adapt-turbulence", "--rough-dwell-s-per-hypothesis", "RUD=1",
                                      "--rough-scale", "6.0")


def test_the_command_line_refuses_before_flying(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", "--bank", "scheduled", "--adapt-turbulence", "--rough-scale", "0.5", "--out", str(out)]) != 0
    assert "--rough-scale 0.5 must lie in (1, 1e+06]" in capsys.readouterr().err
    assert main(["run", "--rough-dwell-s-per-hypothesis", "RUD=1", "--out", str(out)]) != 0
    assert "applies with --adapt-turbulence" in capsys.readouterr().err
    assert not out.exists()


def test_the_daemon_takes_the_flags_and_names_them():
    daemon, bank = str(find_executable("mmae-daemon")), str(load_bank("tuned")[1])
    ready = ready_line("--bank", bank, "--adapt-turbulence", "--rough-dwell-s-per-hypothesis", "RUD=1",
                       "--rough-scale", "6")
    assert ", in rough air (scale >= 6) at least RUD 1 s, " in ready, ready
    for args, why in ((["--rough-dwell-s-per-hypothesis", "RUD=1"],
                       "--rough-dwell-s-per-hypothesis applies with --adapt-turbulence only"),
                      (["--adapt-turbulence", "--rough-scale", "6"],
                       "--rough-scale applies with --rough-dwell-s-per-hypothesis only"),
                      (["--adapt-turbulence", "--rough-dwell-s-per-hypothesis", "RUD=1", "--rough-scale", "1"],
                       "--rough-scale must be a scale in (1, 1e+06], got '1'"),
                      (["--adapt-turbulence", "--rough-dwell-s-per-hypothesis", "RUD=x"],
                       "--rough-dwell-s-per-hypothesis expected NAME=S")):
        r = subprocess.run([daemon, "--bank", bank, *args], capture_output=True, text=True, timeout=20)
        assert r.returncode == 2, (args, r.stderr)
        assert why in r.stderr + r.stdout, (args, r.stderr + r.stdout)


@pytest.fixture(scope="module")
def scheduled():
    return load_bank("scheduled")[2]


class _Scales(Estimator):
    """The estimator with the declarer's rough-air state recorded after each update."""

    def __init__(self, *a, **k):
        super().__init__(*a, **k)
        self.rough = []

    def update(self, z):
        out = super().update(z)
        self.rough.append(bool(self.core_bank.declarer_rough))
        return out


def _flights(bank, turbulence: str):
    # the frame dwells alone: the default's evidence dwell declares a rudder held at the ceiling
    # sooner (its N_k times the rough dwell over the declarer's), which the test leaves out
    settings = bank_defaults({"adapt_turbulence": True, "dwell_nats": 0.0}, bank)
    assert settings["rough_dwell_s_per_hypothesis"] == names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS == "RUD=2,PIT=0.5,AZ=0.5"
    sc = Scenario(turbulence=turbulence, duration_s=8.0, seed=11, failures=(make_failure("RUD", 3.0),))
    with_table = _Scales(bank, **settings)
    held = fly(sc, bank, estimator=with_table, on_frame=lambda *a: None, record_series=True)
    without = Estimator(bank, **{**settings, "rough_dwell_s_per_hypothesis": "RUD=0"})
    plain = fly(sc, bank, estimator=without, on_frame=lambda *a: None, record_series=True)
    return held, plain, np.array(with_table.rough)


def test_in_severe_air_a_failed_rudder_waits_its_rough_dwell(scheduled):
    held, plain, rough = _flights(scheduled, "severe")
    first = held.declarations[0]
    assert first["hypothesis"] == "RUD" == plain.declarations[0]["hypothesis"]
    assert first["time_s"] > plain.declarations[0]["time_s"]
    i = int(np.argmin(np.abs(held.time_s - first["time_s"])))
    # rough air on every frame of the dwell before the last (whose update switched to the level-1
    # declarer, which reads the scale from the next frame on)
    assert rough[i - 127:i].all()
    p = held.probability_of("RUD")
    run = 0
    while i - run >= 0 and p[i - run] > 0.9:
        run += 1
    assert run == 128


def test_the_flight_records_the_dwell_in_force_for_the_candidate(scheduled):
    """FlightResult.dwell_frames_in_force, frame by frame as the declarer had it: 0 with no
    hypothesis above the threshold, the declarer's 16 frames for NONE (presumed), the rudder's 128
    while it is the candidate in severe air; the whole flight in C++ records what the estimator
    flown frame by frame in Python reads."""
    settings = bank_defaults({"adapt_turbulence": True}, scheduled)
    sc = Scenario(turbulence="severe", duration_s=8.0, seed=11, failures=(make_failure("RUD", 3.0),))
    in_cpp = fly(sc, scheduled, estimator_options=settings, record_probabilities=True)
    in_python = fly(sc, scheduled, estimator=Estimator(scheduled, **settings), on_frame=lambda *a: None,
                    record_probabilities=True)
    d = in_cpp.dwell_frames_in_force
    assert d.shape == in_cpp.time_s.shape and np.array_equal(d, in_python.dwell_frames_in_force)
    i = int(np.argmin(np.abs(in_cpp.time_s - in_cpp.declarations[0]["time_s"])))
    assert in_cpp.declarations[0]["hypothesis"] == "RUD"
    p = in_cpp.probability_of("RUD")
    start = i
    while p[start - 1] > 0.9:
        start -= 1
    assert 0 < i - start < 128 and (d[start:i] == 128).all()   # declared by its evidence dwell in rough air
    above = np.nan_to_num(in_cpp.probabilities[:i]) > 0.9
    assert (d[:i][~above.any(axis=1)] == 0).all()
    assert (d[:i][above[:, in_cpp.hypotheses.index("NONE")]] == 16).all()
    assert set(np.unique(d[:i])) == {0, 16, 128}


def test_in_light_air_the_declarations_are_the_banks_without_the_table(scheduled):
    held, plain, rough = _flights(scheduled, "light")
    assert not rough.any()
    assert held.declarations and held.declarations == plain.declarations
    assert held.declarations[0]["hypothesis"] == "RUD"


def test_a_run_records_the_settings(tmp_path):
    out = tmp_path / "run"
    assert main(["run", "--bank", "scheduled", "--adapt-turbulence", "--duration", "1", "--out", str(out)]) == 0
    settings = json.loads((out / "run.json").read_text())["estimator_settings"]
    assert settings["rough_dwell_s_per_hypothesis"] == names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS
    assert settings["rough_scale"] == names.SCHEDULE_ROUGH_SCALE


def test_a_climbs_reference_does_not_make_the_air_rough(scheduled):
    """In a climb the adaptation reads against the climb's own reference, and its scale s rises
    past 4 in light air; the rough-air dwell reads s_b, the scale at the node's reference, and
    stays off (cpp/f16mmae/hierarchical_bank.h, step 6). Flown at Mach 0.5, 15,000 ft, whose
    node's reference (1.0) lies above the climb's (0.6)."""
    settings = bank_defaults({"adapt_turbulence": True}, scheduled)
    est = _Scales(scheduled, **settings)
    scales = []
    sc = Scenario(turbulence="light", duration_s=8.0, seed=11, mach=0.5, alt_ft=15000.0,
                  maneuvers=("climb@2:to=17000ft:rate=3000fpm",))
    fly(sc, scheduled, estimator=est, on_frame=lambda *a: scales.append(est.turbulence_scale))
    assert max(scales) >= names.SCHEDULE_ROUGH_SCALE
    assert not any(est.rough)
