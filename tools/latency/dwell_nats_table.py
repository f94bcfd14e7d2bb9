"""One markdown row per setting from a single-failure campaign and a soak (their directories):
correct, transient-wrong and false-alarm runs with 95 % intervals, the pooled latency median /
p95 over detected runs, the surfaces' and the sensors' medians, and the soak's false
declarations per hour with its interval.

    .venv/bin/python tools/latency/dwell_nats_table.py LABEL=SINGLE_DIR,SOAK_DIR [...]

(SOAK_DIR may be left out: ``LABEL=SINGLE_DIR``.) Then one row per case: each setting's median
latency (s) over the case's detected runs, and VEL's p95.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

SURFACES = ("LS", "RS", "LF", "RF", "RUD")


def _ci(t: dict) -> str:
    lo, hi = t["ci95"]["clopper_pearson"]
    return f"{t['count']}/{t['runs']} [{100 * lo:.1f}-{100 * hi:.1f} %]"


def row(label: str, single: Path, soak: Path | None) -> str:
    s = json.loads((single / "summary.json").read_text())
    lat: dict[str, list[float]] = {"all": [], "surfaces": [], "sensors": []}
    for line in (single / "runs.jsonl").read_text().splitlines():
        r = json.loads(line)
        if r.get("latency_s") is None:
            continue
        lat["all"].append(r["latency_s"])
        lat["surfaces" if r["case"] in SURFACES else "sensors"].append(r["latency_s"])
    t = s["totals"]
    a = np.asarray(lat["all"])
    cells = [label, _ci(t["correct"]), _ci(t["transient_wrong"]), _ci(t["false_alarm"]),
             f"{np.median(a):.2f} / {np.percentile(a, 95):.2f}",
             f"{np.median(lat['surfaces']):.2f}", f"{np.median(lat['sensors']):.2f}"]
    if soak is not None:
        lv = json.loads((soak / "summary.json").read_text())["levels"][0]
        ph = lv["per_hour"]
        cells.append(f"{ph['events']} in {ph['exposure']:g} h = {ph['rate']:.0f}/h "
                     f"[{ph['ci95'][0]:.0f}-{ph['ci95'][1]:.0f}]")
    else:
        cells.append("-")
    return "| " + " | ".join(cells) + " |"


def case_latencies(single: Path) -> dict[str, list[float]]:
    out: dict[str, list[float]] = {}
    for line in (single / "runs.jsonl").read_text().splitlines():
        r = json.loads(line)
        if r.get("latency_s") is not None:
            out.setdefault(r["case"], []).append(r["latency_s"])
    return out


def main() -> None:
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    print("| setting | correct [95 %] | transient-wrong runs | runs with a false alarm | latency median / p95 (s) "
          "| surfaces median | sensors median | soak: false declarations |")
    print("|---|---|---|---|---|---|---|---|")
    for arg in sys.argv[1:]:
        label, _, dirs = arg.partition("=")
        single, _, soak = dirs.partition(",")
        print(row(label, Path(single), Path(soak) if soak else None))
    labels = [a.partition("=")[0] for a in sys.argv[1:]]
    per = [case_latencies(Path(a.partition("=")[2].partition(",")[0])) for a in sys.argv[1:]]
    print()
    print("| case | " + " | ".join(f"{lb}: median (s)" for lb in labels) + " |")
    print("|---|" + "---|" * len(labels))
    cases = [c for c in per[0] if c != "NONE"]
    for c in cases:
        print(f"| {c} | " + " | ".join(f"{np.median(p[c]):.2f}" if p.get(c) else "-" for p in per) + " |")
    print("| VEL p95 | " + " | ".join(f"{np.percentile(p['VEL'], 95):.2f}" if p.get("VEL") else "-"
                                     for p in per) + " |")


if __name__ == "__main__":
    main()
