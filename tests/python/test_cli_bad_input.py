"""Bad input from the command line gets one sentence, exit status 2 and no traceback, and
loses nothing: each case below was a Python traceback once (issue 16, item 5).  Output paths
are checked before the work, so a refused ``--out`` costs no flight."""
from __future__ import annotations

import json

import pytest

from f16mmae.campaign.engine.config import CampaignError
from f16mmae.campaign.single import SingleCampaign
from f16mmae.cli.main import main


@pytest.fixture
def a_file(tmp_path):
    p = tmp_path / "a-file"
    p.write_text("not a directory\n")
    return p


def _refused(capsys, argv, *expected):
    assert main([str(a) for a in argv]) == 2
    out = capsys.readouterr()
    assert "Traceback" not in out.err
    for text in expected:
        assert text in out.err, out.err
    return out


# -- output paths, checked before the flight or campaign -----------------------------------------
def test_run_out_an_existing_file_is_refused_before_the_flight(capsys, a_file):
    out = _refused(capsys, ["run", "--duration", "1", "--out", a_file], f"--out '{a_file}' is a file")
    assert "flight:" not in out.out  # refused before flying
    assert a_file.read_text() == "not a directory\n"


def test_run_out_under_a_file_is_refused_before_the_flight(capsys, a_file):
    out = _refused(capsys, ["run", "--duration", "1", "--out", a_file / "run"],
                   f"lies under '{a_file}', which is a file, not a directory")
    assert "flight:" not in out.out


def test_run_out_that_cannot_be_written_is_refused_before_the_flight(capsys):
    # /proc/self is a directory no one (root included) can create a file in
    out = _refused(capsys, ["run", "--duration", "1", "--out", "/proc/self"], "--out '/proc/self' cannot be written")
    assert "flight:" not in out.out


def test_hil_out_under_a_file_is_refused_before_the_flight(capsys, a_file):
    _refused(capsys, ["hil", "--lcm-url", "memq://", "--duration", "1", "--out", a_file / "x"], "which is a file")


@pytest.mark.parametrize("kind, extra", [
    ("single", ["--cases", "NONE", "--baseline", "none"]),
    ("dual", ["--pairs", "LS+PIT"]),
    ("envelope", ["--mach-alt", "0.45:20000", "--cases", "NONE"]),
])
def test_campaign_out_a_file_is_refused_before_any_flight(capsys, a_file, kind, extra):
    out = _refused(capsys, ["campaign", kind, "--runs", "1", "--workers", "1", "--quiet", *extra, "--out", a_file],
                   f"--out '{a_file}' is a file")
    assert "records:" not in out.out and a_file.read_text() == "not a directory\n"


def test_design_report_a_file_is_refused_before_the_design(capsys, tmp_path, a_file):
    bank = tmp_path / "b.f16bank"
    _refused(capsys, ["design", "--tuning", "untuned", "--out", bank, "--report", a_file],
             f"--report '{a_file}' is a file")
    assert not bank.exists()  # refused before designing (and writing) the bank


def test_design_out_under_a_file_is_refused(capsys, a_file):
    _refused(capsys, ["design", "--tuning", "untuned", "--out", a_file / "b.f16bank"], "which is a file")


# -- report on files that are not what they claim ------------------------------------------------
def test_report_on_a_corrupt_summary_names_the_file(capsys, tmp_path):
    (tmp_path / "summary.json").write_text('{"kind": "single", "cases": [')
    _refused(capsys, ["report", tmp_path], f"{tmp_path / 'summary.json'} is not valid JSON", "line 1")


def test_report_on_a_run_json_holding_an_array_names_the_file(capsys, tmp_path):
    (tmp_path / "run.json").write_text("[1, 2, 3]\n")
    _refused(capsys, ["report", tmp_path], f"{tmp_path / 'run.json'} holds a JSON list, not an object")


def test_report_on_a_summary_missing_a_field_names_the_field(capsys, tmp_path):
    (tmp_path / "summary.json").write_text(json.dumps({"kind": "dual", "ratings": {}}))
    _refused(capsys, ["report", tmp_path], "is not a dual campaign summary: its field", "is missing")


# -- numbers out of range, refused where they enter -------------------------------------------------
@pytest.mark.parametrize("argv, expected", [
    (["run", "--duration", "1e12"], "--duration '1e12' must be <= 3600.0 (valid: (0.0, 3600.0])"),
    (["hil", "--duration", "1e12"], "--duration '1e12' must be <= 3600.0"),
    (["hil", "--timeout", "1e12"], "--timeout '1e12' must be <= 3600.0"),
    (["run", "--seed", "99999999999"], "--seed '99999999999' must be <= 2147483647"),
    (["run", "--alt-ft", "90000"], "--alt-ft '90000' must be <= 35000.0"),
    (["run", "--dwell-s", "3.4e7"], "--dwell-s 34000000.0 must lie in [0, 60]"),
    (["campaign", "single", "--dwell-s", "61"], "--dwell-s 61.0 must lie in [0, 60]"),
    (["run", "--p-min", "0.5"], "--p-min 0.5 must lie in [0, 0.0769231)"),
    (["run", "--level1-p-min", "0.01"], "--level1-p-min 0.01 must lie in [0, 0.00833333)"),
    (["run", "--level1-dwell-s", "-1"], "--level1-dwell-s -1.0 must lie in [0, 60]"),
    (["run", "--threshold", "nan"], "--threshold 'nan' must be finite"),
    (["run", "--trim-tracking", "-1"], "--trim-tracking -1.0 must lie in [0, 1e+06]"),
    (["campaign", "soak", "--trim-tracking", "30", "--trim-freeze-probability", "1.5"],
     "--trim-freeze-probability 1.5 must lie in (0, 1]"),
    (["run", "--trim-freeze-probability", "0.5"], "--trim-freeze-probability applies with --trim-tracking only"),
    (["campaign", "soak", "--adapt-turbulence", "--trim-tracking-steady", "0.1"],
     "--trim-tracking-steady applies with --trim-tracking only (the bank is not scheduled, so no default gives it: "
     "give --trim-tracking) (--tuning tuned)"),
    (["campaign", "soak", "--trim-tracking-steady", "0.1"],
     "--trim-tracking-steady applies with --trim-tracking only (or with --adapt-turbulence on a scheduled bank, "
     "whose default is --trim-tracking 30)"),
    (["run", "--adapt-turbulence", "--set-tempering-rho", "2"],
     "--set-tempering-rho applies with --set-tempering only (the bank is not scheduled, so no default gives it"),
    (["hil", "--adapt-turbulence", "--set-tempering-rho", "2"],
     "--set-tempering-rho applies with --set-tempering only (the bank is not scheduled"),
    (["run", "--bank", "scheduled", "--adapt-turbulence", "--maneuver-setting", "off",
      "--trim-tracking-steady-measurements", "AOA"],
     "--trim-tracking-steady-measurements applies with --trim-tracking-steady only (the scheduled defaults do not "
     "give it with these settings: give --trim-tracking-steady)"),
    (["campaign", "single", "--runs", "1000000000"], "--runs '1000000000' must be <= 1000 (valid: [1, 1000])"),
    (["campaign", "dual", "--runs", "1000000000"], "--runs '1000000000' must be <= 1000"),
    (["campaign", "envelope", "--runs", "1e9"], "--runs '1e9' is not an integer"),
    (["campaign", "single", "--workers", "100000"], "--workers '100000' must be <= 1024"),
    (["campaign", "single", "--seed", "-5"], "--seed '-5' must be >= 1"),
    (["campaign", "single", "--failure-time", "0"], "--failure-time '0' must be > 0.0"),
    (["campaign", "single", "--failure-time", "3598"], "--failure-time 3598 leaves no room for the 5 s after it"),
    (["campaign", "single", "--failure-jitter", "-1"], "--failure-jitter '-1' must be >= 0.0"),
    (["campaign", "single", "--failure-time", "3590", "--failure-jitter", "10"],
     "--failure-jitter 10 takes a 3595-s flight past the longest (3600 s)"),
    (["campaign", "dual", "--duration-s", "1e12"], "--duration-s '1e12' must be <= 3600.0"),
    (["campaign", "dual", "--second-time-s", "inf"], "--second-time-s 'inf' must be finite"),
    (["replay", "x.lcmlog", "--tolerance", "nan"], "--tolerance 'nan' must be finite and >= 0"),
])
def test_numbers_out_of_range_are_refused_with_the_valid_range(capsys, argv, expected):
    _refused(capsys, argv, expected)


def test_campaign_config_bounds_the_dwell_as_the_core_does():
    with pytest.raises(CampaignError, match=r"--dwell-s 61.0 must lie in \[0, 60\]"):
        SingleCampaign(estimator={"dwell_s": 61.0}, duration_s=100.0, failure_time_s=3.0).validate()


def test_a_flag_a_command_lacks_is_refused_by_its_own_name(capsys):
    """No abbreviations: `bench truth` has no --turbulence, and it is not read as the estimator's
    --turbulence-banks (which left 'light' as the unrecognised word)."""
    with pytest.raises(SystemExit) as exc:
        main(["bench", "truth", "--turbulence", "light"])
    assert exc.value.code == 2
    assert "unrecognized arguments: --turbulence light" in capsys.readouterr().err


def test_design_schedule_refuses_the_single_point_level_q_and_a_bad_failure_model(capsys, tmp_path):
    """A scheduled design takes --failure-model (default: the tuning's, else names.SCHEDULE_FAILURE_MODEL), not
    the single point's --failed-sensor-level-q (once ignored silently); a failure model it
    cannot read is refused by name before any work."""
    out = tmp_path / "s.f16sched"
    _refused(capsys, ["design", "--schedule", "--out", out, "--failed-sensor-level-q", "0.01"],
             "--failed-sensor-level-q designs one point", "failed_sensor_level_q")
    _refused(capsys, ["design", "--schedule", "--out", out, "--failure-model", "constant=AY"],
             "--failure-model: failure_model constant: component AY has no trim uncertainty")
    assert not out.exists()
