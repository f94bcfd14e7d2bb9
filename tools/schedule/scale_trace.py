"""Lab driver (not in the wheel): a failure's climb and the adaptation's scale s, second by
second, in the node's own estimator.

    python tools/schedule/scale_trace.py MACH ALT_FT FAILURE [SCHEDULE]

The failure is flown at the node with the design's calibration-flight setup
(``design.flights.fly_closed_loop``: light turbulence, the truth's dither, raw feedback,
complete failure at 3 s, 8 s, tuning flight seeds 1-4) and the node's bank run as the
estimator (``core.HierarchicalBank`` with the node's settings and reference, the adaptation on,
the 1-s start-up).  Printed per second: s, ln(p_f / p_NONE) and the most probable failure
hypothesis; and the declarations.
"""
import sys

import numpy as np

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.design.flights import fly_closed_loop
from evidence import node_of

info = load_bank(sys.argv[4] if len(sys.argv) > 4 else "scheduled")[2].schedule
mach, alt, fail = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
nd = node_of(info, mach, alt)
mb = nd["bank"]
settings = dict(mb.estimator_settings)
k = names.SINGLE_HYPOTHESES.index(fail)
print(f"Mach {mach:.2f}, {alt:.0f} ft: reference {nd['adapt_reference']}, {settings}")
for seed in (1, 2, 3, 4):
    fl = fly_closed_loop(mach, alt, seed=seed, failure=fail, failure_time_s=3.0)
    est = core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference=nd["adapt_reference"], start_up_s=1.0,
                                **settings)
    out = []
    for i in range(len(fl.z)):
        d = est.step(fl.z[i] + mb.z_trim, fl.u[i] + mb.u_trim)
        if d is not None:
            out.append(f"declared {d} at {i / names.FRAME_RATE_HZ:.2f} s")
        if i % names.FRAME_RATE_HZ == names.FRAME_RATE_HZ - 1:
            p = np.asarray(est.probabilities)
            top = names.SINGLE_HYPOTHESES[int(np.argmax(p[1:])) + 1]
            out.append(f"{(i + 1) / names.FRAME_RATE_HZ:.0f} s: s {est.turbulence_scale:.1f}, "
                       f"{np.log(p[k]) - np.log(p[0]):.1f} ({top})")
    print(f"seed {seed}: " + " | ".join(out))
