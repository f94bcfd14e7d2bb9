"""Lab driver (not in the wheel): where, channel by channel, the evidence for a failure and the
gusts' false evidence for it come from at a grid node -- can any weighting of the channels
separate them?

    python tools/schedule/channel_evidence.py --schedule FILE [--nodes 0.35:10000,0.4:20000] \\
        [--failures LS,LF] [--seeds 1,2,3,4] [--turbulence light] [--window-s 1.0]

At each node, each failure and failure-free flights are flown with the design's calibration-flight
setup (``design.flights.fly_closed_loop``: light turbulence, the truth's default dither, raw
feedback, complete failure at 3 s, 8-s flight, tuning flight seeds), and the node's level-0
filters (one ``core.FilterBank``, eq. 2 with the leading term stripped, s = 1) are run over the
record.  The log-odds of hypothesis f on NONE per frame, l_f - l_NONE = (q_NONE - q_f) / 2,
q_k = r_k^T A_k^-1 r_k, is split over the measurement channels j:

    e_j = (c_NONE,j - c_f,j) / 2,   c_k,j = r_k,j (A_k^-1 r_k)_j     (sum_j e_j = l_f - l_NONE)

Printed per failure f and channel j:

  fail   mean e_j per frame after the failure in the flights where f failed (the signal)
  gust   mean e_j per frame in the failure-free flights after the start-up second (the bias the
         gusts give f; negative: the channel speaks for NONE)
  sd     the standard deviation over the failure-free flights' windows of ``--window-s`` of the
         window sums of e_j, divided by the window's frames (the gusts' noise per frame on f's
         log-odds, as a window sees it)
  d'     (fail - gust) / sd: the channel's separation of failure from gusts per frame at the window

and the same for the sum over the channels ("all") and the best separation a fixed weighting
of the channels reaches (Fisher's linear discriminant of the window means, w = C^-1 (fail - gust),
C the channels' covariance over the failure-free windows: "best").  If "best" is not much above
"all", no per-channel tempering of the likelihoods can separate the failure from the gusts better
than the bank does.
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.campaign.envelope.points import dynamic_pressure_psf
from f16mmae.design.flights import fly_closed_loop
from evidence import node_of

FAILURE_S = 3.0
START_UP_S = 1.0


def channel_terms(bank, ainv, z, u):
    """(frames, K, m) per-channel terms c_k,j of the quadratic forms, over one record."""
    bank.reset()
    out = np.empty((len(z), ainv.shape[0], ainv.shape[1]))
    for i in range(len(z)):
        bank.step(z[i], u[i])
        r = np.asarray(bank.residuals)
        out[i] = r * np.einsum("kij,kj->ki", ainv, r)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--schedule", default="scheduled")
    ap.add_argument("--nodes", default="0.35:10000,0.4:20000")
    ap.add_argument("--failures", default="LS,LF")
    ap.add_argument("--seeds", default="1,2,3,4")
    ap.add_argument("--turbulence", default="light")
    ap.add_argument("--window-s", type=float, default=1.0)
    args = ap.parse_args()
    info = load_bank(args.schedule)[2].schedule
    seeds = [int(s) for s in args.seeds.split(",")]
    fails = args.failures.split(",")
    win = int(round(args.window_s * names.FRAME_RATE_HZ))
    first = int(FAILURE_S * names.FRAME_RATE_HZ)
    start = int(START_UP_S * names.FRAME_RATE_HZ)
    chans = list(names.SENSORS)
    for item in args.nodes.split(","):
        mach, alt = (float(x) for x in item.split(":"))
        nd = node_of(info, mach, alt)
        mb = nd["bank"]
        hyps = [mb[name] for name in names.SINGLE_HYPOTHESES]
        ainv = np.stack([np.linalg.pinv(h.a) for h in hyps])
        bank = core.FilterBank([core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a) for h in hyps], p_min=1e-9)
        print(f"Mach {mach:.2f}, {alt:.0f} ft, q {dynamic_pressure_psf(mach, alt):.0f} lbf/ft^2, reference "
              f"{nd['adapt_reference']}, sqrt(A_NONE) "
              + " ".join(f"{c} {np.sqrt(hyps[0].a[j, j]):.3g}" for j, c in enumerate(chans)), flush=True)
        quiet = []
        for seed in seeds:
            fl = fly_closed_loop(mach, alt, seed=seed, failure=None, turbulence_level=args.turbulence)
            quiet.append(channel_terms(bank, ainv, fl.z, fl.u)[start:])
        # consistency: the split sums to the bank's log-likelihoods (checked on the last frame)
        ll = np.asarray(bank.log_likelihoods)
        checked = [0] + [names.SINGLE_HYPOTHESES.index(f) for f in fails]
        assert np.allclose(-0.5 * quiet[-1][-1].sum(axis=1)[checked], ll[checked], rtol=1e-6, atol=1e-6), \
            "the channel split does not sum to the bank's log-likelihoods"
        q_none = np.concatenate([q[:, 0, :] for q in quiet])
        print("  NONE's channel power c_NONE,j (failure-free, after 1 s): "
              + " ".join(f"{c} {v:.2f}" for c, v in zip(chans, q_none.mean(axis=0))), flush=True)
        for fail in fails:
            k = names.SINGLE_HYPOTHESES.index(fail)
            gust_windows = []
            for q in quiet:
                e = 0.5 * (q[:, 0, :] - q[:, k, :])
                n = len(e) // win
                gust_windows.append(e[: n * win].reshape(n, win, -1).mean(axis=1))
            gw = np.concatenate(gust_windows)
            sig = []
            for seed in seeds:
                fl = fly_closed_loop(mach, alt, seed=seed, failure=fail, failure_time_s=FAILURE_S,
                                     turbulence_level=args.turbulence)
                q = channel_terms(bank, ainv, fl.z, fl.u)[first:]
                sig.append(0.5 * (q[:, 0, :] - q[:, k, :]))
            fs = np.concatenate(sig).mean(axis=0)
            gm, gsd = gw.mean(axis=0), gw.std(axis=0)
            tot_f, tot_g, tot_sd = fs.sum(), gw.sum(axis=1).mean(), gw.sum(axis=1).std()
            cov = np.cov(gw.T) + 1e-12 * np.eye(len(chans))
            w = np.linalg.solve(cov, fs - gm)
            best = float((w @ (fs - gm)) / np.sqrt(w @ cov @ w))
            print(f"  {fail}: channel fail / gust / sd / d'", flush=True)
            for j, c in enumerate(chans):
                print(f"    {c:4s} {fs[j]:8.3f} {gm[j]:8.3f} {gsd[j]:7.3f} {(fs[j] - gm[j]) / max(gsd[j], 1e-12):7.2f}")
            print(f"    all  {tot_f:8.3f} {tot_g:8.3f} {tot_sd:7.3f} {(tot_f - tot_g) / tot_sd:7.2f}   "
                  f"best {best:.2f} (w/|w|: " + " ".join(f"{c} {v:+.2f}" for c, v in zip(chans, w / np.abs(w).max()))
                  + ")", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
