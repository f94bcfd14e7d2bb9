"""The maneuver campaign's figures, from its summary and run records.

``maneuver_map.png``: one panel per maneuver, the flight points on Mach-altitude axes coloured
by their correct fraction (red 0 - green 1), each labelled with its false-alarm runs.
``maneuver_strips.png``: probability strips -- per maneuver (panel) and failure case (row),
the mean over its runs and points of the injected hypothesis's probability against time
(white 0 - black 1), with the maneuver's start and the failure time marked.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ...names import NONE
from ...report.figures import pyplot

MAP_FILE = "maneuver_map.png"
STRIPS_FILE = "maneuver_strips.png"


def maneuver_map(summary: dict, path: Path) -> Path:
    plt = pyplot()
    ms = summary["maneuvers"]
    fig, axes = plt.subplots(1, len(ms), figsize=(3.6 * len(ms) + 1.0, 3.8), squeeze=False, sharey=True,
                             layout="constrained")
    cmap = plt.get_cmap("RdYlGn")
    for ax, m in zip(axes[0], ms):
        cells = [c for c in summary["by_point"] if c["maneuver"] == m]
        for c in cells:
            frac = c["correct_fraction"]
            ax.scatter([c["mach"]], [c["alt_ft"]], s=110, c=[cmap(frac if frac is not None else 0.0)],
                       marker="o" if c["false_alarm_runs"] == 0 else "X", edgecolors="k", zorder=3)
            ax.annotate(f"{c['point']} FA {c['false_alarm_runs']}", (c["mach"], c["alt_ft"]), fontsize=6,
                        textcoords="offset points", xytext=(0, 8), ha="center")
        ax.set_xlim(0.28, 0.82)
        ax.set_ylim(3000, 37000)
        ax.set_title(m, fontsize=9)
        ax.set_xlabel("Mach")
        ax.grid(True, alpha=0.25)
    axes[0, 0].set_ylabel("start altitude (ft)")
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0.0, 1.0))
    fig.colorbar(sm, ax=list(axes[0]), label="correct fraction (failure cases)", shrink=0.9)
    fig.suptitle(f"{summary['tuning']} bank, failure at {summary['failure_time_s']:g} s into a maneuver begun at "
                 f"{summary['maneuver_time_s']:g} s; o: no false-alarm run, X: some", fontsize=9)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def strips(summary: dict, records: list[dict], path: Path) -> Path:
    plt = pyplot()
    ms = summary["maneuvers"]
    cases = [c for c in summary["cases"] if c != NONE]
    fig, axes = plt.subplots(1, len(ms), figsize=(3.4 * len(ms) + 0.8, 1.8 + 0.28 * max(len(cases), 1)),
                             squeeze=False, sharey=True, layout="constrained")
    for ax, m in zip(axes[0], ms):
        rows, dt = [], None
        for c in cases:
            ps = [r["p_injected"] for r in records if r["maneuver"] == m and r["case"] == c]
            dt = next((r["p_injected_dt_s"] for r in records if r["maneuver"] == m), dt)
            n = min((len(p) for p in ps), default=0)
            rows.append(np.mean([p[:n] for p in ps], axis=0) if n else np.zeros(1))
        width = max(len(r) for r in rows)
        img = np.full((len(rows), width), np.nan)
        for i, r in enumerate(rows):
            img[i, : len(r)] = r
        span = (dt or 1.0) * width
        ax.imshow(img, aspect="auto", cmap="Greys", vmin=0.0, vmax=1.0, interpolation="nearest",
                  extent=(0.0, span, len(rows) - 0.5, -0.5))
        for t, style in ((summary["maneuver_time_s"], ":"), (summary["failure_time_s"], "--")):
            ax.axvline(t, color="tab:red", ls=style, lw=1)
        ax.set_title(m, fontsize=9)
        ax.set_xlabel("time (s)")
    axes[0, 0].set_yticks(range(len(cases)), cases, fontsize=7)
    fig.suptitle("mean probability of the injected failure (white 0, black 1); dotted: maneuver begins, "
                 "dashed: failure", fontsize=8)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def make_figures(out: Path, summary: dict, records: list[dict]) -> dict:
    """Both figures beside summary.json; returns their file names."""
    if not summary["by_point"]:
        return {}
    out_figs = {"map": maneuver_map(summary, Path(out) / MAP_FILE).name}
    if any(c != NONE for c in summary["cases"]):
        out_figs["strips"] = strips(summary, records, Path(out) / STRIPS_FILE).name
    return out_figs
