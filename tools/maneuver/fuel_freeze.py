"""Whether the truth's fuel burn is what the no-failure filter misfits late in a soak flight:
each run of a soak's ``runs.jsonl`` flown again as recorded and with the truth's fuel frozen
(JSBSim ``propulsion/fuel_freeze``: the weight, centre of gravity and inertia held at the trim's),
everything else the same (seeds, turbulence, maneuvers, estimator settings).

Per run and variant: the false declarations (hypothesis @ time), the truth's weight at the end,
and the NONE filter's mean AOA and AZ residuals over each 90-s segment of the flight, in units
of the recorded flight's RMS (replayed as ``node_bias.py``). A weight that falls with the fuel
lowers the angle of attack a load factor needs; the bank's models and trims are for the trim's
weight, so the misfit it leaves is AOA below and AZ above prediction, growing with time.

Truth (the weight) is read from the flight after the flight, for this diagnosis only; freezing
the fuel changes the truth model, never the estimator.

    .venv/bin/python tools/maneuver/fuel_freeze.py DIR/runs.jsonl [--runs 4,6] [--segment-s 90] [--plot FILE]

``--plot FILE``: the flights' mean AOA and AZ residual per segment, fuel burning and frozen (PNG).
"""
from __future__ import annotations

import argparse
import contextlib

import numpy as np

import f16mmae.truth.model as truth_model
from f16mmae.names import FRAME_RATE_HZ, NONE, SENSORS

import soak_runs  # tools/maneuver: the soak's runs flown again


@contextlib.contextmanager
def fuel_frozen(on: bool):
    """While active, every truth model built freezes its fuel (after its turbulence is set)."""
    original = truth_model.turbulence.apply
    seen = []

    def apply(fdm, level):
        original(fdm, level)
        fdm["propulsion/fuel_freeze"] = 1.0 if on else 0.0
        seen.append(fdm)

    truth_model.turbulence.apply = apply
    try:
        yield seen
    finally:
        truth_model.turbulence.apply = original


def flight(record: dict, bank, freeze: bool, segment_s: float, rms=None) -> dict:
    ia, iz = SENSORS.index("AOA"), SENSORS.index("AZ")
    rows = []

    def residuals(i, est, z_hat, series):
        r = soak_runs.none_residuals(est)
        rows.append((r[ia], r[iz]) if r is not None else (np.nan, np.nan))

    with fuel_frozen(freeze) as fdms:
        f = soak_runs.fly_and_replay(record, bank, after_update=residuals)
        weight = float(fdms[-1]["inertia/weight-lbs"]) if fdms else float("nan")
    res = np.array(rows, float).reshape(-1, 2)
    if rms is None:
        rms = np.sqrt(np.nanmean(res ** 2, axis=0))
    res = res / rms
    k = int(round(segment_s * FRAME_RATE_HZ))
    segments = [np.nanmean(res[j:j + k], axis=0) for j in range(0, len(res), k) if len(res[j:j + k]) > k // 2]
    false = [f"{d['hypothesis']}@{d['time_s']:.1f}" for d in f.declarations if d.get("hypothesis", NONE) != NONE]
    return {"false": false, "weight": weight, "segments": segments, "rms": rms}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    soak_runs.add_arguments(ap)
    ap.add_argument("--segment-s", type=float, default=90.0, help="segment of the residual means, s (default 90)")
    ap.add_argument("--plot", metavar="FILE", help="also draw the segment means of both variants (PNG)")
    args = ap.parse_args(argv)
    records, bank = soak_runs.selected(ap, args)
    totals = {False: 0, True: 0}
    means = {False: [], True: []}
    for r in records:
        base = flight(r, bank, False, args.segment_s)
        frozen = flight(r, bank, True, args.segment_s, rms=base["rms"])
        for label, out, key in (("fuel burns", base, False), ("fuel frozen", frozen, True)):
            totals[key] += len(out["false"])
            means[key].append(out["segments"])
            seg = " ".join(f"{a:+.2f}/{z:+.2f}" for a, z in out["segments"])
            print(f"run {r['run_index']} {label:<11} weight at end {out['weight']:8.1f} lb; false: "
                  f"{', '.join(out['false']) or '-'}; NONE AOA/AZ mean per {args.segment_s:g} s: {seg}")
    print(f"false declarations over {len(records)} flights: fuel burns {totals[False]}, fuel frozen {totals[True]}")
    if args.plot:
        plot(means, totals, args.segment_s, args.plot)


def plot(means: dict, totals: dict, segment_s: float, path: str) -> None:
    """NONE's AOA and AZ residual means per segment, averaged over the flights, both variants."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.6))
    for key, label, style in ((False, "fuel burns", "-"), (True, "fuel frozen", "--")):
        m = np.mean(np.array([seg for seg in means[key] if len(seg) == len(means[key][0])]), axis=0)
        t = segment_s * (np.arange(len(m)) + 0.5)
        ax.plot(t, m[:, 0], "C0" + style, marker="o", label=f"AOA, {label} ({totals[key]} false declarations)")
        ax.plot(t, m[:, 1], "C3" + style, marker="s", label=f"AZ, {label}")
    ax.axhline(0.0, color="grey", lw=0.5)
    ax.set_xlabel("time in flight (s), segment centres")
    ax.set_ylabel("NONE's residual mean (RMS units)")
    ax.legend(fontsize=7)
    ax.set_title("soak flights: the no-failure filter's AOA/AZ misfit with and without fuel burn")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
