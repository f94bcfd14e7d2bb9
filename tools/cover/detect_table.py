"""The loss family of detectability campaigns (``f16mmae campaign detectability --out DIR``) as
one markdown table: per surface and bank, detected / runs at each fraction lost.

Run: .venv/bin/python tools/cover/detect_table.py LABEL=DIR [LABEL=DIR ...]
"""
from __future__ import annotations

import json
import sys


def main(args) -> None:
    rows, sizes = [], None
    for arg in args:
        label, d = arg.split("=", 1)
        fam = json.load(open(f"{d}/summary.json"))["families"]["loss"]
        for comp in fam["components"]:
            pts = comp["points"]
            sizes = [p["size"] for p in pts]
            rows.append((comp["component"], label, [f"{p['detected']['count']}/{p['detected']['runs']}" for p in pts]))
    print("| surface | bank | " + " | ".join(f"lost {s:g}" for s in sizes) + " |")
    print("|---|---|" + "---|" * len(sizes))
    for comp, label, cells in sorted(rows, key=lambda r: (r[0], r[1])):
        print(f"| {comp} | {label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
