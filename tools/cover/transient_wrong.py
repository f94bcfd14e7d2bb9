"""The transient-wrong runs of single campaigns, one row each, with their mechanism's class.

A run is transient-wrong (campaign/engine/scoring.py) when a failure other than the injected one
is declared at or after the onset.  For each such run this prints the mode, the case, the flight
seed, the declarations (hypothesis @ time), the first wrong one: its time after the onset and how
long it stood (until the next declaration, or the end of the flight), and the class:

  dual after a right declaration   the injected component (or its partial form) declared first,
                                   then a dual naming it and another component (level 1);
  read as <kind> first             the first declaration after the onset names another single:
                                   kind = "the other stabilator" (LS/RS), "a surface" (a sensor's
                                   failure read as a surface), "a sensor" (a surface's read as a
                                   sensor), "another sensor" (e.g. VEL read as AOA);
  other                            anything else.

Run: .venv/bin/python tools/cover/transient_wrong.py DIR [DIR ...]   (campaign --out folders;
     --by-flight also counts distinct flights per class)
"""
from __future__ import annotations

import argparse
import collections
import json
import pathlib

SURFACES = {"LS", "RS", "LF", "RF", "RUD"}
STABILATORS = {"LS", "RS"}


def component(name: str) -> str:
    """The component a single or partial hypothesis names ("LS:loss=0.5" -> "LS")."""
    return name.split(":")[0]


def classify(run: dict) -> tuple[str, dict]:
    """(class, details) of a transient-wrong run record."""
    injected = run["failures"][0]["name"]
    onset = run["failures"][0]["time_s"]
    decl = [d for d in run["declarations"] if d["time_s"] >= onset]
    duration = run["scenario"]["duration_s"]
    wrong_i = next(i for i, d in enumerate(decl)
                   if d["hypothesis"] != "NONE" and component(d["hypothesis"]) != injected)
    wrong = decl[wrong_i]
    until = decl[wrong_i + 1]["time_s"] if wrong_i + 1 < len(decl) else duration
    details = {"first_wrong": wrong["hypothesis"], "after_onset_s": wrong["time_s"] - onset,
               "stood_s": until - wrong["time_s"], "ended": run["final_hypothesis"]}
    first = decl[0]["hypothesis"]
    if component(first) == injected and "+" in wrong["hypothesis"]:
        return "dual after a right declaration", details
    if "+" not in first and first != "NONE" and component(first) != injected:
        c = component(first)
        if injected in STABILATORS and c in STABILATORS:
            kind = "the other stabilator"
        elif injected not in SURFACES and c in SURFACES:
            kind = "a surface"
        elif injected in SURFACES and c not in SURFACES:
            kind = "a sensor"
        elif injected not in SURFACES and c not in SURFACES:
            kind = "another sensor"
        else:
            kind = "another surface"
        return f"read as {kind} first", details
    return "other", details


def runs_of(folder: pathlib.Path):
    for line in (folder / "runs.jsonl").read_text().splitlines():
        r = json.loads(line)
        if r.get("transient_wrong"):
            yield r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+", type=pathlib.Path)
    ap.add_argument("--by-flight", action="store_true", help="count distinct flights per class too")
    args = ap.parse_args()
    counts: collections.Counter = collections.Counter()
    flights: dict[str, set] = collections.defaultdict(set)
    print(f"{'mode':9s} {'case':4s} {'seed':>10s}  {'class':34s} {'first wrong':12s} {'at +s':>6s} "
          f"{'stood s':>7s} {'ended':8s} declarations")
    for folder in args.dirs:
        for r in runs_of(folder):
            cls, d = classify(r)
            counts[cls] += 1
            flights[cls].add(r["seed"])
            mode = r["failures"][0]["mode"]
            decl = ", ".join(f"{x['hypothesis']}@{x['time_s']:.2f}" for x in r["declarations"])
            print(f"{mode:9s} {r['case']:4s} {r['seed']:>10d}  {cls:34s} {d['first_wrong']:12s} "
                  f"{d['after_onset_s']:6.2f} {d['stood_s']:7.2f} {d['ended']:8s} {decl}")
    print()
    for cls, n in counts.most_common():
        extra = f" ({len(flights[cls])} flights)" if args.by_flight else ""
        print(f"  {cls:34s} {n:3d} runs{extra}")
    print(f"  {'total':32s} {sum(counts.values()):3d} runs")


if __name__ == "__main__":
    main()
