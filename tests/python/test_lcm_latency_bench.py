"""The LCM latency benchmark's plumbing (its figures are printed by the benchmark, not
tested): where it places the processes, how a child is pinned, the echo's own port, how it
reads the in-process timings back, what it refuses."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from latency_driver import PLACEMENTS, echo_name, find_tool, host_floor, main, next_port_url, place
from f16mmae.lcm.channels import HilError
from f16mmae.lcm.daemon import pin_to, statistics_line

ALLOWED = sorted(os.sched_getaffinity(0))


def test_placements():
    assert place("free") == (None, None)
    assert place("shared") == ({ALLOWED[-1]}, {ALLOWED[-1]})
    harness, servers = place("split")
    if len(ALLOWED) > 1:  # the executive on a core of its own
        assert harness == {ALLOWED[0]} and servers == {ALLOWED[-1]}
    else:
        assert harness == servers == {ALLOWED[0]}
    with pytest.raises(ValueError, match="valid: " + ", ".join(PLACEMENTS)):
        place("everywhere")


def test_a_pinned_child_runs_on_its_cpus():
    assert pin_to(None) is None
    cpu = ALLOWED[-1]
    out = subprocess.run([sys.executable, "-c", "import os; print(sorted(os.sched_getaffinity(0)))"],
                         capture_output=True, text=True, check=True, preexec_fn=pin_to({cpu})).stdout
    assert out.strip() == f"[{cpu}]"


def test_the_echo_listens_on_the_next_port():
    assert next_port_url("udpm://239.255.76.67:7671?ttl=0") == "udpm://239.255.76.67:7672?ttl=0"
    assert next_port_url("udpm://239.255.76.67:7667") == "udpm://239.255.76.67:7668"
    assert next_port_url("memq://") == "memq://"


def test_reads_a_statistics_line_not_the_human_one():
    out = ("mmae-daemon: frames 3 updated, ...; sensor-to-publish p50 40.2 us, p99 99.8 us, max 602.7 us\n"
           'mmae-daemon: statistics {"sensor_to_publish_us": {"count": 3, "p50": 40.2, "p99": 99.8, "max": 602.7}}\n')
    assert statistics_line(out, "mmae-daemon")["sensor_to_publish_us"]["p99"] == 99.8
    with pytest.raises(HilError, match="lcm-echo-f16 printed no statistics line"):
        statistics_line(out, "lcm-echo-f16")
    with pytest.raises(HilError, match="statistics line is not JSON"):
        statistics_line("mmae-daemon: statistics {oops\n", "mmae-daemon")


def test_the_tools_are_built_but_not_installed_in_the_package():
    import f16mmae
    package = Path(f16mmae.__file__).parent
    for name in ("lcm-echo-f16", "f16mmae-idle-jitter"):
        assert find_tool(name).parent.name == "latency"
        assert not (package / "bin" / name).exists()


def test_names_the_echo_by_the_control_it_was_made_into():
    assert echo_name(0, 0) == "bare C++ echo"
    assert echo_name(500, 0) == "C++ echo, wakes 500 us early"
    assert echo_name(500, 5) == "C++ echo, wakes 500 us early, +5 us work"
    assert echo_name(0, 5.5) == "C++ echo, +5.5 us work"


@pytest.mark.parametrize("option", ["--warm-lead-us", "--rewarm-us", "--echo-wake-lead-us", "--echo-rewake-us",
                                    "--echo-work-us"])
def test_refuses_a_lead_or_interval_beyond_a_frame_by_name(option, capsys):
    with pytest.raises(SystemExit) as exc:
        main([option, "16000"])
    assert exc.value.code == 2
    assert f"{option} 16000 must lie in [0, 15625) us" in capsys.readouterr().err


def test_the_host_floor_times_the_work_back_to_back_and_after_a_frame_of_idle():
    floor = host_floor({ALLOWED[-1]}, samples=5)
    assert sorted(floor) == [0.0, 15625.0]
    for q in floor.values():
        assert 0 < q["p50"] <= q["p99"] <= q["max"]


@pytest.mark.parametrize("args, message", [
    (["--idle-us", "1,x"], "--idle-us must be a comma-separated list"),
    (["--work-us", "0"], "--work-us must be in (0, 1e5]"),
    (["--samples", "-3"], "--samples must be a whole number >= 1"),
    (["--frobnicate", "1"], "unknown argument '--frobnicate'"),
    (["--samples"], "--samples needs a value"),
])
def test_idle_jitter_refuses_bad_arguments_by_name(args, message):
    p = subprocess.run([str(find_tool("f16mmae-idle-jitter")), *args], capture_output=True, text=True,
                       timeout=10)
    assert p.returncode == 2 and message in p.stderr and "usage:" in p.stderr


@pytest.mark.parametrize("args, message", [
    (["--work-us", "2e5"], "--work-us must be at most 100000"),
    (["--work-us", "-1"], "--work-us must be a finite number >= 0, got '-1'"),
    (["--rewake-us", "nan"], "--rewake-us must be a finite number >= 0, got 'nan'"),
])
def test_the_echo_refuses_bad_arguments_by_name(args, message):
    p = subprocess.run([str(find_tool("lcm-echo-f16")), "--lcm-url", "memq://", *args], capture_output=True,
                       text=True, timeout=10)
    assert p.returncode == 2 and message in p.stderr
