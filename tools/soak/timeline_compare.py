"""Two soaks' false declarations side by side at one turbulence level: per flight, a bar from
each counted declaration to its end (coloured by hypothesis), the rest of a flight that left its
flight condition hatched and the failure declarations made after it marked x
(campaign/soak/episodes.py). The soaks' runs.jsonl are read as they are; nothing is flown.
Example (docs/results/envelope_scheduled.md, round 40):

    .venv/bin/python tools/soak/timeline_compare.py "round 39=DIR39" "round 40=DIR40" --level moderate --out PNG
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from f16mmae.names import NONE
from f16mmae.report.figures import pyplot


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("soaks", nargs=2, metavar="LABEL=DIR", help="a label and a soak campaign's directory")
    p.add_argument("--level", default="moderate", help="the turbulence level drawn (default moderate)")
    p.add_argument("--title", default="", help="the figure's title")
    p.add_argument("--out", required=True, help="the PNG written")
    a = p.parse_args()
    panels = []
    for spec in a.soaks:
        label, sep, d = spec.partition("=")
        runs = Path(d) / "runs.jsonl"
        if not sep or not runs.is_file():
            p.error(f"{spec!r}: give LABEL=DIR with DIR a soak campaign's directory (its runs.jsonl)")
        records = [json.loads(line) for line in runs.read_text().splitlines()]
        panels.append((label, [r for r in records if r["level"] == a.level]))
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 6), sharey=True)
    colour: dict[str, object] = {}
    cmap = plt.get_cmap("tab10")
    flights = max(r["run_index"] + 1 for _, rs in panels for r in rs)
    for ax, (label, records) in zip(axes, panels):
        flight_s = max(r["scenario"]["duration_s"] for r in records)
        for r in records:
            for e in r["episodes"]:
                c = colour.setdefault(e["hypothesis"], cmap(len(colour) % 10))
                ax.barh(r["run_index"], max(e["duration_s"], flight_s / 300), left=e["time_s"], height=0.8, color=c)
            left = r.get("left_condition_s")
            if left is not None:
                ax.barh(r["run_index"], flight_s - left, left=left, height=0.8, color="none", edgecolor="0.5",
                        hatch="///", linewidth=0.0)
                for d in r.get("declarations_after_leaving", []):
                    if d["hypothesis"] != NONE:
                        ax.plot(d["time_s"], r["run_index"], "x", color="k", ms=5)
        counted = sum(len(r["episodes"]) for r in records)
        gone = sum(1 for r in records if r.get("left_condition_s") is not None)
        ax.set_title(f"{label}\n{counted} false declarations, {gone} flights left the condition")
        ax.set_xlim(0, flight_s)
        ax.set_ylim(-0.5, flights - 0.5)
        ax.invert_yaxis()
        ax.grid(True, axis="x", alpha=0.3)
        ax.set_xlabel("time in flight (s)")
    axes[0].set_ylabel(f"flight, {a.level} air")
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in colour.values()]
    handles += [plt.Rectangle((0, 0), 1, 1, facecolor="none", edgecolor="0.5", hatch="///"),
                plt.Line2D([], [], marker="x", color="k", ls="")]
    names = list(colour) + ["off the flight condition (not counted)", "declared after leaving it"]
    fig.legend(handles, names, loc="lower center", ncol=len(names), fontsize=8)
    fig.suptitle(a.title)
    fig.tight_layout(rect=(0, 0.06, 1, 0.95))
    fig.savefig(a.out, dpi=90)
    plt.close(fig)
    print(a.out)


if __name__ == "__main__":
    main()
