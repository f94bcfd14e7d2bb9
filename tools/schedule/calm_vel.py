"""Lab driver (not in the wheel): why the scheduled default declares a failed VEL in calm air,
and what would not declare it.

    python tools/schedule/calm_vel.py [--mach 0.4] [--alt-ft 20000] [--seeds 11,12,13,14] [--flight-s 30]

Flies no-failure flights (``design.flights.fly_closed_loop``: raw feedback, the truth's dither)
in calm and in light air at the point, and runs over their (u, z) records the no-failure (NONE)
filter of three designs:

- the scheduled bank's node at the point (the file's, as the default flies it: its own
  configuration);
- ``tuned_gust`` (the Dryden gust states) designed for light air, and the same designed for
  calm air (``turbulence = "none"``).

Printed per design and air, after each flight's first 4 s:

- the VEL innovation's RMS (the residual z_VEL - H x⁻ of NONE) and the RMS of its
  conditional part given the other channels, e = (A⁻¹ r)_VEL / (A⁻¹)_VEL,VEL, against the
  design's conditional sigma sqrt(1 / (A⁻¹)_VEL,VEL);
- the RMS of the reading about its running mean, which a failed VEL's constant level fits
  (the ``constant`` model's density: the sensor's noise about a level);
- per frame, the VEL channel's evidence for that level against NONE's conditional Gaussian,
      d = ln N(z - b; 0, R) - ln N(e; 0, c sigma_c^2)      (b the running mean, R the sensor's
                                                            noise variance from the truth),
  for c = 1 (the design's density, the common footing of filter_bank.h) and for c matched to the
  air, c = mean(e^2) / sigma_c^2 (covariance matching on that channel, the density's determinant
  included). d > 0 on average: the level is the better predictor and the VEL hypothesis climbs.
"""
from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from evidence import node_of
from f16mmae import names
from f16mmae.banks import load_bank
from f16mmae.design.bank import design_bank
from f16mmae.design.flights import fly_closed_loop
from f16mmae.design.model import linearize_truth
from f16mmae.design.residuals import filter_residuals
from f16mmae.design.tuning import load_tuning
from f16mmae.truth.sensors import NOISE_SIGMA

SKIP_S = 4.0


def evidence(r: np.ndarray, a: np.ndarray, z_vel: np.ndarray, r_vel: float) -> dict:
    a_inv = np.linalg.inv(a)
    e = (r @ a_inv[0]) / a_inv[0, 0]
    var_c = 1.0 / a_inv[0, 0]
    level = np.concatenate([[z_vel[0]], np.cumsum(z_vel)[:-1] / np.arange(1, len(z_vel))])
    d_level = z_vel - level
    keep = slice(int(SKIP_S * names.FRAME_RATE_HZ), None)
    e, d_level = e[keep], d_level[keep]

    def d(c: float) -> float:
        log_level = -0.5 * np.log(2 * np.pi * r_vel) - 0.5 * d_level ** 2 / r_vel
        log_none = -0.5 * np.log(2 * np.pi * c * var_c) - 0.5 * e ** 2 / (c * var_c)
        return float(np.mean(log_level - log_none))

    matched = float(np.mean(e ** 2) / var_c)
    return {"innovation": float(np.sqrt(np.mean(r[keep, 0] ** 2))), "conditional": float(np.sqrt(np.mean(e ** 2))),
            "sigma_c": float(np.sqrt(var_c)), "level": float(np.sqrt(np.mean(d_level ** 2))),
            "d_design": d(1.0), "c": matched, "d_matched": d(matched)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mach", type=float, default=0.4)
    ap.add_argument("--alt-ft", type=float, default=20000.0)
    ap.add_argument("--seeds", default="11,12,13,14")
    ap.add_argument("--flight-s", type=float, default=30.0)
    args = ap.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
    node = node_of(load_bank("scheduled")[2].schedule, args.mach, args.alt_ft)["bank"].hypotheses[0]
    lin = linearize_truth(args.mach, args.alt_ft)
    gust = load_tuning("tuned_gust")
    designs = {"scheduled node": (np.asarray(node.phi), np.asarray(node.bd), np.asarray(node.h), np.asarray(node.k),
                                  np.asarray(node.a))}
    for air in ("light", "none"):
        f = design_bank(args.mach, args.alt_ft, dataclasses.replace(gust, turbulence=air), linearized=lin,
                        hypotheses=(names.NONE,)).filters[0]
        designs[f"tuned_gust, {'calm' if air == 'none' else air}"] = (
            f.model.phi, f.model.bd, f.model.h, f.gains.k, np.asarray(f.gains.a))
    r_vel = float(NOISE_SIGMA[0]) ** 2
    print(f"Mach {args.mach:.2f}, {args.alt_ft:.0f} ft; seeds {seeds}, {args.flight_s:g} s each, the first {SKIP_S:g} s "
          f"dropped; VEL noise sigma {np.sqrt(r_vel):.3f} ft/s")
    print(f"{'NONE designed':>20} {'air':>6} {'innov':>7} {'cond':>7} {'sigma_c':>8} {'level':>7} "
          f"{'d design':>9} {'c':>6} {'d matched':>10}  (ft/s; d in nats a frame)")
    for air in ("light", "none"):
        flights = [fly_closed_loop(args.mach, args.alt_ft, seed=s, turbulence_level=air, duration_s=args.flight_s)
                   for s in seeds]
        for label, (phi, bd, h, k, a) in designs.items():
            rows = [evidence(filter_residuals(phi, bd, h, k, fl.u, fl.z), a, fl.z[:, 0], r_vel) for fl in flights]
            m = {key: float(np.mean([row[key] for row in rows])) for key in rows[0]}
            print(f"{label:>20} {'calm' if air == 'none' else air:>6} {m['innovation']:7.3f} {m['conditional']:7.3f} "
                  f"{m['sigma_c']:8.3f} {m['level']:7.3f} {m['d_design']:+9.3f} {m['c']:6.2f} {m['d_matched']:+10.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
