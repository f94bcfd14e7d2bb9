"""What a false dual's rise looks like: one flight, the level-1 bank's log-odds of a dual against
the declared single, frame by frame, beside the measured body rates and angle of attack.

After a right first declaration f the level-1 bank is {NONE, f, f+c ...}; a false dual f+c
rises when the data fit "f and c failed" better than "f failed" for the dwell.  This flies the
run (``f16mmae run``'s scenario: seed, failure) and prints every ``--every`` frames from the
first declaration on: ln(p_{f+c} / p_f) (its slope is the dual's evidence per frame), p_{f+c},
|p - p_trim| of the rates (deg/s) and alpha - alpha_trim (deg) as the sensors read them.

Run: .venv/bin/python tools/cover/dual_evidence.py --bank BANK --seed 606972620 --fail AY@3.0:complete \
       --dual RF+AY [--declare-components] [--level1-allowance K] [--every 8]

The last line: the per-frame increments of ln(p_{f+c}/p_f) from the first declaration on, over
the frames the dual is off its floor: their mean (the drift) and standard deviation (the walk's
step), the numbers the level-1 allowance's derivation reads (cpp/f16mmae/level1_allowance.h).
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.flight import fly, scenario_from_dict


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--fail", required=True, help="NAME@T:MODE, as f16mmae run --fail")
    ap.add_argument("--dual", required=True)
    ap.add_argument("--declare-components", action="store_true")
    ap.add_argument("--level1-p-min", type=float, default=0.0)
    ap.add_argument("--level1-allowance", type=float, default=0.0)
    ap.add_argument("--every", type=int, default=8)
    ap.add_argument("--from-onset", action="store_true",
                    help="print from the failure's onset, not from the first declaration (a rival read first: "
                         "--dual names the rival, e.g. --fail VEL@3.0:complete --dual RF)")
    args = ap.parse_args()
    name, rest = args.fail.split("@")
    t, mode = rest.split(":")
    scenario = {"mach": 0.4, "alt_ft": 20000.0, "turbulence": "light", "duration_s": 8.0, "seed": args.seed,
                "feedback": "mmae", "failures": [{"name": name, "time_s": float(t), "mode": mode}]}
    label, _, bank = load_bank(args.bank)
    opts = {"declare_components": args.declare_components}
    if args.level1_p_min:
        opts["level1_p_min"] = args.level1_p_min
    if args.level1_allowance:
        opts["level1_allowance"] = args.level1_allowance
    res = fly(scenario_from_dict(scenario), bank, estimator_options=opts, record_probabilities=True,
              record_series=True)
    print("declarations:", [(d["hypothesis"], round(d["time_s"], 2)) for d in res.declarations])
    z = res.series["z"]
    mz = list(bank.measurement_names)
    z0 = np.asarray(bank.z_trim)
    single = name
    ps, pd = res.probability_of(single), res.probability_of(args.dual)
    first = res.declarations[0]["time_s"] if res.declarations else float(t)
    i0 = int(round((float(t) if args.from_onset else first) / res.frame_dt_s))
    print(f"{'t s':>6s} {'ln(pd/pf)':>10s} {'slope/fr':>9s} {'p_dual':>8s} {'dAOA deg':>8s} "
          f"{'PIT':>6s} {'ROL':>6s} {'YAW':>6s}")
    prev = None
    for i in range(i0, len(res.time_s), args.every):
        lo = np.log(max(pd[i], 1e-300)) - np.log(max(ps[i], 1e-300))
        slope = (lo - prev) / args.every if prev is not None else float("nan")
        prev = lo
        dz = np.degrees(z[i] - z0)
        print(f"{res.time_s[i]:6.2f} {lo:10.2f} {slope:9.3f} {pd[i]:8.2e} {dz[mz.index('AOA')]:8.2f} "
              f"{dz[mz.index('PIT')]:6.2f} {dz[mz.index('ROL')]:6.2f} {dz[mz.index('YAW')]:6.2f}")
    lo = np.log(np.maximum(pd[i0:], 1e-300)) - np.log(np.maximum(ps[i0:], 1e-300))
    floor = lo.min()
    steps = np.diff(lo)[(lo[:-1] > floor + 0.5) & (lo[1:] > floor + 0.5)]
    if steps.size:
        print(f"increments off the floor: {steps.size} frames, mean {steps.mean():+.3f} nats a frame, "
              f"sd {steps.std():.3f}")


if __name__ == "__main__":
    main()
