"""Outcomes of a campaign's PIT, LS, RS and NONE flights flown again with the right stabilator's
dither shifted in phase (a differential component in the stabilator dither).

Reads the flight seeds of the cases PIT, LS, RS, NONE (modes complete and null) from a single
campaign's ``runs.jsonl``, flies each again (``loop.flight.fly``, the bank's recommended
settings) with ``DitherSpec(phase_rad=(0, PHASE, 0.55, -0.55, 0))`` -- the default's phases but
RS's -- and counts the runs that end on the injected case.
Run: .venv/bin/python tools/cover/dither_phase.py BANK RUNS_JSONL 0,1.57,3.14
"""
from __future__ import annotations

import collections
import json
import sys

from f16mmae import core
from f16mmae.loop.flight import fly
from f16mmae.truth.dither import DitherSpec
from f16mmae.truth.failures import FailureSpec
from f16mmae.truth.scenario import Scenario

CASES = ("PIT", "LS", "RS", "NONE")


def main(argv=None) -> None:
    bank_path, runs_path, phases = (argv or sys.argv[1:])[:3]
    mb = core.load_bank(bank_path)
    seeds = collections.defaultdict(list)
    with open(runs_path) as fh:
        for line in fh:
            r = json.loads(line)
            mode = r["failures"][0]["mode"] if r["failures"] else "complete"
            if r["case"] in CASES and mode in ("complete", "null"):
                seeds[(r["case"], mode)].append(r["seed"])
    for phase in (float(x) for x in phases.split(",")):
        dither = DitherSpec(phase_rad=(0.0, phase, 0.55, -0.55, 0.0))
        out = []
        for (case, mode), flight_seeds in sorted(seeds.items()):
            failures = () if case == "NONE" else (FailureSpec(case, 3.0, mode),)
            ok = sum(fly(Scenario(mach=0.4, alt_ft=20_000.0, turbulence="light", seed=s, duration_s=8.0,
                                  failures=failures, dither=dither), mb,
                         record_probabilities=False).final_hypothesis == case for s in flight_seeds)
            out.append(f"{case} {mode} {ok}/{len(flight_seeds)}")
        print(f"RS dither phase {phase:g} rad: " + ", ".join(out), flush=True)


if __name__ == "__main__":
    main()
