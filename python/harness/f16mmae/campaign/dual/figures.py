"""Figures of the dual-failure campaign (paper Fig. 7).

* ``rating_matrix``: the 12 x 12 matrix of Fig. 7 -- rows the first failure, columns the
  second, each cell coloured by its rating (Good / Fair / Poor / ND, see
  ``scoring``) with the correct count ``k/N`` and the median latency after the second
  failure written in it; the diagonal grey, pairs not flown blank.  Beside it, the paper's
  Fig. 7 in the same colours (cells the text extraction lost: hatched).
* ``probability_grid``: the same 12 x 12 layout of small multiples; cell (a, b) plots
  against time the mean over runs of the probability of the dual ``a+b`` (solid) and of the
  first failure's single hypothesis ``a`` (dashed), ``p_bar(t) = (1/N) sum_n p_n(t)`` (0
  while off line), on the rating's colour; diagonal cell (b, b) holds the baseline: the
  mean probability of the lone single failure b.  Failure times: dotted lines.

matplotlib with the non-interactive Agg backend (``report.figures.pyplot``).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ...names import COMPONENTS
from ...report.drawing import deferrable
from ...report.figures import pyplot
from ..engine.scoring import mean_injected_probability
from .scoring import PAPER_FIG7, RATINGS
COLORS = {"Good": "#8bc98b", "Fair": "#f6d55c", "Poor": "#f3a15a", "ND": "#e0605a", "Indistinguishable": "#9aa7c7"}
DIAGONAL = "#c8c8c8"


def _grid_axes(ax, title: str) -> None:
    n = len(COMPONENTS)
    ax.set_xlim(-0.5, n - 0.5)
    ax.set_ylim(n - 0.5, -0.5)
    ax.set_xticks(range(n))
    ax.set_xticklabels(COMPONENTS, fontsize=7, rotation=90)
    ax.set_yticks(range(n))
    ax.set_yticklabels(COMPONENTS, fontsize=7)
    ax.set_xlabel("second failure", fontsize=8)
    ax.set_ylabel("first failure", fontsize=8)
    ax.set_title(title, fontsize=9)
    ax.set_aspect("equal")
    ax.tick_params(length=0)


def _cell(ax, i, j, color, hatch=None) -> None:
    import matplotlib.patches as mpatches

    ax.add_patch(mpatches.Rectangle((j - 0.5, i - 0.5), 1, 1, facecolor=color,
                                    edgecolor="0.6" if hatch else "white", lw=1.0, hatch=hatch))


@deferrable(lambda a: Path(a["path"]), alone=True)
def rating_matrix(summary: dict, path: str | Path) -> Path:
    """Fig. 7 from a dual campaign summary, beside the paper's; returns the file written."""
    plt = pyplot()
    import matplotlib.patches as mpatches

    pairs = {(p["first"], p["second"]): p for p in summary["pairs"]}
    fig, (ax, axp) = plt.subplots(1, 2, figsize=(13.5, 6.8), gridspec_kw={"width_ratios": [1.35, 1]})
    for i, a in enumerate(COMPONENTS):
        for j, b in enumerate(COMPONENTS):
            if a == b:
                _cell(ax, i, j, DIAGONAL)
                _cell(axp, i, j, DIAGONAL)
                continue
            p = pairs.get((a, b))
            if p is not None:
                _cell(ax, i, j, COLORS[p["rating"]])
                med = p["latency_s"]["median"]
                ax.text(j, i - 0.17, f"{p['correct']}/{p['runs']}", ha="center", va="center", fontsize=6)
                ax.text(j, i + 0.2, "-" if med is None else f"{med:.2f}", ha="center", va="center", fontsize=5.5)
                if p.get("absolute_rating") == "Good":  # the absolute criteria, beside the relative rating
                    ax.plot(j + 0.36, i - 0.36, marker="s", ms=2.6, color="black", lw=0)
            theirs = PAPER_FIG7[a][b]
            if theirs:
                _cell(axp, i, j, COLORS[theirs])
                axp.text(j, i, theirs if theirs != "Good" else "", ha="center", va="center", fontsize=5.5)
            else:
                _cell(axp, i, j, "white", hatch="///")
    counts = summary.get("ratings", {})
    absolute = summary.get("absolute_ratings", {})
    _grid_axes(ax, f"f16mmae, {summary.get('tuning')} bank, {summary.get('runs_per_pair')} runs/pair "
                   f"(cell: correct k/N, median latency s)\n"
                   + ", ".join(f"{k} {counts.get(k, 0)}" for k in RATINGS)
                   + f"\n\u25a0 absolutely Good ({absolute.get('Good', 0)}): >= 90% correct, no false alarm, "
                     f"no transient-wrong, median <= 1.5 s")
    cmp_ = summary.get("paper_comparison", {})
    _grid_axes(axp, "paper Fig. 7 (Eide & Maybeck)\n"
                    f"same rating in {cmp_.get('equal', '?')} of {cmp_.get('cells', '?')} known cells")
    handles = [mpatches.Patch(color=COLORS[k], label=k) for k in RATINGS]
    handles.append(mpatches.Patch(facecolor="white", edgecolor="0.5", hatch="///", label="unknown"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
    fig.suptitle(f"Dual failures: first at {summary.get('first_time_s')} s, second at "
                 f"{summary.get('second_time_s')} s, rated against the lone second failure", fontsize=10)
    fig.tight_layout(rect=(0, 0.04, 1, 0.95))
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


@deferrable(lambda a: Path(a["path"]), alone=True)
def probability_grid(records: list[dict], summary: dict, path: str | Path) -> Path:
    """Small multiples of the mean probability of the dual (and of the first single), drawn
    as curves scaled into the cells of one 12 x 12 grid (one axes: fast to draw)."""
    plt = pyplot()
    ratings = {(p["first"], p["second"]): p["rating"] for p in summary["pairs"]}
    duals: dict[tuple[str, str], list[dict]] = {}
    bases: dict[str, list[dict]] = {}
    for r in records:
        if r["kind"] == "dual":
            duals.setdefault((r["first"], r["second"]), []).append(r)
        else:
            bases.setdefault(r["second"], []).append(r)
    t1, t2, dur = summary["first_time_s"], summary["second_time_s"], summary["duration_s"]
    pad = 0.06

    def earliest(rs):  # the earliest run's failure offset: mean_injected_probability aligns on it
        return min(r["second_time_s"] for r in rs) - t2

    def xy(i, j, t, p):  # time 0..dur -> cell's width, probability 0..1 -> cell's height (up)
        return (j - 0.5 + pad + (1 - 2 * pad) * np.asarray(t) / dur,
                i + 0.5 - pad - (1 - 2 * pad) * np.asarray(p))

    def marks(i, j, times):
        for tx in times:
            x, _ = xy(i, j, [tx], [0])
            ax.plot([x[0], x[0]], [i - 0.5 + pad, i + 0.5 - pad], color="0.3", ls=":", lw=0.5)

    fig, ax = plt.subplots(figsize=(12.5, 12.5))
    for i, a in enumerate(COMPONENTS):
        for j, b in enumerate(COMPONENTS):
            if a == b:
                _cell(ax, i, j, DIAGONAL)
                t, p = mean_injected_probability(bases.get(b, []))
                if len(t):
                    ax.plot(*xy(i, j, t, p), color="k", lw=0.9)
                    marks(i, j, (t2 + earliest(bases[b]),))
            elif (a, b) in duals:
                _cell(ax, i, j, COLORS[ratings[(a, b)]])
                rs = duals[(a, b)]
                tf, pf = mean_injected_probability(rs, key="p_first")
                ax.plot(*xy(i, j, tf, pf), color="#8a4b08", lw=0.7, ls="--")
                t, p = mean_injected_probability(rs)
                ax.plot(*xy(i, j, t, p), color="#1f3f9f", lw=1.0)
                marks(i, j, (t1 + earliest(rs), t2 + earliest(rs)))
    _grid_axes(ax, f"Mean probability over runs against time (0 to {dur:g} s per cell; dotted: failures "
                   f"at {t1:g} s and {t2:g} s)\nsolid blue: the dual; dashed brown: the first failure "
                   f"alone; diagonal (black): the lone second failure (baseline)\nbackground: rating "
                   f"(green Good, yellow Fair, orange Poor, red ND)")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
