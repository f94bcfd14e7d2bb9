"""How much evidence a partial loss carries: the bank's hypotheses against a matched one.

A surface that keeps a fraction F of its effectiveness (``--fail C@T:loss=F``: the truth moves
it by F times its command about the trim) differs from a healthy one only by (1 - F) times the
part of the command that moves -- the dither and the FCS's corrections.  Flies ``--runs``
closed-loop flights per component and F (light turbulence, nominal point, the estimator of
``--bank`` in the loop; flight seeds ``--seed * 1000 + run``), records u and z, and replays
them through three level-0 filters as one core.FilterBank (p_min 1e-9, the core's floors):

  NONE     the bank's no-failure filter,
  C        the bank's hypothesis for the surface (under ``cover``: its position an unknown
           random walk, the command's column removed),
  C@F      a hypothesis matched to the truth: the no-failure model with C's column of B_d
           times F, its own steady-state gains (design/gains.py) -- what a partial-loss
           hypothesis for that F could at best gather (designed here, not in any bank),

and prints, from ``--settle-s`` after the onset, the mean evidence per frame of C and of C@F
over NONE (nats; l_k - l_NONE), and for each the frames it needs to climb from the floor to
the threshold at that rate, ln((1 - p_min) / p_min) + ln(0.9 / 0.1) over the rate (s).

Run: .venv/bin/python tools/cover/partial_loss.py --bank results/cover.f16bank \
       --components LS,RS,LF,RF,RUD --losses 0.25,0.5,0.75 --runs 5 --seed 7
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.design.gains import steady_state_gains
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import parse_fail
from f16mmae.truth.scenario import Scenario

P_MIN = 1e-9
THRESHOLD = 0.9


def matched_model(none, column: int, fraction: float, qd: np.ndarray, r: np.ndarray) -> core.FilterModel:
    """NONE's model with B_d's column ``column`` scaled by ``fraction``, with its own gains."""
    bd = np.array(none.bd, dtype=float, copy=True)
    bd[:, column] *= fraction
    g = steady_state_gains(np.asarray(none.phi), np.asarray(none.h), qd, r, name=f"matched F={fraction:g}")
    return core.FilterModel(phi=none.phi, bd=bd, h=none.h, k=g.k, a=g.a)


def main(argv=None) -> None:
    from f16mmae.design.bank import design_bank
    from f16mmae.design.tuning import tuning_from_dict
    import json

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--components", default="LS,RS,LF,RF,RUD")
    ap.add_argument("--losses", default="0.25,0.5,0.75", help="remaining effectiveness fractions F")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--settle-s", type=float, default=0.5)
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    hyps = list(mb.hypothesis_names)
    none = mb.hypotheses[hyps.index("NONE")]
    # the bank's own Q_d and R: its design, from the tuning stored in the bank
    tuning = tuning_from_dict(json.loads(mb.metadata)["tuning"], default_name="bank")
    design = design_bank(mb.mach, mb.alt_ft, tuning, hypotheses=("NONE",))
    qd, r = design.filter("NONE").model.qd, design.r
    climb = np.log((1.0 - P_MIN) / P_MIN) + np.log(THRESHOLD / (1.0 - THRESHOLD))
    print(f"bank {args.bank}; evidence per frame over NONE from {args.settle_s:g} s after the onset at 3 s; "
          f"climb floor -> threshold {climb:.1f} nats; {args.runs} runs each")
    print(f"{'comp':<4} {'F':>5} {'bank C':>8} {'(s)':>6} {'C@F':>8} {'(s)':>6}")
    for comp in args.components.split(","):
        j = names.ACTUATORS.index(comp)
        own = mb.hypotheses[hyps.index(comp)]
        for frac in (float(x) for x in args.losses.split(",")):
            models = [core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a,
                                       uninformative_width=h.uninformative_width,
                                       uninformative_level_q=h.uninformative_level_q) for h in (none, own)]
            models.append(matched_model(none, j, frac, qd, r))
            bank = core.FilterBank(models, p_min=P_MIN)
            rates = []
            for run in range(args.runs):
                spec = parse_fail(f"{comp}@3:loss={frac:g}")
                sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence="light", seed=args.seed * 1000 + run,
                              duration_s=8.0, failures=(spec,))
                res = fly(sc, mb, record_series=True)
                u = res.series["u"] - np.asarray(mb.u_trim)
                z = res.series["z"] - np.asarray(mb.z_trim)
                bank.reset()
                ll = np.zeros((len(z), 3))
                for i in range(len(z)):
                    bank.update(z[i])
                    ll[i] = bank.log_likelihoods
                    bank.propagate(u[i])
                lo = int(round((spec.time_s + args.settle_s) * names.FRAME_RATE_HZ))
                rates.append((ll[lo:, 1:] - ll[lo:, :1]).mean(axis=0))
            d = np.mean(rates, axis=0)
            secs = [climb / x / names.FRAME_RATE_HZ if x > 0 else float("inf") for x in d]
            print(f"{comp:<4} {frac:>5.2f} {d[0]:>+8.3f} {secs[0]:>6.1f} {d[1]:>+8.3f} {secs[1]:>6.1f}")


if __name__ == "__main__":
    main()
