"""The sensor-loss dither (truth/dither.py ``sensor_loss_gains``): where its gain table comes from
and what it does to the subliminal criterion.

``lines``: each dither line's share of every criterion channel at the nominal point (20,000 ft,
Mach 0.4; no noise, no turbulence, the control law on the sensors).  Each line (the stabilators'
pair in phase, the stabilators' pair in opposite phase, the flaperons' pair, the rudder) is flown
alone; the peak over the last 6 s of |Delta n_z|, |p|, |q|, |r|, |Delta n_y| is that line's
A_{l,c}.  A row's gains g_j give the lines the gains (g_LS + g_RS)/2 (in phase),
|g_LS - g_RS|/2 (opposite phase), g_LF = g_RF, g_RUD; the dither's peak is at most
sum_l g_l A_{l,c} (the lines' frequencies are incommensurate, so over a long flight the peaks
add; the two stabilator lines share one frequency, and the bound adds them all the same), and
the table's gains keep that bound within the criterion.

``peaks``: the closed loop as the campaigns fly it (the MMAE's estimate fed back), no noise, no
turbulence, the sensor failed (``complete``) at 1 s (``--fail-at``) and declared by the estimator, with and
without ``--sensor-loss-dither``: the truth's peak |Delta n_z|, |p|, |q|, |r|, |Delta n_y| from
the declaration (the gains' switch included) to the end (about the first frame's, the trim), against the criterion.

    .venv/bin/python tools/dual/sensor_loss_dither.py lines
    .venv/bin/python tools/dual/sensor_loss_dither.py peaks --bank BANK [--sensors PIT,AZ] [--declare-components]
"""
from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from f16mmae.names import SENSORS
from f16mmae.truth import Scenario, fly_raw
from f16mmae.truth.dither import CRITERION, DitherSpec, SENSOR_LOSS_GAINS

#: The lines: name -> (the surfaces, LS RS LF RF RUD indices, on it; RS in opposite phase).
LINES = {"stabilators": ((0, 1), False), "stabilators, opposite": ((0, 1), True), "flaperons": ((2, 3), False),
         "flaperons, opposite": ((2, 3), True), "rudder": ((4,), False)}
#: z indices of the criterion channels and their criterion (n_z, p, q, r in deg/s, n_y).
CHANNELS = (("n_z g", 3, CRITERION["nz_g"], False), ("p deg/s", 4, CRITERION["rate_deg_s"], True),
            ("q deg/s", 2, CRITERION["rate_deg_s"], True), ("r deg/s", 5, CRITERION["rate_deg_s"], True),
            ("n_y g", 6, CRITERION["ny_g"], False))


def peaks(dz: np.ndarray) -> np.ndarray:
    """Peak of each criterion channel over the rows of ``dz`` (frames, 7), rates in deg/s."""
    out = []
    for _, j, _, deg in CHANNELS:
        v = float(np.abs(dz[:, j]).max())
        out.append(np.degrees(v) if deg else v)
    return np.array(out)


def line_peaks(duration_s: float = 8.0) -> dict[str, np.ndarray]:
    """A_{l,c}: each line alone, peaks over the last 6 s (module docstring)."""
    base = DitherSpec()
    out = {}
    for name, (idx, opposite) in LINES.items():
        amp = [a if j in idx else 0.0 for j, a in enumerate(base.amplitude_deg)]
        phase = list(base.phase_rad)
        if opposite:
            phase[idx[1]] += np.pi
        sc = Scenario(duration_s=duration_s, noise=False, feedback="raw",
                      dither=dataclasses.replace(base, amplitude_deg=tuple(amp), phase_rad=tuple(phase)))
        truth, _ = fly_raw(sc)
        log = truth.truth_log
        keep = log["time_s"] >= duration_s - 6.0
        out[name] = peaks((log["z_ideal"] - truth.trim.z)[keep])
    return out


def line_gains(row) -> dict[str, float]:
    """The lines' gains of a row of gains per surface (module docstring)."""
    return {"stabilators": abs(row[0] + row[1]) / 2.0, "stabilators, opposite": abs(row[0] - row[1]) / 2.0,
            "flaperons": abs(row[2] + row[3]) / 2.0, "flaperons, opposite": abs(row[2] - row[3]) / 2.0,
            "rudder": abs(row[4])}


def _lines(args) -> None:
    a = line_peaks()
    crit = np.array([c for *_, c, _ in CHANNELS])
    print("line".ljust(22) + "".join(f"{n:>10s}" for n, *_ in CHANNELS))
    for name, v in a.items():
        print(name.ljust(22) + "".join(f"{x:10.4f}" for x in v))
    print("criterion".ljust(22) + "".join(f"{x:10.4f}" for x in crit))
    print("\nper sensor: line gains of the table and the bound sum_l g_l A_lc / criterion")
    for s in SENSORS:
        g = SENSOR_LOSS_GAINS.get(s)
        if g is None:
            continue
        bound = sum(w * a[n] for n, w in line_gains(g).items())
        print(f"{s:4s} gains {g}  bound/criterion " + " ".join(f"{x:.2f}" for x in bound / crit))


def _peaks(args) -> None:
    from f16mmae.banks import load_bank
    from f16mmae.loop.flight import fly, scenario_from_dict

    _, _, bank = load_bank(args.bank)
    crit = np.array([c for *_, c, _ in CHANNELS])
    print(f"{'sensor':6s} {'option':>6s} {'declared':>14s} " + "".join(f"{n:>9s}" for n, *_ in CHANNELS)
          + "   largest share")
    for s in args.sensors.split(","):
        for on in (False, True):
            scenario = {"mach": 0.4, "alt_ft": 20000.0, "turbulence": "none", "noise": args.noise,
                        "duration_s": args.duration, "seed": 1, "feedback": "mmae",
                        "failures": [{"name": s, "time_s": args.fail_at, "mode": "complete"}]}
            opts = {"declare_components": args.declare_components}
            if on:
                opts["sensor_loss_dither"] = True
            res = fly(scenario_from_dict(scenario), bank, estimator_options=opts, record_probabilities=False,
                      record_series=True)
            log = res.series["truth_log"]
            first = next((d for d in res.declarations if d["hypothesis"] != "NONE"), None)
            t0 = (first["time_s"] if first else args.fail_at) + args.after
            keep = log["time_s"] >= t0
            p = peaks((log["z_ideal"] - log["z_ideal"][0])[keep])  # frame 0: the trim
            decl = f"{first['hypothesis']}@{first['time_s']:.2f}" if first else "-"
            print(f"{s:6s} {'on' if on else 'off':>6s} {decl:>14s} " + "".join(f"{x:9.4f}" for x in p)
                  + f"   {float((p / crit).max()):.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("lines", help="each line's share of the criterion channels")
    p = sub.add_parser("peaks", help="closed-loop peaks after a declared sensor, with and without the option")
    p.add_argument("--bank", required=True)
    p.add_argument("--sensors", default=",".join(SENSOR_LOSS_GAINS))
    p.add_argument("--declare-components", action="store_true")
    p.add_argument("--duration", type=float, default=10.0)
    p.add_argument("--noise", action="store_true",
                   help="the sensors' noise on (flight seed 1): a noise-free flight declares VEL by 2.2 s")
    p.add_argument("--fail-at", type=float, default=1.0, help="the sensor's failure time (s)")
    p.add_argument("--after", type=float, default=0.0, help="start the window this many seconds after the declaration")
    args = ap.parse_args()
    {"lines": _lines, "peaks": _peaks}[args.cmd](args)


if __name__ == "__main__":
    main()
