"""Lab driver (not in the wheel): at grid nodes, which failure hypothesis comes closest to a
false alarm on the node's own no-failure calibration flights, and when.

    python tools/schedule/node_peaks.py --schedule FILE [--nodes 0.3:10000,0.35:10000,0.4:10000]
                                        [--flight-s 8] [--reference RHO]

At each node the node's estimator (its bank and recommended settings, the turbulence
adaptation on at the node's reference from the file) is run over the node's calibration
flights (``calibrate.node_flights``: light turbulence, the truth's dither, raw feedback, tuning
flight seeds 1-8, 8 s or ``--flight-s``), as the design's false-alarm bound runs it
(``calibrate.failure_log_odds_peak``), at ``--reference`` in place of the node's if given.  Printed per node: its reference and floor (file and
own, from the metadata), the NONE filter's var/A after calibration, and the design's candidate
rows; per flight: the peak failure log-odds max_k ln(p_k / p_NONE), the frame time and the
hypothesis that reached it, and the adaptation's scale s there ("declared" if a failure was).
"""
from __future__ import annotations

import argparse
import json

import numpy as np

from evidence import node_of
from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.design.calibrate import NODE_FLIGHT_S, node_flights


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--schedule", default="scheduled")
    ap.add_argument("--nodes", default="0.3:10000,0.35:10000,0.4:10000,0.5:10000")
    ap.add_argument("--flight-s", type=float, default=NODE_FLIGHT_S,
                    help="length of each calibration flight (default: the design's)")
    ap.add_argument("--reference", type=float, default=None, help="the adaptation's reference (default: the node's)")
    args = ap.parse_args()
    info = load_bank(args.schedule)[2].schedule
    records = {(n["mach"], n["alt_ft"]): n for n in json.loads(info["metadata"])["nodes"]}
    for item in args.nodes.split(","):
        mach, alt = (float(x) for x in item.split(":"))
        nd, rec = node_of(info, mach, alt), records[(mach, alt)]
        mb = nd["bank"]
        print(f"Mach {mach:.2f}, {alt:.0f} ft: reference {nd['adapt_reference']} (own {rec.get('adapt_reference_node')}), "
              f"p_min {mb.p_min:g} (own {rec.get('p_min_node', mb.p_min):g}), var/A {rec['var_over_a_after']}")
        for row in rec.get("candidates", []):
            print(f"  candidate p_min {row[0]:g}: reference {row[1]}, peak {row[2]}, s {row[3]}, bound met {row[4]}")
        reference = float(nd["adapt_reference"] if args.reference is None else args.reference)
        est = core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference=reference,
                                    **mb.estimator_settings)
        u_trim, z_trim = np.asarray(mb.u_trim), np.asarray(mb.z_trim)
        for n, fl in enumerate(node_flights(mach, alt, "light", args.flight_s), start=1):
            est.reset()
            peak, when, who, scale = -np.inf, 0.0, "", 1.0
            for i in range(len(fl.z)):
                u = u_trim.copy()
                u[:fl.u.shape[1]] += fl.u[i]
                declared = est.step(fl.z[i] + z_trim, u)
                p = est.probabilities
                k = int(np.argmax(p[1:])) + 1
                value = float(np.log(p[k]) - np.log(p[0]))
                if declared is not None or value > peak:
                    peak, when, who, scale = value, i / names.FRAME_RATE_HZ, names.SINGLE_HYPOTHESES[k], est.turbulence_scale
                if declared is not None:
                    who += " declared"
                    break
            print(f"  flight {n}: peak {peak:6.1f} at {when:4.2f} s by {who} (s {scale:.2f})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
