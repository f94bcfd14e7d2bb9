"""Lab driver (not in the wheel): how far the scheduled bank's trims are from the aircraft's, where
the grid misses a corner.

    python tools/schedule/trim_errors.py                          # scan the low-speed corner
    python tools/schedule/trim_errors.py --points 0.3453:26582,0.37:33000
    python tools/schedule/trim_errors.py --bank FILE --mach 0.30:0.42:0.01 --alt-ft 24000:35000:1000

For each air-data point the truth model trims (``f16mmae.truth.aircraft.trimmed_fdm``), the
scheduled trims in force at that air data (``core.HierarchicalBank.schedule``, no low-pass
left: three selections at the point) as the schedule had them before round 37 (``plane_trims``,
``row_trims``, ``lift_trims`` and ``stabilator_trims`` off: the nearest covered node's trims in a
cell's uncovered half, bilinear where no 4 x 4 stencil is covered) and as it has them now (the
defaults: the covered triangle's plane, the neighbours' planes where a cell misses more corners,
row by row, linear trims in the lift coordinate, past the trimmable edge the stabilators along the
edge's trim alpha; cpp/f16mmae/scheduled_filters.h), and the truth's trim
minus each: VEL (ft/s), AOA (rad), AZ (g) and the left stabilator (rad). A scan (``--mach``, ``--alt-ft``:
START:STOP:STEP) lists only the points whose trims changed (docs/results/envelope_scheduled.md,
rounds 37 to 39); ``--points`` lists the points given.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import statistics

import numpy as np

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.errors import F16mmaeError
from f16mmae.truth import aircraft


def _range(text: str) -> list[float]:
    try:
        start, stop, step = (float(x) for x in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected START:STOP:STEP, got {text!r}") from None
    if not step > 0 or stop < start:
        raise argparse.ArgumentTypeError(f"expected STOP >= START and STEP > 0, got {text!r}")
    return [round(float(v), 6) for v in np.arange(start, stop + step / 2, step)]


def _points(text: str) -> list[tuple[float, float]]:
    try:
        return [(float(m), float(h)) for m, h in (p.split(":") for p in text.split(","))]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected MACH:ALT_FT[,MACH:ALT_FT...], got {text!r}") from None


def scheduled_trims(bank, mach: float, alt_ft: float) -> tuple[np.ndarray, np.ndarray]:
    """(z_trim, u_trim) in force at the air data (mach, alt_ft)."""
    bank.reset()
    for _ in range(3):
        bank.schedule(mach, alt_ft)
    return np.asarray(bank.z_trim), np.asarray(bank.u_trim)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bank", default="scheduled", help="a scheduled bank (default: the shipped schedule)")
    parser.add_argument("--points", type=_points, help="MACH:ALT_FT[,...]: these points, scanned or not")
    parser.add_argument("--mach", type=_range, default=_range("0.30:0.42:0.01"), help="scan: START:STOP:STEP")
    parser.add_argument("--alt-ft", type=_range, default=_range("24000:35000:1000"), help="scan: START:STOP:STEP")
    args = parser.parse_args()
    _, _, model = load_bank(args.bank)
    if not model.schedule:
        parser.error(f"--bank {args.bank}: not a scheduled bank")
    before = core.HierarchicalBank(model, plane_trims=False, row_trims=False, lift_trims=False,
                                   stabilator_trims=False)
    now = core.HierarchicalBank(model)
    points = args.points or [(m, h) for m in args.mach for h in args.alt_ft]
    cols = ((0, "VEL ft/s"), (1, "AOA rad"), (3, "AZ g"))
    print(f"{'point':>14}  " + "  ".join(f"{name:>17}" for _, name in cols) + f"  {'LS rad':>17}   (before -> now)")
    errors = {name: ([], []) for _, name in (*cols, (None, "LS rad"))}
    for mach, alt_ft in points:
        try:
            with contextlib.redirect_stdout(io.StringIO()):   # JSBSim's trim chatter
                _, trim = aircraft.trimmed_fdm(mach, alt_ft)
        except (F16mmaeError, ValueError, RuntimeError):
            continue   # the truth does not trim here
        z0, u0 = scheduled_trims(before, mach, alt_ft)
        z1, u1 = scheduled_trims(now, mach, alt_ft)
        if args.points is None and np.allclose(z0, z1, rtol=0, atol=1e-9) and np.allclose(u0, u1, rtol=0, atol=1e-9):
            continue   # the same trims
        dz0, dz1 = trim.z - z0, trim.z - z1
        cells = [f"{dz0[j]:+8.4f} -> {dz1[j]:+8.4f}" if j else f"{dz0[j]:+8.2f} -> {dz1[j]:+8.2f}" for j, _ in cols]
        ls = f"{trim.u_rad[0] - u0[0]:+8.4f} -> {trim.u_rad[0] - u1[0]:+8.4f}"
        print(f"{mach:.4f}:{alt_ft:<7.0f}  " + "  ".join(cells) + f"  {ls}")
        for j, name in cols:
            errors[name][0].append(abs(dz0[j]))
            errors[name][1].append(abs(dz1[j]))
        errors["LS rad"][0].append(abs(trim.u_rad[0] - u0[0]))
        errors["LS rad"][1].append(abs(trim.u_rad[0] - u1[0]))
    n = len(errors["VEL ft/s"][0])
    print(f"{n} points")
    for name, (e0, e1) in errors.items():
        if e0:
            print(f"  |{name}|: median {statistics.median(e0):.4g} -> {statistics.median(e1):.4g}, "
                  f"largest {max(e0):.4g} -> {max(e1):.4g}")


if __name__ == "__main__":
    main()
