"""The LCM link's names: channels (UPPER_SNAKE, with an optional prefix, as the daemon's
``--channel-prefix``), the default LCM URL, and the error of the link."""
from __future__ import annotations

import os
from dataclasses import dataclass

from ..errors import F16mmaeError

#: LCM's default URL (what LCM tools use when $LCM_DEFAULT_URL is unset).
DEFAULT_LCM_URL = "udpm://239.255.76.67:7667?ttl=0"


class HilError(F16mmaeError, RuntimeError):
    """The executive cannot be reached, started, or answered wrongly: the message says why."""


@dataclass(frozen=True)
class Channels:
    sensors: str
    commands: str
    status: str
    reset: str
    run_marker: str


def channels(prefix: str = "") -> Channels:
    """The channel names with ``prefix`` prepended (the daemon's ``--channel-prefix``)."""
    return Channels(prefix + "F16_SENSORS", prefix + "F16_COMMANDS", prefix + "MMAE_STATUS",
                    prefix + "MMAE_RESET", prefix + "F16_RUN_MARKER")


def default_lcm_url() -> str:
    return os.environ.get("LCM_DEFAULT_URL") or DEFAULT_LCM_URL


