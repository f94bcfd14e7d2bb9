"""The surface dither's calm-air peaks against the subliminal criterion over dynamic pressure.

Flies the truth model in calm air without noise, the FCS closed and the default dither on
(truth/dither.py ``Dither``: the amplitude schedule and the pairs' high-q̄ rule), for 8 s at each
point, and prints one row per point: q̄ / Q0, each peak's share of its criterion (n_z 0.05 g,
n_y 0.02 g, p, q, r 1 deg/s), the largest, and the pairs' scheduled amplitudes and rate
amplitudes 2 pi f a (stabilators, flaperons) against the rate limits 60 and 80 deg/s.

    .venv/bin/python tools/excitation/surface_dither_shares.py [--mach 0.35,0.4,...] [--alt-ft 10000,20000] [--figure FILE]

With --figure it draws each share against q̄ / Q0.
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from f16mmae.outputs import OutputError, writable_file
from f16mmae.report.figures import pyplot, save_figure
from f16mmae.truth import Scenario, aircraft, fly_raw
from f16mmae.truth.dither import CRITERION, Dither
from f16mmae.truth.fcs import DESIGN_QBAR_PSF

SHARES = ("nz", "ny", "p", "q", "r")


def shares(mach: float, alt_ft: float, duration_s: float = 8.0) -> dict:
    """The peaks' shares of the criterion at one point, q̄ / Q0, and the pairs' amplitudes (deg)
    and rate amplitudes (deg/s); aircraft.TrimError where the F-16 cannot be trimmed."""
    truth, _ = fly_raw(Scenario(mach=mach, alt_ft=alt_ft, duration_s=duration_s, noise=False, feedback="raw"))
    peak = np.abs(truth.truth_log["z_ideal"] - truth.trim.z).max(axis=0)   # VEL AOA PIT AZ ROL YAW AY
    rate = CRITERION["rate_deg_s"]
    row = {"nz": peak[3] / CRITERION["nz_g"], "ny": peak[6] / CRITERION["ny_g"],
           "p": math.degrees(peak[4]) / rate, "q": math.degrees(peak[2]) / rate, "r": math.degrees(peak[5]) / rate}
    a, w, _ = Dither(scale=DESIGN_QBAR_PSF / truth.trim.qbar_psf).terms()
    return {"qbar_ratio": truth.trim.qbar_psf / DESIGN_QBAR_PSF, **row, "largest": max(row.values()),
            "amplitude_deg": (math.degrees(a[0]), math.degrees(a[2])),
            "rate_deg_s": (math.degrees(a[0] * w[0]), math.degrees(a[2] * w[2]))}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--mach", default="0.35,0.38,0.4,0.42,0.44,0.46,0.48,0.5,0.53,0.56",
                   help="comma-separated Mach numbers (default: %(default)s)")
    p.add_argument("--alt-ft", default="10000,20000", help="comma-separated altitudes, ft (default: %(default)s)")
    p.add_argument("--figure", default=None, metavar="FILE", help="draw the shares against q̄ / Q0 into FILE (.png)")
    args = p.parse_args(argv)
    try:
        machs = [float(x) for x in args.mach.split(",")]
        alts = [float(x) for x in args.alt_ft.split(",")]
    except ValueError as e:
        p.error(f"--mach and --alt-ft take comma-separated numbers: {e}")
    for mach in machs:   # the truth's flight envelope, before any flight
        for alt in alts:
            try:
                aircraft.check_flight_condition(mach, alt)
            except ValueError as exc:
                p.error(f"--mach {mach:g} --alt-ft {alt:g}: {exc}")
    if args.figure:   # checked before the flights
        try:
            args.figure = writable_file(args.figure, "--figure")
        except OutputError as exc:
            p.error(str(exc))
    print("| Mach / alt (ft) | q̄ / Q0 | n_z | n_y | p | q | r | largest | amplitude stab / flap (deg) | rate amplitude stab / flap (deg/s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for alt in alts:
        for mach in machs:
            try:
                r = shares(mach, alt)
            except aircraft.TrimError as exc:
                print(f"| {mach:g} / {alt:,.0f} | cannot be trimmed: {exc} |", flush=True)
                continue
            rows.append(r)
            print(f"| {mach:g} / {alt:,.0f} | {r['qbar_ratio']:.2f} | " + " | ".join(f"{r[k]:.2f}" for k in SHARES)
                  + f" | {r['largest']:.2f} | {r['amplitude_deg'][0]:.2f} / {r['amplitude_deg'][1]:.2f} | "
                  f"{r['rate_deg_s'][0]:.0f} / {r['rate_deg_s'][1]:.0f} |", flush=True)
    if args.figure:
        fig, ax = pyplot().subplots(figsize=(7.5, 4.2))
        rows.sort(key=lambda r: r["qbar_ratio"])
        x = [r["qbar_ratio"] for r in rows]
        for k in SHARES:
            ax.plot(x, [r[k] for r in rows], marker="o", ms=3, label=k)
        ax.axhline(1.0, color="k", lw=0.8)
        ax.set_xlabel("q̄ / Q0 (Q0 = 109 psf, the design point)")
        ax.set_ylabel("calm-air peak / criterion")
        ax.set_title("Surface dither against the subliminal criterion")
        ax.set_ylim(0.0, 1.05)
        ax.legend(ncol=5, fontsize=8, loc="lower left")
        ax.grid(alpha=0.3)
        print(f"wrote {save_figure(fig, args.figure)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
