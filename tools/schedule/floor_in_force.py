"""Lab driver (not in the wheel): the scheduled estimator's probability floor in force around a
declaration, flown with two scheduled banks.

    python tools/schedule/floor_in_force.py RUNS_JSONL --seed N --turbulence LEVEL \\
        --banks scheduled,OTHER.f16sched --around T [--window 20] [--labels A,B] [--figure FILE]

Flies the run of RUNS_JSONL (a campaign's runs.jsonl) with seed N in air LEVEL again with the
options it was given (its record's ``estimator``, as its reproduce command flies it), once with
each bank of ``--banks`` (the first is the record's own: the flight must declare what the record
says), recording after every update the floor in force (``p_min_in_force``: a scheduled bank's
nodes' floors blended over the cell in force, ``node_p_min``; cpp/f16mmae/scheduled_filters.h)
and the probability of the hypothesis the record declared first. Prints, per bank, the
declarations and the floors met in the window ``--around`` T +- ``--window`` / 2 seconds with the
share of its frames at each; ``--figure`` draws the floor (log scale) and that probability over
the window, one colour per bank (docs/results/envelope_scheduled.md, round 45).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import f16mmae.design.schedule  # noqa: F401 -- registers the scheduled bank's generator (designed on first use)
from f16mmae.banks import BankError, load_bank
from f16mmae.campaign.engine.drilldown import flies_as_recorded
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict


def fly_recording_floor(record: dict, bank) -> tuple[object, np.ndarray]:
    """(FlightResult, the floor in force after each update) of ``record`` flown with ``bank``."""
    est = Estimator(bank, **record["estimator"])
    floors = []   # after each frame's update (propagate leaves the floor alone)
    result = fly(scenario_from_dict(record["scenario"]), bank, estimator=est, record_probabilities=True,
                 on_frame=lambda *frame: floors.append(est._bank.p_min_in_force))
    return result, np.asarray(floors)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", type=Path, help="a campaign's runs.jsonl")
    ap.add_argument("--seed", type=int, required=True, help="the run's flight seed (its record's scenario.seed)")
    ap.add_argument("--turbulence", required=True, help="the run's air: none, light, moderate or severe")
    ap.add_argument("--banks", required=True, help="two banks, comma-separated: the record's, then another "
                                                   "(a name such as scheduled, or a .f16sched file)")
    ap.add_argument("--around", type=float, required=True, help="the window's centre, s of flight")
    ap.add_argument("--window", type=float, default=20.0, help="the window's length, s (default 20)")
    ap.add_argument("--labels", help="the two banks' names in the print and the figure, comma-separated "
                                     "(default: --banks as given)")
    ap.add_argument("--figure", type=Path, help="write the floor and the probability over the window here")
    a = ap.parse_args(argv)
    if not a.runs.is_file():
        ap.error(f"{a.runs} does not exist: give a campaign's runs.jsonl")
    if a.figure is not None and not a.figure.parent.is_dir():
        ap.error(f"--figure {a.figure}: the folder {a.figure.parent} does not exist")
    if not a.window > 0.0:
        ap.error(f"--window {a.window} must be a positive number of seconds")
    names = a.banks.split(",")
    if len(names) != 2:
        ap.error(f"--banks {a.banks!r}: give two banks, comma-separated")
    labels = a.labels.split(",") if a.labels else names
    if len(labels) != 2:
        ap.error(f"--labels {a.labels!r}: give two names, comma-separated")
    try:
        banks = [load_bank(n)[2] for n in names]
    except BankError as exc:
        ap.error(f"--banks: {exc}")
    record = next((r for r in map(json.loads, a.runs.read_text().splitlines())
                   if r["scenario"]["seed"] == a.seed and r["scenario"]["turbulence"] == a.turbulence), None)
    if record is None:
        ap.error(f"{a.runs} has no run of seed {a.seed} in {a.turbulence} air")
    first = next((d["hypothesis"] for d in record["declarations"] if d["hypothesis"] != "NONE"), None)
    if first is None:
        ap.error(f"the run of seed {a.seed} in {a.turbulence} air declared no failure: nothing to draw")
    flown = []
    for name, bank in zip(labels, banks):
        result, floors = fly_recording_floor(record, bank)
        if name == labels[0] and not flies_as_recorded(record, result.declarations):
            sys.exit(f"floor_in_force: the run flown again with {name} does not declare what its record says: "
                     "not the code or bank that flew it")
        rate = 1.0 / result.frame_dt_s
        lo, hi = max(0, int((a.around - a.window / 2) * rate)), min(len(floors), int((a.around + a.window / 2) * rate))
        values, counts = np.unique(floors[lo:hi], return_counts=True)
        print(f"{name}: declarations {[(d['hypothesis'], round(d['time_s'], 3)) for d in result.declarations] or 'none'}; "
              f"floors in {lo / rate:.1f}-{hi / rate:.1f} s: "
              + ", ".join(f"{v:.0e} ({c / (hi - lo):.0%})" for v, c in zip(values, counts)))
        flown.append((name, result, floors, lo, hi, rate))
    if a.figure is not None:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 5.0), sharex=True)
        for (name, result, floors, lo, hi, rate), colour in zip(flown, ("C3", "C0")):
            t = np.arange(lo, hi) / rate
            top.semilogy(t, floors[lo:hi], color=colour, label=name)
            bottom.plot(t, result.probability_of(first)[lo:hi], color=colour, label=name)
        top.set_ylabel("floor in force, p_min")
        bottom.set_ylabel(f"p({first})")
        bottom.axhline(0.9, color="0.5", lw=0.8, ls=":")
        bottom.set_xlabel("time of flight, s")
        top.legend(loc="upper left", fontsize=8)
        s = record["scenario"]
        top.set_title(f"Mach {s['mach']:g}, {s['alt_ft']:.0f} ft, {s['turbulence']} air, seed {s['seed']}", fontsize=9)
        fig.tight_layout()
        fig.savefig(a.figure, dpi=110)
        print(f"figure: {a.figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
