"""Lab driver (not in the wheel): can the scheduled default tell calm air from light turbulence at
each node by the power ratio its turbulence adaptation measures?

    python tools/schedule/calm_rho.py [--points 0.4:20000,0.7:30000,...] [--seeds 11,12]
                                      [--flight-s 30] [--from-s 15]

Flies no-failure flights (the truth's dither, MMAE feedback) with the scheduled default
(``--bank scheduled --adapt-turbulence``, as ``f16mmae run`` flies it) in calm air and in light
turbulence at each point, and prints per point and air the mean over the frames from ``--from-s``
on (after the adaptation's running start and average) of the adaptation's power ratio rho
(``turbulence_power_ratio``: min over the hypotheses on line of q_k / m, averaged;
cpp/f16mmae/turbulence_adaptation.h) and of its scale s, averaged over the seeds, and the ratio
of the two airs' rho. A selector that picks a bank by the air (the turbulence bank set) needs
that ratio well above 1 at every node (docs/results/envelope_scheduled.md, round 23).
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.truth.scenario import Scenario

POINTS = "0.4:20000,0.7:30000,0.35:25000,0.3:10000,0.5:15000,0.65:9000,0.8:15000,0.45:33900,0.6:25000"


def mean_rho(bank, mach: float, alt_ft: float, air: str, seed: int, flight_s: float, from_s: float):
    """(rho, s) averaged over the frames from ``from_s`` on of one no-failure flight."""
    estimator = Estimator(bank, adapt_turbulence=True)
    rows = []

    def on_frame(t, u, z, air_data):
        if t >= from_s:
            rows.append((estimator.core_bank.turbulence_power_ratio, estimator.turbulence_scale))

    fly(Scenario(mach=mach, alt_ft=alt_ft, turbulence=air, duration_s=flight_s, seed=seed), bank,
        estimator=estimator, on_frame=on_frame)
    return np.mean(rows, axis=0)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", default=POINTS, help="MACH:ALT_FT,... (default: nine across the envelope)")
    ap.add_argument("--seeds", default="11,12")
    ap.add_argument("--flight-s", type=float, default=30.0)
    ap.add_argument("--from-s", type=float, default=15.0)
    args = ap.parse_args()
    if not 0.0 <= args.from_s < args.flight_s:
        ap.error(f"--from-s {args.from_s:g} must lie in [0, --flight-s {args.flight_s:g})")
    seeds = [int(s) for s in args.seeds.split(",")]
    bank = load_bank("scheduled")[2]
    print(f"seeds {seeds}, {args.flight_s:g}-s flights, frames from {args.from_s:g} s")
    print(f"{'Mach':>5} {'alt_ft':>7} {'calm rho':>9} {'s':>5} {'light rho':>10} {'s':>5} {'light/calm':>11}")
    for point in args.points.split(","):
        mach, alt_ft = (float(v) for v in point.split(":"))
        calm, light = (np.mean([mean_rho(bank, mach, alt_ft, air, s, args.flight_s, args.from_s) for s in seeds], axis=0)
                       for air in ("none", "light"))
        print(f"{mach:5.2f} {alt_ft:7.0f} {calm[0]:9.3f} {calm[1]:5.2f} {light[0]:10.3f} {light[1]:5.2f} "
              f"{light[0] / calm[0]:11.2f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
