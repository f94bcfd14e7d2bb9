"""Markdown rows comparing declaration rules (e.g. evidence dwells) from their campaigns' records:
one row per setting and campaign -- correct, transient-wrong and false-alarm runs with 95 %
Wilson intervals, the latency median / p95 over detected runs VEL apart, and the surfaces' and
the sensors' medians -- then the soaks' false declarations per hour (their summaries' Poisson
95 % intervals) with the hypotheses involved, then each case's median latency per setting.

    .venv/bin/python tools/latency/dwell_nats_table.py LABEL=DIR[,DIR...] [LABEL=DIR[,DIR...] ...]

Each DIR is a campaign's output (its ``runs.jsonl``: single, envelope, maneuver or soak, every
turbulence level it flew); the settings are compared campaign by campaign, in the order given.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from f16mmae.campaign.engine.intervals import wilson

SURFACES = ("LS", "RS", "LF", "RF", "RUD")


def runs(d: Path) -> list[dict]:
    f = d / "runs.jsonl"
    if not f.is_file():
        raise SystemExit(f"dwell_nats_table: {d} holds no runs.jsonl (a campaign's output directory)")
    return [json.loads(line) for line in f.read_text().splitlines() if line.strip()]


def _share(k: int, n: int) -> str:
    lo, hi = wilson(k, n)
    return f"{k}/{n} [{100 * lo:.1f}-{100 * hi:.1f} %]"


def failure_row(label: str, d: Path, rs: list[dict]) -> str:
    failed = [r for r in rs if r["case"] != "NONE"]
    lat = {"all": [], "surfaces": [], "sensors": []}
    for r in failed:
        if r.get("latency_s") is None or r["case"] == "VEL":
            continue
        lat["all"].append(r["latency_s"])
        lat["surfaces" if r["case"] in SURFACES else "sensors"].append(r["latency_s"])
    a = np.asarray(lat["all"])

    def med(v):
        return f"{np.median(v):.2f}" if len(v) else "-"
    return "| " + " | ".join([
        label, d.name, _share(sum(r["outcome"] == "correct" for r in failed), len(failed)),
        _share(sum(bool(r.get("transient_wrong")) for r in failed), len(failed)),
        _share(sum(bool(r.get("false_alarm")) for r in rs), len(rs)),
        f"{np.median(a):.2f} / {np.percentile(a, 95):.2f}" if len(a) else "-",
        med(lat["surfaces"]), med(lat["sensors"])]) + " |"


def soak_rows(label: str, d: Path) -> list[str]:
    """The soak's summary per level: false declarations per hour (Poisson 95 %), the hypotheses."""
    out = []
    for lv in json.loads((d / "summary.json").read_text())["levels"]:
        ph = lv["per_hour"]
        lo, hi = ph["ci95"]
        hyps = ", ".join(f"{h} {c}" for h, c in sorted(lv["hypotheses"].items())) or "-"
        out.append(f"| {label} | {d.name} | {lv['level']} | {ph['events']} in {lv['hours']:.2f} h = "
                   f"{ph['events'] / lv['hours']:.2f}/h [{lo:.2f}-{hi:.2f}] | {hyps} |")
    return out


def main() -> None:
    if len(sys.argv) < 2 or any("=" not in a for a in sys.argv[1:]):
        raise SystemExit(__doc__)
    settings = []
    for arg in sys.argv[1:]:
        label, _, dirs = arg.partition("=")
        settings.append((label, [(Path(x), runs(Path(x))) for x in dirs.split(",") if x]))
    print("| setting | campaign | correct [95 %] | transient-wrong runs | runs with a false alarm "
          "| latency median / p95, VEL apart (s) | surfaces median | sensors median |")
    print("|---|---|---|---|---|---|---|---|")
    for label, campaigns in settings:
        for d, rs in campaigns:
            if any(r["case"] != "NONE" for r in rs):
                print(failure_row(label, d, rs))
    soaks = [(label, d, rs) for label, campaigns in settings for d, rs in campaigns if rs and rs[0].get("kind") == "soak"]
    if soaks:
        print()
        print("| setting | soak | turbulence | false declarations [95 %] | hypotheses |")
        print("|---|---|---|---|---|")
        for label, d, rs in soaks:
            for line in soak_rows(label, d):
                print(line)
    print()
    labels = [label for label, _ in settings]
    per = []
    for _, campaigns in settings:
        cases: dict[str, list[float]] = {}
        for _, rs in campaigns:
            for r in rs:
                if r["case"] != "NONE" and r.get("latency_s") is not None:
                    cases.setdefault(r["case"], []).append(r["latency_s"])
        per.append(cases)
    print("| case | " + " | ".join(f"{lb}: median (s)" for lb in labels) + " |")
    print("|---|" + "---|" * len(labels))
    for c in sorted({c for p in per for c in p}):
        print(f"| {c} | " + " | ".join(f"{np.median(p[c]):.2f}" if p.get(c) else "-" for p in per) + " |")


if __name__ == "__main__":
    main()
