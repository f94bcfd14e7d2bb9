"""One soak declaration traced frame by frame: the AOA and AZ channels around it against the
truth, to tell a trim that is off from a misfit of the no-failure filter.

Re-flies run RUN of a soak's ``runs.jsonl`` and replays the estimator with the record's
settings (``transition_lag.py``'s replay, the same flight bit for bit); prints every ``--every``
seconds from ``--before`` s before time T to ``--after`` s after it:

- ``phi``: the true bank angle and the blended estimate's (deg);
- ``nz``: the true load factor (the noise-free AZ reading, g) and the blended AZ prediction;
- for the channel ``--sensor`` (default AOA): its noise-free truth, its reading and the blended
  prediction z_hat, each minus the channel's trim in force (the scheduled trim plus the trim
  tracker's offset; angles in deg, rates in deg/s); ``res``: the reading minus the blended
  prediction, and ``resN``: the NONE filter's own residual of the channel, each its mean over
  the printing interval in units of its RMS over the flight; ``NONE r``: the NONE filter's
  residuals of all seven channels (VEL AOA PIT AZ ROL YAW AY), likewise;
- ``dz``: the trim tracker's offset of the channel in force, and the maneuver trim's gamma
  (deg) and a (ft/s^2);
- ``lo``: ln(p_H / p_NONE) of the hypothesis ``--hyp`` (default AOA).

``--plot FILE`` also draws, frame by frame over the window: ln(p_H / p_NONE); NONE's residuals
of VEL, AOA, PIT and AZ (1/8-s running means, RMS units); the channel's truth, reading and
blended prediction about its trim in force.

Truth is read from the flight's log after the flight, for this diagnosis only.

Run: .venv/bin/python tools/maneuver/rollout_trace.py DIR/runs.jsonl --run 4 --t 264.2 [--sensor VEL --hyp VEL]
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from f16mmae.banks import load_bank  # noqa: E402
from f16mmae.loop.estimator import Estimator  # noqa: E402
from f16mmae.loop.flight import fly, scenario_from_dict  # noqa: E402
from f16mmae.names import FRAME_RATE_HZ, NONE, SENSOR_UNITS, SENSORS, STATES  # noqa: E402


def trace(record: dict, bank, hyp: str, sensor: str, i0: int, i1: int) -> tuple[list[dict], dict, float]:
    """Per frame i0..i1 of the replayed flight: the quantities of the module docstring."""
    flight = fly(scenario_from_dict(record["scenario"]), bank, estimator_options=record["estimator"],
                 record_series=True)
    s = flight.series
    log = s["truth_log"]
    est = Estimator(bank, **record["estimator"])
    a, z, v = SENSORS.index(sensor), SENSORS.index("AZ"), STATES.index("phi_rad")
    unit = math.degrees(1.0) if SENSOR_UNITS[a].startswith("rad") else 1.0
    res_a, res_n = np.zeros(len(s["z"])), np.full((len(s["z"]), len(SENSORS)), np.nan)
    rows = []
    for i in range(len(s["z"])):
        est.schedule(*s["air_data"][i])
        z_hat = np.asarray(est.update(s["z"][i]))
        res_a[i] = s["z"][i][a] - z_hat[a]
        names = list(est.hypotheses)
        if NONE in names:
            res_n[i] = np.asarray(est.core_bank.residuals)[names.index(NONE)]
        if i0 <= i <= i1:
            cb = est.core_bank
            _, dz = cb.trim_offset
            trim_a = float(cb.z_trim[a]) + float(dz[a])
            p = np.asarray(est.probabilities, float)
            lo = (math.log(max(p[names.index(hyp)], 1e-300) / p[names.index(NONE)])
                  if hyp in names and NONE in names else float("nan"))
            g, acc, _, _ = cb.maneuver_trim if hasattr(cb, "maneuver_trim") else (0.0, 0.0, None, None)
            rows.append({"i": i, "phi": math.degrees(log["state"][i, list(log["state_names"]).index("phi_rad")]),
                         "phi_hat": math.degrees(float(np.asarray(cb.blended_state)[v])),
                         "nz": log["z_ideal"][i, z], "nz_hat": z_hat[z],
                         "alpha": unit * (log["z_ideal"][i, a] - trim_a),
                         "aoa": unit * (s["z"][i][a] - trim_a), "aoa_hat": unit * (z_hat[a] - trim_a),
                         "dz": unit * float(dz[a]), "gamma": math.degrees(g),
                         "accel": acc, "lo": lo})
        est.propagate(s["u"][i])
    rms, rms_n = float(np.sqrt(np.mean(res_a ** 2))), np.sqrt(np.nanmean(res_n ** 2, axis=0))
    for r in rows:
        r["res"], r["res_n_all"] = res_a[r["i"]] / rms, res_n[r["i"]] / rms_n
        r["res_n"] = r["res_n_all"][a]
    return rows, log, rms


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", help="a soak's runs.jsonl")
    ap.add_argument("--run", type=int, required=True, help="the record's run_index")
    ap.add_argument("--t", type=float, required=True, help="the time to trace about (s), e.g. a declaration's")
    ap.add_argument("--hyp", default="AOA", help="the hypothesis whose log-odds are printed (default AOA)")
    ap.add_argument("--sensor", default="AOA", choices=SENSORS, help="the channel traced (default AOA)")
    ap.add_argument("--before", type=float, default=12.0, help="seconds before T (default 12)")
    ap.add_argument("--after", type=float, default=1.0, help="seconds after T (default 1)")
    ap.add_argument("--plot", metavar="FILE", help="also write the figure of the module docstring (PNG)")
    ap.add_argument("--every", type=float, default=0.5, help="printing interval, s (default 0.5)")
    args = ap.parse_args(argv)
    if not (args.before >= 0 and args.after >= 0 and args.every > 0):
        ap.error("--before and --after must be >= 0 and --every > 0")
    records = [json.loads(line) for line in open(args.runs)]
    found = [r for r in records if r["run_index"] == args.run]
    if not found:
        ap.error(f"no record with run_index {args.run} in {args.runs}")
    record = found[0]
    bank = load_bank(record["bank"])[2]
    i0 = max(0, int(round((args.t - args.before) * FRAME_RATE_HZ)))
    i1 = int(round((args.t + args.after) * FRAME_RATE_HZ))
    rows, _, rms = trace(record, bank, args.hyp, args.sensor, i0, i1)
    step = max(1, int(round(args.every * FRAME_RATE_HZ)))
    for k in range(0, len(rows), step):  # the residuals' means over the interval ending at the printed frame
        span = rows[max(0, k - step + 1):k + 1]
        rows[k]["res_mean"] = float(np.mean([r["res"] for r in span]))
        rows[k]["res_n_mean"] = float(np.nanmean([r["res_n"] for r in span]))
        rows[k]["res_n_all_mean"] = np.nanmean([r["res_n_all"] for r in span], axis=0)
    unit = math.degrees(1.0) if SENSOR_UNITS[SENSORS.index(args.sensor)].startswith("rad") else 1.0
    print(f"run {args.run}, {args.sensor} residual RMS over the flight {unit * rms:.3f}; the channel minus its trim in force")
    print(f"{'t s':>7} {'phi':>6} {'phi^':>6} {'nz':>6} {'nz^':>6} {'true':>6} {args.sensor:>6} {args.sensor + '^':>6} {'res':>5} {'resN':>5} "
          f"{'dz':>6} {'gamma':>6} {'a':>6} {'lo ' + args.hyp:>8}  NONE r (VEL AOA PIT AZ ROL YAW AY)")
    for r in rows[::step]:
        print(f"{r['i'] / FRAME_RATE_HZ:7.2f} {r['phi']:+6.1f} {r['phi_hat']:+6.1f} {r['nz']:+6.3f} {r['nz_hat']:+6.3f} "
              f"{r['alpha']:+6.2f} {r['aoa']:+6.2f} {r['aoa_hat']:+6.2f} {r['res_mean']:+5.1f} {r['res_n_mean']:+5.1f} {r['dz']:+6.2f} "
              f"{r['gamma']:+6.2f} {r['accel']:+6.2f} {r['lo']:+8.2f}  " + " ".join(f"{v:+4.1f}" for v in r['res_n_all_mean']))
    if args.plot:
        plot(rows, args.sensor, args.hyp, args.run, args.plot)


def plot(rows: list[dict], sensor: str, hyp: str, run: int, path: str) -> None:
    """The figure of the module docstring."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.array([r["i"] for r in rows]) / FRAME_RATE_HZ
    k = max(1, int(FRAME_RATE_HZ) // 8)
    res = np.array([r["res_n_all"] for r in rows])
    smooth = np.array([np.convolve(res[:, j], np.ones(k) / k, mode="same") for j in range(res.shape[1])]).T
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(8, 7))
    ax[0].plot(t, [r["lo"] for r in rows], "k")
    ax[0].set_ylabel(f"ln(p_{hyp} / p_NONE)")
    for name in ("VEL", "AOA", "PIT", "AZ"):
        ax[1].plot(t, smooth[:, SENSORS.index(name)], label=name)
    ax[1].axhline(0.0, color="grey", lw=0.5)
    ax[1].set_ylabel("NONE's residual (RMS units)")
    ax[1].legend(ncol=4, fontsize=8)
    for key, label in (("alpha", "truth"), ("aoa", "reading"), ("aoa_hat", "prediction (blended)")):
        ax[2].plot(t, [r[key] for r in rows], label=label)
    ax[2].set_ylabel(f"{sensor} about its trim")
    ax[2].set_xlabel("t (s)")
    ax[2].legend(fontsize=8)
    ax[0].set_title(f"soak flight {run}: the {hyp} declaration's rise")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
