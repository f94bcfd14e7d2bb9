"""The runs of a soak that a diagnosis tool flies again: its ``runs.jsonl`` and a selection of
them by run index (``--runs 4,6``), with the bank they flew.  Shared by fuel_freeze.py and
node_bias.py."""
from __future__ import annotations

import argparse
import json

from f16mmae.banks import load_bank


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
