"""What the freeze rule of the maneuver trim's inertial rates does in one flight with a failed
sensor (a maneuver campaign's run flown with ``--maneuver-trim-rates inertial``).

Re-flies the selected runs (``evidence.py``'s selections, e.g. ``climb:PIT:0``) and replays the
estimator with the record's settings, printing every 0.25 s from 1 s before the failure to 4 s
after: the maneuver trim's gamma (deg) in force, the true gamma (asin of the true climb rate over
the true airspeed), whether the freeze condition held (level 1, a failure declared, or a
failure hypothesis on line above the trim tracker's freeze probability, default 0.05: the
inertial rates read no sensor), ln(p/p_NONE) of the run's case, and the failed sensor's
reading minus its noise-free truth. Then the counterfactual the freeze prevents: the integral of
(reading - truth) over the flight after the failure, in deg for a rate gyro (what theta would
have gained from the failed reading with the sensor read throughout, before the blend and the
gap limit) and the gap limit that would have held it.

Truth is read from the flight's log after the flight, for this diagnosis only.

Run: .venv/bin/python tools/maneuver/inertial_freeze.py DIR/runs.jsonl --select climb:PIT:0 [--extra JSON]
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from evidence import selected  # noqa: E402
from transition_lag import truth_rates  # noqa: E402

from f16mmae.banks import load_bank  # noqa: E402
from f16mmae.loop.estimator import Estimator  # noqa: E402
from f16mmae.loop.flight import fly, scenario_from_dict  # noqa: E402
from f16mmae.names import FRAME_RATE_HZ, NONE, SENSORS  # noqa: E402


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs")
    ap.add_argument("--select", required=True)
    ap.add_argument("--extra", default="{}", help="estimator settings over the record's (JSON), in the replay and the flight")
    args = ap.parse_args(argv)
    records = [json.loads(line) for line in open(args.runs)]
    for record in selected(records, args.select):
        bank = load_bank(record["bank"])[2]
        options = {**record["estimator"], **json.loads(args.extra)}
        flight = fly(scenario_from_dict(record["scenario"]), bank, estimator_options=options, record_series=True)
        s, log = flight.series, flight.series["truth_log"]
        est = Estimator(bank, **options)
        n, case = len(s["z"]), record["case"]
        freeze_p = float(options.get("trim_freeze_probability", 0.05))
        gamma, frozen, lo = np.zeros(n), np.zeros(n, bool), np.zeros(n)
        for i in range(n):
            est.schedule(*s["air_data"][i])
            est.update(s["z"][i])
            p = np.asarray(est.probabilities, float)
            names = est.hypotheses
            lo[i] = math.log(max(p[names.index(case)], 1e-300) / p[names.index(NONE)]) if case in names else math.nan
            est.propagate(s["u"][i])
            gamma[i] = est.core_bank.maneuver_trim[0]
            frozen[i] = est.level != 0 or est.declared != NONE or any(
                p[k] > freeze_p for k, h in enumerate(names) if h != NONE)
        g_true, _ = truth_rates(log)
        t0 = float(record["failure_time_s"])
        i0 = round(t0 * FRAME_RATE_HZ)
        k = SENSORS.index(case) if case in SENSORS else None
        print(f"\n== {record.get('maneuver')} {case} run {record['run_index']} (seed {record['seed']}), failure at "
              f"{t0} s: outcome {record['outcome']}, declarations "
              + ", ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in flight.declarations))
        print(f"{'t s':>6} {'gamma trim°':>11} {'gamma true°':>11} {'frozen':>6} {'ln p/pNONE':>10} {'reading-truth':>13}")
        for i in range(max(0, i0 - 64), min(n, i0 + 4 * 64 + 1), 16):
            err = (log["z"][i, k] - log["z_ideal"][i, k]) if k is not None else math.nan
            print(f"{i / FRAME_RATE_HZ:6.2f} {math.degrees(gamma[i]):11.3f} {math.degrees(g_true[i]):11.3f} "
                  f"{'F' if frozen[i] else '.':>6} {lo[i]:10.1f} {err:13.5f}")
        pre = frozen[:i0]
        print(f"before the failure the freeze condition held on {100 * pre.mean():.0f} % of the frames")
        if k is not None and SENSORS[k] in ("PIT", "ROL", "YAW"):
            drift = float(np.sum(log["z"][i0:, k] - log["z_ideal"][i0:, k])) / FRAME_RATE_HZ
            print(f"integral of (reading - truth) after the failure: {math.degrees(drift):+.2f} deg "
                  f"(frozen on {100 * frozen[i0:].mean():.0f} % of those frames; the gap limit 8.6 deg); "
                  f"max |gamma trim - gamma true| after the failure {np.degrees(np.max(np.abs(gamma[i0:] - g_true[i0:]))):.2f} deg")


if __name__ == "__main__":
    main()
