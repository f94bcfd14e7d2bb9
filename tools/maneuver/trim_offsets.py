"""What a steady climb changes in the trim the estimator assumes, at a few schedule nodes.

For each node: JSBSim trims in straight flight at flight-path angles gamma = 0 and +-G deg
(the truth model's own trim, with the flight-path angle set), and the linear model's climb
trim of the node's NONE filter (cpp/f16mmae/maneuver_trim.h, ``core.maneuver_trim_sensitivities``)
times gamma. Printed per node: the change of angle of attack, pitch attitude, stabilator,
throttle and of the measurements z (VEL AOA PIT AZ ROL YAW AY) in units of the NONE filter's
residual sigma (sqrt of the diagonal of its residual covariance A), JSBSim's and the linear
model's; and the thrust acceleration the linear climb trim needs (g sin gamma to first order).

    python tools/maneuver/trim_offsets.py BANK.f16sched [--gamma-deg 3] [--nodes 0.4:20000,0.6:30000]
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from f16mmae import core
from f16mmae.names import SENSORS
from f16mmae.truth import aircraft


def jsbsim_trim(mach: float, alt_ft: float, gamma_deg: float) -> dict:
    """The truth model's trim at (mach, alt_ft) in straight flight at flight-path angle gamma_deg
    (aircraft.trim; the leading-edge flap from its schedule)."""
    t = aircraft.trim(aircraft.load_fdm(seed=1, dt_s=1.0 / 128), mach, alt_ft, gamma_deg=gamma_deg)
    return {"alpha": t.alpha_rad, "theta": t.theta_rad, "de": float(t.u_rad[0]), "throttle": t.throttle,
            "z": np.asarray(t.z, float)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bank")
    ap.add_argument("--gamma-deg", type=float, default=3.0)
    ap.add_argument("--nodes", default="0.4:20000,0.3:10000,0.6:30000",
                    help="comma-separated MACH:ALT_FT of schedule nodes")
    args = ap.parse_args()
    bank = core.load_bank(args.bank)
    sens = core.maneuver_trim_sensitivities(bank)
    nodes = bank.schedule["nodes"] if bank.schedule else None
    g = math.radians(args.gamma_deg)
    states = list(bank.state_names)
    ia, it = states.index("alpha_rad"), states.index("theta_rad")
    for spec in args.nodes.split(","):
        mach, alt = (float(v) for v in spec.split(":"))
        k = next(i for i, s in enumerate(sens) if abs(s["mach"] - mach) < 1e-9 and abs(s["alt_ft"] - alt) < 1e-6)
        node_bank = nodes[k]["bank"] if nodes else bank
        a = np.asarray(node_bank.hypotheses[0].a)
        sigma = np.sqrt(np.diag(a))
        t0 = jsbsim_trim(mach, alt, 0.0)
        print(f"node Mach {mach}, {alt:.0f} ft; residual sigma of NONE: " +
              ", ".join(f"{n} {s:.3g}" for n, s in zip(SENSORS, sigma)))
        for sign in (1.0, -1.0):
            tg = jsbsim_trim(mach, alt, sign * args.gamma_deg)
            s = sens[k]
            lin_x = np.asarray(s["x"])[:, 0] * sign * g
            lin_u = np.asarray(s["u"])[:, 0] * sign * g
            lin_z = np.asarray(s["z"])[:, 0] * sign * g
            dz = tg["z"] - t0["z"]
            print(f"  gamma {sign * args.gamma_deg:+.1f} deg: d alpha JSBSim {math.degrees(tg['alpha'] - t0['alpha']):+.3f} "
                  f"linear {math.degrees(lin_x[ia]):+.3f} deg; d theta JSBSim "
                  f"{math.degrees(tg['theta'] - t0['theta']):+.3f} linear {math.degrees(lin_x[it]):+.3f} deg; "
                  f"d stabilator JSBSim {math.degrees(tg['de'] - t0['de']):+.3f} linear {math.degrees(lin_u[0]):+.3f} deg; "
                  f"d throttle JSBSim {tg['throttle'] - t0['throttle']:+.3f}; linear thrust "
                  f"{s['thrust'][0] * sign * g:+.2f} ft/s^2 (g sin gamma {32.174 * math.sin(sign * g):+.2f})")
            print("    dz / sigma JSBSim: " + ", ".join(f"{n} {v:+.2f}" for n, v in zip(SENSORS, dz / sigma)))
            print("    dz / sigma linear: " + ", ".join(f"{n} {v:+.2f}" for n, v in zip(SENSORS, lin_z / sigma)))
        s = sens[k]
        print(f"  per 1 ft/s^2 of acceleration: d alpha {math.degrees(np.asarray(s['x'])[ia, 1]):+.4f} deg, "
              f"d stabilator {math.degrees(np.asarray(s['u'])[0, 1]):+.4f} deg, thrust {s['thrust'][1]:+.3f} ft/s^2; "
              "dz / sigma: " + ", ".join(f"{n} {v:+.3f}" for n, v in zip(SENSORS, np.asarray(s['z'])[:, 1] / sigma)))


if __name__ == "__main__":
    main()
