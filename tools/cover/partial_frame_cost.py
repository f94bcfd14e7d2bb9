"""The estimator's frame with and without partial-loss hypotheses: the fixed-size C++
hierarchical bank of each bank file (13 filters on line; 18 with a partial hypothesis per
surface, ``f16mmae design --partial-loss``), timed in C++ (``core._bench_hierarchical_loop``,
as ``f16mmae bench estimator`` times its synthetic banks) over the same frames: one closed-loop
flight at the first bank's design point (light turbulence, flight seed ``--seed``, the first
bank in the loop, ``--fail`` injected), u and z recorded and replayed through each bank.
Prints the mean frame (us) and the slowest, best of ``--repeat`` timings.

Run: .venv/bin/python tools/cover/partial_frame_cost.py BANK_A BANK_B --seed 7 --fail LS@3:loss=0.5
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import parse_fail
from f16mmae.truth.scenario import Scenario


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("banks", nargs="+")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--fail", default="LS@3:loss=0.5")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--min-time-s", type=float, default=0.3)
    args = ap.parse_args(argv)
    banks = [core.load_bank(b) for b in args.banks]
    scenario = Scenario(mach=float(banks[0].mach), alt_ft=float(banks[0].alt_ft), turbulence="light",
                        seed=args.seed, failures=(parse_fail(args.fail),), duration_s=8.0)
    res = fly(scenario, banks[0], record_series=True)
    u, z = np.asarray(res.series["u"]), np.asarray(res.series["z"])
    for path, mb in zip(args.banks, banks):
        runs = [core._bench_hierarchical_loop(mb, z, u, min_time_s=args.min_time_s) for _ in range(args.repeat)]
        mean = min(r[0] for r in runs) * 1e6
        slow = min(r[1] for r in runs) * 1e6
        level0 = sum(1 for n in mb.hypothesis_names if "+" not in n)
        print(f"{path}: {level0} filters on line at level 0; frame {mean:.3f} us (best of {args.repeat}), "
              f"slowest frame {slow:.2f} us")


if __name__ == "__main__":
    main()
