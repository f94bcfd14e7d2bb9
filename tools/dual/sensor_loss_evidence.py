"""The second failure's evidence after a declared sensor, with and without the sensor-loss dither
(``--sensor-loss-dither``, truth/dither.py ``sensor_loss_gains``).

Flies ``FIRST>SECOND`` (first at 3 s, second at 5 s) on the dual campaign's seeds
(``campaign.dual.run_seed``) twice, the option off and on, and reads the bank's own probabilities:
the log-odds of the dual h* = FIRST+SECOND against the declared single FIRST,
L(t) = ln p_h*(t) - ln p_FIRST(t), per frame from the second failure on.  Per run:

  first_decl  the first failure's declaration (s)
  rate        the mean slope of L over the climb, from the last frame at its floor after t2 to
              the first frame with L > 0 (nats per frame): what the dither changes
  lift_s      the time from t2 until L > 0
  top_s       the time from t2 until h* is the most probable hypothesis on line; rival the one
              most often most probable between the two (what holds h* off once it passes FIRST)
  lat_s       the dual's declaration latency (after t2; the dwell included)

    .venv/bin/python tools/dual/sensor_loss_evidence.py PIT>LS [PIT>RS ...] --tuning BANK [--seed 7] [--runs 3]
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.campaign.dual.campaign import DualCampaign, run_seed
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import dual_name


def climb(res, first: str, target: str, t2: float) -> dict:
    """lift_s and the climb's mean rate of L = ln p_target - ln p_first after t2 (module docstring)."""
    pt, pf = res.probability_of(target), res.probability_of(first)
    i2 = int(round(t2 / res.frame_dt_s))
    lo = np.log(np.maximum(pt, 1e-300)) - np.log(np.maximum(pf, 1e-300))
    up = next((i for i in range(i2, len(lo)) if pt[i] > 0 and lo[i] > 0.0), None)
    if up is None:
        return {"lift_s": None, "rate": None, "top_s": None, "rival": None}
    floor = float(np.nanmin(lo[i2:up + 1]))
    start = max(i for i in range(i2, up + 1) if lo[i] <= floor + 1e-6)
    rate = (lo[up] - lo[start]) / max(up - start, 1)
    # from the lift on: the first frame the dual is above every hypothesis, and the one that held it off
    p = np.nan_to_num(res.probabilities, nan=0.0)
    k = res.hypotheses.index(target)
    top = next((i for i in range(up, len(p)) if p[i, k] >= p[i].max()), None)
    end = top if top is not None and top > up else len(p)
    others = p[up:end].copy()
    others[:, k] = -1.0
    rival = res.hypotheses[int(np.bincount(others.argmax(axis=1)).argmax())] if end > up else None
    return {"lift_s": (up - i2) * res.frame_dt_s, "rate": float(rate),
            "top_s": None if top is None else (top - i2) * res.frame_dt_s, "rival": rival}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pairs", nargs="+", help="FIRST>SECOND")
    ap.add_argument("--tuning", required=True)
    ap.add_argument("--seed", type=int, default=7, help="campaign seed (7: tuning seeds)")
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args(argv)
    _, _, bank = load_bank(args.tuning)
    cfg = DualCampaign(seed=args.seed, tuning=args.tuning)
    fmt = lambda x, f="{:.2f}": "-" if x is None else f.format(x)  # noqa: E731
    print(f"{'pair':8s} {'run':>3s} {'option':>6s} {'first_decl':>10s} {'rate':>7s} {'lift_s':>6s} {'top_s':>6s} {'rival':>8s} {'lat_s':>6s}  declarations")
    for pair in args.pairs:
        first, second = pair.split(">")
        target = dual_name(first, second)
        for n in range(args.runs):
            seed = run_seed(args.seed, second, n)
            failures = ((first, cfg.first_time_s), (second, cfg.second_time_s))
            for on in (False, True):
                opts = {"declare_components": True, **({"sensor_loss_dither": True} if on else {})}
                res = fly(scenario_from_dict(cfg.scenario_dict(bank, failures, seed)), bank, estimator_options=opts)
                decl1 = next((d["time_s"] for d in res.declarations if d["hypothesis"] == first), None)
                lat = next((d["time_s"] - cfg.second_time_s for d in res.declarations
                            if d["hypothesis"] == target and d["time_s"] >= cfg.second_time_s), None)
                c = climb(res, first, target, cfg.second_time_s)
                print(f"{pair:8s} {n:>3d} {'on' if on else 'off':>6s} {fmt(decl1):>10s} {fmt(c['rate'], '{:.3f}'):>7s} "
                      f"{fmt(c['lift_s']):>6s} {fmt(c['top_s']):>6s} {c['rival'] or '-':>8s} {fmt(lat):>6s}  "
                      + ", ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in res.declarations))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
