"""Lab driver (not in the wheel): can the scheduled default tell calm air from light turbulence at
each node by the power ratio its turbulence adaptation measures?

    python tools/schedule/calm_rho.py [--points 0.4:20000,0.7:30000,...] [--seeds 11,12]
                                      [--flight-s 30] [--from-s 15]
    python tools/schedule/calm_rho.py --per-second --points 0.4:20000 --seeds 100-129 --flight-s 10
    python tools/schedule/calm_rho.py --per-second --measure whiteness --seeds 100-109 --flight-s 10

Flies no-failure flights (the truth's dither, MMAE feedback) with the scheduled default
(``--bank scheduled --adapt-turbulence``, as ``f16mmae run`` flies it) in calm air and in light
turbulence at each point, and prints per point and air the mean over the frames from ``--from-s``
on (after the adaptation's running start and average) of the adaptation's power ratio rho
(``turbulence_power_ratio``: min over the hypotheses on line of q_k / m, averaged;
cpp/f16mmae/turbulence_adaptation.h) and of its scale s, averaged over the seeds, and the ratio
of the two airs' rho. A selector that picks a bank by the air (the turbulence bank set) needs
that ratio well above 1 at every node (docs/results/envelope_scheduled.md, round 23).

``--per-second``: per point and second of flight, the measured power ratio rho-bar (the
calm-air complete model's measure, ``measured_power_ratio``; cpp/f16mmae/calm_air_complete.h)
averaged over the seeds' frames of that second, its largest seed mean in calm air and least in
light air, against the calm-air bound in force (the node's reference times the default's
``names.SCHEDULE_CALM_COMPLETE`` VEL bound), and the share of frames read calm in each air
(round 24: the two airs' overlap at the start of a flight). With ``--measure whiteness`` the
measure is the residual whiteness W-bar (``calm_whiteness``, ``--calm-measure whiteness`` at
its default bound; cpp/f16mmae/residual_whiteness.h) and the share read calm is its rule's
(round 25); seconds before its first block count as NaN and are left out of the means.
"""
from __future__ import annotations

import argparse
import warnings

import numpy as np

from f16mmae import names
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import parse_calm_complete_table as calm_bounds
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


def per_second(bank, mach: float, alt_ft: float, air: str, seeds: list[int], flight_s: float,
               measure: str = "power") -> np.ndarray:
    """(seeds, seconds, 3): per seed and second of one no-failure flight the mean of the measure
    (rho-bar, or W-bar with ``measure`` whiteness), the power ratio's bound in force (NaN for
    the whiteness) and the share of frames whose VEL is read complete."""
    bound = calm_bounds(names.SCHEDULE_CALM_COMPLETE)["VEL"]
    whiteness = measure == "whiteness"
    out = []
    for seed in seeds:
        estimator = Estimator(bank, adapt_turbulence=True, calm_measure=measure)
        core_bank, rows = estimator.core_bank, []

        def on_frame(t, u, z, air_data):
            rows.append((int(t), core_bank.calm_whiteness if whiteness else core_bank.measured_power_ratio,
                         np.nan if whiteness else bound * core_bank.calm_reference,
                         core_bank.calm_complete_channels >> names.SENSORS.index("VEL") & 1))

        fly(Scenario(mach=mach, alt_ft=alt_ft, turbulence=air, duration_s=flight_s, seed=seed), bank,
            estimator=estimator, on_frame=on_frame)
        r = np.array(rows)
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)   # a second before the first block: NaN
            out.append([np.nanmean(r[r[:, 0] == k, 1:], axis=0) for k in range(int(flight_s))])
    return np.array(out)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", default=POINTS, help="MACH:ALT_FT,... (default: nine across the envelope)")
    ap.add_argument("--seeds", default="11,12")
    ap.add_argument("--flight-s", type=float, default=30.0)
    ap.add_argument("--from-s", type=float, default=15.0)
    ap.add_argument("--per-second", action="store_true", help="rho-bar second by second against the calm-air "
                    "bound (module docstring); --seeds takes FIRST-LAST too")
    ap.add_argument("--measure", choices=("power", "whiteness"), default="power",
                    help="--per-second's measure of the air: rho-bar (power) or W-bar (whiteness)")
    args = ap.parse_args()
    if not args.per_second and not 0.0 <= args.from_s < args.flight_s:
        ap.error(f"--from-s {args.from_s:g} must lie in [0, --flight-s {args.flight_s:g})")
    first, _, last = args.seeds.partition("-")
    seeds = list(range(int(first), int(last) + 1)) if last else [int(s) for s in args.seeds.split(",")]
    bank = load_bank("scheduled")[2]
    if args.per_second:
        what = "W-bar" if args.measure == "whiteness" else "rho-bar"
        print(f"seeds {seeds[0]}-{seeds[-1]} ({len(seeds)}), {args.flight_s:g}-s flights; per second: {what} "
              "calm mean / largest, light mean / least, the bound, the share read calm (calm air, light air)")
        for point in args.points.split(","):
            mach, alt_ft = (float(v) for v in point.split(":"))
            calm, light = (per_second(bank, mach, alt_ft, air, seeds, args.flight_s, args.measure)
                           for air in ("none", "light"))
            print(f"Mach {mach:.2f}, {alt_ft:.0f} ft")
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)   # the seconds before the first block
                for k in range(calm.shape[1]):
                    print(f"  {k:3d} s  {np.nanmean(calm[:, k, 0]):.3f} / {np.nanmax(calm[:, k, 0]):.3f}  "
                          f"{np.nanmean(light[:, k, 0]):.3f} / {np.nanmin(light[:, k, 0]):.3f}  "
                          f"{np.mean(calm[:, k, 1]):.3f}  {calm[:, k, 2].mean():.2f} {light[:, k, 2].mean():.2f}",
                          flush=True)
        return 0
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
