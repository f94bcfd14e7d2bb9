"""The soak's figures, from its flight records: each false declaration on a timeline per
flight (one panel per turbulence level, a bar from the declaration to its end, coloured by
hypothesis, the nine most declared by name, the rest grey; hatched from where a flight left its
flight condition, not counted), the histogram of how long they lasted, and false declarations per flight hour
against the turbulence level with the 95 % Poisson intervals."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ...report.figures import pyplot, save_figure

_COLOURS = "tab10"
#: Hypotheses coloured by name (the most declared); the rest share one grey.
_NAMED = 9
_OTHER = "0.55"


def timeline(records: list[dict], levels: tuple[str, ...], flight_s: float, path: Path) -> Path:
    plt = pyplot()
    counts: dict[str, int] = {}
    for e in (e for r in records for e in r["episodes"]):
        counts[e["hypothesis"]] = counts.get(e["hypothesis"], 0) + 1
    ranked = sorted(counts, key=lambda h: (-counts[h], h))
    cmap = plt.get_cmap(_COLOURS)
    colour = {h: cmap(i) for i, h in enumerate(ranked[:_NAMED])}
    rest = ranked[_NAMED:]
    colour.update({h: _OTHER for h in rest})
    hyps = ranked[:_NAMED]
    flights = max([r["run_index"] + 1 for r in records] or [1])
    fig, axes = plt.subplots(len(levels), 1, figsize=(11, 1.6 + min(0.12 * flights, 6) * len(levels)),
                             squeeze=False, sharex=True)
    for ax, lvl in zip(axes[:, 0], levels):
        for r in (r for r in records if r["level"] == lvl):
            for e in r["episodes"]:
                ax.barh(r["run_index"], max(e["duration_s"], flight_s / 400), left=e["time_s"], height=0.8,
                        color=colour[e["hypothesis"]])
            if r.get("left_condition_s") is not None:   # not counted from here (episodes.left_condition_s)
                ax.barh(r["run_index"], flight_s - r["left_condition_s"], left=r["left_condition_s"], height=0.8,
                        color="none", edgecolor=_OTHER, hatch="///", linewidth=0.0)
        ax.set_ylim(-0.5, flights - 0.5)
        ax.invert_yaxis()
        ax.set_ylabel(f"{lvl}\nflight")
        ax.set_xlim(0, flight_s)
        ax.grid(True, axis="x", alpha=0.3)
    axes[-1, 0].set_xlabel("time in flight (s)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=colour[h]) for h in hyps]
    names = list(hyps)
    if rest:
        handles.append(plt.Rectangle((0, 0), 1, 1, color=_OTHER))
        names.append(f"{len(rest)} others")
    if any(r.get("left_condition_s") is not None for r in records):
        handles.append(plt.Rectangle((0, 0), 1, 1, facecolor="none", edgecolor=_OTHER, hatch="///"))
        names.append("off the flight\ncondition (not counted)")
    if handles:
        axes[0, 0].legend(handles, names, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7,
                          title="hypothesis", title_fontsize=7)
    axes[0, 0].set_title("False declarations, each from its time to its back-out (or the flight's end)")
    return save_figure(fig, path)


def durations(records: list[dict], levels: tuple[str, ...], path: Path) -> Path:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 3.5))
    data = [[e["duration_s"] for r in records if r["level"] == lvl for e in r["episodes"]] for lvl in levels]
    top = max([max(d) for d in data if d] or [1.0])
    bins = np.linspace(0.0, top, 21)
    for lvl, d in zip(levels, data):
        if d:
            ax.hist(d, bins=bins, alpha=0.6, label=f"{lvl} ({len(d)})")
    ax.set_xlabel("how long a false declaration lasted (s)")
    ax.set_ylabel("false declarations")
    if any(data):
        ax.legend(fontsize=8)
    else:
        ax.text(0.5, 0.5, "no false declaration", ha="center", va="center", transform=ax.transAxes)
    return save_figure(fig, path)


def rate_by_level(level_rates: list[dict], path: Path) -> Path:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 3.5))
    xs = np.arange(len(level_rates))
    rates = [lv["per_hour"]["rate"] or 0.0 for lv in level_rates]
    lo = [r - (lv["per_hour"]["ci95"] or [0, 0])[0] for r, lv in zip(rates, level_rates)]
    hi = [(lv["per_hour"]["ci95"] or [0, 0])[1] - r for r, lv in zip(rates, level_rates)]
    ax.errorbar(xs, rates, yerr=[lo, hi], fmt="o", capsize=4, label="rate, 95 % Poisson interval")
    ax.scatter(xs, [lv["per_hour"].get("goal", np.nan) for lv in level_rates], marker="_", s=400, color="k",
               label="goal")
    ax.set_xticks(xs, [lv["level"] for lv in level_rates])
    ax.set_xlabel("turbulence")
    ax.set_ylabel("false declarations per flight hour")
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def make_figures(out: Path, records: list[dict], level_rates: list[dict], flight_s: float) -> dict:
    """Write the three figures into ``out`` (``level_rates``: the summary's ``levels``); their
    file names by role."""
    if not records:
        return {}
    levels = tuple(lv["level"] for lv in level_rates)
    return {"timeline": timeline(records, levels, flight_s, out / "soak_timeline.png").name,
            "durations": durations(records, levels, out / "soak_durations.png").name,
            "rate_by_level": rate_by_level(level_rates, out / "soak_rate_by_level.png").name}
