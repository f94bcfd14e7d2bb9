"""Test support shared by the tests that read what ``mmae-daemon`` says when it starts."""
from __future__ import annotations

import subprocess

from f16mmae.lcm.daemon import find_executable


def ready_line(*args) -> str:
    """The first line ``mmae-daemon`` prints when started with ``args`` on ``memq://`` (its
    ready line, naming the settings in force), the daemon then stopped."""
    p = subprocess.Popen([str(find_executable("mmae-daemon")), *map(str, args), "--lcm-url", "memq://"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        return p.stdout.readline()
    finally:
        p.terminate()
        p.communicate(timeout=5)
