"""Where a turbulence bank set's false declarations come from: one failure-free flight with the
set (``--turbulence-banks``), and for each declaration the member in force, the standby (if one
runs), the selector's rho of the member in force and its adaptation's scale s; then the
handovers and rho at a few times (docs/results/turbulence_banks.md).

    .venv/bin/python tools/turbulence_set_trace.py --turbulence moderate --seed 886684863
    .venv/bin/python tools/turbulence_set_trace.py --turbulence severe --profile hold --seed 1713771395 \
        --duration 243 --around 238.36 [--option maneuver_tempering_g=1]

A soak flight's seed is its record's ``seed`` (runs.jsonl of ``f16mmae campaign soak``).
``--around T`` adds, every 0.25 s from T - 3 s to T + 1 s, the truth's angle of attack and
airspeed (read from the truth log after the flight, for the analysis only), the stabilators'
command minus position and the stabilator and flaperon hypotheses' probabilities.
"""
from __future__ import annotations

import argparse

import numpy as np

import f16mmae.design.turbulence_banks  # noqa: F401  (registers the set)
from f16mmae.banks import load_bank
from f16mmae.campaign.soak.campaign import PROFILES, profile
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--turbulence", default="moderate")
    p.add_argument("--seed", type=int, required=True)
    p.add_argument("--duration", type=float, default=600.0)
    p.add_argument("--feedback", default="reconfigure")
    p.add_argument("--trim-tracking", type=float, default=None, metavar="TAU_S")
    p.add_argument("--profile", default=None, choices=PROFILES, help="a soak profile (hold: the pilot holds the trim)")
    p.add_argument("--option", action="append", default=[], metavar="KEY=VALUE",
                   help="a further estimator setting (core keyword, a number), e.g. maneuver_tempering_g=1")
    p.add_argument("--around", type=float, default=None, metavar="T_S")
    args = p.parse_args()
    bank = load_bank("turbulence")[2]
    options = {} if args.trim_tracking is None else {"trim_time_constant_s": args.trim_tracking}
    options.update({k: float(v) for k, _, v in (o.partition("=") for o in args.option)})
    maneuvers = () if args.profile is None else profile(args.profile, bank.mach, bank.alt_ft)[0]
    est = Estimator(bank, turbulence_banks=True, **options)
    rows = []

    def frame(t, u, z, air_data):
        b = est.core_bank
        rows.append((t, b.active, b.standby, b.turbulence_power_ratio, b.turbulence_scale))

    r = fly(Scenario(turbulence=args.turbulence, duration_s=args.duration, seed=args.seed, feedback=args.feedback,
                     maneuvers=maneuvers), bank, estimator=est, on_frame=frame, record_series=args.around is not None)
    rows = np.array(rows)
    changes = np.flatnonzero(np.diff(rows[:, 1]) != 0) + 1
    print(f"{args.turbulence}, seed {args.seed}, {args.duration:g} s: {est.core_bank.switches} handovers "
          f"({', '.join(f'member {int(rows[i, 1])} at {rows[i, 0]:.2f} s' for i in changes) or 'none'})")
    for d in r.declarations:
        i = min(int(round(d["time_s"] * 64)), len(rows) - 1)
        print(f"  {d['time_s']:8.2f} s  {d['hypothesis']:8s} member {int(rows[i, 1])}, standby {int(rows[i, 2])}, "
              f"rho {rows[i, 3]:.3f}, s {rows[i, 4]:.2f}")
    for t in np.arange(60.0, args.duration, 60.0):
        i = int(t * 64)
        print(f"  t {t:5.0f} s: member {int(rows[i, 1])}, rho {rows[i, 3]:.3f}, s {rows[i, 4]:.2f}")
    if args.around is not None:
        _around(r, rows, args.around)


def _around(r, rows, t0: float) -> None:
    log = r.series["truth_log"]
    names = list(log["state_names"])
    state, cmd, pos = log["state"], log["u_cmd_rad"], log["surface_rad"]
    for t in np.arange(t0 - 3.0, t0 + 1.0, 0.25):
        i = min(int(round(t * 64)), len(rows) - 1, len(cmd) - 1)
        lag = np.degrees(cmd[i, :2] - pos[i, :2])
        p = " ".join(f"{h} {r.probability_of(h)[i]:.3f}" for h in ("LS", "RS", "LF", "RF"))
        print(f"  {t:8.2f} s  alpha {np.degrees(state[i, names.index('alpha_rad')]):5.1f} deg, "
              f"airspeed {state[i, names.index('vt_fps')]:5.0f} ft/s, stabilators cmd - pos "
              f"{lag[0]:+.2f} {lag[1]:+.2f} deg, rho {rows[i, 3]:.2f}, s {rows[i, 4]:.1f}, {p}")


if __name__ == "__main__":
    main()
