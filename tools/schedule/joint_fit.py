"""Lab driver (not in the wheel): whether the no-failure filter's residual covariance A fits its
residuals jointly, not only channel by channel, at grid nodes.

    python tools/schedule/joint_fit.py NODES [SCHEDULE]      # NODES e.g. 0.35:10000,0.4:20000

At each node, no-failure flights with the design's calibration-flight setup
(``design.flights.fly_closed_loop``: light turbulence, the truth's dither, raw feedback, 8 s,
tuning flight seeds 1-4), the node's own NONE filter (``core.FilterBank``, started at x = 0) run
over them after the first second.  Printed: NIS / m = mean(r^T A^-1 r) / m (1 when A fits), the
channel pairs whose correlation in A or in the residuals' covariance C exceeds 0.3 (A / C), the
eigenvalues of A^-1/2 C A^-T/2 (1 when A fits; the largest: how much more power than A gives
it the worst direction carries) and that direction in sigma units.
"""
import sys

import numpy as np

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.design.flights import fly_closed_loop
from evidence import node_of

info = load_bank(sys.argv[2] if len(sys.argv) > 2 else "scheduled")[2].schedule
for item in sys.argv[1].split(","):
    mach, alt = (float(x) for x in item.split(":"))
    h = node_of(info, mach, alt)["bank"]["NONE"]
    bank = core.FilterBank([core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a)])
    res = []
    for seed in (1, 2, 3, 4):
        fl = fly_closed_loop(mach, alt, seed=seed, failure=None)
        bank.reset()
        for i in range(len(fl.z)):
            bank.step(fl.z[i], fl.u[i])
            if i >= names.FRAME_RATE_HZ:
                res.append(np.asarray(bank.residuals)[0])
    r = np.array(res)
    c, a = r.T @ r / len(r), np.asarray(h.a)
    da, dc = np.sqrt(np.diag(a)), np.sqrt(np.diag(c))
    ca, cc = a / np.outer(da, da), c / np.outer(dc, dc)
    nis = np.einsum("ij,jk,ik->i", r, np.linalg.inv(a), r).mean()
    pairs = [f"{names.SENSORS[i]}-{names.SENSORS[j]} {ca[i, j]:+.2f} / {cc[i, j]:+.2f}"
             for i in range(names.NZ) for j in range(i + 1, names.NZ) if max(abs(ca[i, j]), abs(cc[i, j])) > 0.3]
    low = np.linalg.cholesky(a)
    w = np.linalg.inv(low) @ c @ np.linalg.inv(low).T
    ev, vec = np.linalg.eigh(w)
    top = low @ vec[:, -1]
    print(f"Mach {mach:.2f}, {alt:.0f} ft: NIS / m {nis / names.NZ:.2f}; correlation A / residuals: {', '.join(pairs)}")
    print(f"  eigenvalues {np.round(ev, 2)}; worst direction (sigma units): "
          + " ".join(f"{names.SENSORS[i]} {top[i] / da[i]:+.2f}" for i in range(names.NZ)))
