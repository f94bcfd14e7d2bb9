"""Detection latency against dynamic pressure, from finished envelope campaigns.

Reads each campaign's ``runs.jsonl`` and, for the hypotheses named (default the four pairs'
surfaces), prints the median latency of the correct runs and the correct fraction per band of
q̄ / Q0 (Q0 = 109 psf, the design point), one column per campaign; q̄ is the point's, from
its Mach and pressure altitude (the envelope campaign's ``dynamic_pressure_psf``).

    .venv/bin/python tools/excitation/latency_by_qbar.py DIR_A DIR_B [--labels A,B] [--cases LF,RF] [--figure FILE]

With --figure it draws the medians per band, one line per campaign and case.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from f16mmae.campaign.envelope.points import dynamic_pressure_psf
from f16mmae.outputs import OutputError, writable_file
from f16mmae.report.figures import pyplot, save_figure
from f16mmae.truth.fcs import DESIGN_QBAR_PSF

#: The bands' edges in q̄ / Q0.
EDGES = (0.0, 0.75, 1.1, 1.5, 2.0, 3.0, 5.0, 10.0)


def bands(directory: Path, cases: list[str]) -> dict[str, list[tuple[int, int, float]]]:
    """Per case: (correct, runs, median latency of the correct runs) per band of EDGES; ValueError
    naming the line for a record that is not a run of a campaign."""
    out = {c: [[0, 0, []] for _ in EDGES[:-1]] for c in cases}
    with open(directory / "runs.jsonl") as f:
        for n, line in enumerate(f, 1):
            try:
                r = json.loads(line)
                case, mach, alt_ft, outcome = r["case"], r["scenario"]["mach"], r["scenario"]["alt_ft"], r["outcome"]
            except (ValueError, KeyError, TypeError) as exc:
                raise ValueError(f"{directory / 'runs.jsonl'} line {n} is not a run record ({exc!r})") from None
            if case not in out:
                continue
            x = dynamic_pressure_psf(mach, alt_ft) / DESIGN_QBAR_PSF
            i = int(np.searchsorted(EDGES, x, side="right")) - 1
            if not 0 <= i < len(EDGES) - 1:
                continue
            cell = out[r["case"]][i]
            cell[1] += 1
            if outcome == "correct":
                cell[0] += 1
                cell[2].append(r["latency_s"])
    return {c: [(k, n, float(np.median(v)) if v else float("nan")) for k, n, v in rows] for c, rows in out.items()}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dirs", nargs="+", type=Path, help="finished envelope campaign directories")
    p.add_argument("--labels", default=None, help="comma-separated labels, one per directory (default: the names)")
    p.add_argument("--cases", default="LS,RS,LF,RF", help="comma-separated hypotheses (default: %(default)s)")
    p.add_argument("--figure", default=None, metavar="FILE", help="draw the medians per band into FILE (.png)")
    args = p.parse_args(argv)
    labels = args.labels.split(",") if args.labels else [d.name for d in args.dirs]
    if len(labels) != len(args.dirs):
        p.error(f"--labels names {len(labels)} campaigns, {len(args.dirs)} directories given")
    for d in args.dirs:
        if not (d / "runs.jsonl").is_file():
            p.error(f"{d}: no runs.jsonl (not a finished campaign directory)")
    cases = [c.strip() for c in args.cases.split(",") if c.strip()]
    if args.figure:   # checked before the work
        try:
            args.figure = writable_file(args.figure, "--figure")
        except OutputError as exc:
            p.error(str(exc))
    try:
        data = [bands(d, cases) for d in args.dirs]
    except ValueError as exc:
        p.error(str(exc))
    names = [f"{a:g}-{b:g}" for a, b in zip(EDGES[:-1], EDGES[1:])]
    print("| case | q̄ / Q0 | " + " | ".join(f"{lab}: correct, median (s)" for lab in labels) + " |")
    print("|---|---|" + "---|" * len(labels))
    for c in cases:
        for i, name in enumerate(names):
            cells = [dat[c][i] for dat in data]
            if all(n == 0 for _, n, _ in cells):
                continue
            print(f"| {c} | {name} | " + " | ".join(f"{k}/{n}, {m:.2f}" if n else "-" for k, n, m in cells) + " |")
    if args.figure:
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(7.5, 4.2))
        mids = [0.5 * (a + b) if b < 10 else a + 1.0 for a, b in zip(EDGES[:-1], EDGES[1:])]
        styles = ["--", "-", ":", "-."]
        colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        for j, (lab, dat) in enumerate(zip(labels, data)):
            for k, c in enumerate(cases):
                xs = [m for m, (_, n, _) in zip(mids, dat[c]) if n]
                ys = [v for _, n, v in dat[c] if n]
                ax.plot(xs, ys, styles[j % len(styles)], color=colours[k % len(colours)], marker="o", ms=3,
                        label=f"{c} ({lab})")
        ax.set_xlabel("q̄ / Q0 (band middles; Q0 = 109 psf, the design point)")
        ax.set_ylabel("median latency of the correct runs (s)")
        ax.set_title("Detection latency against dynamic pressure")
        ax.legend(ncol=2, fontsize=7)
        ax.grid(alpha=0.3)
        print(f"wrote {save_figure(fig, args.figure)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
