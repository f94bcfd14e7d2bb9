"""The soak's figures, from its flight records (each with its ``point``) and its summary: each
false declaration on a timeline per flight (one panel per turbulence level, a row per point and
flight, a bar from the declaration to its end, coloured by hypothesis, the nine most declared by
name, the rest grey; hatched from where a flight left its flight condition, not counted), the
histogram of how long they lasted, false declarations per flight hour against the turbulence
level with the 95 % Poisson intervals (pooled over the points), and with two or more points
``soak_map.png``: one panel per level, the points on Mach-altitude axes coloured by their false
declarations per flight hour (green: none; a colour scale above), each with its count."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...report.evidence import describe_counts
from ...report.figures import pyplot, save_figure

MAP_FILE = "soak_map.png"

_COLOURS = "tab10"
#: Hypotheses coloured by name (the most declared); the rest share one grey.
_NAMED = 9
_OTHER = "0.55"
#: The map's colour of a point without a false declaration, and the scale above none.
_CLEAN = "tab:green"
_RATES = "YlOrRd"
#: The timeline's tallest panel (in) and the smallest print of a point's label on it (pt).
_PANEL_IN_MAX = 6.0
_LABEL_PT_MIN = 5.0


def timeline(records: list[dict], levels: tuple[str, ...], flight_s: float, path: Path,
             points: tuple[str, ...] = ()) -> Path:
    """One panel per level; with two or more ``points`` (labels in order) flight n of point i is
    row ``i F + n`` (F flights per point), each point's rows labelled by its label."""
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
    several = len(points) > 1
    where = {label: i for i, label in enumerate(points)}

    def row(r: dict) -> int:
        return where[r["point"]] * flights + r["run_index"] if several else r["run_index"]

    rows = flights * len(points) if several else flights
    panel_in = min(max(0.12 * rows, 0.22 * len(points), 1.0) if several else 0.12 * rows, _PANEL_IN_MAX)
    fig, axes = plt.subplots(len(levels), 1, figsize=(11, 1.6 + panel_in * len(levels)),
                             squeeze=False, sharex=True)
    for ax, lvl in zip(axes[:, 0], levels):
        for r in (r for r in records if r["level"] == lvl):
            for e in r["episodes"]:
                ax.barh(row(r), max(e["duration_s"], flight_s / 400), left=e["time_s"], height=0.8,
                        color=colour[e["hypothesis"]])
            if r.get("left_condition_s") is not None:   # not counted from here (episodes.left_condition_s)
                ax.barh(row(r), flight_s - r["left_condition_s"], left=r["left_condition_s"], height=0.8,
                        color="none", edgecolor=_OTHER, hatch="///", linewidth=0.0)
        ax.set_ylim(-0.5, rows - 0.5)
        ax.invert_yaxis()
        if several:
            for i in range(1, len(points)):
                ax.axhline(i * flights - 0.5, color="0.8", lw=0.5)
            per_label_pt = 72.0 * panel_in / len(points)
            step = max(1, math.ceil(_LABEL_PT_MIN / per_label_pt))
            shown = range(0, len(points), step)
            ax.set_yticks([i * flights + (flights - 1) / 2 for i in shown], [points[i] for i in shown],
                          fontsize=min(8.0, max(_LABEL_PT_MIN, 0.8 * per_label_pt * step)))
            ax.tick_params(axis="y", length=0)
            ax.set_ylabel(f"{lvl}\npoint")
        else:
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
    axes[0, 0].set_title("False declarations, each from its time to its back-out (or the flight's end)"
                         + (f"\nrows: each point's {flights} flight{'s' if flights > 1 else ''}" if several else ""))
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


def soak_map(summary: dict, path: Path) -> Path:
    """One panel per level: each point of ``summary["points"]`` at its Mach and altitude,
    green without a false declaration, else coloured by its false declarations per flight hour
    (one scale over the panels, logarithmic when the rates span a factor of ten or more),
    labelled with its count and, when at most two, the hypotheses; hollow grey where no hour
    was flown; the bank's design point a black star."""
    plt = pyplot()
    from matplotlib.colors import LogNorm, Normalize

    points, levels = summary["points"], [lv["level"] for lv in summary["levels"]]
    rates = [q["per_hour"]["rate"] for p in points for q in p["levels"] if q["per_hour"]["rate"]]
    low, high = (min(rates), max(rates)) if rates else (1.0, 1.0)
    norm = LogNorm(low, high) if high >= 10.0 * low else Normalize(0.0, high)
    cmap = plt.get_cmap(_RATES)
    design = summary.get("design_point") or {}
    machs = [p["mach"] for p in points] + ([design["mach"]] if design else [])
    alts = [p["alt_ft"] for p in points] + ([design["alt_ft"]] if design else [])
    pad_m = max(0.02, 0.08 * (max(machs) - min(machs)))
    pad_h = max(1000.0, 0.08 * (max(alts) - min(alts)))
    fig, axes = plt.subplots(1, len(levels), figsize=(4.6 * len(levels) + 1.4, 4.6), squeeze=False,
                             sharey=True, layout="constrained")
    for j, (ax, lvl) in enumerate(zip(axes[0], levels)):
        clean = 0
        for p in points:
            q = p["levels"][j]
            count = q["per_hour"]["events"] if q["per_hour"]["rate"] is not None else None
            if count is None:
                ax.scatter([p["mach"]], [p["alt_ft"]], s=70, facecolors="none", edgecolors="0.6", zorder=3)
                note = f"{p['label']} -"
            elif count == 0:
                clean += 1
                ax.scatter([p["mach"]], [p["alt_ft"]], s=70, c=_CLEAN, edgecolors="k", linewidths=0.5, zorder=3)
                note = f"{p['label']} 0"
            else:
                ax.scatter([p["mach"]], [p["alt_ft"]], s=110, c=[cmap(norm(q["per_hour"]["rate"]))],
                           edgecolors="k", linewidths=0.8, zorder=4)
                hyps = q["hypotheses"]
                note = f"{p['label']} {count}" + (f" ({describe_counts(hyps)})" if len(hyps) <= 2 else "")
            ax.annotate(note, (p["mach"], p["alt_ft"]), fontsize=6, textcoords="offset points", xytext=(0, 6),
                        ha="center", zorder=5)
        if design:
            ax.scatter([design["mach"]], [design["alt_ft"]], s=260, marker="*", facecolors="none",
                       edgecolors="k", linewidths=1.0, zorder=6, label="bank's design point")
        pooled = summary["levels"][j]["per_hour"]
        total = "-" if pooled["rate"] is None else f"{pooled['events']} in {pooled['exposure']:.2f} h"
        ax.set_title(f"{lvl} turbulence: {total}; {clean}/{len(points)} points with none", fontsize=8)
        ax.set_xlim(min(machs) - pad_m, max(machs) + pad_m)
        ax.set_ylim(min(alts) - pad_h, max(alts) + pad_h)
        ax.set_xlabel("Mach")
        ax.grid(True, alpha=0.25)
    axes[0, 0].set_ylabel("altitude (ft)")
    if design:
        axes[0, 0].legend(loc="lower right", fontsize=7, markerscale=0.6)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=norm)
    fig.colorbar(sm, ax=list(axes[0]), shrink=0.9,
                 label="false declarations per flight hour (green: none)")
    fig.suptitle(f"{summary['tuning']} bank, {summary['flights_per_level']} flight(s) of {summary['flight_s']:g} s "
                 f"per point and level; labels: point, false declarations (hypotheses)", fontsize=9)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def make_figures(out: Path, records: list[dict], summary: dict) -> dict:
    """Write the figures into ``out`` from the flight ``records`` (each with its ``point``) and
    the soak's ``summary``: the three of every soak, and ``soak_map.png`` with two or more
    points; their file names by role."""
    if not records:
        return {}
    level_rates = summary["levels"]
    levels = tuple(lv["level"] for lv in level_rates)
    points = tuple(p["label"] for p in summary["points"])
    figs = {"timeline": timeline(records, levels, summary["flight_s"], out / "soak_timeline.png", points).name,
            "durations": durations(records, levels, out / "soak_durations.png").name,
            "rate_by_level": rate_by_level(level_rates, out / "soak_rate_by_level.png").name}
    if len(points) > 1:
        figs["map"] = soak_map(summary, out / MAP_FILE).name
    return figs
