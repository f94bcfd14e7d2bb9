"""The dual campaign's pairs that are not absolutely Good, by reason, with each flagged run.

For each pair whose ``absolute_rating`` is not Good (campaign/dual scoring: >= 90 % correct, no
false alarm, no transient-wrong run, median latency <= 1.5 s) this prints its reasons and, per
run, the declarations and what went wrong:

  FA@start    a false declaration before the first failure (the flight's own start, the same
              for every pair flown on that run's seed: the dither rules act only on a declared
              sensor, so none of them can make it);
  FA@t        a false declaration after the first failure at t (s) that was not transient-wrong;
  FA=partial  the run's false alarm is only the first surface's partial-loss hypothesis
              ("LF:loss=0.5" for a complete LF failure): the dual scoring counts any declaration
              before the second failure other than the first failure's own name as an alarm,
              while the single scoring takes a partial hypothesis as its surface's isolation;
  TW <h>@t    the first declaration after the first failure naming a component that did not
              fail (t s after the first failure), and how long it stood;
  late        latency (s) after the second failure;
  no-first    the first failure not declared before the second failure (the rules that act on
              a declared first failure cannot act in time).

With a second campaign folder (``--compare``, the same seed and runs, another dither rule) each
flagged run is marked ``same`` when the other folder's run has the same flags, ``new`` when the
other has none of them (what this folder's rule made), ``gone`` lists the other's flagged runs
this folder does not flag.  Reason classes at the end: latency alone, correct < 90 %, FA, TW.

    .venv/bin/python tools/dual/not_good.py DIR [--compare DIR_OTHER] [--first VEL,AOA,...]
"""
from __future__ import annotations

import argparse
import collections
import json
import pathlib


def load(folder: str) -> tuple[dict, dict]:
    """(summary pairs by name, run records by (pair, run index)) of a dual campaign folder."""
    d = pathlib.Path(folder)
    if not (d / "summary.json").is_file() or not (d / "runs.jsonl").is_file():
        raise SystemExit(f"{folder}: not a dual campaign folder (summary.json and runs.jsonl needed)")
    summary = json.loads((d / "summary.json").read_text())
    if summary.get("kind") != "dual":
        raise SystemExit(f"{folder}: a {summary.get('kind')!r} campaign, not a dual one")
    pairs = {p["case"]: p for p in summary["pairs"]}
    runs = {}
    for line in (d / "runs.jsonl").read_text().splitlines():
        r = json.loads(line)
        if r.get("kind") == "dual" and ">" in r.get("pair", ""):
            runs[(r["pair"], r["run_index"])] = r
    return pairs, runs


def components(h: str) -> set[str]:
    """The components a hypothesis names ("LF:loss=0.5+AZ" -> {"LF", "AZ"}; NONE -> {})."""
    if h == "NONE":
        return set()
    return {part.split(":")[0] for part in h.split("+")}


def run_flags(r: dict) -> list[str]:
    """The run's problems (module docstring)."""
    t1, t2 = r["first_time_s"], r["second_time_s"]
    failed = {r["first"], r["second"]}
    decl = r["declarations"]
    out = []
    if any(d["time_s"] < t1 and d["hypothesis"] != "NONE" for d in decl):
        out.append("FA@start")
    after = [d for d in decl if d["time_s"] >= t1]
    wrong = [i for i, d in enumerate(after) if components(d["hypothesis"]) - failed]
    if r.get("transient_wrong") and wrong:
        i = wrong[0]
        until = after[i + 1]["time_s"] if i + 1 < len(after) else r["scenario"]["duration_s"]
        out.append(f"TW {after[i]['hypothesis']}@{after[i]['time_s'] - t1:.2f}+{until - after[i]['time_s']:.2f}s")
    elif r.get("false_alarm") and wrong:
        out.append(f"FA@{after[wrong[0]]['time_s']:.2f}")
    early = [d["hypothesis"] for d in decl if d["time_s"] < t2 and d["hypothesis"] not in ("NONE", r["first"])]
    if r.get("false_alarm") and early and all(components(h) == {r["first"]} for h in early):
        out.append("FA=partial")
    if not any(components(d["hypothesis"]) == {r["first"]} and d["time_s"] < t2 for d in decl):
        out.append("no-first")
    if r["outcome"] != "correct":
        out.append(r["outcome"])
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder")
    ap.add_argument("--compare", help="another campaign folder, same seed and runs")
    ap.add_argument("--first", help="only pairs whose first failure is one of these (comma list)")
    args = ap.parse_args()
    pairs, runs = load(args.folder)
    other = load(args.compare) if args.compare else None
    firsts = set(args.first.split(",")) if args.first else None
    classes = collections.defaultdict(list)
    partial_only = []
    for name, p in pairs.items():
        if ">" not in name or p["absolute_rating"] == "Good" or (firsts and p["first"] not in firsts):
            continue
        reason = p.get("absolute_rating_reason", "")
        kinds = [k for k, key in (("correct", "correct "), ("FA", "false alarm"), ("TW", "transient-wrong"),
                                  ("latency", "latency")) if key in reason]
        classes["latency alone" if kinds == ["latency"] else "+".join(kinds)].append(name)
        tag = ""
        if other and name in other[0]:
            o = other[0][name]
            tag = f"  [other: {o['absolute_rating']}, median {o['latency_s']['median'] or 0:.2f} s]"
        print(f"{name:8s} {reason}{tag}")
        idx = sorted(i for (n, i) in runs if n == name)
        fa_runs = [i for i in idx if runs[(name, i)].get("false_alarm")]
        if fa_runs and kinds == ["FA"] and all("FA=partial" in run_flags(runs[(name, i)]) for i in fa_runs):
            partial_only.append(name)
        for i in idx:
            r = runs[(name, i)]
            flags = run_flags(r)
            lat = r.get("latency_s")
            decl = ", ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in r["declarations"])
            mark = ""
            if other and flags:
                o = other[1].get((name, i))
                of = run_flags(o) if o else []
                mark = " same" if of == flags else (" new" if not of else f" other: {' '.join(of)}")
            lat_s = f"{lat:.2f}" if lat is not None else "-"
            print(f"    run {i} seed {r['seed']:>10d} lat {lat_s:>5s}  {' '.join(flags) or 'ok'}{mark}  | {decl}")
        if other:
            gone = [i for i in idx if other[1].get((name, i)) and run_flags(other[1][(name, i)])
                    and not run_flags(runs[(name, i)])]
            if gone:
                print(f"    gone (flagged in the other only): runs {gone}")
    print()
    for k, v in sorted(classes.items(), key=lambda kv: -len(kv[1])):
        print(f"{k:28s} {len(v):3d}  {' '.join(v)}")
    print(f"not Good only through FA=partial: {len(partial_only)}  {' '.join(partial_only)}")


if __name__ == "__main__":
    main()
