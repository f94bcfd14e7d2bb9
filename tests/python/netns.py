"""Private network namespaces for the two-process (udpm) tests.

``run_in_private_netns(argv)`` runs ``argv`` as a child inside a network namespace of its
own, made by an unprivileged user namespace (``unshare --user --map-root-user --net``), with
the loopback up, multicast on and a route for 224.0.0.0/4: LCM's udpm multicast then works
between the processes of the test and no packet can reach a real interface, for the only
interface in the namespace is ``lo``. ``netns_unavailable()`` says why that cannot be done
here (None where it can).
"""
from __future__ import annotations

import shutil
import subprocess

SETUP = "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo"


def only_loopback() -> bool:
    """True inside a namespace whose only network interface is ``lo`` (/proc/net/dev is per
    namespace; /sys/class/net is not remounted by unshare)."""
    with open("/proc/net/dev") as f:
        names = {line.split(":", 1)[0].strip() for line in f.readlines()[2:]}
    return names == {"lo"}


def netns_unavailable() -> str | None:
    for tool in ("unshare", "ip"):
        if shutil.which(tool) is None:
            return f"'{tool}' is not installed (util-linux / iproute2): no private network namespace"
    p = subprocess.run(["unshare", "--user", "--map-root-user", "--net", "sh", "-c", SETUP],
                       capture_output=True, text=True, timeout=30)
    if p.returncode != 0:
        return (f"this host refuses an unprivileged network namespace ({p.stderr.strip() or p.returncode}); "
                f"enable user namespaces (sysctl kernel.unprivileged_userns_clone=1)")
    return None


def run_in_private_netns(argv: list[str], timeout_s: float) -> subprocess.CompletedProcess:
    """``argv`` inside a fresh private network namespace (loopback multicast set up)."""
    return subprocess.run(["unshare", "--user", "--map-root-user", "--net", "sh", "-c", SETUP + ' && exec "$@"',
                           "netns", *argv], capture_output=True, text=True, timeout=timeout_s)
