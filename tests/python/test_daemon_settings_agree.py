"""The estimator settings rule exists twice -- in C++ for mmae-daemon
(``cpp/daemon/bank_settings.cpp``) and in Python for the in-process loop
(``banks.bank_estimator_settings``) -- so the daemon and ``f16mmae run`` run the same
estimator on the same bank.  This test holds the two to each other: banks that differ only in
their metadata, each read by both; the daemon reports what it runs on its ready line."""
from __future__ import annotations

import json
import re
import subprocess

import pytest

from f16mmae import banks, core
from f16mmae.banks import load_bank
from f16mmae.lcm.daemon import find_executable

DAEMON = str(find_executable("mmae-daemon"))  # part of every build: a missing daemon fails here

#: The core's defaults, the paper's: p_min 0.001, threshold 0.9, dwell 0.25 s.
PAPER = {"p_min": 1e-3, "threshold": 0.9, "dwell_s": 0.25}
READY = re.compile(r"p_min ([^,]+), threshold ([^,]+), dwell ([^ ]+) s")


def _with_metadata(bank, metadata: str, path):
    copy = core.ModelBank(
        bank.hypotheses, state_names=bank.state_names, input_names=bank.input_names,
        measurement_names=bank.measurement_names, frame_rate_hz=bank.frame_rate_hz,
        u_trim=bank.u_trim, z_trim=bank.z_trim, h_output=bank.h_output, mach=bank.mach,
        alt_ft=bank.alt_ft, tuning=bank.tuning, metadata=metadata)
    copy.save(path)
    return copy


def _daemon_settings(path) -> tuple[int, dict | None, str]:
    p = subprocess.Popen([DAEMON, "--bank", str(path), "--lcm-url", "memq://"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline()
    p.terminate()
    out, err = p.communicate(timeout=10)
    m = READY.search(line)
    settings = None if m is None else dict(zip(("p_min", "threshold", "dwell_s"), map(float, m.groups())))
    return p.returncode, settings, line + out + err


@pytest.mark.parametrize("metadata", [
    None,  # the shipped tuned bank's own
    "",
    "[1, 2]",
    json.dumps({"estimator": 5}),
    json.dumps({"estimator": {"p_min": 1e-6}}),
    json.dumps({"estimator": {"threshold": 0.95, "dwell_s": 0.5, "unknown": 3}, "tuning": "x"}),
    json.dumps({"design": {"estimator": {"p_min": 1e-4}}}),  # only the top-level object counts
])
def test_daemon_and_closed_loop_read_the_same_settings(metadata, tmp_path):
    tuned = load_bank("tuned")[2]
    bank = tuned if metadata is None else _with_metadata(tuned, metadata, tmp_path / "b.f16bank")
    path = load_bank("tuned")[1] if metadata is None else tmp_path / "b.f16bank"
    rc, daemon, text = _daemon_settings(path)
    assert rc == 0 and daemon is not None, text
    python = {**PAPER, **banks.bank_estimator_settings(bank)}
    assert daemon == pytest.approx(python, rel=1e-5), text  # the ready line prints %g


def test_a_non_numeric_setting_is_refused_by_both(tmp_path):
    bank = _with_metadata(load_bank("tuned")[2], json.dumps({"estimator": {"p_min": "low"}}),
                          tmp_path / "b.f16bank")
    with pytest.raises(ValueError):
        banks.bank_estimator_settings(bank)
    rc, settings, text = _daemon_settings(tmp_path / "b.f16bank")
    assert rc == 1 and settings is None and "p_min" in text
