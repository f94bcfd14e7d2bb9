"""The level-1 walk measured: a dual's per-frame log-likelihood ratio against the single when only
the single has failed, beside what the models say it should be.

Flies closed-loop flights (light turbulence, nominal point, the estimator of ``--bank`` in the
loop, ``loop.flight.fly``) with one failure ``--fail NAME@T:MODE`` on the flight seeds
``--flight-seeds`` (e.g. a tuning campaign's runs of that case), records u and z, and replays
them through the single's and the duals' filters (``--duals``) as one core.FilterBank. Over the
frames from ``--settle-s`` after the onset to the end, per dual d:

  mean   E[lambda], lambda = l_d - l_f a frame (the models' value is -D_s, tools/cover/
         distinguishability.py; the difference is the part they do not explain),
  sd     its standard deviation a frame,
  lrv    its long-run variance a frame, Var(sum of W frames) / W with W = --window (the gusts
         correlate the frames: this, not sd^2, sets how far a walk reflected at the floor climbs;
         cpp/f16mmae/level1_allowance.h),
  max W  the largest mean over W frames.

The last lines pool the flights: mean, lrv, and m0 = lrv ln(N / alpha) / (2 h) for ``--alpha`` (a
flight's chance of a false dual) and N = ``--starts`` (excursions a flight's duals start): the
drift -(D_s + k) a walk needs so that none of N excursions reaches h = 22.9 nats but with
probability alpha (P(one reaches h) = exp(-2 mu h / lrv) for a walk of drift -mu).

Run: .venv/bin/python tools/cover/level1_walk.py --bank BANK --fail PIT@3.0:complete --duals LS+PIT,RS+PIT \
       --flight-seeds S1,S2,... [--window 32] [--alpha 1e-3] [--starts 132]
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from f16mmae import core, names
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import parse_fail
from f16mmae.truth.scenario import Scenario

P_MIN = 1e-9


def long_run_variance(x: np.ndarray, window: int) -> float:
    """Var(sum over ``window`` frames) / window over the non-overlapping windows of x (frames,)."""
    if window < 1 or len(x) < 2 * window:
        raise ValueError(f"need at least two windows of {window} frames, got {len(x)} frames")
    n = len(x) // window
    sums = x[: n * window].reshape(n, window).sum(axis=1)
    return float(((sums - x.mean() * window) ** 2).mean() / window)


def mismatch_rate(lrv: float, starts: float, alpha: float, h: float) -> float:
    """m0 = lrv ln(N / alpha) / (2 h), nats a frame (module docstring)."""
    if not (lrv >= 0.0 and starts >= 1.0 and 0.0 < alpha < 1.0 and h > 0.0):
        raise ValueError(f"need lrv >= 0, N >= 1, 0 < alpha < 1, h > 0; got {lrv}, {starts}, {alpha}, {h}")
    return lrv * math.log(starts / alpha) / (2.0 * h)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--fail", required=True)
    ap.add_argument("--duals", required=True)
    ap.add_argument("--flight-seeds", required=True)
    ap.add_argument("--duration-s", type=float, default=10.0)
    ap.add_argument("--settle-s", type=float, default=1.0)
    ap.add_argument("--window", type=int, default=32)
    ap.add_argument("--alpha", type=float, default=1e-3)
    ap.add_argument("--starts", type=float, default=132.0)
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    spec = parse_fail(args.fail)
    hyps = [h.name for h in mb.hypotheses]
    duals = args.duals.split(",")
    missing = [d for d in [spec.name, *duals] if d not in hyps]
    if missing:
        raise SystemExit(f"level1_walk: {','.join(missing)} not in the bank")
    sel = [hyps.index(spec.name)] + [hyps.index(d) for d in duals]
    models = []
    for i in sel:
        h = mb.hypotheses[i]
        models.append(core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a, uninformative_width=h.uninformative_width,
                                       uninformative_level_q=h.uninformative_level_q))
    fb = core.FilterBank(models, p_min=P_MIN)
    pooled = []
    for seed in (int(s) for s in args.flight_seeds.split(",")):
        sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence="light", seed=seed, duration_s=args.duration_s,
                      failures=(spec,))
        res = fly(sc, mb, record_series=True, estimator_options={"declare_components": True})
        u = res.series["u"] - np.asarray(mb.u_trim)
        z = res.series["z"] - np.asarray(mb.z_trim)
        fb.reset()
        ll = np.zeros((len(z), len(sel)))
        for i in range(len(z)):
            fb.update(z[i])
            ll[i] = fb.log_likelihoods
            fb.propagate(u[i])
        lo = int(round((spec.time_s + args.settle_s) * names.FRAME_RATE_HZ))
        lam = ll[lo:, 1:] - ll[lo:, [0]]
        pooled.append(lam)
        decl = ",".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in res.declarations) or "-"
        cells = []
        for k, d in enumerate(duals):
            x = lam[:, k]
            w = np.convolve(x, np.ones(args.window) / args.window, mode="valid")
            cells.append(f"{d}: mean {x.mean():+.3f} sd {x.std():.2f} lrv {long_run_variance(x, args.window):.2f} "
                         f"max{args.window} {w.max():+.3f}")
        print(f"{seed} [{decl}] " + "; ".join(cells))
    h = math.log(mb.threshold / (1.0 - mb.threshold)) - math.log(mb.p_min / (1.0 - mb.p_min))
    print(f"pooled over {len(pooled)} flights (h = {h:.1f} nats, N = {args.starts:g}, alpha = {args.alpha:g}):")
    for k, d in enumerate(duals):
        x = [p[:, k] for p in pooled]
        lrv = float(np.mean([long_run_variance(v, args.window) for v in x]))
        print(f"  {d}: mean {np.mean(np.concatenate(x)):+.4f} nats a frame, lrv {lrv:.3f}, "
              f"m0 = {mismatch_rate(lrv, args.starts, args.alpha, h):.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
