"""Lab driver (not in the wheel): the cost of a scheduled frame on the real scheduled bank, with
its leading-edge-flap layers and without them (the same own-position nodes, one layer), timed
in C++ in one run (``core._bench_hierarchical_loop``, the fastest pass) so the ratio compares
like with like.  The air data sweeps Mach 0.34 -> 0.52 and 5,000 -> 16,000 ft over the frames
(cells the flap's 5-deg switch crosses, with the air-data sensor's noise); z and u are the
bank's trim with noise.

    python tools/schedule/layer_cost.py --schedule FILE [--frames 4000]

FILE: a scheduled bank with flap layers (``f16mmae design --schedule``); the layer-free copy is
made from it in a temporary directory.
"""
from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

from f16mmae import core, names


def without_layers(bank, path: Path):
    """``bank``'s own-position nodes in one layer (its flap alternates dropped), loaded."""
    s = bank.schedule
    alternates = {(a["mach"], a["alt_ft"], a["layer"]) for a in json.loads(s["metadata"])["flap_layers"]["alternates"]}
    nodes = [(n["i_mach"], n["i_alt"], n["bank"], n["x_trim"], n["adapt_reference"], 0) for n in s["nodes"]
             if (n["mach"], n["alt_ft"], n["layer"]) not in alternates]
    core.save_schedule(list(s["mach"]), list(s["alt_ft"]), nodes, primary=s["primary"], metadata=s["metadata"],
                       path=str(path))
    return core.load_bank(str(path))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--schedule", required=True)
    ap.add_argument("--frames", type=int, default=4000)
    args = ap.parse_args()
    layered = core.load_bank(args.schedule)
    rng = np.random.default_rng(1)
    n = args.frames
    x = np.linspace(0.0, 1.0, n)
    air = np.column_stack([0.34 + 0.18 * x + 0.002 * rng.standard_normal(n),
                           5000.0 + 11000.0 * x + 10.0 * rng.standard_normal(n)])
    z = np.asarray(layered.z_trim) + 0.01 * rng.standard_normal((n, names.NZ)) * (np.abs(np.asarray(layered.z_trim)) + 1.0)
    u = np.asarray(layered.u_trim) + np.radians(0.5) * rng.standard_normal((n, names.NU))
    with tempfile.TemporaryDirectory() as tmp:
        flat = without_layers(layered, Path(tmp) / "flat.f16sched")
    rows = {}
    for label, bank in (("one layer", flat), ("flap layers", layered)):
        for mode in ("interpolate", "nearest"):
            per_frame, worst = core._bench_hierarchical_loop(bank, z, u, air_data=air, min_time_s=0.5, schedule_mode=mode)
            rows[f"{label}, {mode}"] = (per_frame * 1e6, worst * 1e6)
    print(f"{'variant':28s} {'us/frame':>9s} {'slowest us':>11s}")
    for label, (us, worst) in rows.items():
        print(f"{label:28s} {us:9.3f} {worst:11.1f}")
    for mode in ("interpolate", "nearest"):
        print(f"flap layers / one layer, {mode}: {rows[f'flap layers, {mode}'][0] / rows[f'one layer, {mode}'][0]:.2f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
