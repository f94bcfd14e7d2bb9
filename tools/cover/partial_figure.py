"""Figure of the partial-loss hypotheses: (left) detection of a surface's loss against the
fraction lost, the five surfaces pooled (detectability campaigns, 50 runs a point, 95 %
Clopper-Pearson intervals), one line per bank; (right) correct runs per mode (single
campaigns, NONE runs included) per bank, with their intervals.

Run: .venv/bin/python tools/cover/partial_figure.py --detect LABEL=DIR ... --single LABEL=DIR[+DIR] ... --out FIG.png
"""
from __future__ import annotations

import argparse
import json
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.stats import beta  # noqa: E402

MODES = ("complete", "stuck", "hardover", "null", "loss=0.5")


def cp(k: int, n: int) -> tuple[float, float]:
    lo = 0.0 if k == 0 else beta.ppf(0.025, k, n - k + 1)
    hi = 1.0 if k == n else beta.ppf(0.975, k + 1, n - k)
    return lo, hi


def mode_counts(dirs: list[str]) -> dict[str, tuple[int, int]]:
    out = {}
    for d in dirs:
        runs = [json.loads(line) for line in open(f"{d}/runs.jsonl") if line.strip()]
        none = [r for r in runs if not r["scenario"].get("failures")]
        by = defaultdict(list)
        for r in runs:
            f = r["scenario"].get("failures") or []
            if f:
                m = f[0].get("mode", "complete")
                by[f"loss={f[0]['value']:g}" if m == "loss" else m].append(r)
        for m, rs in by.items():
            rs = rs + none
            out[m] = (sum(r["outcome"] == "correct" for r in rs), len(rs))
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--detect", nargs="+", default=[])
    ap.add_argument("--single", nargs="+", default=[])
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for i, arg in enumerate(args.detect):
        label, d = arg.split("=", 1)
        fam = json.load(open(f"{d}/summary.json"))["families"]["loss"]
        sizes = [p["size"] for p in fam["components"][0]["points"]]
        k = np.array([sum(c["points"][j]["detected"]["count"] for c in fam["components"]) for j in range(len(sizes))])
        n = np.array([sum(c["points"][j]["detected"]["runs"] for c in fam["components"]) for j in range(len(sizes))])
        ci = np.array([cp(int(a), int(b)) for a, b in zip(k, n)])
        x = np.array(sizes) + 0.006 * (i - (len(args.detect) - 1) / 2)
        a1.errorbar(x, k / n, yerr=[k / n - ci[:, 0], ci[:, 1] - k / n], marker="o", capsize=3, label=label)
    a1.set_xlabel("fraction of effectiveness lost")
    a1.set_ylabel("surface declared after the onset (5 surfaces pooled)")
    a1.set_ylim(-0.02, 1.02)
    a1.grid(alpha=0.3)
    a1.legend(fontsize=8)
    a1.set_title("detectability, evaluation seed, 50 runs a point")
    width = 0.8 / max(1, len(args.single))
    for i, arg in enumerate(args.single):
        label, ds = arg.split("=", 1)
        counts = mode_counts(ds.split("+"))
        ks = np.array([counts.get(m, (0, 1))[0] for m in MODES])
        ns = np.array([counts.get(m, (0, 1))[1] for m in MODES])
        ci = np.array([cp(int(a), int(b)) for a, b in zip(ks, ns)])
        x = np.arange(len(MODES)) + (i - (len(args.single) - 1) / 2) * width
        a2.bar(x, ks / ns, width, label=label, alpha=0.8)
        a2.errorbar(x, ks / ns, yerr=[ks / ns - ci[:, 0], ci[:, 1] - ks / ns], fmt="none", ecolor="k", capsize=2)
    a2.set_xticks(np.arange(len(MODES)), MODES)
    a2.set_ylabel("correct runs (NONE runs included)")
    a2.set_ylim(0.4, 1.02)
    a2.axhline(0.99, color="grey", ls=":", lw=1)
    a2.legend(fontsize=8, loc="lower left")
    a2.set_title("single failures, evaluation seed, 10 runs a case")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(args.out)


if __name__ == "__main__":
    main()
