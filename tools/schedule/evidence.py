"""Lab driver (not in the wheel): the evidence per frame a failure gives its hypothesis, at grid
nodes from the design point to high dynamic pressure, against what the declaration rule needs.

    python tools/schedule/evidence.py --schedule FILE [--nodes 0.4:20000,0.6:10000] \\
        [--failures LS,RS,LF,RF,ROL] [--seeds 1,2,3,4] [--turbulence none] [--dither-scale 1,1,2,2,2] \\
        [--dither-frequency 1.7,1.7,2.9,2.9,2.3]

At each node, each failure is flown with the design's calibration-flight setup
(``design.flights.fly_closed_loop``: light turbulence, the truth's default dither, raw
feedback, complete failure at 3 s, 8-s flight, tuning flight seeds), and the node's level-0
filters (NONE and the 12 single failures, one ``core.FilterBank``, likelihoods of eq. 2 with
the leading term stripped, s = 1) are run over the record.  Printed per failure, over the
frames after the failure (mean over the seeds):

  e_NONE   mean per frame of l_f - l_NONE: the log-odds the failed hypothesis gains on NONE
  e_next   min over k != f of the mean per frame of l_f - l_k: on its closest competitor (named)
  need     what the declaration rule asks of e_NONE at s = 1: from the floor ln p_min to
           ln(threshold / (1 - threshold)) within the frames left after the failure, less the dwell
  s        the turbulence adaptation's scale the node's estimator holds over those frames
           (reference = the node's; the likelihoods are divided by it)
--turbulence flies another turbulence level than the calibration's light (none: what the
turbulence costs the evidence); --dither-scale multiplies the surface dither amplitudes (one
factor, or one per surface LS,RS,LF,RF,RUD; dither_margin.py: what the criterion allows);
--dither-frequency gives the five surfaces' frequencies (Hz) instead of the default lines.
--failures NONE flies no failure: e_next is then NONE's margin on its closest competitor
(negative: that hypothesis fits the failure-free flight better than NONE, frame by frame).
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.campaign.envelope.points import dynamic_pressure_psf
from f16mmae.design.flights import fly_closed_loop
from dither_margin import scaled_dither

FAILURE_S = 3.0


def node_of(info, mach, alt_ft):
    own = [n for n in info["nodes"] if abs(n["mach"] - mach) < 1e-9 and n["alt_ft"] == alt_ft]
    return own[0]   # own configuration first (the design writes the alternates after)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--schedule", default="scheduled")
    ap.add_argument("--nodes", default="0.4:20000,0.5:15000,0.6:10000,0.7:10000,0.8:5000")
    ap.add_argument("--failures", default="LS,RS,LF,RF,ROL")
    ap.add_argument("--seeds", default="1,2,3,4")
    ap.add_argument("--turbulence", default="light")
    ap.add_argument("--dither-scale", default="1")
    ap.add_argument("--dither-frequency", default=None)
    args = ap.parse_args()
    dither = scaled_dither(args.dither_scale, args.dither_frequency)
    info = load_bank(args.schedule)[2].schedule
    seeds = [int(s) for s in args.seeds.split(",")]
    for item in args.nodes.split(","):
        mach, alt = (float(x) for x in item.split(":"))
        nd = node_of(info, mach, alt)
        mb = nd["bank"]
        settings = dict(mb.estimator_settings)
        models = [core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a)
                  for h in (mb[name] for name in names.SINGLE_HYPOTHESES)]
        plain = core.FilterBank(models, p_min=settings["p_min"])
        frames_left = int((8.0 - FAILURE_S - settings["dwell_s"]) * names.FRAME_RATE_HZ)
        need = (np.log(settings["threshold"] / (1 - settings["threshold"])) - np.log(settings["p_min"])) / frames_left
        print(f"Mach {mach:.2f}, {alt:.0f} ft, q {dynamic_pressure_psf(mach, alt):.0f} lbf/ft^2, reference "
              f"{nd['adapt_reference']}: need e_NONE >= {need:.3f} per frame at s = 1", flush=True)
        for fail in args.failures.split(","):
            k = names.SINGLE_HYPOTHESES.index(fail)
            e_none, diffs, scales = [], [], []
            for seed in seeds:
                fl = fly_closed_loop(mach, alt, seed=seed, failure=None if fail == names.NONE else fail, failure_time_s=FAILURE_S,
                                     turbulence_level=args.turbulence, dither=dither)
                est = core.HierarchicalBank(mb, adapt_turbulence=True, adapt_reference=nd["adapt_reference"], **settings)
                plain.reset()
                first = int(FAILURE_S * names.FRAME_RATE_HZ)
                for i in range(len(fl.z)):
                    plain.step(fl.z[i], fl.u[i])
                    est.step(fl.z[i] + mb.z_trim, fl.u[i] + mb.u_trim)
                    if i >= first:
                        ll = plain.log_likelihoods
                        e_none.append(ll[k] - ll[0])
                        diffs.append(ll[k] - ll)
                        scales.append(est.turbulence_scale)
            mean_diff = np.mean(diffs, axis=0)
            mean_diff[k] = np.inf
            nxt = int(np.argmin(mean_diff))
            print(f"  {fail:4s} e_NONE {np.mean(e_none):7.3f}  e_next {mean_diff[nxt]:7.3f} ({names.SINGLE_HYPOTHESES[nxt]})  "
                  f"s {np.mean(scales):4.1f}  e_NONE/s {np.mean(e_none) / np.mean(scales):7.3f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
