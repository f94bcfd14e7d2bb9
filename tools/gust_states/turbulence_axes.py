"""The heading of JSBSim's turbulence axes at each grid point: the one the trimmed initial
condition's round-off mean wind gives (what every flight flew before ``turbulence.hold_axes``)
and the one a flight now starts with.

JSBSim turns its Dryden gusts by the mean wind's heading ``atmosphere/psiw-rad``, recomputed as
atan2(east, north) whenever the wind's north component is not zero; after ``run_ic`` the
trimmed aircraft's mean wind is a round-off of about 1e-12 ft/s whose sign varies from one
flight condition to the next (truth/turbulence.py).  Prints one row per altitude, one column per
Mach: the round-off heading / the heading after ``aircraft.restart`` (``0`` or ``pi``).

    .venv/bin/python tools/gust_states/turbulence_axes.py [--grid mach=...,alt=...] [--figure FILE]

With --figure it draws the grid, each point marked by the round-off heading.
"""
from __future__ import annotations

import argparse
import math

from f16mmae.design.schedule import DEFAULT_GRID, parse_grid
from f16mmae.names import SIM_RATE_HZ
from f16mmae.truth import aircraft, turbulence


def headings(mach: float, alt_ft: float) -> tuple[float, float] | None:
    """(round-off heading, heading after restart) in rad, or None where the F-16 cannot be trimmed."""
    fdm = aircraft.load_fdm(seed=1, dt_s=1.0 / SIM_RATE_HZ, cxx=True)
    try:
        trim = aircraft.trim(fdm, mach, alt_ft)
    except aircraft.TrimError:
        return None
    start = aircraft.start_state(fdm)
    fdm.run_ic()
    north, east = fdm["atmosphere/wind-north-fps"], fdm["atmosphere/wind-east-fps"]
    before = math.atan2(east, north) if north != 0.0 else 0.0
    aircraft.restart(fdm, trim, start, 1)
    turbulence.apply(fdm, "light")
    fdm.run()
    return before, fdm["atmosphere/psiw-rad"]


def label(psi: float) -> str:
    """0 or pi where the heading is one of them (either sign, modulo 2 pi), else its value."""
    folded = abs(math.remainder(psi, 2 * math.pi))
    return "0" if folded < 1e-9 else "pi" if abs(folded - math.pi) < 1e-9 else f"{psi:.3f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--grid", default=DEFAULT_GRID)
    ap.add_argument("--figure", metavar="FILE", help="draw the round-off headings over the grid")
    args = ap.parse_args()
    grid = parse_grid(args.grid)
    found = {}
    print("alt_ft  " + "  ".join(f"Mach {m:<7.2f}" for m in grid.mach))
    for alt in grid.alt_ft:
        cells = []
        for mach in grid.mach:
            h = found[(mach, alt)] = headings(mach, alt)
            cells.append("-" if h is None else f"{label(h[0])} / {label(h[1])}")
        print(f"{alt:6.0f}  " + "  ".join(f"{c:<12}" for c in cells))
    if args.figure:
        draw(found, args.figure)


def draw(found: dict, path: str) -> None:
    """The grid points marked by the round-off heading: 0 (open circles) or pi (filled)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 4.2))
    for name, marker, fill in (("0", "o", "none"), ("pi", "o", "tab:blue")):
        pts = [(m, a) for (m, a), h in found.items() if h is not None and label(h[0]) == name]
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=70, marker=marker, facecolors=fill,
                   edgecolors="tab:blue", label=f"heading {name} ({len(pts)} points)")
    gone = [k for k, h in found.items() if h is None]
    ax.scatter([p[0] for p in gone], [p[1] for p in gone], marker="x", color="grey", label="not trimmable")
    ax.set_xlabel("Mach")
    ax.set_ylabel("pressure altitude (ft)")
    ax.set_title("JSBSim's turbulence axes from the trim's round-off wind\n(every flight now at pi)", fontsize=10)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"figure: {path}")


if __name__ == "__main__":
    main()
