"""Figures of the off-nominal campaign, from its ``summary.json`` (paper Fig. 9).

* ``envelope_map``: the points on Mach (x) vs altitude (y) axes, each filled by its correct
  fraction over the failure cases (red 0 .. green 1), a circle when acceptable and a cross
  when not, annotated with its number and its false-alarm runs; lines of constant dynamic
  pressure q̄ = 0.7 p(h) M^2 (ISA, :mod:`.points`) at steps of 5 % (local view) or
  10 % (wide view) of the design point's q̄, the one through the design point drawn bold --
  the paper's axis of constant q̄ (points 9, 12, NOM, 17, 19).  When the points reach far
  beyond the local envelope (the extrema 21-24), a second panel zooms on the local points.
* ``case_table``: a heat map of the correct fraction per point (rows, highest q̄ on top)
  and case (columns: NONE, then the failures), each cell annotated ``correct/runs`` and
  ``FA n`` when it has false-alarm runs, row labels green (acceptable) or red (not) -- which
  failures break first off nominal.
* ``compare_maps``: two (or more) campaigns' maps side by side on the same axes -- e.g. the
  unscheduled nominal bank and a scheduled bank flown over the same points
  (``f16mmae campaign envelope --compare DIR_A,DIR_B``), each panel titled by its bank and, below,
  by the estimator settings in which the campaigns differ (``settings_differences``): two
  settings of one bank are told apart by them.

matplotlib with the non-interactive Agg backend (``report.figures.pyplot``).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ...report.drawing import deferrable
from ...report.figures import pyplot
from .points import GAMMA_AIR, TROPOPAUSE_FT, pressure_psf

MAP_FILE = "envelope_map.png"
COMPARE_FILE = "envelope_compare.png"
TABLE_FILE = "envelope_cases.png"


def _limits(points, pad_frac=0.12, min_mach=0.01, min_alt=1000.0):
    m = np.array([p["mach"] for p in points])
    h = np.array([p["alt_ft"] for p in points])
    dm = max(m.max() - m.min(), min_mach)
    dh = max(h.max() - h.min(), min_alt)
    return ((m.min() - pad_frac * dm, m.max() + pad_frac * dm),  # q̄ is drawn in the troposphere only
            (max(h.min() - pad_frac * dh, 0.0), min(h.max() + pad_frac * dh, TROPOPAUSE_FT)))


def _panel(ax, points, design, cmap, step, annotate=None, limits=None):
    (x0, x1), (y0, y1) = limits or _limits(points)
    mach, alt = np.linspace(x0, x1, 120), np.linspace(y0, y1, 120)
    mm, hh = np.meshgrid(mach, alt)
    # dynamic_pressure_psf on the grid, the ISA pressure once per altitude row: the same
    # products in the same order, so the same values
    qq = 0.5 * GAMMA_AIR * np.array([pressure_psf(h) for h in alt])[:, None] * mm * mm
    q_nom = design["qbar_psf"]
    ks = np.arange(-12, 13)
    levels = sorted({round(q_nom * (1 + k * step), 6) for k in ks if k != 0 and q_nom * (1 + k * step) > 0})
    cs = ax.contour(mm, hh, qq, levels=levels, colors="0.6", linewidths=0.7)
    ax.clabel(cs, fmt="%.0f", fontsize=7)
    cn = ax.contour(mm, hh, qq, levels=[q_nom], colors="k", linewidths=1.6, linestyles="--")
    h_lab = y0 + 0.12 * (y1 - y0)  # label the design q̄ line near the bottom, clear of the points
    m_lab = float(np.sqrt(q_nom / (0.5 * GAMMA_AIR * pressure_psf(h_lab))))
    where = [(m_lab, h_lab)] if x0 < m_lab < x1 else None
    ax.clabel(cn, fmt=lambda v: f"q̄ {v:.0f} (design)", fontsize=7, manual=where)
    for p in points:
        frac = p["correct_fraction"]
        color = "0.7" if frac is None else cmap(frac)
        marker = "o" if p["acceptable"] else "X"
        ax.scatter([p["mach"]], [p["alt_ft"]], s=190, c=[color], marker=marker,
                   edgecolors="k", linewidths=1.0, zorder=3)
        if annotate is not None and p["label"] not in annotate:
            continue
        ax.annotate(f"{p['label']}\nFA {p['false_alarm_runs']}", (p["mach"], p["alt_ft"]),
                    textcoords="offset points", xytext=(0, 10), ha="center", va="bottom",
                    fontsize=7, zorder=4)
    ax.scatter([design["mach"]], [design["alt_ft"]], s=420, marker="*", facecolors="none",
               edgecolors="k", linewidths=1.0, zorder=2)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_xlabel("Mach")
    ax.set_ylabel("altitude (ft)")
    ax.grid(True, alpha=0.25)


@deferrable(lambda a: Path(a["path"]), alone=True)
def envelope_map(summary: dict, path: Path) -> Path:
    """The Fig. 9-style map of ``summary["points"]`` (module docstring)."""
    plt = pyplot()
    from matplotlib.lines import Line2D

    points = summary["points"]
    design = summary["design_point"]
    local = [p for p in points if p["group"] in ("nominal", "local")]
    panels = [(points, "all points", 0.10, None)]
    if len(local) >= 2 and len(local) < len(points):  # zoom on the local points, named there
        far = {p["label"] for p in points if p not in local}
        panels = [(points, "all points", 0.10, far), (local, "local envelope", 0.05, None)]
    cmap = plt.get_cmap("RdYlGn")
    fig, axes = plt.subplots(1, len(panels), figsize=(6.2 * len(panels) + 1.2, 6.2), squeeze=False,
                             layout="constrained")
    for ax, (pts, title, step, named) in zip(axes[0], panels):
        _panel(ax, pts, design, cmap, step, named)
        ax.set_title(f"{title}: iso-q̄ lines every {step:.0%} of the design q̄ (lbf/ft²)", fontsize=9)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0.0, 1.0))
    fig.colorbar(sm, ax=list(axes[0]), label="correct fraction (failure cases)", shrink=0.9)
    rule = summary["acceptable_rule"]
    handles = [
        Line2D([], [], marker="o", ls="", mfc="w", mec="k", ms=9,
               label=f"acceptable (>= {rule['correct_fraction_min']:.0%} correct, "
                     f"<= {rule['false_alarm_runs_max']} false-alarm runs)"),
        Line2D([], [], marker="X", ls="", mfc="w", mec="k", ms=9, label="not acceptable"),
        Line2D([], [], marker="*", ls="", mfc="none", mec="k", ms=13, label="design point"),
        Line2D([], [], color="k", ls="--", label="constant q̄ through the design point"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=2 if len(panels) == 1 else 4, fontsize=8)
    fig.suptitle(f"{summary['tuning']} bank (designed at Mach {design['mach']:g}, "
                 f"{design['alt_ft']:.0f} ft) flown off design:\n{summary['runs_per_case']} run(s) "
                 f"x {len(summary['cases'])} cases per point, {summary['turbulence']} turbulence",
                 fontsize=10)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


@deferrable(lambda a: Path(a["path"]), alone=True)
def case_table(summary: dict, path: Path) -> Path:
    """Heat map of the correct fraction per point and case (module docstring)."""
    plt = pyplot()
    points = sorted(summary["points"], key=lambda p: -p["qbar_psf"])
    cases = summary["cases"]
    frac = np.full((len(points), len(cases)), np.nan)
    for i, p in enumerate(points):
        for j, c in enumerate(p["cases"]):
            if c["runs"]:
                frac[i, j] = c["correct"] / c["runs"]
    fig, ax = plt.subplots(figsize=(3.2 + 0.62 * len(cases), 1.4 + 0.34 * len(points)))
    ax.imshow(np.ma.masked_invalid(frac), cmap="RdYlGn", vmin=0.0, vmax=1.0, aspect="auto")
    for i, p in enumerate(points):
        for j, c in enumerate(p["cases"]):
            text = f"{c['correct']}/{c['runs']}"
            if c["false_alarms"]:
                text += f"\nFA {c['false_alarms']}"
            ax.text(j, i, text, ha="center", va="center", fontsize=6)
    ax.set_xticks(range(len(cases)), cases, fontsize=8)
    ax.xaxis.tick_top()
    ax.set_yticks(range(len(points)),
                  [f"{p['label']:>3}  M {p['mach']:.3f}  {p['alt_ft']:5.0f} ft  q̄ {p['qbar_psf']:5.1f}"
                   for p in points], fontsize=7, family="monospace")
    for tick, p in zip(ax.get_yticklabels(), points):
        tick.set_color("tab:green" if p["acceptable"] else "tab:red")
    ax.set_title("correct runs per point and case (rows by q̄, lbf/ft²; label green = acceptable)",
                 fontsize=9, pad=22)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def make_figures(out: Path, summary: dict) -> dict:
    """Both figures beside summary.json; returns their file names."""
    if not summary["points"]:
        return {}
    return {"map": envelope_map(summary, Path(out) / MAP_FILE).name,
            "cases": case_table(summary, Path(out) / TABLE_FILE).name}


def settings_differences(summaries: list[dict], width: int = 80, max_lines: int = 3) -> list[str]:
    """Per summary, the estimator settings (``estimator_settings``, else the options given,
    ``estimator``) in which the summaries differ, as ``name=value`` in name order, wrapped to
    lines of at most ``width`` characters; ``-`` for a setting a summary does not carry, ``""``
    for a summary where nothing differs. A panel title stays readable: an item longer than a
    line is cut to ``width`` characters ending in ``...``, and beyond ``max_lines`` lines the
    last line says how many more settings differ."""
    settings = [s.get("estimator_settings") or s.get("estimator") or {} for s in summaries]
    names = sorted({k for d in settings for k in d if len({repr(e.get(k, "-")) for e in settings}) > 1})
    out = []
    for d in settings:
        lines: list[list[str]] = []
        for item in (f"{k}={d.get(k, '-')}" for k in names):
            if len(item) > width:
                item = item[:width - 3] + "..."
            if lines and len(", ".join(lines[-1] + [item])) <= width:
                lines[-1].append(item)
            else:
                lines.append([item])
        if len(lines) > max_lines:
            kept = lines[:max_lines - 1]
            lines = kept + [[f"... and {len(names) - sum(map(len, kept))} more settings"]]
        out.append("\n".join(", ".join(line) for line in lines))
    return out


def compare_maps(summaries: list[dict], path: Path) -> Path:
    """The maps of several envelope summaries side by side, on the axes of all their points."""
    plt = pyplot()
    limits = _limits([p for s in summaries for p in s["points"]])
    cmap = plt.get_cmap("RdYlGn")
    fig, axes = plt.subplots(1, len(summaries), figsize=(6.0 * len(summaries) + 1.2, 6.0), squeeze=False,
                             layout="constrained", sharex=True, sharey=True)
    for ax, s, differing in zip(axes[0], summaries, settings_differences(summaries, width=60)):
        _panel(ax, s["points"], s["design_point"], cmap, 0.10, limits=limits)
        ok = sum(1 for p in s["points"] if p["acceptable"])
        ax.set_title(f"{s['tuning']} bank ({str(s['bank_hash'])[:12]}): {ok}/{len(s['points'])} acceptable, "
                     f"{s['runs_per_case']} run(s) per case" + (f"\n{differing}" if differing else ""), fontsize=9)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0.0, 1.0))
    fig.colorbar(sm, ax=list(axes[0]), label="correct fraction (failure cases)", shrink=0.9)
    fig.suptitle("envelope map: o acceptable, X not; annotated with false-alarm runs", fontsize=10)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
