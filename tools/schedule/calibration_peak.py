"""Lab driver (not in the wheel): the largest failure log-odds a scheduled bank's node reaches
on its own calibration flights, at its reference and at FACTOR times it.

    python tools/schedule/calibration_peak.py SCHEDULE MACH:ALT_FT[,...] [--factor 1.1666667] [--layer 1] [--no-own-channels]

For each named node (and flap layer): the node's 8 no-failure calibration flights
(``calibrate.node_flights``, light turbulence), flown through the node's own bank as the
scheduled file holds it (``core.HierarchicalBank`` with the node's settings, the adaptation on
at the reference, own channels on unless told, the 1-s start-up), and printed: the largest
max_t max_(k != NONE) ln(p_k / p_NONE), the runs that declared a failure, and the bound
``calibrate.log_odds_bound`` (-6.0 at p_min 1e-9) the design's reference was chosen against
(there on the node's ``complete`` design, without own channels)."""
from __future__ import annotations

import argparse
import sys

import numpy as np

from f16mmae import core
from f16mmae.design.calibrate import absolute_frames, log_odds_bound, node_flights


def peak(nb, flights, reference: float, own: bool) -> tuple[float, int]:
    settings = dict(nb.estimator_settings)
    bank = core.HierarchicalBank(nb, adapt_turbulence=True, adapt_own_channels=own, adapt_reference=reference,
                                 start_up_s=1.0, **settings)
    top, declared = -np.inf, 0
    for fl in flights:
        bank.reset()
        u, z = absolute_frames(nb, fl)
        for i in range(len(z)):
            if bank.step(z[i], u[i]) is not None:
                declared += 1
                break
            p = bank.probabilities
            top = max(top, float(np.log(np.max(p[1:])) - np.log(p[0])))
    return top, declared


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("schedule", metavar="SCHEDULE")
    ap.add_argument("nodes", metavar="MACH:ALT_FT[,...]")
    ap.add_argument("--factor", type=float, default=7.0 / 6.0)
    ap.add_argument("--layer", type=int, default=1)
    ap.add_argument("--no-own-channels", action="store_true")
    a = ap.parse_args(argv)
    try:
        want = [tuple(float(x) for x in n.split(":")) for n in a.nodes.split(",")]
    except ValueError:
        ap.error(f"nodes {a.nodes!r}: expected MACH:ALT_FT[,...], e.g. 0.35:25000")
    if not (np.isfinite(a.factor) and a.factor > 0.0):
        ap.error(f"--factor {a.factor}: must be finite and > 0")
    s = core.load_bank(a.schedule).schedule
    if s is None:
        ap.error(f"SCHEDULE {a.schedule!r} is not a scheduled bank")
    found = 0
    for n in s["nodes"]:
        nb = n["bank"]
        if n["layer"] != a.layer or not any(abs(nb.mach - m) < 1e-6 and abs(nb.alt_ft - h) < 1e-3 for m, h in want):
            continue
        found += 1
        flights = node_flights(nb.mach, nb.alt_ft, "light")
        bound = log_odds_bound(dict(nb.estimator_settings)["p_min"], nb.threshold)
        for f in (1.0, a.factor):
            ref = n["adapt_reference"] * f
            top, declared = peak(nb, flights, ref, not a.no_own_channels)
            print(f"Mach {nb.mach:g}, {nb.alt_ft:.0f} ft, layer {n['layer']}: reference {ref:.3f}, "
                  f"{len(flights)} flights, peak {top:+.2f}, declared {declared}, bound {bound:+.2f}", flush=True)
    if found == 0:
        ap.error(f"no node {a.nodes} in layer {a.layer}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
