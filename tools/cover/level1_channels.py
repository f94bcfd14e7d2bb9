"""Which channels carry a false dual's walk at level 1: the flight's l_{f+c} - l_f split by channel,
beside the models' expected split.

Flies one closed-loop flight (light turbulence, nominal point, the estimator of ``--bank`` in the
loop with ``--declare-components``, ``loop.flight.fly``) with the single failure ``--fail
NAME@T:MODE`` on ``--seed``, records u and z, and replays them through the single's filter f and
the dual's ``--dual`` (f+c) from the flight's start (steady-state filters: by ``--from-s`` both
have forgotten their start). Per frame lambda = l_{f+c} - l_f, the frame's log-likelihood ratio
the level-1 bank adds to ln(p_{f+c}/p_f) (cpp/f16mmae/level1_allowance.h), split as
-(1/2) r_j (A^-1 r)_j per channel j of each filter's residual r (uninformative channels' rows
of A^-1 zeroed, as the bank scores them) plus the rest u (a failed sensor's level term).
Prints the split summed over windows of ``--window-s`` from ``--from-s`` (default: the loop's
first declaration) to the end, and its mean a frame.

The models' split (``design.distinguish``, the bank redesigned from the tuning its metadata
records; f failed ``complete``, light air, the dither): per channel
E[q_j] = -(1/2) [(A^-1 S)_jj + mean_t m_j(t) (A^-1 m(t))_j] for each filter (S its residual's
stationary covariance, m(t) its residual's mean under the dither), dual minus single; their
sum plus the level terms is -D(f, f+c). A channel whose flight mean exceeds the models' by
much is where the dual's freedom explains what the single's model does not.

``--figure PNG``: the flight's cumulative lambda per channel (and in total) from ``--from-s``,
beside the models' expected lines (dashed).

Run: .venv/bin/python tools/cover/level1_channels.py --bank BANK --seed 606972620 --fail AY@3.0:complete \
       --dual RF+AY [--from-s 4.0] [--duration-s 8] [--window-s 0.5] [--figure PNG]
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import parse_fail
from f16mmae.truth.scenario import Scenario

P_MIN = 1e-9


def scored_inverse(a: np.ndarray, width: np.ndarray) -> np.ndarray:
    """A^-1 with the uninformative channels' rows and columns zeroed (steady_state_filter.h)."""
    a_inv = np.linalg.inv(a)
    for j, w in enumerate(width):
        if w > 0.0:
            a_inv[j, :] = 0.0
            a_inv[:, j] = 0.0
    return a_inv


def model_split(bank, single: str, dual: str) -> tuple[np.ndarray, float]:
    """(per-channel E[q_dual - q_single] a frame, D(single, dual)) from the models (docstring)."""
    from f16mmae.campaign.dual.models import bank_design
    from f16mmae.design import distinguish as dz

    design, why = bank_design(bank)
    if design is None:
        raise SystemExit(f"level1_channels: the bank cannot be redesigned ({why})")
    bd_t, h_t = dz.truth_matrices(design, single)
    own, rival = dz.scored_filter(design, single), dz.scored_filter(design, dual)
    u = dz.dither_inputs(int(20.0 * design.frame_rate_hz), design.frame_rate_hz)
    stoch = dz._stochastic(design.discrete.phi, design.discrete.qd, design.r, h_t, [own, rival])
    means = dz._deterministic(design.discrete.phi, bd_t, h_t, [own, rival], u, keep=len(u) // 2)
    per = []
    for f, (cov, _), (m, _) in zip((own, rival), stoch, means):
        quad = np.diag(f.a_inv @ cov) + np.mean(m * (m @ f.a_inv.T), axis=0)
        per.append(-0.5 * quad)
    d = dz.rates(design.discrete.phi, design.discrete.qd, design.r, bd_t, h_t, own, [rival], u)[0]
    return per[1] - per[0], float(d)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--fail", required=True, help="the single failure NAME@T:MODE")
    ap.add_argument("--dual", required=True, help="the dual hypothesis f+c, as the bank names it")
    ap.add_argument("--from-s", type=float, default=None, help="window start (default: the first declaration)")
    ap.add_argument("--duration-s", type=float, default=8.0)
    ap.add_argument("--window-s", type=float, default=0.5)
    ap.add_argument("--no-models", action="store_true", help="leave out the models' split")
    ap.add_argument("--figure", default=None, help="write the cumulative split to this PNG")
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    spec = parse_fail(args.fail)
    hyps = list(mb.hypothesis_names)
    for h in (spec.name, args.dual):
        if h not in hyps:
            raise SystemExit(f"level1_channels: {h!r} is not a hypothesis of the bank")
    if spec.name not in names.failed_components(args.dual):
        raise SystemExit(f"level1_channels: {args.dual!r} is no dual of {spec.name!r}")
    chosen = [mb.hypotheses[hyps.index(h)] for h in (spec.name, args.dual)]
    models = [core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a, uninformative_width=h.uninformative_width,
                               uninformative_level_q=h.uninformative_level_q) for h in chosen]
    a_inv = [scored_inverse(np.asarray(h.a), np.asarray(h.uninformative_width)) for h in chosen]
    fb = core.FilterBank(models, p_min=P_MIN)
    sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence="light", seed=args.seed, duration_s=args.duration_s,
                  failures=(spec,))
    res = fly(sc, mb, record_series=True, estimator_options={"declare_components": True})
    print("declarations (the loop):", ", ".join(f"{d['hypothesis']}@{d['time_s']:.3f}" for d in res.declarations) or "-")
    u = res.series["u"] - np.asarray(mb.u_trim)
    z = res.series["z"] - np.asarray(mb.z_trim)
    n, m = len(z), z.shape[1]
    q = np.zeros((n, 2, m))
    rest = np.zeros((n, 2))
    for i in range(n):
        fb.update(z[i])
        ll = np.asarray(fb.log_likelihoods)
        r = np.asarray(fb.residuals).reshape(2, -1)
        for k in range(2):
            q[i, k] = -0.5 * r[k] * (a_inv[k] @ r[k])
            rest[i, k] = ll[k] - q[i, k].sum()
        fb.propagate(u[i])
    rate = names.FRAME_RATE_HZ
    start = args.from_s if args.from_s is not None else (
        res.declarations[0]["time_s"] if res.declarations else spec.time_s + 1.0)
    i0 = int(round(start * rate))
    if i0 >= n - 1:
        raise SystemExit(f"level1_channels: --from-s {start:g} is past the flight's end ({n / rate:g} s)")
    lam_q = q[i0:, 1] - q[i0:, 0]
    lam_u = rest[i0:, 1] - rest[i0:, 0]
    sensors = list(names.SENSORS)
    print(f"lambda = l_{args.dual} - l_{spec.name} summed over {args.window_s:g}-s windows from {start:.3f} s "
          "(per channel, then the level terms u, then the total)")
    w = max(1, int(round(args.window_s * rate)))
    print(f"{'t s':>6s} " + " ".join(f"{s:>6s}" for s in sensors) + f" {'u':>6s} {'total':>7s} {'cum':>7s}")
    cum = 0.0
    for a in range(0, len(lam_u), w):
        sq, su = lam_q[a:a + w].sum(axis=0), float(lam_u[a:a + w].sum())
        cum += sq.sum() + su
        print(f"{start + a / rate:6.2f} " + " ".join(f"{v:+6.1f}" for v in sq) + f" {su:+6.1f} {sq.sum() + su:+7.1f} {cum:+7.1f}")
    mean_q, mean_u = lam_q.mean(axis=0), float(lam_u.mean())
    print(f"flight, mean a frame ({len(lam_u)} frames): " + ", ".join(f"{s} {v:+.3f}" for s, v in zip(sensors, mean_q))
          + f", u {mean_u:+.3f}; total {mean_q.sum() + mean_u:+.3f}")
    split = None
    if not args.no_models:
        split, d = model_split(mb, spec.name, args.dual)
        print(f"models, E a frame ({spec.name} complete, light air, dither): "
              + ", ".join(f"{s} {v:+.3f}" for s, v in zip(sensors, split))
              + f"; quadratic total {split.sum():+.3f}, -D({spec.name}, {args.dual}) = {-d:+.3f}")
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        t = start + np.arange(len(lam_u)) / rate
        fig, ax = plt.subplots(figsize=(8, 4.5))
        shown = [j for j in range(len(sensors)) if np.abs(np.cumsum(lam_q[:, j])).max() > 2.0]
        for j in shown:
            line, = ax.plot(t, np.cumsum(lam_q[:, j]), label=sensors[j])
            if split is not None:
                ax.plot(t, split[j] * np.arange(1, len(t) + 1), "--", color=line.get_color(), lw=0.8)
        total, = ax.plot(t, np.cumsum(lam_q.sum(axis=1) + lam_u), "k", lw=2, label="total")
        if split is not None:
            ax.plot(t, -d * np.arange(1, len(t) + 1), "k--", lw=1, label="models (dashed)")
        ax.set_xlabel("t (s)")
        ax.set_ylabel(f"sum of l_{args.dual} - l_{spec.name} (nats)")
        ax.set_title(f"{spec.name}@{spec.time_s:g}:{spec.mode}, flight seed {args.seed}: the walk of {args.dual} by channel")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, ncol=2)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=110)
        print(f"figure: {args.figure}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
