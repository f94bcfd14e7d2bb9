"""The single-failure campaign's figures: the paper's Figs. 3-6 and the latency chart.

* ``probability_strips``: one strip per case (NONE then the twelve single failures), the
  mean over runs of the probability of the *injected* hypothesis against time,
  ``p_bar(t) = (1/N) sum_n p_{h*,n}(t)``, with the failure time marked -- the paper's
  Figs. 3-6.  One column per bank tuning (``untuned`` left, as Fig. 3; ``tuned`` right,
  as Fig. 6), so the effect of tuning reads at a glance.  A hypothesis that is off line
  (the bank moved to a level-1 bank without it) counts as probability 0.
* ``latency_chart``: per case, every run's detection latency (dots), the median (bar)
  and the 95th percentile (tick), one row per case, one colour per tuning; the same image
  whatever the order of the records (a pool stores them in the order they finish).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ...names import NONE, SINGLE_HYPOTHESES
from ...report.drawing import deferrable
from ...report.figures import pyplot, save_figure
from ..engine.scoring import mean_injected_probability

TUNING_ORDER = ("untuned", "tuned")


def _ordered_tunings(labels) -> list[str]:
    known = [t for t in TUNING_ORDER if t in labels]
    return known + sorted(t for t in labels if t not in TUNING_ORDER)


@deferrable(lambda a: Path(a["path"]), alone=True)
def probability_strips(
    records_by_tuning: Mapping[str, Sequence[dict]],
    path: str | Path,
    cases: Sequence[str] = SINGLE_HYPOTHESES,
) -> Path:
    """The Figs. 3-6 strip plots, one column per tuning; returns the file written."""
    plt = pyplot()
    tunings = _ordered_tunings(records_by_tuning)
    cases = [c for c in cases if any(r["case"] == c for t in tunings for r in records_by_tuning[t])]
    fig, axes = plt.subplots(
        len(cases), len(tunings), figsize=(4.2 * len(tunings) + 0.8, 0.78 * len(cases) + 1.0),
        sharex=True, sharey=True, squeeze=False,
    )
    for j, tuning in enumerate(tunings):
        recs = records_by_tuning[tuning]
        for i, case in enumerate(cases):
            ax = axes[i][j]
            rc = [r for r in recs if r["case"] == case]
            t, p = mean_injected_probability(rc)
            if len(t):
                ax.plot(t, p, color="C0" if tuning == "tuned" else "C3", lw=1.2)
                tf = min((r["failure_time_s"] for r in rc if r.get("failure_time_s") is not None), default=None)
                if tf is not None and case != NONE:   # the earliest: mean_injected_probability aligns on it
                    ax.axvline(tf, color="0.4", ls="--", lw=0.8)
            ax.set_ylim(-0.05, 1.05)
            ax.set_yticks([0, 1])
            ax.tick_params(labelsize=7)
            ax.grid(alpha=0.3)
            if j == 0:
                ax.set_ylabel(case, rotation=0, ha="right", va="center", fontsize=9)
            if i == 0:
                ax.set_title(f"{tuning} bank (mean of {len(rc)} runs)", fontsize=9)
        axes[-1][j].set_xlabel("time (s)", fontsize=8)
    fig.suptitle("Probability of the injected hypothesis (failure at the dashed line)", fontsize=10)
    return save_figure(fig, path)


@deferrable(lambda a: Path(a["path"]), alone=True)
def latency_chart(
    records_by_tuning: Mapping[str, Sequence[dict]],
    path: str | Path,
    cases: Sequence[str] = SINGLE_HYPOTHESES[1:],
) -> Path:
    """Per-case detection latency: runs (dots), median (bar), p95 (tick)."""
    plt = pyplot()
    tunings = _ordered_tunings(records_by_tuning)
    fig, ax = plt.subplots(figsize=(7.5, 0.36 * len(cases) + 1.4))
    offsets = np.linspace(-0.18, 0.18, len(tunings)) if len(tunings) > 1 else [0.0]
    for k, tuning in enumerate(tunings):
        color = "C0" if tuning == "tuned" else ("C3" if tuning == "untuned" else f"C{k + 2}")
        for i, case in enumerate(cases):
            # ascending: the overlapping translucent dots do not depend on the records' order
            lat = sorted(r["latency_s"] for r in records_by_tuning[tuning]
                         if r["case"] == case and r.get("latency_s") is not None)
            y = i + offsets[k]
            if lat:
                ax.plot(lat, [y] * len(lat), "o", ms=3, alpha=0.5, color=color)
                med, p95 = np.percentile(lat, 50), np.percentile(lat, 95)
                ax.plot([med, med], [y - 0.15, y + 0.15], color=color, lw=2.5)
                ax.plot([p95], [y], "D", ms=5, mfc="white", mew=1.5, color=color)
            else:
                ax.text(0.02, y, "no detection", fontsize=7, color=color, va="center")
        ax.plot([], [], "o", color=color, label=f"{tuning} bank (dots: runs, bar: median, diamond: p95)")
    ax.axvline(1.0, color="0.5", ls=":", lw=1)
    ax.axvline(2.0, color="0.5", ls="--", lw=1)
    ax.set_yticks(range(len(cases)))
    ax.set_yticklabels(cases)
    ax.invert_yaxis()
    ax.set_xlabel("detection latency (s): first correct declaration - failure time "
                  "(goal: median <= 1 s dotted, p95 <= 2 s dashed)", fontsize=8)
    ax.set_xlim(left=0)
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    return save_figure(fig, path)
