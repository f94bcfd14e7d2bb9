"""Flights where the trim tracker's freeze rule matters (docs/results/trim_tracking.md).

Each flight: the shipped tuned bank at its design point, calm air, one AOA sensor failure
at 30 s -- a slow drift or a bias -- flown four ways: without trim tracking, with it
(time constant TAU_S) and its freeze rule (a failure hypothesis above 0.05, a declaration,
level 1; held 2 s), with it frozen only by a declaration or level 1 (freeze probability 1),
and never frozen. Prints one markdown table row per flight and way: the first declaration,
the number of declarations, and the hypothesis declared at the end.

    python tools/trim_tracking/freeze_flights.py [--tau-s 30] [--duration-s 240] [--seed 101]
                                                 [--fail NAME@TIME:MODE=VALUE ...]

``--fail`` replaces the three AOA failures by the ones given (``f16mmae run --fail`` syntax, values
in the sensor's units: rad, rad/s, g).
"""
from __future__ import annotations

import argparse
import math

from f16mmae.banks import load_bank
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure, parse_fail

FAILURES = (("AOA drift 0.002 deg/s", "drift", 0.002), ("AOA drift 0.01 deg/s", "drift", 0.01),
            ("AOA bias 0.5 deg", "bias", 0.5))


def ways(tau_s: float) -> tuple[tuple[str, dict], ...]:
    return (("no tracking", {}),
            ("tracking, freeze rule", {"trim_time_constant_s": tau_s}),
            ("tracking, frozen by a declaration only", {"trim_time_constant_s": tau_s, "trim_freeze_probability": 1.0}),
            ("tracking, never frozen", {"trim_time_constant_s": tau_s, "trim_freeze": False}))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tau-s", type=float, default=30.0)
    ap.add_argument("--duration-s", type=float, default=240.0)
    ap.add_argument("--seed", type=int, default=101)
    ap.add_argument("--fail", nargs="*", default=None)
    args = ap.parse_args()
    bank = load_bank("tuned")[2]
    if args.fail:
        failures = [(text, parse_fail(text)) for text in args.fail]
    else:
        failures = [(f"{label} at 30 s", make_failure("AOA", 30.0, mode, math.radians(value_deg)))
                    for label, mode, value_deg in FAILURES]
    print("| failure | estimator | first declaration | declarations | declared at the end |")
    print("|---|---|---|---|---|")
    for label, failure in failures:
        sc = Scenario(mach=float(bank.mach), alt_ft=float(bank.alt_ft), turbulence="none",
                      duration_s=args.duration_s, seed=args.seed, failures=(failure,))
        for name, options in ways(args.tau_s):
            r = fly(sc, bank, estimator_options=options, record_probabilities=False)
            first = r.declarations[0] if r.declarations else None
            first_text = f"{first['hypothesis']} at {first['time_s']:.1f} s" if first else "none"
            print(f"| {label} | {name} | {first_text} | {len(r.declarations)} | {r.final_hypothesis} |", flush=True)


if __name__ == "__main__":
    main()
