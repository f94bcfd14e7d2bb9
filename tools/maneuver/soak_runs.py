"""The runs of a soak that a diagnosis tool flies again: its ``runs.jsonl`` and a selection of
them by run index (``--runs 4,6``), with the bank they flew, and the one flight-and-replay
that fuel_freeze.py, node_bias.py and transition_lag.py share (``fly_and_replay``)."""
from __future__ import annotations

import argparse
import json
from typing import Callable

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import NONE


def add_arguments(ap: argparse.ArgumentParser) -> None:
    """The positional ``runs`` (a soak's runs.jsonl) and ``--runs`` (comma-separated run_index values)."""
    ap.add_argument("runs", help="a soak's runs.jsonl")
    ap.add_argument("--runs", dest="select", help="comma-separated run_index values (default all)")


def selected(ap: argparse.ArgumentParser, args: argparse.Namespace) -> tuple[list[dict], object]:
    """(the selected records, the bank of the first), or the parser's error when none is selected."""
    with open(args.runs) as f:
        records = [json.loads(line) for line in f if line.strip()]
    if args.select:
        keep = {int(v) for v in args.select.split(",")}
        records = [r for r in records if r["run_index"] in keep]
    if not records:
        ap.error("no run selected")
    return records, load_bank(records[0]["bank"])[2]


def fly_and_replay(record: dict, bank, extra: dict | None = None,
                   after_update: Callable | None = None, after_propagate: Callable | None = None):
    """A run flown again as recorded (its scenario, the estimator settings of the record with
    ``extra`` over them), then the estimator replayed on the flight's series with the same
    settings: per frame i ``schedule(air data)``, ``z_hat = update(z)``, ``after_update(i, est,
    z_hat, series)``, ``propagate(u)``, ``after_propagate(i, est, series)``, ``series`` the
    flight's (z, u, the air data and the truth's log).  Returns the flight."""
    options = dict(record["estimator"])
    options.update(extra or {})
    flight = fly(scenario_from_dict(record["scenario"]), bank, estimator_options=options, record_series=True)
    s = flight.series
    est = Estimator(bank, **options)
    for i in range(len(s["z"])):
        est.schedule(*s["air_data"][i])
        z_hat = est.update(s["z"][i])
        if after_update is not None:
            after_update(i, est, z_hat, s)
        est.propagate(s["u"][i])
        if after_propagate is not None:
            after_propagate(i, est, s)
    return flight


def none_residuals(est) -> np.ndarray | None:
    """The no-failure filter's residuals z - H x after the update, or None while NONE is not on line."""
    names = list(est.hypotheses)
    if NONE not in names:
        return None
    return np.asarray(est.core_bank.residuals)[names.index(NONE)]
