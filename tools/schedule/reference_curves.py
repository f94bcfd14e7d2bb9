"""Lab driver (not in the wheel): the turbulence adaptation's per-node reference against the
false-alarm bound, on an existing scheduled bank, without designing it again.

    python tools/schedule/reference_curves.py --schedule FILE --out curves.json [--workers 2]
    python tools/schedule/reference_curves.py --curves curves.json --schedule FILE \\
        --bound -6 --write bounded.f16sched

The first form flies every own-configuration node's no-failure calibration flights (the same
tuning flight seeds the design flies there, ``calibrate.node_flights``) and records, per node,
the estimator's peak failure log-odds (``calibrate.failure_log_odds_peak``) at every reference
of ``calibrate.REFERENCE_RANGE`` (step ``--step``), with the node's stored (mean power ratio)
reference.  The second writes a copy of FILE whose nodes carry, each, the largest reference of
that grid with a peak at or below ``--bound`` (what ``calibrate.bounded_reference`` finds by
bisection), optionally capped at the node's stored reference (``--cap mean``); a node in its
other flap position takes its own-position node's reference, as the design does.
"""
from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.design.calibrate import REFERENCE_RANGE, failure_log_odds_peak, node_flights


def _own_nodes(info) -> list[int]:
    meta = json.loads(info["metadata"])
    alternates = {(a["mach"], a["alt_ft"], a["layer"]) for a in (meta.get("flap_layers") or {}).get("alternates", [])}
    return [n for n, nd in enumerate(info["nodes"]) if (nd["mach"], nd["alt_ft"], nd["layer"]) not in alternates]


def _curve(task):
    path, n, grid = task
    info = load_bank(path)[2].schedule
    nd = info["nodes"][n]
    flights = node_flights(nd["mach"], nd["alt_ft"], "light")
    peaks = [failure_log_odds_peak(nd["bank"], flights, r) for r in grid]
    return {"node": n, "mach": nd["mach"], "alt_ft": nd["alt_ft"], "layer": nd["layer"],
            "stored_reference": nd["adapt_reference"], "references": grid, "peaks": peaks}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--schedule", required=True)
    ap.add_argument("--out", help="curves JSON to write (first form)")
    ap.add_argument("--curves", help="curves JSON to read (second form)")
    ap.add_argument("--bound", type=float, default=-6.0)
    ap.add_argument("--cap", choices=("none", "mean"), default="none")
    ap.add_argument("--erode", choices=("none", "all", "bounded"), default="none",
                    help="then each node takes the smallest reference of itself and its covered grid neighbours "
                         "(all of them, or those whose bound was met)")
    ap.add_argument("--step", type=float, default=0.05)
    ap.add_argument("--write")
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    path = str(load_bank(args.schedule)[1])
    info = load_bank(path)[2].schedule
    if args.out:
        lo, hi = REFERENCE_RANGE
        grid = [round(lo + k * args.step, 6) for k in range(int(round((hi - lo) / args.step)) + 1)]
        with ProcessPoolExecutor(args.workers) as pool:
            curves = list(pool.map(_curve, [(path, n, grid) for n in _own_nodes(info)]))
        for c in curves:
            print(f"Mach {c['mach']:.2f} {c['alt_ft']:6.0f} ft  stored {c['stored_reference']:.3f}  "
                  + " ".join(f"{r:.2f}:{p:6.1f}" for r, p in zip(c["references"], c["peaks"])), flush=True)
        Path(args.out).write_text(json.dumps(curves, indent=1))
    if args.write:
        curves = json.loads(Path(args.curves or args.out).read_text())
        chosen, c_by = {}, {(c["mach"], c["alt_ft"]): c for c in curves}
        for c in curves:
            r = c["references"][0]   # the largest reference below which every one passes
            for ref, peak in zip(c["references"], c["peaks"]):
                if peak > args.bound:
                    break
                r = ref
            if args.cap == "mean":
                r = min(r, c["stored_reference"])
            chosen[(c["mach"], c["alt_ft"])] = r
        if args.erode != "none":   # each node: the smallest over itself and its covered grid neighbours
            idx = {(nd["mach"], nd["alt_ft"]): (nd["i_mach"], nd["i_alt"]) for nd in info["nodes"]}
            at = {idx[k]: r for k, r in chosen.items()
                  if args.erode == "all" or c_by[k]["peaks"][0] <= args.bound}
            chosen = {k: min([chosen[k]] + [at[(i + di, j + dj)] for di in (-1, 0, 1) for dj in (-1, 0, 1)
                                            if (i + di, j + dj) in at]) for k, (i, j) in idx.items() if k in chosen}
        nodes = [(nd["i_mach"], nd["i_alt"], nd["bank"], np.asarray(nd["x_trim"]), chosen[(nd["mach"], nd["alt_ft"])],
                  nd["layer"]) for nd in info["nodes"]]
        h = core.save_schedule(list(info["mach"]), list(info["alt_ft"]), nodes, primary=info["primary"],
                               metadata=info["metadata"], path=args.write, switch_state=info["switch_state"],
                               switch_thresholds=list(info["switch_thresholds"]))
        refs = sorted(chosen.values())
        print(f"wrote {args.write} ({h[:12]}): references {refs[0]:.2f}-{refs[-1]:.2f}, median {np.median(refs):.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
