"""How far the schedule's interpolated trim lies from the truth model's own trim between grid
nodes, where the soak's tour flies (Mach 0.4-0.5, 20,000-24,000 ft).

For each point (MACH:ALT_FT): JSBSim's straight and level trim of the truth model there
(aircraft.trim, the leading-edge flap from its schedule), and the trim the estimator holds
there once its air-data low-pass has settled (``Estimator.schedule`` at the point for
``--frames`` frames; cubic trims where the 4 x 4 stencil is covered, as in flight). Printed:
the layer and the corners blended, and the interpolated z_trim minus JSBSim's z in
units of the NONE filter's residual sigma at the point (sqrt of the diagonal of the blended
A, read as the nearest node's), plus alpha, theta and the stabilator in deg.

    python tools/maneuver/trim_interpolation.py BANK.f16sched [--points 0.45:22000,...] [--cubic on|off]
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.names import SENSORS
from f16mmae.truth import aircraft

DEFAULT_POINTS = ("0.4:20000,0.425:20000,0.45:20000,0.475:20000,0.5:20000,0.4:22000,0.45:22000,"
                  "0.5:22000,0.4:24000,0.45:24000,0.5:24000,0.5:25000")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bank")
    ap.add_argument("--points", default=DEFAULT_POINTS, help="comma-separated MACH:ALT_FT")
    ap.add_argument("--frames", type=int, default=400, help="frames of air data held at the point")
    args = ap.parse_args()
    bank = load_bank(args.bank)[2]
    nodes = bank.schedule["nodes"]
    fdm = aircraft.load_fdm(seed=1, dt_s=1.0 / 128)
    print("point            layer, corners " + " ".join(f"{n:>6}" for n in SENSORS[:4]) +
          "   (interp - JSBSim)/sigma_NONE | d alpha, d theta, d stab (deg)")
    for spec in args.points.split(","):
        mach, alt = (float(v) for v in spec.split(":"))
        est = Estimator(bank, air_data_time_constant_s=0.5)
        for _ in range(args.frames):
            est.schedule(mach, alt)
        cb = est.core_bank
        st = cb.schedule_state
        z_int, u_int = np.asarray(cb.z_trim, float), np.asarray(cb.u_trim, float)
        x_int = np.asarray(st["x_trim"], float)
        near = min(nodes, key=lambda n: (n["mach"] - mach) ** 2 + ((n["alt_ft"] - alt) / 50000.0) ** 2)
        sigma = np.sqrt(np.diag(np.asarray(near["bank"].hypotheses[0].a)))
        t = aircraft.trim(fdm, mach, alt)
        dz = (z_int - np.asarray(t.z, float)) / sigma
        states = list(bank.state_names)
        da = math.degrees(x_int[states.index("alpha_rad")] - t.alpha_rad)
        dth = math.degrees(x_int[states.index("theta_rad")] - t.theta_rad)
        dst = math.degrees(u_int[0] - float(t.u_rad[0]))
        print(f"{mach:.3f}:{alt:<7.0f} L{st['layer']} {len(st['nodes'])} nodes  " +
              " ".join(f"{v:+6.2f}" for v in dz[:4]) + f"   | {da:+.3f}, {dth:+.3f}, {dst:+.3f}")


if __name__ == "__main__":
    main()
