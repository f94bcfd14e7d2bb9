"""The LCM latency driver (tools/latency/lcm_latency.py: lab code, not in the package), loaded
by path for the tests, as `f16mmae bench lcm` loads it."""
from __future__ import annotations

import importlib.util
from pathlib import Path

_PATH = Path(__file__).resolve().parents[2] / "tools" / "latency" / "lcm_latency.py"
_spec = importlib.util.spec_from_file_location("lcm_latency", _PATH)
_driver = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_driver)

PLACEMENTS = _driver.PLACEMENTS
echo_name = _driver.echo_name
find_tool = _driver.find_tool
host_floor = _driver.host_floor
main = _driver.main
next_port_url = _driver.next_port_url
place = _driver.place
