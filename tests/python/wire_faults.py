"""The wire-fault script shared by the replay test (in process, memq://) and the udpm test
against mmae-daemon: what a lossy wire does to frames 0..11, and the publisher of one step.

    frames 0-3 in order; sensor 2 twice (duplicate); frames 4, 5 lost; sensor 1 again after
    7 (out of order); sensor 8 with a valid flag false and sensor 10 with a NaN (rejected);
    command 10 lost.
Expected at the executive: statuses for 0 1 2 3 6 7 9 11; stale at 6 (2 frames without
update), 9 (1) and 11 (1); 2 dropped, 2 rejected, 4 stale, 3 commands missed."""
from __future__ import annotations

import math

import numpy as np

from f16mmae.lcm.codec import command_frame_bytes, sensor_frame_bytes

WIRE = [("s", 0), ("c", 0), ("s", 1), ("c", 1),
        ("s", 2), ("s", 2), ("c", 2),          # a duplicate sensor frame
        ("s", 3), ("c", 3),                    # frames 4 and 5 lost
        ("s", 6), ("c", 6),
        ("s", 7), ("s", 1), ("c", 7),          # frame 1 again, late
        ("s", 8, "invalid"), ("c", 8),         # a valid flag false: rejected
        ("s", 9), ("c", 9),
        ("s", 10, "nan"),                      # non-finite: rejected; command 10 lost too
        ("s", 11), ("c", 11)]
STATUS_FRAMES = [0, 1, 2, 3, 6, 7, 9, 11]
STALE = {6: 2, 9: 1, 11: 1}


def publish_step(lc, chans, step, bank, rng, z_sigma: float, u_sigma: float, nan_index: int = 2) -> str:
    """Publish one step of WIRE near the bank's trim; returns its kind ("s" or "c")."""
    kind, i, *fault = step
    if kind == "s":
        z = np.array(bank.z_trim) + z_sigma * rng.standard_normal(len(bank.z_trim))
        if fault == ["nan"]:
            z[nan_index] = math.nan
        lc.publish(chans.sensors, sensor_frame_bytes(i, z, valid=fault != ["invalid"]))
    else:
        lc.publish(chans.commands, command_frame_bytes(i, np.array(bank.u_trim) + u_sigma * rng.standard_normal(len(bank.u_trim))))
    return kind
