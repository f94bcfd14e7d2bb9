"""The detectability curves: one figure per family (bias, drift, loss), one panel per
component, P(detect) against the failure's size with its 95 % Clopper-Pearson interval as
bars, and P(any failure declared after the onset) beside it (hollow markers) so that
mis-isolation shows as the gap between the two."""
from __future__ import annotations

import math
from pathlib import Path

from ...report.figures import pyplot, save_figure

TITLES = {"bias": "sensor bias (size in multiples of the sensor's noise sigma)",
          "drift": "sensor drift (rate in sigma per second)",
          "loss": "actuator loss of effectiveness (fraction lost)"}

XLABELS = {"bias": "bias (sigma)", "drift": "drift rate (sigma/s)", "loss": "fraction of effectiveness lost"}


def _panel(ax, comp: dict, log_x: bool) -> None:
    pts = [p for p in comp["points"] if p["runs"]]
    x = [p["size"] for p in pts]
    for k, (field, style, label) in enumerate((
            ("detected", dict(fmt="o-", color="C0"), "its hypothesis declared"),
            ("any_declared", dict(fmt="s", mfc="none", color="0.45", ms=5), "any failure declared"))):
        # the two series side by side, a little apart, so that their bars do not hide each other
        xs = [v * 1.06 ** k for v in x] if log_x else [v + 0.012 * k for v in x]
        y = [p[field]["fraction"] for p in pts]
        lo = [p[field]["fraction"] - p[field]["ci95"]["clopper_pearson"][0] for p in pts]
        hi = [p[field]["ci95"]["clopper_pearson"][1] - p[field]["fraction"] for p in pts]
        ax.errorbar(xs, y, yerr=[lo, hi], capsize=3, lw=1.2, label=label, **style)
    if log_x:
        ax.set_xscale("log")
        ax.minorticks_off()
    ax.set_xticks(x)
    ax.set_xticklabels([f"{v:g}" for v in x])
    ax.set_ylim(-0.05, 1.05)
    ax.set_title(comp["component"], fontsize=9)
    ax.grid(alpha=0.3)
    ax.tick_params(labelsize=7)


def family_figure(family: str, fam: dict, runs: int, path: Path) -> Path:
    plt = pyplot()
    comps = fam["components"]
    cols = min(4, len(comps))
    rows = math.ceil(len(comps) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(max(3.1 * cols + 0.4, 6.0), 2.5 * rows + 1.0), squeeze=False,
                             sharey=True)
    for i, comp in enumerate(comps):
        ax = axes[i // cols][i % cols]
        _panel(ax, comp, log_x=family != "loss")
        ax.set_xlabel(XLABELS[family], fontsize=8)
        if i % cols == 0:
            ax.set_ylabel("probability", fontsize=8)
    for j in range(len(comps), rows * cols):
        axes[j // cols][j % cols].set_visible(False)
    axes[0][0].legend(fontsize=7, loc="best")
    fig.suptitle(f"Detection probability against {TITLES[family]}\n{runs} runs per point, "
                 f"bars: 95 % Clopper-Pearson intervals", fontsize=9)
    return save_figure(fig, path)


def curves(out: Path, summary: dict) -> dict:
    """Write ``<family>.png`` per family in the summary; returns {family: file name}."""
    return {family: family_figure(family, fam, summary["runs_per_size"], out / f"{family}.png").name
            for family, fam in summary["families"].items()}
