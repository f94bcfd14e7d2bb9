"""The partial hypotheses' floor against what it buys and costs: the half loss's latency (median
and p95 of the runs that declared the injected surface) and the failure-free flights with a
false alarm, one point per floor.

Each point is a pair of ``f16mmae campaign single`` folders: one holding the ``loss=0.5`` mode
(its runs.jsonl), one the failure-free flights (``--cases NONE --runs 200``).

Run: .venv/bin/python tools/cover/partial_floor_figure.py --point 1e-9 DIR DIR_NONE --point 1e-5 DIR DIR_NONE \
       --title "tuning seed 7" --out docs/results/figures/failure_models_round13_partial_floor.png
"""
from __future__ import annotations

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def loss_latencies(folder: str) -> np.ndarray:
    out = []
    with open(f"{folder}/runs.jsonl") as fh:
        for line in fh:
            r = json.loads(line)
            f = r["failures"]
            if f and f[0]["mode"] == "loss" and r["latency_s"] is not None and r["outcome"] == "correct":
                out.append(r["latency_s"])
    return np.asarray(out)


def false_alarm_flights(folder: str) -> tuple[int, int]:
    n = k = 0
    with open(f"{folder}/runs.jsonl") as fh:
        for line in fh:
            r = json.loads(line)
            n += 1
            k += bool(r["false_alarm"])
    return k, n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--point", nargs=3, action="append", metavar=("FLOOR", "DIR", "DIR_NONE"), required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    floors, med, p95, fa, n = [], [], [], [], []
    for floor, d, dn in args.point:
        lat = loss_latencies(d)
        k, m = false_alarm_flights(dn)
        floors.append(float(floor))
        med.append(np.median(lat))
        p95.append(np.percentile(lat, 95))
        fa.append(k)
        n.append(m)
        print(f"floor {floor}: half-loss latency median {med[-1]:.2f} s, p95 {p95[-1]:.2f} s ({len(lat)} runs); "
              f"false-alarm flights {k} of {m}")
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.4))
    ax[0].semilogx(floors, med, "o-", label="median")
    ax[0].semilogx(floors, p95, "s--", label="p95")
    ax[0].set_xlabel("partial hypotheses' floor")
    ax[0].set_ylabel("half-loss latency (s)")
    ax[0].legend()
    ax[0].grid(alpha=0.3)
    ax[1].semilogx(floors, fa, "o-", color="C3")
    ax[1].set_xlabel("partial hypotheses' floor")
    ax[1].set_ylabel(f"flights with a false alarm (of {n[0]})")
    ax[1].grid(alpha=0.3)
    fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
