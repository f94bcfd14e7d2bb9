"""Runs whose outcome differs between two campaign directories flown on the same seeds (e.g. one
bank with and without ``--declare-components``): per run, the outcome, the declarations with
their times, and the false-alarm / transient-wrong flags, matched by (failure mode or
size, component, seed).

Run: .venv/bin/python tools/cover/component_diff.py DIR_A DIR_B [DIR_A2 DIR_B2 ...]
"""
from __future__ import annotations

import glob
import json
import sys


def records(d: str) -> dict:
    out = {}
    for path in sorted(glob.glob(f"{d}/runs.jsonl")):
        with open(path) as fh:
            for line in fh:
                if not line.strip():
                    continue
                r = json.loads(line)
                mode = r["failures"][0].get("mode") if r.get("failures") else r.get("size")
                key = (mode, r.get("component", r.get("case")), r["seed"])
                out[key] = r
    return out


def brief(r: dict) -> str:
    decl = " ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in r.get("declarations", []))
    flags = ("FA " if r.get("false_alarm") else "") + ("TW " if r.get("transient_wrong") else "")
    return f"{r['outcome']:<10} {flags}[{decl}]"


def main(args: list[str]) -> None:
    if len(args) < 2 or len(args) % 2:
        raise SystemExit("usage: component_diff.py DIR_A DIR_B [DIR_A2 DIR_B2 ...]")
    for a_dir, b_dir in zip(args[::2], args[1::2]):
        a, b = records(a_dir), records(b_dir)
        print(f"{a_dir} -> {b_dir}: {len(a)} / {len(b)} runs")
        for key in sorted(set(a) & set(b), key=str):
            ra, rb = a[key], b[key]
            if (ra["outcome"], ra.get("false_alarm"), ra.get("transient_wrong")) != (
                    rb["outcome"], rb.get("false_alarm"), rb.get("transient_wrong")):
                print(f"  {key}: {brief(ra)}  ->  {brief(rb)}")


if __name__ == "__main__":
    main(sys.argv[1:])
