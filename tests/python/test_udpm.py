"""The two-process tests over UDP multicast (udpm_scenarios.py: mmae-daemon, lcm-logger,
lcm-logplayer, wire faults, hostile messages, the latency echo), each run by a pytest of its
own inside a private network namespace (f16mmae.lcm.netns) that this test makes: they need no
multicast set-up on the host, never skip for the lack of it, and never send a packet on a
real interface. They skip, saying why, only where the host refuses such namespaces."""
from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

from f16mmae.lcm.netns import netns_unavailable, run_in_private_netns

SCENARIOS = Path(__file__).with_name("udpm_scenarios.py")
NAMES = [node.name for node in ast.parse(SCENARIOS.read_text()).body
         if isinstance(node, ast.FunctionDef) and node.name.startswith("test_")]

_reason = netns_unavailable()


@pytest.mark.skipif(_reason is not None, reason=_reason or "")
@pytest.mark.parametrize("name", NAMES)
def test_in_a_private_network_namespace(name, tmp_path):
    p = run_in_private_netns([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--basetemp",
                              str(tmp_path / "inner"), f"{SCENARIOS}::{name}"], timeout_s=300)
    assert p.returncode == 0, f"{name} failed inside its network namespace:\n{p.stdout[-6000:]}\n{p.stderr[-2000:]}"


def test_every_scenario_is_run():
    assert len(NAMES) >= 6 and len(set(NAMES)) == len(NAMES)
