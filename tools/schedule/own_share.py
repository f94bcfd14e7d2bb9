"""Lab driver (not in the wheel): a failure's evidence against the adaptation's scale, with
and without own channels, frame by frame.

    python tools/schedule/own_share.py --runs DIR [--bank FILE] [--case VEL] [--points T9,T10] [--seeds 3]

Flies again the CASE runs of an envelope campaign's records (DIR/runs.jsonl) at the named
points twice: with the records' estimator settings and own channels off, and on. Prints per
window after the failure: the scale s (mean), the per-frame l_CASE - l_NONE (the bank's
stripped eq. 2, the tempered evidence), s times it (the quadratic forms' part as at s = 1; a
failed-sensor hypothesis's level density, which s does not scale, is multiplied too), the
ln p_CASE / p_NONE at the window's end, and the run's declarations (hypothesis, time). A declaration from p_min = 1e-9 to the 0.9 threshold within 5 s of the
failure needs ln(0.9 / 0.1) - ln(1e-9) = 22.9 nats: 0.072 per frame at 64 Hz over 4.75 s
(the 0.25-s dwell left out).
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict

WINDOWS = ((3.0, 4.0), (4.0, 5.0), (5.0, 6.0), (6.0, 8.0))


def fly_once(r, bank, case, own):
    opts = dict(r["estimator"])
    opts["adapt_own_channels"] = own
    est = Estimator(bank, **opts)
    rec, decl = [], []

    def frame(t, u, z, air, est=est):
        cb = est.core_bank
        hyps = list(cb.hypotheses)
        if "NONE" in hyps and case in hyps:
            ll = np.asarray(cb.log_likelihoods)
            p = np.asarray(cb.probabilities)
            i0, i1 = hyps.index("NONE"), hyps.index(case)
            rec.append((t, cb.turbulence_scale, ll[i1] - ll[i0], np.log(max(p[i1], 1e-300)) - np.log(max(p[i0], 1e-300))))
        d = cb.declared
        if d and (not decl or decl[-1][0] != d):
            decl.append((d, round(t, 2)))

    fly(scenario_from_dict(r["scenario"]), bank, estimator=est, on_frame=frame)
    return rec, decl


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", required=True)
    ap.add_argument("--bank", default=None)
    ap.add_argument("--case", default="VEL")
    ap.add_argument("--points", default=None, help="comma-separated point labels (default every point)")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--own", default="0,1", help="own-channel settings flown (default 0,1)")
    args = ap.parse_args()
    pts = None if args.points is None else set(args.points.split(","))
    runs = [json.loads(line) for line in open(Path(args.runs) / "runs.jsonl")]
    runs = [r for r in runs if r["case"] == args.case and (pts is None or r.get("point") in pts)]
    for r in runs[: args.seeds * (len(pts) if pts else 1000)]:
        _, _, bank = load_bank(args.bank or r["bank"])
        sc = r["scenario"]
        print(f"{r.get('point')} Mach {sc['mach']}, {sc['alt_ft']:.0f} ft, seed {r['seed']}")
        for own in [bool(int(x)) for x in args.own.split(",")]:
            rec, decl = fly_once(r, bank, args.case, own)
            cells = []
            for lo, hi in WINDOWS:
                sel = [x for x in rec if lo <= x[0] < hi]
                if not sel:
                    continue
                s = np.mean([x[1] for x in sel])
                e = np.mean([x[2] for x in sel])
                e1 = np.mean([x[1] * x[2] for x in sel])
                cells.append(f"{lo:g}-{hi:g} s: s {s:.2f}, l {e:+.3f}, s*l {e1:+.3f}, lnp {sel[-1][3]:+.1f}")
            print(f"  own {int(own)}: {decl}; " + "; ".join(cells))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
