"""f16mmae.lcm.netns: a tool that re-executes itself through reexec_in_private_netns runs
inside a namespace whose only interface is the loopback, with multicast routed on it."""
from __future__ import annotations

import subprocess
import sys

import pytest

from f16mmae.lcm.netns import netns_unavailable

TOOL = """
import sys, subprocess
from f16mmae.lcm.netns import only_loopback, reexec_in_private_netns
status = reexec_in_private_netns([__file__, *sys.argv[1:]])
if status is not None:
    sys.exit(status)
route = subprocess.run(["ip", "route", "show", "224.0.0.0/4"], capture_output=True, text=True).stdout
print("inside", only_loopback(), "route" if "dev lo" in route else "no-route", *sys.argv[1:])
sys.exit(3)
"""


def test_a_tool_reexecutes_itself_in_a_loopback_only_namespace(tmp_path):
    reason = netns_unavailable()
    assert reason is None, reason  # the two-process tests do not skip: the host must allow it
    tool = tmp_path / "tool.py"
    tool.write_text(TOOL)
    p = subprocess.run([sys.executable, str(tool), "a", "b"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 3, p.stderr  # the child's status comes back
    assert p.stdout.split() == ["inside", "True", "route", "a", "b"]


@pytest.mark.parametrize("tool", ["tools/soak/daemon_soak.py", "tools/latency/lcm_latency.py"])
def test_the_two_process_tools_make_their_namespace(tool):
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / tool).read_text()
    assert "reexec_in_private_netns(" in text
