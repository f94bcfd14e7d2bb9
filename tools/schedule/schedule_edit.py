"""Lab drivers' shared part (not in the wheel): read a scheduled-bank file, and write an edited
copy of it with the same grid, switch rule and metadata plus the edit's description.

Used by failed_sensor_window.py and reference_scale.py (each edits the nodes its own way)."""
from __future__ import annotations

import argparse
import json
import math

from f16mmae import core


def number(text: str, what: str, positive: bool) -> float:
    """An argparse type: a finite number, > 0 (positive) or >= 0; the error names ``what``."""
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{what} {text!r} is not a number") from None
    if not math.isfinite(x) or (x <= 0.0 if positive else x < 0.0):
        raise argparse.ArgumentTypeError(f"{what} {text!r} must be finite and {'> 0' if positive else '>= 0'}")
    return x


def load_schedule(parser: argparse.ArgumentParser, path: str) -> dict:
    """The schedule of the file at ``path`` (core.load_bank(path).schedule); a parser error that
    names the file when it cannot be read or is a bank designed at one point."""
    try:
        b = core.load_bank(path)
    except (OSError, RuntimeError, ValueError) as exc:
        parser.error(f"SCHEDULE {path!r}: {exc}")
    if b.schedule is None:
        parser.error(f"SCHEDULE {path!r} is a bank designed at one point, not a scheduled bank")
    return b.schedule


def save_edited(s: dict, nodes: list, out: str, experiment: str, start_up_s: float | None = None) -> str:
    """Writes ``nodes`` (core.save_schedule's tuples) on the grid of schedule ``s`` to ``out``,
    its metadata's "experiment" set to ``experiment`` and its start-up ``start_up_s`` (None:
    the file's); prints ``out`` and the content hash's first 12 digits, and returns the hash."""
    meta = json.loads(s["metadata"])
    meta["experiment"] = experiment
    h = core.save_schedule(list(s["mach"]), list(s["alt_ft"]), nodes, primary=s["primary"],
                           metadata=json.dumps(meta, sort_keys=True, separators=(",", ":")), path=out,
                           switch_state=s["switch_state"], switch_thresholds=list(s["switch_thresholds"]),
                           start_up_s=s["start_up_s"] if start_up_s is None else start_up_s)
    print(out, h[:12])
    return h
