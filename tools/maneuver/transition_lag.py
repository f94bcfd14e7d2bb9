"""The false declarations of a soak against the maneuver trim's rates: how long after a phase
change each one comes, which hypothesis, which residual channels carry its evidence, and how
far the rates the maneuver trim used (gamma, dV/dt) were from the truth at that moment.

Re-flies each run with a false alarm of a soak's ``runs.jsonl`` (``evidence.py``'s flight, bit
for bit) and replays the estimator with the record's settings (a run flown with
``--maneuver-trim``), recording per frame the maneuver trim's (gamma, a) and z - z_hat. Per
failure declaration one row:

- ``phase`` as ``soak_phases.py`` (measured air data, true bank angle and roll rate) and
  ``since``: the seconds since the last change of the true maneuver state (``event``: the
  true |gamma| through 0.5 deg (2-s mean), |dV/dt| through 2 ft/s^2 (4-s mean) or |phi|
  through 5 deg (1-s mean); ``climb+``/``climb-`` its start/end, ``accel+/-``, ``bank+/-``);
- ``rise``: the seconds from the onset (ln(p_H/p_NONE) up through -5) to the declaration;
- ``channels``: the two sensors with the largest mean |z - z_hat| over the rise, in units of
  that channel's RMS residual over the whole flight (signed);
- ``gamma err`` (deg) and ``a err`` (ft/s^2): the trim's gamma and a minus the truth's
  (gamma = asin(dh/dt / V_t), a = dV_t/dt from the true altitude and true airspeed, 1-s
  central differences), at the onset and at the declaration; ``lag``: the delay (s, 0-10) that
  best aligns the trim's gamma with the truth's over the 20 s before the declaration, and
  ``a lag`` the same for the trim's acceleration against the truth's (its 2-s mean).

For the VEL declarations also the VEL reading, the bank's prediction z_hat and the noise-free
truth, each minus the trim's VEL in force (the schedule's airspeed), at the onset and at the
declaration.

Truth is read from the flight's log after the flight, for this diagnosis only.

Run: .venv/bin/python tools/maneuver/transition_lag.py DIR/runs.jsonl [--extra '{"k": v}']
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
import soak_runs  # noqa: E402  (the soak's runs flown again)
from evidence import selected  # noqa: E402
from soak_phases import phases  # noqa: E402

from f16mmae.banks import load_bank  # noqa: E402
from f16mmae.names import FRAME_RATE_HZ, NONE, SENSORS  # noqa: E402


def replay(record: dict, bank, extra: dict | None = None) -> dict:
    out = {"gamma": [], "accel": [], "res": [], "log_odds": [], "declarations": [], "vel": []}
    v = SENSORS.index("VEL")
    last = [NONE]

    def observe(i, est, z_hat, series):
        z = np.asarray(series["z"][i])
        out["res"].append(z - np.asarray(z_hat))
        trim_v = float(est.core_bank.z_trim[v])
        out["vel"].append((z[v] - trim_v, z_hat[v] - trim_v, series["truth_log"]["z_ideal"][i, v] - trim_v))
        p = np.asarray(est.probabilities, float)
        names = est.hypotheses
        p_none = p[names.index(NONE)] if NONE in names else float("nan")
        out["log_odds"].append({h: math.log(max(p[k], 1e-300) / p_none) for k, h in enumerate(names) if h != NONE})
        if est.declared != last[0]:
            last[0] = est.declared
            if last[0] != NONE:
                out["declarations"].append((i, last[0]))

    def trim_rates(i, est, series):
        g, a, _, _ = est.core_bank.maneuver_trim
        out["gamma"].append(g)
        out["accel"].append(a)

    flight = soak_runs.fly_and_replay(record, bank, extra, after_update=observe, after_propagate=trim_rates)
    for key in ("gamma", "accel", "res", "vel"):
        out[key] = np.array(out[key], float)
    return {"flight": flight, "truth": flight.series["truth_log"], "trace": out}


def truth_rates(log: dict) -> tuple[np.ndarray, np.ndarray]:
    names = list(log["state_names"])
    h, v = log["state"][:, names.index("alt_ft")], log["state"][:, names.index("vt_fps")]
    n, w = len(h), int(FRAME_RATE_HZ) // 2
    idx = np.arange(n)
    lo, hi = np.clip(idx - w, 0, n - 1), np.clip(idx + w, 0, n - 1)
    span = np.maximum(hi - lo, 1) / FRAME_RATE_HZ
    hdot, vdot = (h[hi] - h[lo]) / span, (v[hi] - v[lo]) / span
    return np.arcsin(np.clip(hdot / v, -1, 1)), vdot


def events(g_true: np.ndarray, a_true: np.ndarray, phi: np.ndarray, i: int) -> tuple[float, str]:
    """Seconds since the last true maneuver-state change before frame i, and which."""
    best, name = math.inf, "-"
    for tag, x, lim, w in (("climb", np.degrees(g_true), 0.5, 2), ("accel", a_true, 2.0, 4),
                           ("bank", np.degrees(phi), 5.0, 1)):
        k = np.ones(w * int(FRAME_RATE_HZ)) / (w * FRAME_RATE_HZ)
        on = np.abs(np.convolve(x, k, mode="same")[:i + 1]) > lim
        ch = np.nonzero(on[1:] != on[:-1])[0]
        if len(ch):
            dt = (i - ch[-1] - 1) / FRAME_RATE_HZ
            if dt < best:
                best, name = dt, tag + ("+" if on[ch[-1] + 1] else "-")
    return best, name


def rows(record: dict, run: dict) -> list[dict]:
    tr, log = run["trace"], run["truth"]
    ph = phases({"flight": run["flight"], "truth": log})
    g_true, a_true = truth_rates(log)
    rms = np.sqrt(np.mean(tr["res"] ** 2, axis=0))
    phi = log["state"][:, list(log["state_names"]).index("phi_rad")]
    out = []
    for i, h in tr["declarations"]:
        onset = i
        while onset > 0 and tr["log_odds"][onset].get(h, -math.inf) > -5.0:
            onset -= 1
        since, event = events(g_true, a_true, phi, i)
        m = np.mean(tr["res"][onset:i + 1] / rms, axis=0)
        top = np.argsort(-np.abs(m))[:2]
        w0 = max(0, i - 20 * int(FRAME_RATE_HZ))
        a_mean = np.convolve(a_true, np.ones(2 * int(FRAME_RATE_HZ)) / (2 * FRAME_RATE_HZ), mode="same")
        lags = []
        for est, ref in ((tr["gamma"], g_true), (tr["accel"], a_mean)):
            best, lag = math.inf, 0.0
            for d in range(0, 10 * int(FRAME_RATE_HZ) + 1, 8):
                if w0 - d < 0:
                    break
                e = float(np.mean((est[w0:i + 1] - ref[w0 - d:i + 1 - d]) ** 2))
                if e < best:
                    best, lag = e, d / FRAME_RATE_HZ
            lags.append(lag)
        lag, a_lag = lags
        out.append({"run": record["run_index"], "t": i / FRAME_RATE_HZ, "h": h, "phase": ph[i],
                    "since": since, "event": event, "rise": (i - onset) / FRAME_RATE_HZ,
                    "channels": " ".join(f"{SENSORS[k]}{m[k]:+.1f}" for k in top),
                    "g_on": math.degrees(tr["gamma"][onset] - g_true[onset]),
                    "g_at": math.degrees(tr["gamma"][i] - g_true[i]),
                    "g_true": math.degrees(g_true[i]),
                    "a_on": tr["accel"][onset] - a_true[onset], "a_at": tr["accel"][i] - a_true[i],
                    "a_true": a_true[i], "lag": lag, "a_lag": a_lag,
                    "vel": (tr["vel"][onset], tr["vel"][i])})
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", help="a soak's runs.jsonl (flown with --maneuver-trim)")
    ap.add_argument("--extra", default="{}", help="estimator settings over the record's (JSON)")
    args = ap.parse_args(argv)
    records = [json.loads(line) for line in open(args.runs)]
    extra = json.loads(args.extra)
    banks: dict[str, object] = {}
    table = []
    print(f"{'run':>3} {'t s':>7} {'hyp':>5} {'phase':>9} {'event':>6} {'since':>5} {'rise':>5} {'channels (rms)':>16} "
          f"{'gamma°':>7} {'err on/at °':>12} {'a ft/s2':>7} {'err on/at':>11} {'lag s':>5} {'a lag':>5}")
    for record in (records if extra else selected(records, "false-alarms")):
        bank = banks.setdefault(record["bank"], load_bank(record["bank"])[2])
        for r in rows(record, replay(record, bank, extra)):
            table.append(r)
            print(f"{r['run']:3d} {r['t']:7.2f} {r['h']:>5} {r['phase']:>9} {r['event']:>6} {r['since']:5.1f} {r['rise']:5.2f} "
                  f"{r['channels']:>16} {r['g_true']:+7.2f} {r['g_on']:+6.2f}/{r['g_at']:+5.2f} {r['a_true']:+7.2f} "
                  f"{r['a_on']:+5.2f}/{r['a_at']:+5.2f} {r['lag']:5.2f} {r['a_lag']:5.2f}")
    vel_rows = [r for r in table if r["h"] == "VEL"]
    if vel_rows:
        print("\nVEL declarations: VEL measured / predicted (z_hat) / true, minus the trim's VEL in force (ft/s), "
              "at the onset -> at the declaration")
        for r in vel_rows:
            (m0, p0, t0), (m1, p1, t1) = r["vel"]
            print(f"  {r['run']:3d} {r['t']:7.2f}: {m0:+6.2f} / {p0:+6.2f} / {t0:+6.2f}  ->  {m1:+6.2f} / {p1:+6.2f} / {t1:+6.2f}")
    print(f"\n{len(table)} declarations; by phase: "
          + ", ".join(f"{p} {n}" for p, n in collections.Counter(r['phase'] for r in table).most_common())
          + "; by hypothesis: " + ", ".join(f"{p} {n}" for p, n in collections.Counter(r['h'] for r in table).most_common()))
    if table:
        print("median |gamma err| at the declaration %.2f deg, |a err| %.2f ft/s^2, since the phase change %.1f s"
              % (np.median([abs(r['g_at']) for r in table]), np.median([abs(r['a_at']) for r in table]),
                 np.median([r['since'] for r in table])))


if __name__ == "__main__":
    main()
