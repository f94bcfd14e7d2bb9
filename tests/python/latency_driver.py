"""The LCM latency driver (tools/latency/lcm_latency.py: lab code, not in the package), loaded
by path for the tests, as `f16mmae bench lcm` loads it."""
from __future__ import annotations

from tool_module import load_tool

_driver = load_tool("latency/lcm_latency.py")

PLACEMENTS = _driver.PLACEMENTS
echo_name = _driver.echo_name
find_tool = _driver.find_tool
host_floor = _driver.host_floor
main = _driver.main
next_port_url = _driver.next_port_url
place = _driver.place
