"""The longest stretch above the threshold of each failure hypothesis and of each component
(a surface's forms summed: its complete/cover and partial-loss hypotheses, as
``--declare-components`` declares them, cpp/f16mmae/declarer.h) over a bank's no-failure
calibration flights (``calibrate.node_flights``: the design's own tuning flights, seeds 1-8),
and the dwell the calibration rule of design/dwell.py recommends for each: the smallest
candidate whose frames exceed the longest stretch.

Run: .venv/bin/python tools/cover/component_dwell.py BANK
"""
from __future__ import annotations

import sys

import numpy as np

from f16mmae import core
from f16mmae.design.calibrate import absolute_frames, node_flights
from f16mmae.design.dwell import DWELL_CANDIDATES_S, MEASURE_DWELL_S, dwell_frames


def component(name: str) -> str:
    """A partial hypothesis' single ("LS:loss=0.5" -> "LS"); any other name itself."""
    return name.split(":")[0] if ":" in name and "+" not in name else name


def longest(mb, flights, grouped: bool) -> tuple[int, str, list[int]]:
    settings = {**mb.estimator_settings, "dwell_s": MEASURE_DWELL_S}
    threshold = float(settings["threshold"])
    bank = core.HierarchicalBank(mb, **settings)
    hyps = list(bank.hypotheses)
    comps = sorted({component(h) for h in hyps[1:]}) if grouped else hyps[1:]
    members = [[i for i, h in enumerate(hyps) if i > 0 and (component(h) if grouped else h) == c] for c in comps]
    best, who, per_flight = 0, "NONE", []
    for fl in flights:
        bank.reset()
        u, z = absolute_frames(mb, fl)
        run, cand, flight_best = 0, -1, 0
        for i in range(len(z)):
            if bank.step(z[i], u[i]) is not None:
                raise ValueError(f"declared at frame {i} with a dwell of {MEASURE_DWELL_S} s")
            p = np.asarray(bank.probabilities)
            mass = [p[m].sum() for m in members]
            c = int(np.argmax(mass))
            if mass[c] > threshold:
                run = run + 1 if c == cand else 1
                cand = c
                flight_best = max(flight_best, run)
                if run > best:
                    best, who = run, comps[c]
            else:
                run, cand = 0, -1
        per_flight.append(flight_best)
    return best, who, per_flight


def main(path: str) -> None:
    mb = core.load_bank(path)
    rate = float(mb.frame_rate_hz)
    flights = node_flights(float(mb.mach), float(mb.alt_ft), "light")
    for grouped in (False, True):
        n, who, per = longest(mb, flights, grouped)
        ok = [d for d in sorted(DWELL_CANDIDATES_S) if dwell_frames(d, rate) > n]
        label = "components (forms summed)" if grouped else "each hypothesis alone"
        print(f"{label}: longest {n} frames ({n / rate:.3f} s, {who}); per flight {per}; "
              f"recommended dwell {ok[0] if ok else max(DWELL_CANDIDATES_S)} s"
              + ("" if ok else " (bound not met)"))


if __name__ == "__main__":
    main(sys.argv[1])
