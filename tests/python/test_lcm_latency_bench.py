"""The LCM latency benchmark's plumbing (its figures are printed by the benchmark, not
tested): where it places the processes, how a child is pinned, the echo's own port."""
from __future__ import annotations

import os
import subprocess
import sys

import pytest

from f16mmae.benchmarks.lcm_latency import PLACEMENTS, next_port_url, place
from f16mmae.hil import pin_to

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
