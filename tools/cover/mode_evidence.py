"""Evidence per frame for the injected failure's hypothesis against each rival, in closed loop.

Flies ``--runs`` closed-loop flights (light turbulence, nominal point, the estimator of
``--bank`` in the loop with its recommended settings, ``loop.flight.fly``) with one failure
``--fail NAME@TIME[:MODE[=VALUE]]`` on flight seeds ``--seed * 1000 + run`` (or the
flight seeds ``--flight-seeds``, e.g. a campaign's failing runs from its runs.jsonl), records u and z, and
replays them through the bank's level-0 filters as one core.FilterBank (p_min 1e-9, the
core's floors).  Over the frames from ``--settle-s`` after the onset to the end:

  D_k    mean of l_true - l_k per frame (nats; > 0: the data favour the injected failure's
         hypothesis over k on average; the per-frame likelihoods do not depend on which
         hypothesis the estimator in the loop declared, only on u and z),
  final  the level-0 hypothesis of largest probability at the end, per run,
  declared  the declarations, each with the truth's bank and angle of attack at its time,
  truth  for an actuator, the effective surface position (deg, mean over the window) and its
         command (deg); for a sensor, the mean of the sensor's error and of the true channel.

Run: .venv/bin/python tools/cover/mode_evidence.py --bank BANK --fail PIT@3:bias [--runs 5]
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import parse_fail
from f16mmae.truth.scenario import Scenario

P_MIN = 1e-9


def level0(model_bank) -> core.FilterBank:
    models = [core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a, uninformative_width=h.uninformative_width,
                               uninformative_level_q=h.uninformative_level_q)
              for h in list(model_bank.hypotheses)[:names.K_BANK]]
    return core.FilterBank(models, p_min=P_MIN)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--fail", required=True)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--flight-seeds", default=None,
                    help="comma-separated flight seeds (e.g. a campaign's runs.jsonl seeds) instead of --seed/--runs")
    ap.add_argument("--settle-s", type=float, default=0.5)
    ap.add_argument("--dwell-s", type=float, default=None)
    ap.add_argument("--turbulence", default="light")
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    spec = parse_fail(args.fail)
    hyps = names.SINGLE_HYPOTHESES
    true_k = hyps.index(spec.name)
    bank = level0(mb)
    opts = {} if args.dwell_s is None else {"dwell_s": args.dwell_s}
    diffs, finals, truths = [], [], []
    seeds = ([int(x) for x in args.flight_seeds.split(",")] if args.flight_seeds
             else [args.seed * 1000 + run for run in range(args.runs)])
    for run, seed in enumerate(seeds):
        sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence=args.turbulence, seed=seed,
                      duration_s=8.0, failures=(spec,))
        res = fly(sc, mb, record_series=True, estimator_options=opts)
        u = res.series["u"] - np.asarray(mb.u_trim)
        z = res.series["z"] - np.asarray(mb.z_trim)
        bank.reset()
        ll = np.zeros((len(z), len(hyps)))
        for i in range(len(z)):
            p = bank.update(z[i])
            ll[i] = bank.log_likelihoods
            bank.propagate(u[i])
        lo = int(round((spec.time_s + args.settle_s) * names.FRAME_RATE_HZ))
        diffs.append((ll[lo:, true_k][:, None] - ll[lo:]).mean(axis=0))
        finals.append(hyps[int(np.argmax(p))])
        log = res.series["truth_log"]
        if spec.is_actuator:
            j = spec.index
            truths.append(f"pos {np.degrees(log['surface_rad'][lo:, j].mean()):+.2f} deg, "
                          f"cmd {np.degrees(log['u_cmd_rad'][lo:, j].mean()):+.2f} deg")
        else:
            j = spec.index
            err = log["z"][lo:len(log["z_ideal"]), j] - log["z_ideal"][lo:, j]
            truths.append(f"error {err.mean():+.4g}, true channel - trim {(log['z_ideal'][lo:, j] - mb.z_trim[j]).mean():+.4g}")
        st, names_st = log["state"], list(log["state_names"])

        def attitude(t_s):
            i = min(int(np.searchsorted(log["time_s"], t_s)), len(st) - 1)
            return (f"phi {np.degrees(st[i, names_st.index('phi_rad')]):+.0f}, "
                    f"alpha {np.degrees(st[i, names_st.index('alpha_rad')]):+.0f} deg")
        decl = ",".join(f"{d['hypothesis']}@{d['time_s']:.2f} ({attitude(d['time_s'])})" for d in res.declarations)
        print(f"run {run}: final level-0 {finals[-1]}, declared {decl or '-'}; truth {truths[-1]}")
    d = np.mean(diffs, axis=0)
    print(f"{args.fail}: D_k = mean l_{spec.name} - l_k per frame from {args.settle_s:g} s after the onset, "
          f"{len(seeds)} runs")
    print("  " + " ".join(f"{h} {d[k]:+.3f}" for k, h in enumerate(hyps) if k != true_k))


if __name__ == "__main__":
    main()
