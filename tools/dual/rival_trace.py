"""One dual flight frame by frame: the log-odds of a rival dual against the injected one.

Flies FIRST>SECOND (the dual campaign's scenario: light turbulence, nominal point, FIRST at 3 s,
SECOND at 5 s, the flight seed given) with ``--sensor-loss-dither`` and prints from ``--from`` on,
every ``--every`` frames: L = ln p_rival - ln p_injected (its per-frame slope is the rival's
evidence), p_rival, p_injected, the sensor-loss gains on LS RS LF RF in force, and the measured
p, q (deg/s) about the first frame's.  ``--row SENSOR=g,g,g,g,g`` flies another row of the
gain table for that sensor (the table as shipped otherwise), to set two rows side by side.

    .venv/bin/python tools/dual/rival_trace.py --bank BANK --pair AOA>PIT --seed 91830081 --rival LS+AOA \
        [--row AOA=1,1,1.3,1.3,1] [--from 5.0] [--to 6.5] [--every 4]

The last lines: the mean increment of L per frame over [SECOND's onset, the rival's declaration or
--to], and how many frames L climbed.
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import dual_name
from f16mmae.truth import dither


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--pair", required=True, help="FIRST>SECOND")
    ap.add_argument("--seed", type=int, required=True, help="the flight seed (a campaign record's 'seed')")
    ap.add_argument("--rival", required=True, help="the rival hypothesis, e.g. LS+AOA")
    ap.add_argument("--row", action="append", default=[], help="SENSOR=g_LS,g_RS,g_LF,g_RF,g_RUD")
    ap.add_argument("--from", dest="t0", type=float, default=5.0)
    ap.add_argument("--to", dest="t1", type=float, default=7.0)
    ap.add_argument("--every", type=int, default=4)
    args = ap.parse_args()
    if ">" not in args.pair:
        raise SystemExit(f"--pair needs FIRST>SECOND, got {args.pair!r}")
    first, second = args.pair.split(">")
    for r in args.row:
        name, _, vals = r.partition("=")
        g = tuple(float(x) for x in vals.split(","))
        if name not in dither.SENSOR_LOSS_GAINS or len(g) != 5:
            raise SystemExit(f"--row needs a listed sensor and 5 gains, got {r!r}")
        dither.SENSOR_LOSS_GAINS[name] = g
    injected = dual_name(first, second)
    sc = {"mach": 0.4, "alt_ft": 20000.0, "turbulence": "light", "duration_s": 10.0, "seed": args.seed,
          "feedback": "mmae", "failures": [{"name": first, "time_s": 3.0, "mode": "complete"},
                                           {"name": second, "time_s": 5.0, "mode": "complete"}]}
    _, _, bank = load_bank(args.bank)
    res = fly(scenario_from_dict(sc), bank, estimator_options={"declare_components": True, "sensor_loss_dither": True},
              record_probabilities=True, record_series=True)
    print("declarations:", ", ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in res.declarations))
    pr, pi = res.probability_of(args.rival), res.probability_of(injected)
    lo = np.log(np.maximum(pr, 1e-300)) - np.log(np.maximum(pi, 1e-300))
    z = res.series["z"]
    mz = list(bank.measurement_names)
    rates = np.degrees(z[:, [mz.index("ROL"), mz.index("PIT")]] - z[0, [mz.index("ROL"), mz.index("PIT")]])
    declared = {}
    rule = dither.SensorLossDither()
    gains = []
    decl = sorted(res.declarations, key=lambda d: d["time_s"])
    for i, t in enumerate(res.time_s):
        while decl and decl[0]["time_s"] <= t:
            declared["h"] = decl.pop(0)["hypothesis"]
        gains.append(rule.gains(declared.get("h", "NONE"), res.frame_dt_s)[0])
    gains = np.array(gains)
    print(f"{'t s':>6s} {'L':>9s} {'p_rival':>8s} {'p_inj':>8s}  g_LS  g_RS  g_LF  g_RF "
          f"{'p deg/s':>8s} {'q deg/s':>8s}")
    i0, i1 = int(round(args.t0 / res.frame_dt_s)), min(int(round(args.t1 / res.frame_dt_s)), len(lo) - 1)
    for i in range(i0, i1 + 1, args.every):
        g = gains[i]
        print(f"{res.time_s[i]:6.2f} {lo[i]:9.2f} {pr[i]:8.2e} {pi[i]:8.2e} "
              f"{g[0]:5.2f} {g[1]:5.2f} {g[2]:5.2f} {g[3]:5.2f} {rates[i, 0]:8.2f} {rates[i, 1]:8.2f}")
    i2 = int(round(5.0 / res.frame_dt_s))
    rival_at = next((d["time_s"] for d in res.declarations if d["hypothesis"] == args.rival), None)
    end = int(round(rival_at / res.frame_dt_s)) if rival_at is not None else i1
    inc = np.diff(lo[i2:end + 1])
    inc = inc[np.isfinite(inc) & (np.abs(inc) < 50)]
    if inc.size:
        print(f"from {second}'s onset to {'the rival declared' if rival_at else '--to'}: mean increment of L "
              f"{inc.mean():+.3f} nats a frame over {inc.size} frames, {int((inc > 0).sum())} climbing")


if __name__ == "__main__":
    main()
