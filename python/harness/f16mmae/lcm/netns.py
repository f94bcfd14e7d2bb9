"""Private network namespaces for everything that runs two LCM processes on this host.

The daemon's tests, its soak and the LCM latency benchmark all need udpm multicast between
processes of one machine and must never put a packet on a real interface. They run inside a
network namespace of their own, made by an unprivileged user namespace (``unshare --user
--map-root-user --net``) with the loopback up, multicast on and a route for 224.0.0.0/4: the
only interface in it is ``lo``.

* :func:`only_loopback` -- true inside such a namespace.
* :func:`netns_unavailable` -- why one cannot be made here (None where it can).
* :func:`run_in_private_netns` -- run ``argv`` as a child inside a fresh one.
* :func:`reexec_in_private_netns` -- run this Python command again inside a fresh one (for a
  command line tool: call it first thing; inside the namespace it returns None).
"""
from __future__ import annotations

import shutil
import subprocess
import sys

from ..errors import F16mmaeError

SETUP = "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo"
UNSHARE = ("unshare", "--user", "--map-root-user", "--net")


class NetnsError(F16mmaeError):
    """A private network namespace cannot be made on this host."""


def only_loopback() -> bool:
    """True inside a namespace whose only network interface is ``lo`` (/proc/net/dev is per
    namespace; /sys/class/net is not remounted by unshare)."""
    with open("/proc/net/dev") as f:
        names = {line.split(":", 1)[0].strip() for line in f.readlines()[2:]}
    return names == {"lo"}


def netns_unavailable() -> str | None:
    """Why a private network namespace cannot be made here, or None when it can."""
    for tool in ("unshare", "ip"):
        if shutil.which(tool) is None:
            return f"'{tool}' is not installed (util-linux / iproute2): no private network namespace"
    p = subprocess.run([*UNSHARE, "sh", "-c", SETUP], capture_output=True, text=True, timeout=30)
    if p.returncode != 0:
        return (f"this host refuses an unprivileged network namespace ({p.stderr.strip() or p.returncode}); "
                f"enable user namespaces (sysctl kernel.unprivileged_userns_clone=1)")
    return None


def _wrapped(argv: list[str]) -> list[str]:
    return [*UNSHARE, "sh", "-c", SETUP + ' && exec "$@"', "netns", *argv]


def run_in_private_netns(argv: list[str], timeout_s: float) -> subprocess.CompletedProcess:
    """``argv`` inside a fresh private network namespace; output captured as text."""
    return subprocess.run(_wrapped(argv), capture_output=True, text=True, timeout=timeout_s)


def reexec_in_private_netns(argv: list[str]) -> int | None:
    """Inside a private namespace already: None (go on). Otherwise run ``python argv`` (this
    interpreter, e.g. ``[script, *args]`` or ``["-m", "module", *args]``) in a fresh one,
    output passed through, and return its exit status; NetnsError when none can be made."""
    if only_loopback():
        return None
    reason = netns_unavailable()
    if reason is not None:
        raise NetnsError(reason)
    return subprocess.call(_wrapped([sys.executable, *argv]))
