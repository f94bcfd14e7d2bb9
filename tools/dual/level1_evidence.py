"""Per-frame evidence of a dual run at level 1 (issue 13 item 5), against the lone second
failure at level 0 in the same seeds.

Flies ``FIRST>SECOND`` (first at 3 s, second at 5 s) and the baseline ``SECOND`` alone at 5 s on
the dual campaign's seeds (``campaign.dual.run_seed``), records u and z, and replays them into a
fresh estimator (the same frames: the replay's declarations are checked equal to the flight's).
Per frame after the second failure it takes the on-line filters' log-likelihoods
l_k = -r_k' A_k^-1 r_k / 2 (the bank's, leading term stripped; a bank whose hypotheses have no
uninformative channel, e.g. ``tuned``) and reports, per run:

  lift_s      time from the second failure until ln p(h*) - ln p(rival) > 0 for every rival
  decl_s      the declaration latency of h* (the dwell included)
  D           mean l_h* - l_first per frame over [t2, t2 + window) (nats; level 1), and for the
              baseline mean l_SECOND - l_NONE (level 0)
  D_rival     mean l_h* - l_r per frame against the strongest rival r (the one h* leads least)

    .venv/bin/python tools/dual/level1_evidence.py PIT>LS [--seed 7] [--runs 3] [-o key=value ...]
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.campaign.dual.campaign import DualCampaign, run_seed
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import dual_name


def replay(bank, series, options: dict):
    """Per frame: hypotheses on line, probabilities, log-likelihoods; and the declarations."""
    est = Estimator(bank, **options)
    core = est.core_bank
    a_inv = {h.name: np.linalg.inv(np.asarray(h.a)) for h in bank.hypotheses}
    rows, decls = [], []
    for i, (z, u) in enumerate(zip(series["z"], series["u"])):
        est.schedule(*series["air_data"][i])
        est.update(z)
        if est.last_declaration is not None:
            decls.append((i / bank.frame_rate_hz, est.last_declaration))
        names = core.hypotheses
        r = np.asarray(core.residuals)
        ll = np.array([-0.5 * r[k] @ a_inv[n] @ r[k] for k, n in enumerate(names)])
        rows.append((names, np.asarray(core.probabilities).copy(), ll))
        est.propagate(u)
    return rows, decls


def analyse(rows, frame_rate_hz: float, t2: float, target: str, reference: str, window_s: float) -> dict:
    i2 = int(round(t2 * frame_rate_hz))
    lift = None
    diffs, rival_diffs = [], {}
    for i in range(i2, len(rows)):
        names, p, ll = rows[i]
        if target not in names:
            continue
        k = names.index(target)
        if lift is None and all(p[k] > p[j] for j in range(len(names)) if j != k):
            lift = (i - i2) / frame_rate_hz
        if i < i2 + window_s * frame_rate_hz:
            if reference in names:
                diffs.append(ll[k] - ll[names.index(reference)])
            for j, n in enumerate(names):
                if j != k:
                    rival_diffs.setdefault(n, []).append(ll[k] - ll[j])
    worst = min(rival_diffs, key=lambda n: np.mean(rival_diffs[n])) if rival_diffs else None
    return {"lift_s": lift, "D": float(np.mean(diffs)) if diffs else None,
            "rival": worst, "D_rival": float(np.mean(rival_diffs[worst])) if worst else None}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("pair", help="FIRST>SECOND")
    ap.add_argument("--seed", type=int, default=7, help="campaign seed (7: tuning seeds)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--tuning", default="tuned")
    ap.add_argument("--window-s", type=float, default=1.0, help="frames after t2 that D averages")
    ap.add_argument("-o", "--option", action="append", default=[], help="estimator setting key=value")
    args = ap.parse_args(argv)
    first, second = args.pair.split(">")
    options = {k: float(v) for k, v in (o.split("=") for o in args.option)}
    _, _, bank = load_bank(args.tuning)
    cfg = DualCampaign(seed=args.seed, tuning=args.tuning)
    target = dual_name(first, second)
    print(f"pair {args.pair} (h* = {target}), campaign seed {args.seed}, options {options}")
    print(f"{'run':>3} {'case':>8} {'lift_s':>7} {'decl_s':>7} {'D':>8} {'D_rival':>8} rival / declarations")
    for n in range(args.runs):
        seed = run_seed(args.seed, second, n)
        for label, failures, tgt, ref in (
                ("dual", ((first, cfg.first_time_s), (second, cfg.second_time_s)), target, first),
                ("alone", ((second, cfg.second_time_s),), second, "NONE")):
            scen = scenario_from_dict(cfg.scenario_dict(bank, failures, seed))
            res = fly(scen, bank, estimator_options=options, record_series=True)
            rows, decls = replay(bank, res.series, options)
            flown = [(round(d["time_s"], 6), d["hypothesis"]) for d in res.declarations]
            if [(round(t, 6), h) for t, h in decls] != flown:
                print(f"replay differs from the flight: {decls} vs {flown}", file=sys.stderr)
                return 1
            a = analyse(rows, bank.frame_rate_hz, cfg.second_time_s, tgt, ref, args.window_s)
            lat = next((t - cfg.second_time_s for t, h in decls if h == tgt and t >= cfg.second_time_s), None)
            fmt = lambda x: "-" if x is None else f"{x:.2f}"  # noqa: E731
            print(f"{n:>3} {label:>8} {fmt(a['lift_s']):>7} {fmt(lat):>7} {fmt(a['D']):>8} {fmt(a['D_rival']):>8} "
                  f"{a['rival']} / {', '.join(f'{h}@{t:.2f}' for t, h in decls)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
