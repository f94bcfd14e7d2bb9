"""The false declarations of a soak (or the declarations of chosen maneuver runs) by flight
phase, with what the trim tracker and the turbulence adaptation did before each.

Re-flies each selected run of a ``runs.jsonl`` (``evidence.replay``: the same flight, bit for
bit, and the estimator replayed frame by frame with the record's settings) and, for every
failure declaration, prints one row:

- ``phase`` at the declaration, from the flight after the fact: ``turn`` while the true bank
  angle exceeds 5 deg, ``roll`` while the true roll rate exceeds 5 deg/s, ``climb`` /
  ``descent`` while the measured pressure altitude changes faster than 5 ft/s (its 2-s
  central difference), ``accel`` / ``decel`` while the measured Mach changes faster than
  0.001/s (2-s central difference), ``level-off`` for the 30 s after the end of a climb,
  descent, acceleration or deceleration, else ``level``;
- ``onset``: the last time before the declaration at which ln(p_H/p_NONE) of the declared
  hypothesis H rose through -5 (its rise, s before the declaration);
- ``dur``: how long it stayed declared (the record's episode);
- ``rho`` at the declaration and its largest value over the 5 s before; ``s`` the adaptation's
  scale there (1 + 20 (rho - rho_0) clamped to [1, 100]: the core's defaults) when the run flew
  the adaptation (with the run's --adapt-reference; under --adapt-reference-climb the reference
  in force in a climb is the climb reference, which this column does not apply);
- ``frozen``: the share of the 10 s before the declaration on which the trim tracker was
  frozen, and dz(AOA) (deg) at the declaration (a run flown with --trim-tracking).

Then a count by phase and hypothesis. Truth (bank angle, roll rate) is read only from the
flight's log, after the flight, to name the phase.

Run: .venv/bin/python tools/maneuver/soak_phases.py results/DIR/runs.jsonl [--select false-alarms]
"""
from __future__ import annotations

import argparse
import collections
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from evidence import replay, selected  # noqa: E402  (the sibling tool's re-flight)

from f16mmae.banks import load_bank  # noqa: E402
from f16mmae.names import FRAME_RATE_HZ, NONE, SENSORS  # noqa: E402

LEVEL_OFF_S = 30.0
ADAPT_GAIN, S_MIN, S_MAX = 20.0, 1.0, 100.0   # TurbulenceAdaptationOptions' defaults


def phases(run: dict) -> list[str]:
    """The phase of every frame (module docstring)."""
    air = np.asarray(run["flight"].series["air_data"], float)
    log = run["truth"]
    phi = np.degrees(log["state"][:, 5])
    p = np.degrees(log["z_ideal"][:, SENSORS.index("ROL")])   # the true roll rate
    n = len(air)
    w = int(FRAME_RATE_HZ)   # +- 1 s
    idx = np.arange(n)
    lo, hi = np.clip(idx - w, 0, n - 1), np.clip(idx + w, 0, n - 1)
    span = np.maximum(hi - lo, 1) / FRAME_RATE_HZ
    hdot = (air[hi, 1] - air[lo, 1]) / span
    mdot = (air[hi, 0] - air[lo, 0]) / span
    out, last_transient = [], -1e9
    for i in range(n):
        t = i / FRAME_RATE_HZ
        if abs(hdot[i]) > 5.0:
            ph = "climb" if hdot[i] > 0 else "descent"
        elif abs(mdot[i]) > 0.001:
            ph = "accel" if mdot[i] > 0 else "decel"
        else:
            ph = ""
        if ph:
            last_transient = t
        if abs(p[i]) > 5.0:
            ph = "roll"
        elif abs(phi[i]) > 5.0:
            ph = "turn"
        elif not ph:
            ph = "level-off" if t - last_transient <= LEVEL_OFF_S else "level"
        out.append(ph)
    return out


def rows(record: dict, run: dict) -> list[dict]:
    """One row per failure declaration of the re-flown run (module docstring)."""
    tr, fl = run["trace"], run["flight"]
    ph = phases(run)
    episodes = {round(e["time_s"], 6): e for e in record.get("episodes", [])}
    est = {**record.get("estimator_settings", {}), **record["estimator"]}
    adapt = bool(est.get("adapt_turbulence"))
    rho0 = float(est.get("adapt_reference", 0.6))
    aoa = SENSORS.index("AOA")
    out = []
    for d in fl.declarations:
        h = d["hypothesis"]
        if h == NONE:
            continue
        i = min(len(ph) - 1, round(d["time_s"] * FRAME_RATE_HZ))
        onset = i
        while onset > 0 and tr["log_odds"][onset].get(h, -math.inf) > -5.0:
            onset -= 1
        w5, w10 = max(0, i - 5 * int(FRAME_RATE_HZ)), max(0, i - 10 * int(FRAME_RATE_HZ))
        rho, rho_max = float(tr["rho"][i]), float(np.max(tr["rho"][w5:i + 1]))
        frozen = [tr["trim"][k][2] for k in range(w10, i + 1)]
        ep = episodes.get(round(d["time_s"], 6), {})
        out.append({
            "run": record["run_index"], "t": d["time_s"], "h": h, "phase": ph[i],
            "rise_s": (i - onset) / FRAME_RATE_HZ, "dur": ep.get("duration_s", float("nan")),
            "rho": rho, "rho_max": rho_max,
            "s": min(S_MAX, max(S_MIN, 1.0 + ADAPT_GAIN * (rho - rho0))) if adapt else float("nan"),
            "frozen": float(np.mean(frozen)), "dz_aoa": math.degrees(tr["trim"][i][1][aoa])})
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", help="a soak's (or maneuver campaign's) runs.jsonl")
    ap.add_argument("--select", default="false-alarms", help="as evidence.py's (default false-alarms)")
    args = ap.parse_args(argv)
    records = [json.loads(line) for line in open(args.runs)]
    banks: dict[str, object] = {}
    table = []
    print(f"{'run':>3} {'t s':>7} {'hyp':>6} {'phase':>9} {'rise s':>6} {'dur s':>6} {'rho':>5} {'rhomax':>6} "
          f"{'s':>5} {'frozen':>6} {'dzAOA°':>7}")
    for record in selected(records, args.select):
        bank = banks.setdefault(record["bank"], load_bank(record["bank"])[2])
        for r in rows(record, replay(record, bank)):
            table.append(r)
            print(f"{r['run']:3d} {r['t']:7.2f} {r['h']:>6} {r['phase']:>9} {r['rise_s']:6.2f} {r['dur']:6.2f} "
                  f"{r['rho']:5.2f} {r['rho_max']:6.2f} {r['s']:5.2f} {r['frozen']:6.2f} {r['dz_aoa']:+7.3f}")
    count = collections.Counter((r["phase"], r["h"]) for r in table)
    print("\nby phase and hypothesis: " + ", ".join(f"{ph} {h} {n}" for (ph, h), n in count.most_common()))
    by_phase = collections.Counter(r["phase"] for r in table)
    print("by phase: " + ", ".join(f"{ph} {n}" for ph, n in by_phase.most_common()))


if __name__ == "__main__":
    main()
