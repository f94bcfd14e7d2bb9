"""The turbulence bank set's selector thresholds, measured (design/turbulence_banks.py).

Flies failure-free closed-loop flights (feedback raw: the estimators watch, the flight is the
same for every member) at each turbulence level on the tuning flight seeds (1-8), with every
member of the set running side by side with its adaptation on, and prints each member's
averaged residual power ratio rho (turbulence_adaptation.h) after the first --skip seconds:
the 1st, 5th, 50th, 95th and 99th percentiles over the frames of all flights.  A member's
band for the selector lies between its rho at the level below and at the level above.

    .venv/bin/python tools/turbulence_banks.py --seconds 60 --flights 8
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf

import numpy as np

from f16mmae import core
from f16mmae.banks import bank_estimator_settings
from f16mmae.design.turbulence_banks import load_set
from f16mmae.loop.estimator import core_arguments
from f16mmae.loop.flight import fly
from f16mmae.names import FRAME_RATE_HZ, NONE, TURBULENCE_LEVELS
from f16mmae.seeds import TUNING_FLIGHT_SEEDS
from f16mmae.truth import Scenario


class SideBySide:
    """Every member on the same frames; the loop sees member ``show`` (feedback raw anyway)."""

    def __init__(self, banks, references, show: int):
        self.members = [core.HierarchicalBank(b, **core_arguments({**bank_estimator_settings(b),
                                                                   "adapt_turbulence": True,
                                                                   "adapt_own_channels": True,
                                                                   "adapt_reference": r}, b.nu))
                        for b, r in zip(banks, references)]
        self.show = self.members[show]
        self.rho: list[list[float]] = []
        self.bank_hash = "side-by-side"
        self.last_declaration = None

    def schedule(self, mach, alt):
        for m in self.members:
            m.schedule(float(mach), float(alt))

    def update(self, z):
        z = np.array(z, dtype=float)
        for m in self.members:
            m.update(z)
        self.rho.append([m.turbulence_power_ratio for m in self.members])
        return self.show.z_hat

    def propagate(self, u):
        u = np.array(u, dtype=float)
        for m in self.members:
            m.propagate(u)

    @property
    def hypotheses(self):
        return self.show.hypotheses

    @property
    def probabilities(self):
        return self.show.probabilities

    @property
    def declared(self):
        return NONE


def flight(level: str, seed: int, seconds: float, skip: float) -> np.ndarray:
    s = load_set()
    est = SideBySide(s.banks, s.adapt_reference, s.selector["start"])
    fly(Scenario(turbulence=level, duration_s=seconds, seed=seed, feedback="raw"), s.banks[s.selector["start"]],
        estimator=est, record_probabilities=False)
    return np.array(est.rho)[int(skip * FRAME_RATE_HZ):]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--levels", default=",".join(TURBULENCE_LEVELS))
    p.add_argument("--seconds", type=float, default=60.0)
    p.add_argument("--skip", type=float, default=10.0, help="seconds left out at the start (rho settling)")
    p.add_argument("--flights", type=int, default=8, help="tuning flight seeds 1..N")
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args(argv)
    s = load_set()
    seeds = TUNING_FLIGHT_SEEDS[:args.flights]
    print(f"set {s.path} ({s.set_hash[:12]}); rho percentiles 1/5/50/95/99 over {len(seeds)} flights of "
          f"{args.seconds:g} s after {args.skip:g} s")
    print("| flown in | " + " | ".join(f"member {x}" for x in s.levels) + " |")
    print("|---|" + "---|" * len(s.levels))
    with cf.ProcessPoolExecutor(args.workers) as pool:
        for level in args.levels.split(","):
            runs = list(pool.map(flight, [level] * len(seeds), seeds, [args.seconds] * len(seeds),
                                 [args.skip] * len(seeds)))
            rho = np.vstack(runs)
            cells = ["/".join(f"{v:.2f}" for v in np.percentile(rho[:, j], [1, 5, 50, 95, 99]))
                     for j in range(rho.shape[1])]
            print(f"| {level} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
