"""Figure: the dual campaign's sensor-first pairs, median latency of the dual without and with the
sensor-loss dither (two ``campaign dual`` summaries of the same seed), the absolute rule's 1.5 s
drawn; a filled marker is a pair rated absolutely Good.

    .venv/bin/python tools/dual/sensor_loss_figure.py OFF_DIR ON_DIR -o FIGURE.png [--title T]
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from f16mmae.names import SENSORS  # noqa: E402


def pairs(summary_dir: str) -> dict[str, dict]:
    s = json.loads((Path(summary_dir) / "summary.json").read_text())
    return {p["case"]: p for p in s["pairs"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("off")
    ap.add_argument("on")
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--title", default="")
    args = ap.parse_args()
    off, on = pairs(args.off), pairs(args.on)
    cases = [c for c in off if c.split(">")[0] in SENSORS and c in on]
    fig, ax = plt.subplots(figsize=(14, 4.5))
    for x, c in enumerate(cases):
        for d, colour, dx in ((off, "tab:grey", -0.15), (on, "tab:blue", 0.15)):
            lat = d[c]["latency_s"]["median"]
            if lat is None:
                continue
            good = d[c]["absolute_rating"] == "Good"
            ax.plot(x + dx, lat, "o", color=colour, markerfacecolor=colour if good else "white", markersize=6)
        lo, hi = off[c]["latency_s"]["median"], on[c]["latency_s"]["median"]
        if lo is not None and hi is not None:
            ax.plot([x - 0.15, x + 0.15], [lo, hi], "-", color="0.7", lw=0.8)
    ax.axhline(1.5, color="tab:red", lw=0.8, ls="--")
    ax.set_xticks(range(len(cases)))
    ax.set_xticklabels(cases, rotation=90, fontsize=7)
    ax.set_ylabel("dual's median latency (s)")
    ax.plot([], [], "o", color="tab:grey", label="fixed dither")
    ax.plot([], [], "o", color="tab:blue", label="--sensor-loss-dither")
    ax.plot([], [], "o", color="k", markerfacecolor="white", label="open: not absolutely Good")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(args.title, fontsize=9)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
