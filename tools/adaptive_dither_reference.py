"""The adaptive dither's reference for one adapted bank (truth/dither.py
``ADAPTED_DITHER_REFERENCE``): the measured residual power ratio rho-bar of the turbulence
adaptation (cpp/f16mmae/turbulence_adaptation.h ``measured_power_ratio``) on no-failure flights
of the scheduled default (``--adapt-turbulence``, as flown, fixed dither) in moderate and in
severe air, by altitude.  rho-bar is each node's residual power over its own design's, but
the Dryden intensities of a level grow with altitude, so the reference is scheduled on the
measured air data: at each grid point the geometric mean of the moderate and severe
medians (frames from 1 s on), as the set's members' references are, on the grid of the
throttle dither's table (Mach 0.3-0.8 x 5,000-35,000 ft); the table is printed to paste.  Tuning
seeds: kind ``dither_reference`` at campaign seed 7.

    .venv/bin/python tools/adaptive_dither_reference.py --runs 3
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import FRAME_RATE_HZ
from f16mmae.seeds import evaluation_seed
from f16mmae.truth import Scenario
from f16mmae.truth.aircraft import TrimError
from f16mmae.truth.dither import THROTTLE_GRID_ALT_FT, THROTTLE_GRID_MACH, adaptive_mix

LEVELS = ("moderate", "severe")


def measured_rho(model_bank, mach: float, alt_ft: float, level: str, seed: int, duration_s: float) -> np.ndarray:
    """rho-bar after each frame from 1 s on of one no-failure flight."""
    est = Estimator(model_bank, adapt_turbulence=True)
    rho: list[float] = []
    fly(Scenario(mach=mach, alt_ft=alt_ft, turbulence=level, duration_s=duration_s, seed=seed), model_bank,
        estimator=est, on_frame=lambda t, u, z, a: rho.append(est.core_bank.measured_power_ratio))
    return np.array(rho[int(FRAME_RATE_HZ):])


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--bank", default="scheduled", help="a scheduled bank (default: the scheduled default's)")
    p.add_argument("--runs", type=int, default=3, help="flights per grid point and level")
    p.add_argument("--duration", type=float, default=20.0, help="flight length, s")
    args = p.parse_args(argv)
    _, _, mb = load_bank(args.bank)
    print("| Mach | altitude, ft | moderate rho-bar p5 / median / p95 | severe p5 / median / p95 | reference "
          "| h at moderate p95 | h at severe p5 |")
    print("|---|---|---|---|---|---|---|")
    table = []
    for mach in THROTTLE_GRID_MACH:
        row = []
        for alt in THROTTLE_GRID_ALT_FT:
            try:
                xs = [np.concatenate([measured_rho(mb, mach, alt, level, evaluation_seed(
                    "dither_reference", 7, mach, alt, level, n), args.duration) for n in range(args.runs)])
                      for level in LEVELS]
            except TrimError:   # does not trim: Mach 0.4's value (as THRUST_ACCEL_FPS2)
                print(f"| {mach:g} | {alt:g} | does not trim | | | | |", flush=True)
                row.append(None)
                continue
            q = [np.percentile(x, [5, 50, 95]) for x in xs]
            ref = round(float(np.sqrt(q[0][1] * q[1][1])), 2)
            row.append(ref)
            print(f"| {mach:g} | {alt:g} | {q[0][0]:.2f} / {q[0][1]:.2f} / {q[0][2]:.2f} | {q[1][0]:.2f} / "
                  f"{q[1][1]:.2f} / {q[1][2]:.2f} | {ref:.2f} | {adaptive_mix(q[0][2], ref):.2f} | "
                  f"{adaptive_mix(q[1][0], ref):.2f} |", flush=True)
        table.append(row)
    for i, row in enumerate(table):   # a point that does not trim takes the next Mach's value
        for j, v in enumerate(row):
            if v is None:
                row[j] = table[i + 1][j]
    print("\nADAPTED_DITHER_REFERENCE = (")
    for row in table:
        print("    (" + ", ".join(f"{v:.2f}" for v in row) + "),")
    print(")")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
