"""Lab driver (not in the wheel): why a failed VEL is or is not declared, and why it is backed
out, frame by frame.

    python tools/schedule/vel_evidence.py --runs DIR [--bank FILE] [--seeds 3] [--case VEL] [--point P]

Flies again the VEL runs (or --case's, at --point) of an envelope campaign's records (DIR/runs.jsonl: their scenarios,
estimator settings and bank, or --bank instead) and prints per run, over windows after the
failure, the mean per frame of each channel's part of l_VEL - l_NONE (the stripped eq. 2,
its total from the bank's own log-likelihoods, split per channel as -r_j^2 / (2 A_jj) with
each filter's diagonal A of the primary node; the VEL column is the rest: the total less the
other channels, i.e. VEL's uninformative density under VEL against its Gaussian under NONE,
and the cross terms of NONE's A), and the level-1 episodes: when the
bank went to level 1, which filters it brought on line, which one led when it backed out, and
the same per-channel evidence of VEL against NONE at level 1. The residuals are the core's
(``residuals`` of the bank, frame by frame); the probabilities are the bank's.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from f16mmae import names
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict

WINDOWS = ((0.0, 1.0), (1.0, 2.0), (2.0, 3.0), (3.0, 4.0), (4.0, 6.0), (6.0, 8.0))


def diag_a(bank, name):
    """A_jj of hypothesis ``name`` in the bank (the primary node's for a scheduled one)."""
    h = next(h for h in bank.hypotheses if h.name == name)
    return np.diag(np.asarray(h.a))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", required=True, help="an envelope campaign's output folder")
    ap.add_argument("--bank", default=None, help="bank file (default: the records')")
    ap.add_argument("--seeds", type=int, default=3, help="how many runs to fly (default 3)")
    ap.add_argument("--case", default="VEL", help="the case flown again (default VEL)")
    ap.add_argument("--point", default=None, help="only this point's runs (default every point)")
    args = ap.parse_args()
    runs = [json.loads(line) for line in open(Path(args.runs) / "runs.jsonl")]
    runs = [r for r in runs if r["case"] == args.case and args.point in (None, r.get("point"))][: args.seeds]
    for r in runs:
        _, _, bank = load_bank(args.bank or r["bank"])
        est = Estimator(bank, **r["estimator"])
        a_none, a_vel = diag_a(bank, "NONE"), diag_a(bank, "VEL")
        rec = []

        def frame(t, u, z, air, est=est):
            cb = est.core_bank
            hyps = list(cb.hypotheses)
            res = np.asarray(cb.residuals)
            p = np.asarray(cb.probabilities)
            rec.append((t, cb.level, hyps, p, res, np.asarray(cb.log_likelihoods)))

        fly(scenario_from_dict(r["scenario"]), bank, estimator=est, on_frame=frame)
        print(f"seed {r['seed']}: {r['outcome']}, declarations "
              f"{[(d['hypothesis'], round(d['time_s'], 2)) for d in r.get('declarations', [])]}")
        rows = []
        for t, lvl, hyps, p, res, ll in rec:
            if "NONE" not in hyps or "VEL" not in hyps:
                continue
            i0, iv = hyps.index("NONE"), hyps.index("VEL")
            g_none = -0.5 * res[i0] ** 2 / a_none
            g_vel = -0.5 * res[iv] ** 2 / a_vel
            g_vel[0] = 0.0
            e = g_vel - g_none
            e[0] += (ll[iv] - ll[i0]) - e.sum()   # VEL's channel: the rest of the exact total
            rows.append((t, lvl, e, np.log(p[iv]) - np.log(p[i0]), hyps, ll[iv] - ll[i0]))
        for lo, hi in WINDOWS:
            for lvl in (0, 1):
                sel = [x for x in rows if lo <= x[0] < hi and x[1] == lvl]
                if not sel:
                    continue
                e = np.mean([x[2] for x in sel], axis=0)
                parts = " ".join(f"{n} {v:+.2f}" for n, v in zip(names.SENSORS, e))
                print(f"  {lo:g}-{hi:g} s level {lvl} ({len(sel)} frames): per frame l_VEL - l_NONE "
                      f"{np.mean([x[5] for x in sel]):+.2f}: {parts}; "
                      f"ln p_VEL/p_NONE {sel[0][3]:+.1f} -> {sel[-1][3]:+.1f}")
        prev = 0
        for t, lvl, hyps, p, res, ll in rec:
            if lvl != prev:
                lead = hyps[int(np.argmax(p))]
                print(f"  t {t:.2f} s: level {prev} -> {lvl}; on line {','.join(hyps[:4])}...; leading {lead}")
                prev = lvl
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
