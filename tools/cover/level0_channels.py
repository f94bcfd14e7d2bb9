"""Which channels give a rival its lead over the failed component's hypothesis at level 0.

Flies one closed-loop flight (light turbulence, nominal point, the estimator of ``--bank`` in the
loop with ``--declare-components``, ``loop.flight.fly``) with the failure ``--fail NAME@T:MODE``
on the flight seed ``--seed``, records u and z, and replays them through the bank's level-0
filters (NONE, the singles, the partial hypotheses) as one core.FilterBank (p_min 1e-9, the
core's floors; the replay leaves out what the estimator in the loop adds, e.g. trim tracking,
so its probabilities are close to the loop's, not equal). Prints:

  ln p of NONE, the failed component's hypothesis and each rival every ``--every`` frames from
  just before the onset to ``--after-s`` past the first declaration;
  per frame for the first frames after the onset (``--frames``), l_rival - l_true split by
  channel: -(1/2) r_j (A^-1 r)_j of each hypothesis' residual r (the uninformative channels'
  rows of A^-1 zeroed, as the bank scores them), and the rest of each hypothesis' log-likelihood
  (u: a failed sensor's level density and its footing, filter_bank.h) apart;
  the same split summed from the onset to the first declaration.

Run: .venv/bin/python tools/cover/level0_channels.py --bank BANK --seed 823195340 --fail PIT@3.0:complete \
       --rivals RS,LS [--duration-s 4.6] [--every 3] [--frames 10]
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import parse_fail
from f16mmae.truth.scenario import Scenario

P_MIN = 1e-9


def channel_split(r: np.ndarray, a_inv: np.ndarray) -> np.ndarray:
    """-(1/2) r_j (A^-1 r)_j per channel j: sums to -(1/2) r' A^-1 r."""
    return -0.5 * r * (a_inv @ r)


def scored_inverse(a: np.ndarray, width: np.ndarray) -> np.ndarray:
    """A^-1 with the uninformative channels' rows and columns zeroed (steady_state_filter.h)."""
    a_inv = np.linalg.inv(a)
    for j, w in enumerate(width):
        if w > 0.0:
            a_inv[j, :] = 0.0
            a_inv[:, j] = 0.0
    return a_inv


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--fail", required=True)
    ap.add_argument("--rivals", required=True)
    ap.add_argument("--duration-s", type=float, default=5.0)
    ap.add_argument("--every", type=int, default=3)
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--after-s", type=float, default=0.15)
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    spec = parse_fail(args.fail)
    level0 = [i for i, h in enumerate(mb.hypotheses) if "+" not in h.name]
    hyps = [mb.hypotheses[i].name for i in level0]
    rivals = args.rivals.split(",")
    missing = [h for h in [spec.name, *rivals] if h not in hyps]
    if missing:
        raise SystemExit(f"level0_channels: {','.join(missing)} not in the bank's level 0")
    models, a_inv = [], {}
    for i in level0:
        h = mb.hypotheses[i]
        models.append(core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a, uninformative_width=h.uninformative_width,
                                       uninformative_level_q=h.uninformative_level_q))
        a_inv[h.name] = scored_inverse(np.asarray(h.a), np.asarray(h.uninformative_width))
    fb = core.FilterBank(models, p_min=P_MIN)
    sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence="light", seed=args.seed, duration_s=args.duration_s,
                  failures=(spec,))
    res = fly(sc, mb, record_series=True, estimator_options={"declare_components": True})
    print("declarations (the loop):", ", ".join(f"{d['hypothesis']}@{d['time_s']:.3f}" for d in res.declarations) or "-")
    u = res.series["u"] - np.asarray(mb.u_trim)
    z = res.series["z"] - np.asarray(mb.z_trim)
    n, k = len(z), len(models)
    p = np.zeros((n, k))
    ll = np.zeros((n, k))
    res_k = np.zeros((n, k, z.shape[1]))
    for i in range(n):
        p[i] = fb.update(z[i])
        ll[i] = fb.log_likelihoods
        res_k[i] = np.asarray(fb.residuals).reshape(k, -1)
        fb.propagate(u[i])
    rate = names.FRAME_RATE_HZ
    t0 = int(round(spec.time_s * rate))
    first = res.declarations[0]["time_s"] if res.declarations else spec.time_s + 1.0
    t1 = min(int(round(first * rate)), n - 1)
    true = spec.name
    sensors = list(names.SENSORS)
    shown = ["NONE", true, *rivals]
    print(f"replay at the first declaration: " + ", ".join(f"p_{h} {p[t1, hyps.index(h)]:.3f}" for h in shown))
    print(f"{'t s':>6s} " + " ".join(f"{'ln p_' + h:>10s}" for h in shown) + f" {'z-trim ' + true:>12s}")
    j_true = sensors.index(true) if true in sensors else None
    for i in range(max(t0 - 2, 0), min(t1 + int(args.after_s * rate), n), args.every):
        zt = f"{np.degrees(z[i, j_true]):+12.2f}" if j_true is not None else ""
        print(f"{i / rate:6.3f} " + " ".join(f"{np.log(max(p[i, hyps.index(h)], 1e-300)):10.2f}" for h in shown) + " " + zt)

    def split(h: str, i: int) -> tuple[np.ndarray, float]:
        kk = hyps.index(h)
        q = channel_split(res_k[i, kk], a_inv[h])
        return q, float(ll[i, kk] - q.sum())

    rv = rivals[0]
    print(f"per frame: l_{rv} - l_{true} = sum over channels + (u_{rv} - u_{true})")
    for i in range(t0, min(t0 + args.frames, n)):
        qa, ua = split(rv, i)
        qb, ub = split(true, i)
        print(f"{i / rate:6.3f} {ll[i, hyps.index(rv)] - ll[i, hyps.index(true)]:+6.2f} | "
              + " ".join(f"{s} {v:+5.2f}" for s, v in zip(sensors, qa - qb)) + f" | u_{true} {ub:+6.2f} u_{rv} {ua:+5.2f}")
    for rv in rivals:
        tot, un = np.zeros(len(sensors)), 0.0
        for i in range(t0, t1):
            qa, ua = split(rv, i)
            qb, ub = split(true, i)
            tot += qa - qb
            un += ua - ub
        print(f"onset to the first declaration ({t1 - t0} frames), l_{rv} - l_{true}: {tot.sum() + un:+.1f} = "
              + ", ".join(f"{s} {v:+.1f}" for s, v in zip(sensors, tot)) + f", u {un:+.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
