"""Per-frame evidence of chosen runs of a maneuver campaign: which hypothesis rises, when, in
which flight phase, and what the failed sensor reads against the truth.

Re-flies each selected run of a campaign's ``runs.jsonl`` (its scenario, bank and estimator
settings, ``fly(record_series=True)``: the same flight, bit for bit) and replays the recorded
u, z and air data through a fresh ``loop.estimator.Estimator`` with the same settings, frame by
frame, recording what the estimator is (its level, its declaration, its probabilities, the
adaptation's residual power ratio rho). Truth is read only from the flight's log, after the
flight, for the printout (bank angle, true speed minus the VEL reading).

Selections (``--select``, comma-separated): ``false-alarms`` (every run with a false alarm),
``wrong`` (every failure run not ending correct), ``MANEUVER:CASE`` (every run of it),
``MANEUVER:CASE:N`` (run N).

Per run: its declarations, then every ``--every`` seconds (and at each declaration) one row:
t, level, declared, the three hypotheses with the largest probability besides NONE as
``name ln(p/p_NONE)``, rho (the turbulence adaptation's residual power ratio: its reference
while the adaptation is off), bank angle phi, n_z, VEL truth - reading (ft/s), and the measured
air data (Mach, pressure altitude); with ``--trim`` also the trim tracker's offsets dz of AOA
(deg), ROL and YAW (deg/s), AZ (g), du of the stabilators (deg) and the throttle, and whether it
was frozen (a run flown with ``--trim-tracking``). A soak's runs.jsonl works too (``false-alarms``). For VEL runs a
summary: the truth-minus-reading at 6/8/10/12/14 s, and ln(p_VEL/p_NONE) per second at level 0
after the failure (the evidence rate) until the first declaration.

Evidence rates (``--rates``): the runs are replayed with a floor of 1e-300 (690 nats down, so
the log-odds are the cumulative log-likelihood ratio and no level switch happens in practice),
and per run the mean rate of ln(p_VEL/p_NONE) (nats/s, the hypothesis of the run's case against
NONE) from the failure to the end is printed, one line a run; ``--throttle-dither A[@F]``
flies a fixed throttle dither amplitude A (command units) at F Hz (default 0.1) instead of the
scheduled one (a_th = 0.9 x 0.02 g / b_x, 0.0215 at Mach 0.4 / 20,000 ft; A = 1e-12: none).

Run: .venv/bin/python tools/maneuver/evidence.py results/DIR/runs.jsonl --select false-alarms
     .venv/bin/python tools/maneuver/evidence.py results/DIR/runs.jsonl --select turn:VEL --rates
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import FRAME_RATE_HZ, NONE, SENSORS


def selected(records: list[dict], select: str) -> list[dict]:
    out = []
    for item in select.split(","):
        if item == "false-alarms":
            out += [r for r in records if r["false_alarm"]]
        elif item == "wrong":
            out += [r for r in records if r["case"] != NONE and r["outcome"] != "correct"]
        else:
            parts = item.split(":")
            out += [r for r in records if r.get("maneuver") == parts[0] and r["case"] == parts[1]
                    and (len(parts) < 3 or r["run_index"] == int(parts[2]))]
    seen, unique = set(), []
    for r in out:
        if r["run_key"] not in seen:
            seen.add(r["run_key"])
            unique.append(r)
    return unique


def replay(record: dict, bank, p_min: float | None = None, throttle: tuple[float, float] | None = None,
           extra: dict | None = None) -> dict:
    """The flight of ``record`` and its frame-by-frame estimator trace (the replayed estimator
    with the floor ``p_min`` and the settings ``extra`` if given; the truth with the fixed
    throttle dither (amplitude, Hz) if given)."""
    options = dict(record["estimator"])
    scenario = scenario_from_dict(record["scenario"])
    if throttle is not None:
        scenario = dataclasses.replace(scenario, dither=dataclasses.replace(
            scenario.dither, throttle_amplitude=throttle[0], throttle_frequency_hz=throttle[1]))
    flight = fly(scenario, bank, estimator_options=options, record_series=True)
    if p_min is not None:
        options["p_min"] = p_min
    options.update(extra or {})
    s = flight.series
    est = Estimator(bank, **options)
    n = len(s["z"])
    trace = {"level": np.zeros(n, int), "declared": [], "rho": np.zeros(n), "log_odds": [], "trim": []}
    for i in range(n):
        est.schedule(*s["air_data"][i])
        est.update(s["z"][i])
        p = np.asarray(est.probabilities, float)
        names = est.hypotheses
        trace["level"][i] = est.level
        trace["declared"].append(est.declared)
        trace["rho"][i] = est.turbulence_power_ratio
        p_none = p[names.index(NONE)] if NONE in names else float("nan")
        trace["log_odds"].append({h: math.log(max(p[k], 1e-300) / p_none) for k, h in enumerate(names) if h != NONE})
        est.propagate(s["u"][i])
        du, dz = est.core_bank.trim_offset
        trace["trim"].append((np.array(du), np.array(dz), bool(est.core_bank.trim_frozen)))
    return {"flight": flight, "truth": s["truth_log"], "trace": trace}


def trim_columns(trim: tuple) -> str:
    """dz of AOA, ROL, YAW (deg, deg/s), AZ (g); du of LS, RS (deg) and the throttle; frozen."""
    du, dz, frozen = trim
    m = {name: i for i, name in enumerate(SENSORS)}
    th = f"{du[5]:+7.4f}" if len(du) > 5 else "      -"
    return (f" {math.degrees(dz[m['AOA']]):+6.3f} {math.degrees(dz[m['ROL']]):+6.3f} {math.degrees(dz[m['YAW']]):+6.3f}"
            f" {dz[m['AZ']]:+6.3f} {math.degrees(du[0]):+6.3f} {math.degrees(du[1]):+6.3f} {th} {'F' if frozen else '.'}")


def show(record: dict, run: dict, every_s: float, trim: bool = False) -> None:
    fl, log, tr = run["flight"], run["truth"], run["trace"]
    t = fl.time_s
    print(f"\n== {record.get('maneuver', record['kind'])} {record['case']} run {record['run_index']} (seed {record['seed']}, "
          f"{', '.join(record['scenario']['maneuvers'])}, failure at {record.get('failure_time_s')}): outcome "
          f"{record['outcome']}{' + false alarm' if record['false_alarm'] else ''}, declarations "
          + ", ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in fl.declarations))
    phi = np.degrees(log["state"][:, 5])
    nz = log["z_ideal"][:, 3]
    dvel = log["z_ideal"][:, 0] - log["z"][:, 0]
    step = max(1, round(every_s * FRAME_RATE_HZ))
    marks = set(range(0, len(t), step)) | {round(d["time_s"] * FRAME_RATE_HZ) for d in fl.declarations}
    air = fl.series["air_data"]
    print(f"{'t':>6} {'lvl':>3} {'declared':>9} {'top ln(p/p_NONE)':<48} {'rho':>5} {'phi':>6} {'n_z':>6} {'dVEL':>6} "
          f"{'Mach':>6} {'h_p ft':>7}"
          + (" dzAOA° dzROL  dzYAW  dzAZ   duLS°  duRS°  du_th   frz" if trim else ""))
    for i in sorted(m for m in marks if m < len(t)):
        top = sorted(tr["log_odds"][i].items(), key=lambda kv: -kv[1])[:3]
        print(f"{t[i]:6.2f} {tr['level'][i]:3d} {tr['declared'][i]:>9} "
              f"{'  '.join(f'{h} {v:6.1f}' for h, v in top):<48} {tr['rho'][i]:5.2f} {phi[i]:6.1f} "
              f"{nz[i]:6.2f} {dvel[i]:6.1f} {air[i, 0]:6.3f} {air[i, 1]:7.0f}"
              + (trim_columns(tr["trim"][i]) if trim else ""))
    if record["case"] == "VEL":
        at = [min(len(t) - 1, round(x * FRAME_RATE_HZ)) for x in (6, 8, 10, 12, 14)]
        i0 = round(record["failure_time_s"] * FRAME_RATE_HZ)
        first = next((round(d["time_s"] * FRAME_RATE_HZ) for d in fl.declarations
                      if d["time_s"] >= record["failure_time_s"]), len(t) - 1)
        lo = [tr["log_odds"][i].get("VEL", float("nan")) for i in range(i0, first + 1)]
        rate = (lo[-1] - lo[0]) / max(1e-9, (first - i0) / FRAME_RATE_HZ) if len(lo) > 1 else float("nan")
        print("VEL truth - reading at 6/8/10/12/14 s (ft/s, 1-s means): "
              + " / ".join(f"{dvel[max(0, i - 32):i + 32].mean():+.1f}" for i in at)
              + f"; ln(p_VEL/p_NONE) {lo[0]:.1f} -> {lo[-1]:.1f} over {(first - i0) / FRAME_RATE_HZ:.2f} s "
              f"({rate:.1f} nats/s) at level 0 until the first declaration")


def rate(record: dict, run: dict) -> float:
    """Mean d/dt ln(p_case/p_NONE) from the failure to the end of the flight, nats/s."""
    lo = [x.get(record["case"], float("nan")) for x in run["trace"]["log_odds"]]
    i0 = round(record["failure_time_s"] * FRAME_RATE_HZ)
    return (lo[-1] - lo[i0]) / ((len(lo) - 1 - i0) / FRAME_RATE_HZ)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", help="a maneuver campaign's runs.jsonl")
    ap.add_argument("--select", default="false-alarms")
    ap.add_argument("--every", type=float, default=0.5, help="seconds between rows (default 0.5)")
    ap.add_argument("--rates", action="store_true", help="evidence rates with the floor at 1e-300 (module docstring)")
    ap.add_argument("--trim", action="store_true", help="the trim tracker's offsets in each row (module docstring)")
    ap.add_argument("--throttle-dither", metavar="A[@F]", help="a fixed throttle dither instead of the scheduled")
    ap.add_argument("--replay-option", metavar="KEY=VALUE", action="append", default=[],
                    help="an estimator setting of the replay only (the flight is the record's), e.g. "
                         "adapt_turbulence=true to read rho; numbers and true/false")
    args = ap.parse_args(argv)
    extra = {}
    for item in args.replay_option:
        key, _, value = item.partition("=")
        extra[key] = value == "true" if value in ("true", "false") else float(value)
    throttle = None
    if args.throttle_dither:
        a, _, f = args.throttle_dither.partition("@")
        throttle = (float(a), float(f or 0.1))
    records = [json.loads(line) for line in open(args.runs)]
    banks: dict[str, object] = {}
    rates = []
    for record in selected(records, args.select):
        bank = banks.setdefault(record["bank"], load_bank(record["bank"])[2])
        run = replay(record, bank, p_min=1e-300 if args.rates else None, throttle=throttle, extra=extra)
        if args.rates:
            rates.append(rate(record, run))
            print(f"{record['maneuver']} {record['case']} run {record['run_index']}: "
                  f"{rates[-1]:+.2f} nats/s of {record['case']} against NONE after the failure")
        else:
            show(record, run, args.every, trim=args.trim)
    if rates:
        print(f"mean {np.mean(rates):+.2f} nats/s, median {np.median(rates):+.2f}, "
              f"{sum(r > 0 for r in rates)} of {len(rates)} positive")


if __name__ == "__main__":
    main()
