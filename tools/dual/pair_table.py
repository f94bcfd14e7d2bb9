"""One row per dual campaign folder: the pairs' numbers of docs/results/dual.md's tables.

absolutely Good pairs; relative Good / Fair / Poor / ND; correct runs of the pairs' (the baselines
left out) with the 95 % Clopper-Pearson interval; transient-wrong and false-alarm runs; the dual
latency's median and 95th percentile over the pairs' runs with a latency; and for the pairs with a
sensor first and a surface second: correct runs, latency median / p95.  With ``--diff`` the
pairs Good in one folder and not in the other, and the runs whose outcome differs.

    .venv/bin/python tools/dual/pair_table.py DIR [DIR ...] [--diff]
"""
from __future__ import annotations

import argparse
import json
import pathlib

import numpy as np
from scipy.stats import beta

SURFACES = {"LS", "RS", "LF", "RF", "RUD"}


def clopper_pearson(k: int, n: int) -> tuple[float, float]:
    lo = 0.0 if k == 0 else float(beta.ppf(0.025, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(0.975, k + 1, n - k))
    return lo, hi


def load(folder: str) -> tuple[dict, list[dict]]:
    d = pathlib.Path(folder)
    if not (d / "summary.json").is_file():
        raise SystemExit(f"{folder}: no summary.json (not a campaign folder)")
    s = json.loads((d / "summary.json").read_text())
    if s.get("kind") != "dual":
        raise SystemExit(f"{folder}: a {s.get('kind')!r} campaign, not a dual one")
    runs = [r for r in map(json.loads, (d / "runs.jsonl").read_text().splitlines()) if ">" in r.get("pair", "")]
    return s, runs


def row(folder: str) -> str:
    s, runs = load(folder)
    pairs = [p for p in s["pairs"] if ">" in p["case"]]
    good = sum(p["absolute_rating"] == "Good" for p in pairs)
    rel = {k: sum(p["rating"] == k for p in pairs) for k in ("Good", "Fair", "Poor", "ND")}
    n, k = len(runs), sum(r["outcome"] == "correct" for r in runs)
    lo, hi = clopper_pearson(k, n)
    tw = sum(bool(r["transient_wrong"]) for r in runs)
    fa = sum(bool(r["false_alarm"]) for r in runs)
    lat = np.array([r["latency_s"] for r in runs if r.get("latency_s") is not None])
    sf = [r for r in runs if r["first"] not in SURFACES and r["second"] in SURFACES]
    sf_lat = np.array([r["latency_s"] for r in sf if r.get("latency_s") is not None])
    sf_ok = sum(r["outcome"] == "correct" for r in sf)
    return (f"| {folder} | {good} | {rel['Good']} / {rel['Fair']} / {rel['Poor']} / {rel['ND']} | "
            f"{k} [{100 * lo:.1f}-{100 * hi:.1f} %] of {n} | {tw} | {fa} | "
            f"{np.median(lat):.2f} / {np.percentile(lat, 95):.2f} | "
            f"{sf_ok}/{len(sf)}, {np.median(sf_lat):.2f} / {np.percentile(sf_lat, 95):.2f} |")


def diff(a: str, b: str) -> None:
    (sa, ra), (sb, rb) = load(a), load(b)
    ga = {p["case"] for p in sa["pairs"] if p["absolute_rating"] == "Good" and ">" in p["case"]}
    gb = {p["case"] for p in sb["pairs"] if p["absolute_rating"] == "Good" and ">" in p["case"]}
    lat = {f: {p["case"]: p["latency_s"]["median"] for p in s["pairs"]} for f, s in ((a, sa), (b, sb))}
    fmt = lambda x: "-" if x is None else f"{x:.2f}"  # noqa: E731
    print(f"Good in {b} only:", ", ".join(f"{c} ({fmt(lat[a][c])} -> {fmt(lat[b][c])} s)" for c in sorted(gb - ga)))
    print(f"Good in {a} only:", ", ".join(f"{c} ({fmt(lat[a][c])} -> {fmt(lat[b][c])} s)" for c in sorted(ga - gb)))
    oa = {(r["pair"], r["run_index"]): r for r in ra}
    changed = [(k, oa[k]["outcome"], r["outcome"]) for r in rb if (k := (r["pair"], r["run_index"])) in oa
               and oa[k]["outcome"] != r["outcome"]]
    decl = sum(1 for r in rb if (k := (r["pair"], r["run_index"])) in oa and oa[k]["declarations"] != r["declarations"])
    print(f"runs whose outcome differs: {len(changed)}", changed)
    print(f"runs whose declarations differ: {decl} of {len(rb)}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--diff", action="store_true", help="pairs and runs that differ between the first two folders")
    args = ap.parse_args()
    print("| folder | absolute Good | relative Good / Fair / Poor / ND | correct [95 %] | TW runs | FA runs | "
          "dual latency median / p95 (s) | sensor first, surface second: correct, median / p95 |")
    for f in args.folders:
        print(row(f))
    if args.diff and len(args.folders) >= 2:
        diff(args.folders[0], args.folders[1])


if __name__ == "__main__":
    main()
