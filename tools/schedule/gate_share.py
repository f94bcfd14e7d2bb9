"""Lab driver (not in the wheel): how often the maneuver dwell's gate (maneuver_dwell.h) is
open in the runs of an envelope campaign flown with ``--maneuver-dwell``, before and after the
failure, and what opened it: the low-passed estimated load factor or the air data's rates.

Re-flies each selected run of ``runs.jsonl`` (its scenario, bank and estimator settings,
``fly(record_series=True)``: the same flight) and replays its u, z and air data through a
fresh ``loop.estimator.Estimator`` with the same settings, reading the gate on every frame
(``core_bank.maneuvering``) and, apart, the gate's inputs recomputed from what the estimator
sees: the first-order low-pass (tau, default 2 s) of z_hat's AZ entry off the trim, and the
air-data rates (air_data_rates.h: low-passes of 1 s and 5 s, their difference over 4 s).

    python tools/schedule/gate_share.py DIR/runs.jsonl --points R25,R27 [--cases NONE,LF] [--runs 0,1,2]

Per run: the share of frames with the gate open before and after the failure, the first open
frame's time, the largest |n_lp| (g) before and after, the outcome and first declaration."""
from __future__ import annotations

import argparse
import json
import math

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import FRAME_RATE_HZ, SENSORS


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("runs", help="an envelope campaign's runs.jsonl")
    p.add_argument("--points", required=True, help="point labels, comma-separated (R25,R27)")
    p.add_argument("--cases", default=None, help="cases, comma-separated (default all)")
    p.add_argument("--runs-index", default=None, help="run indices, comma-separated (default all)")
    p.add_argument("--tau", type=float, default=2.0, help="the load factor's low-pass time constant, s (default 2)")
    a = p.parse_args(argv)
    points = set(a.points.split(","))
    cases = None if a.cases is None else set(a.cases.split(","))
    idx = None if a.runs_index is None else {int(v) for v in a.runs_index.split(",")}
    az = SENSORS.index("AZ")
    c = 1.0 - math.exp(-1.0 / (a.tau * FRAME_RATE_HZ))
    for line in open(a.runs):
        r = json.loads(line)
        if r["point"] not in points or (cases and r["case"] not in cases) or (idx and r["run_index"] not in idx):
            continue
        _, _, bank = load_bank(r["bank"])
        options = dict(r["estimator"])
        flight = fly(scenario_from_dict(r["scenario"]), bank, estimator_options=options, record_series=True)
        s = flight.series
        est = Estimator(bank, **options)
        n = len(s["z"])
        gate = np.zeros(n, bool)
        nlp = np.zeros(n)
        lp = 0.0
        air = np.asarray(s["air_data"], float)      # (Mach, pressure altitude ft) per frame
        g1, g5 = 1.0 - math.exp(-1.0 / FRAME_RATE_HZ), 1.0 - math.exp(-1.0 / (5.0 * FRAME_RATE_HZ))
        f1, f5 = air[0].copy(), air[0].copy()
        rates = np.zeros((n, 2))                    # air_data_rates.h: (lp_1s - lp_5s) / 4 s
        for i in range(n):
            f1 += g1 * (air[i] - f1)
            f5 += g5 * (air[i] - f5)
            rates[i] = (f1 - f5) / 4.0
        for i in range(n):
            est.schedule(*s["air_data"][i])
            z_hat = est.update(s["z"][i])
            gate[i] = bool(est.core_bank.maneuvering)
            dn = float(z_hat[az] - est.core_bank.z_trim[az])
            lp += c * (dn - lp)
            nlp[i] = lp
            est.propagate(s["u"][i])
        k = round((r.get("failure_time_s") or 0.0) * FRAME_RATE_HZ) if r["case"] != "NONE" else n
        first = np.flatnonzero(gate)
        before = gate[:k].mean() if k else float("nan")
        after = gate[k:].mean() if k < n else float("nan")
        print(f"{r['point']} {r['case']:>4} run {r['run_index']}: gate open {before:.2f} before / {after:.2f} after "
              f"the failure, first at {first[0] / FRAME_RATE_HZ if len(first) else float('nan'):.2f} s; "
              f"max |n_lp| {np.abs(nlp[:k]).max() if k else float('nan'):.3f} / "
              f"{np.abs(nlp[k:]).max() if k < n else float('nan'):.3f} g; max |M_dot| {np.abs(rates[:k, 0]).max():.4f}/s, "
              f"|h_dot| {np.abs(rates[:k, 1]).max():.1f} ft/s before; {r['outcome']} "
              + ", ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in r["declarations"][:2]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
