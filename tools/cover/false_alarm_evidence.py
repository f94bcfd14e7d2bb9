"""Evidence per frame of each single-failure hypothesis against NONE in no-failure flights.

Flies the no-failure tuning flights (design/flights.py fly_closed_loop: full truth, light
turbulence, FCS on raw feedback, seeds ``--seeds``, 8 s) and runs the level-0 bank of a
tuning (``tuned`` with ``--failure-model``, ``--surface-q``, ``--level-q``) over them as one
core.FilterBank (p_min 1e-9, the core's floors). Per hypothesis k, over the frames after the
first second:
  D     mean of l_NONE - l_k per frame (nats; > 0: the data favour NONE on average),
  sd    its standard deviation per frame,
  peak  the largest ln(p_k / p_NONE) the bank reached (the floor is about -20.7, lower by the
        level's Occam factor for a failed sensor that tracks its level; a declaration needs
        more than ln(0.9/0.1) = 2.2 held for the dwell), and
  >2.2  the number of flights whose peak exceeds 2.2.
Run: .venv/bin/python tools/cover/false_alarm_evidence.py [--surface-q Q] [--level-q Q] [--seeds 1-8]
"""
from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from f16mmae import core, names
from f16mmae.design.bank import design_bank
from f16mmae.design.flights import fly_closed_loop
from f16mmae.design.model import linearize_truth
from f16mmae.design.tuning import load_tuning

P_MIN = 1e-9
DECLARE = float(np.log(0.9 / 0.1))


def seeds_arg(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--failure-model", default="cover")
    ap.add_argument("--surface-q", type=float, default=None, help="failed_surface_q (rad^2/s)")
    ap.add_argument("--level-q", type=float, default=None, help="failed_sensor_level_q (noise variances)")
    ap.add_argument("--seeds", type=seeds_arg, default=seeds_arg("1-8"))
    ap.add_argument("--keep-leading-term", action="store_true",
                    help="eq. 2 with its leading term (2 pi)^(-m/2) |A_k|^(-1/2) kept")
    args = ap.parse_args(argv)
    tun = dataclasses.replace(load_tuning("tuned"), failure_model=args.failure_model)
    if args.surface_q is not None:
        tun = dataclasses.replace(tun, failed_surface_q=args.surface_q)
    if args.level_q is not None:
        tun = dataclasses.replace(tun, failed_sensor_level_q=args.level_q)
    d = design_bank(tuning=tun, linearized=linearize_truth(0.4, 20_000.0), hypotheses=names.SINGLE_HYPOTHESES)
    models = [core.FilterModel(phi=f.model.phi, bd=f.model.bd, h=f.model.h, k=f.gains.k, a=f.gains.a,
                               uninformative_width=f.model.uninformative_width,
                               uninformative_level_q=f.model.uninformative_level_q) for f in d.filters]
    bank = core.FilterBank(models, p_min=P_MIN, strip_leading_term=not args.keep_leading_term)
    hyps = names.SINGLE_HYPOTHESES
    diffs, peaks = {h: [] for h in hyps[1:]}, {h: [] for h in hyps[1:]}
    start = names.FRAME_RATE_HZ
    for s in args.seeds:
        fl = fly_closed_loop(0.4, 20_000.0, seed=s)
        bank.reset()
        ll = np.zeros((len(fl.z), len(hyps)))
        lo = np.zeros((len(fl.z), len(hyps)))
        for i in range(len(fl.z)):
            p = bank.update(fl.z[i])
            ll[i] = bank.log_likelihoods
            lo[i] = np.log(p) - np.log(p[0])
            bank.propagate(fl.u[i])
        for k, h in enumerate(hyps[1:], start=1):
            diffs[h].append(ll[start:, 0] - ll[start:, k])
            peaks[h].append(float(lo[start:, k].max()))
    print(f"failure model {args.failure_model}, surface q {tun.failed_surface_q}, level q "
          f"{tun.failed_sensor_level_q}, leading term {'kept' if args.keep_leading_term else 'stripped'}, "
          f"seeds {args.seeds[0]}-{args.seeds[-1]}")
    print(f"{'hyp':<5} {'D':>8} {'sd':>7} {'peak':>7} {'>2.2':>5}")
    for h in hyps[1:]:
        x, pk = np.concatenate(diffs[h]), np.array(peaks[h])
        print(f"{h:<5} {x.mean():8.4f} {x.std():7.3f} {pk.max():7.2f} {int((pk > DECLARE).sum()):5d}")


if __name__ == "__main__":
    main()
