"""Lab driver (not in the wheel): how large the no-failure filter's residuals are against its own
residual covariance A at grid nodes, per sensor, in calm air and in turbulence -- the model's fit
at the node (a bias: the trim or the linearization; a power above 1 in calm air: the dynamics).

    python tools/schedule/residual_power.py --schedule FILE [--nodes 0.4:20000,0.35:10000] \\
        [--seeds 1,2,3,4] [--turbulence none,light] [--first-s 1.0]

At each node, no-failure flights with the design's calibration-flight setup
(``design.flights.fly_closed_loop``: the truth's dither, raw feedback, 8 s, tuning flight
seeds), the node's own level-0 NONE filter (``core.FilterBank`` of the node's bank, started at
x = 0) run over the record.  Printed per turbulence level and sensor, over the first
``--first-s`` seconds and over the rest of the flight (mean over the seeds):

  bias   mean residual / sqrt(A_jj)            (the residual's mean in its own sigmas)
  power  mean residual^2 / A_jj                (1 when the filter's A matches its residual)
  s      the turbulence adaptation's scale the node's estimator holds (its reference from the
         file), the mean over the same frames
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.campaign.envelope.points import dynamic_pressure_psf
from f16mmae.design.flights import fly_closed_loop
from evidence import node_of


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--schedule", default="scheduled")
    ap.add_argument("--nodes", default="0.4:20000,0.3:10000,0.35:10000,0.4:10000,0.35:5000")
    ap.add_argument("--seeds", default="1,2,3,4")
    ap.add_argument("--turbulence", default="none,light")
    ap.add_argument("--first-s", type=float, default=1.0)
    args = ap.parse_args()
    info = load_bank(args.schedule)[2].schedule
    seeds = [int(s) for s in args.seeds.split(",")]
    first = int(args.first_s * names.FRAME_RATE_HZ)
    sensors = " ".join(f"{s:>11s}" for s in names.SENSORS)
    for item in args.nodes.split(","):
        mach, alt = (float(x) for x in item.split(":"))
        nd = node_of(info, mach, alt)
        mb = nd["bank"]
        settings = dict(mb.estimator_settings)
        none = mb[names.NONE]
        sigma = np.sqrt(np.diag(none.a))
        print(f"Mach {mach:.2f}, {alt:.0f} ft, q {dynamic_pressure_psf(mach, alt):.0f} lbf/ft^2, reference "
              f"{nd['adapt_reference']}; sqrt(A) " + " ".join(f"{x:.3g}" for x in sigma), flush=True)
        print(f"  {'':14s} {sensors}   s")
        for level in args.turbulence.split(","):
            r_all, s_all = [], []
            for seed in seeds:
                fl = fly_closed_loop(mach, alt, seed=seed, turbulence_level=level)
                bank = core.FilterBank([core.FilterModel(phi=none.phi, bd=none.bd, h=none.h, k=none.k, a=none.a)],
                                       p_min=settings["p_min"])
                est = core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference=nd["adapt_reference"], **settings)
                rs, ss = [], []
                for i in range(len(fl.z)):
                    bank.step(fl.z[i], fl.u[i])
                    est.step(fl.z[i] + mb.z_trim, fl.u[i] + mb.u_trim)
                    rs.append(np.asarray(bank.residuals)[0] / sigma)
                    ss.append(est.turbulence_scale)
                r_all.append(rs)
                s_all.append(ss)
            r, s = np.asarray(r_all), np.asarray(s_all)
            for label, sl in ((f"0-{args.first_s:g} s", slice(0, first)), (f"{args.first_s:g}-8 s", slice(first, None))):
                bias = r[:, sl].mean(axis=(0, 1))
                power = (r[:, sl] ** 2).mean(axis=(0, 1))
                print(f"  {level:5s} {label:8s} " + " ".join(f"{b:+5.2f}/{p:5.2f}" for b, p in zip(bias, power))
                      + f"  {s[:, sl].mean():4.1f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
