"""Lab driver (not in the wheel): in a no-failure flight of the scheduled default, how does a
failure hypothesis come to fit a healthy aircraft better than the no-failure filter does?

    python tools/schedule/calm_fit.py --point 0.6853:6624 --seed 5 --hypothesis AZ
    python tools/schedule/calm_fit.py --point 0.3453:26582 --seed 415358841 --hypothesis VEL --duration 9

Flies one no-failure flight (the truth's dither, MMAE feedback; ``--turbulence``, calm air by
default) with the scheduled default (``--bank scheduled --adapt-turbulence``, as ``f16mmae run``
flies it) and prints:

* the declarations;
* over the level-0 frames from 1 s on, the mean log-likelihood of every hypothesis against the
  no-failure filter's (l_k - l_0, eq. 2 as the bank tempers it: the evidence a frame gives it);
* the residual rms per measurement of the no-failure filter and of ``--hypothesis``;
* second by second the calm-air rule's measures (the residual whiteness W-bar and the power
  ratio rho-bar against the node's reference; cpp/f16mmae/calm_air_complete.h), whether VEL is
  read complete, and the probability of ``--hypothesis``.

docs/results/envelope_scheduled.md, round 25, reads the false AZ at high q-bar and the false VEL
at Mach 0.35, 26,600 ft in calm air with it.
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import names
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.truth.scenario import Scenario


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--point", default="0.6853:6624", help="MACH:ALT_FT (default 0.6853:6624)")
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--duration", type=float, default=20.0, help="seconds of flight (default 20)")
    ap.add_argument("--turbulence", default="none", choices=("none", "light", "moderate", "severe"))
    ap.add_argument("--hypothesis", default="AZ", choices=names.SINGLE_HYPOTHESES[1:],
                    help="the single failure hypothesis to set against the no-failure filter (default AZ)")
    args = ap.parse_args()
    try:
        mach, alt_ft = (float(v) for v in args.point.split(":"))
    except ValueError:
        ap.error(f"--point {args.point!r} must be MACH:ALT_FT")
    if not args.duration > 1.0:
        ap.error(f"--duration {args.duration:g} must exceed 1 s (the first second is left out)")
    bank = load_bank("scheduled")[2]
    estimator = Estimator(bank, adapt_turbulence=True)
    core_bank = estimator.core_bank
    k = list(names.SINGLE_HYPOTHESES).index(args.hypothesis)
    vel = names.SENSORS.index("VEL")
    frames = []

    def on_frame(t, u, z, air_data):
        level0 = core_bank.level == 0
        frames.append({"t": t, "level0": level0,
                       "l": np.asarray(core_bank.log_likelihoods).copy() if level0 else None,
                       "r": np.asarray(core_bank.residuals).copy() if level0 else None,
                       "w": core_bank.calm_whiteness, "rho": core_bank.measured_power_ratio,
                       "ref": core_bank.calm_reference, "calm": core_bank.calm_complete_channels >> vel & 1,
                       "p": float(np.asarray(core_bank.probabilities)[k]) if level0 else float("nan")})

    fly(Scenario(mach=mach, alt_ft=alt_ft, turbulence=args.turbulence, duration_s=args.duration, seed=args.seed),
        bank, estimator=estimator, on_frame=on_frame)
    print(f"Mach {mach:g}, {alt_ft:.0f} ft, {args.turbulence} air, seed {args.seed}, {args.duration:g} s; "
          f"declarations: {[(d['hypothesis'], round(d['time_s'], 2)) for d in core_bank.declarations]}")
    kept = [f for f in frames if f["level0"] and f["t"] >= 1.0]
    if kept:
        dl = np.mean([f["l"] - f["l"][0] for f in kept], axis=0)
        print("mean l_k - l_0 per frame, level 0 from 1 s: "
              + ", ".join(f"{h} {v:+.3f}" for h, v in zip(names.SINGLE_HYPOTHESES, dl)))
        for label, i in (("NONE", 0), (args.hypothesis, k)):
            rms = np.sqrt(np.mean([f["r"][i] ** 2 for f in kept], axis=0))
            print(f"residual rms, {label:5s}: " + ", ".join(f"{s} {v:.4g}" for s, v in zip(names.SENSORS, rms)))
    print("second  W-bar  rho-bar  reference  VEL complete  p(" + args.hypothesis + ")")
    for second in range(int(args.duration)):
        rows = [f for f in frames if int(f["t"]) == second]
        if not rows:
            continue
        last = rows[-1]
        print(f"{second:6d}  {last['w']:5.2f}  {last['rho']:7.3f}  {last['ref']:9.3f}  "
              f"{np.mean([f['calm'] for f in rows]):12.2f}  {last['p']:.2e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
