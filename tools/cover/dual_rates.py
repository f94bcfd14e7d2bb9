"""The duals' climb rates measured on a dual campaign, and the per-dual drift allowance from them.

For each ordered pair f>c of a dual campaign (`f16mmae campaign dual`, flown WITHOUT an
allowance) and each run whose first declaration after f's onset is f (or a form of f) and comes
before c's onset, the dual f+c's log-odds against f climb from the level-1 floor to the
threshold, h = ln(T / (1 - T)) - ln(p_min / (1 - p_min)) nats (T, p_min: the run's estimator
settings; h = 22.9 nats for 0.9 and 1e-9), in n = (t_declared - dwell - t_onset_c) * 64 frames:
the pair's mean drift over the climb is r = h / n nats a frame (cpp/f16mmae/level1_allowance.h).
A pair's r is the median over its runs; a pair whose dual was never declared within the flight
gets the bound r <= h / n_end (n_end the frames from c's onset to the flight's end): its dual,
if real, is slower than that.  The allowance k = min(fraction * r, max_k) (level1_allowance.h:
every dual's climb then takes at most 1 / (1 - fraction) times as long; a walk's excursion
reaches h with probability about exp(-2 k h / sigma^2)).  max_k: a dual whose climb is a jump
(a sensor's reading lost: the threshold crossed on the onset's frame, r = h nats a frame) holds
far less evidence a frame once above the threshold, and its dwell must survive k.

Writes the file `--level1-allowance-pairs FILE` reads:
  {"fraction": a, "max_k": k_max, "h_nats": h, "frame_rate_hz": 64, "source": ..., "pairs": {"AY>RF": k, ...},
   "rates": {"AY>RF": {"r": r, "runs": n, "bound": false}, ...}}

Run: .venv/bin/python tools/cover/dual_rates.py DUAL_DIR --fraction 0.2 --max-k 0.12 --out FILE [--print]
"""
from __future__ import annotations

import argparse
import json
import math
import pathlib
import statistics

FRAME_RATE_HZ = 64.0


def component(name: str) -> str:
    """The component a single or partial hypothesis names ("LS:loss=0.5" -> "LS")."""
    return name.split(":")[0]


def barrier(threshold: float, p_min: float) -> float:
    """h: the log-odds from the floor p_min to the threshold T, nats."""
    return math.log(threshold / (1.0 - threshold)) - math.log(p_min / (1.0 - p_min))


def allowance(r: float, fraction: float, max_k: float) -> float:
    """k = min(fraction * r, max_k), nats a frame."""
    return min(fraction * r, max_k)


def pair_rates(runs: list[dict]) -> dict[str, dict]:
    """{pair "f>c": {"r": nats a frame, "runs": runs measured, "bound": True when no run's dual
    was declared (r is then the upper bound h / n_end)}} over the dual runs of a campaign."""
    measured: dict[str, list[float]] = {}
    bounds: dict[str, float] = {}
    for run in runs:
        if run.get("kind") != "dual":
            continue
        s = run["estimator_settings"]
        h = barrier(s["threshold"], s.get("level1_p_min") or s["p_min"])
        f, c = run["first"], run["second"]
        pair = f"{f}>{c}"
        t_f, t_c = run["first_time_s"], run["second_time_s"]
        decl = [d for d in run["declarations"] if d["time_s"] >= t_f]
        if not decl or component(decl[0]["hypothesis"]) != f or decl[0]["time_s"] >= t_c:
            continue   # the level-1 bank of f was not on line at c's onset: no climb from its floor
        n_end = (run["scenario"]["duration_s"] - t_c) * FRAME_RATE_HZ
        bounds[pair] = h / n_end
        dual = next((d for d in decl if d["hypothesis"] == run["hypothesis"] and d["time_s"] > t_c), None)
        if dual is None:
            continue
        n = max(1.0, (dual["time_s"] - s["dwell_s"] - t_c) * FRAME_RATE_HZ)
        measured.setdefault(pair, []).append(h / n)
    out = {}
    for pair, b in bounds.items():
        if pair in measured:
            out[pair] = {"r": statistics.median(measured[pair]), "runs": len(measured[pair]), "bound": False}
        else:
            out[pair] = {"r": b, "runs": 0, "bound": True}
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dual_dir", type=pathlib.Path, help="a dual campaign's --out folder (runs.jsonl), no allowance")
    ap.add_argument("--fraction", type=float, required=True, help="k = fraction * r, 0 <= fraction < 1")
    ap.add_argument("--max-k", type=float, required=True, help="k's ceiling, nats a frame (> 0)")
    ap.add_argument("--out", type=pathlib.Path, help="the pair table to write")
    ap.add_argument("--print", action="store_true", help="print the pairs, slowest first")
    a = ap.parse_args()
    if not 0.0 <= a.fraction < 1.0:
        ap.error(f"--fraction {a.fraction} must lie in [0, 1): k = fraction * r, and a dual climbs at r - k")
    if not a.max_k > 0.0:
        ap.error(f"--max-k {a.max_k} must be > 0 nats a frame")
    path = a.dual_dir / "runs.jsonl"
    if not path.is_file():
        ap.error(f"{path} not found: give a dual campaign's --out folder")
    runs = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    if any(r.get("kind") == "dual" and (r.get("estimator") or {}).get("level1_allowance")
           or (r.get("estimator") or {}).get("level1_allowance_pairs") for r in runs):
        ap.error(f"{path}: flown with an allowance; the rates are measured without one")
    rates = pair_rates(runs)
    if not rates:
        ap.error(f"{path}: no dual run whose first failure was declared before the second's onset")
    s = next(r["estimator_settings"] for r in runs if r.get("kind") == "dual")
    table = {"fraction": a.fraction, "max_k": a.max_k, "h_nats": barrier(s["threshold"], s.get("level1_p_min") or s["p_min"]),
             "frame_rate_hz": FRAME_RATE_HZ, "source": str(a.dual_dir),
             "pairs": {p: allowance(v["r"], a.fraction, a.max_k) for p, v in sorted(rates.items())},
             "rates": dict(sorted(rates.items()))}
    if a.print:
        for p, v in sorted(rates.items(), key=lambda kv: kv[1]["r"]):
            how = "(bound, never declared)" if v["bound"] else f"({v['runs']} runs)"
            print(f"{p:9s} r {v['r']:.3f} nats/frame {how}  k {allowance(v['r'], a.fraction, a.max_k):.3f}")
    if a.out:
        a.out.write_text(json.dumps(table, indent=1) + "\n")
        print(f"wrote {a.out}: {len(rates)} pairs, fraction {a.fraction}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
