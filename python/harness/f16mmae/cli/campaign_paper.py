"""``f16mmae campaign paper``: the paper's whole campaign, one command.

The paper's three campaigns, each flown and written exactly as its own command would, one after
the other on one executor -- one pool, whose workers keep their banks, estimators and trimmed
aircraft from one campaign to the next -- with the command's start (imports, the pool) paid
once instead of three times::

    envelope  f16mmae campaign envelope --runs N --seed S --out DIR/envelope
    single    f16mmae campaign single   --runs N --seed S --baseline none --out DIR/single
    dual      f16mmae campaign dual     --runs N --seed S --out DIR/dual

(the 25 points of Fig. 9; the 13 cases; the 132 ordered pairs with the 12 lone second
failures -- the shipped tuned bank, light turbulence, complete failures).  Each summary names the
single command that gives the same records.  The three directories are checked writable before
the first flight; with ``--check`` the exit status is 1 when any of the three misses a goal.
The single campaign's runs are the envelope's at its nominal point NOM (the same specs): they
are flown once, for the envelope, and stored for the single part too (``engine.shared_flights``).
Each part's figures are drawn by the pool's processes, side by side, before the next part's
flights, and its report page on a background thread (``report.drawing``); every file is
written when the command returns.  The parts run in the order above: the single part, which
flies nothing, while the pool draws the envelope's figures, and the dual last, so that after
its last flight only its own two figures are left to draw.
"""
from __future__ import annotations

import argparse
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from ..campaign.engine.config import RUNS_MAX
from ..campaign.engine import shared_flights
from ..campaign.engine.executor import WORKERS_MAX, default_workers, make_executor
from ..outputs import writable_dir
from ..report.drawing import drawing_in_background
from . import campaign_dual, campaign_envelope, campaign_single
from .options import number, seed

#: The campaigns in the order they fly: (name, command-line module, what its command adds).
PARTS = (("envelope", campaign_envelope, ()),
         ("single", campaign_single, ("--baseline", "none")),
         ("dual", campaign_dual, ()))


def register(kinds) -> None:
    p = kinds.add_parser("paper", help="the paper's whole campaign (single, dual, envelope) on one pool",
                         description=__doc__.split("\n", 1)[1].replace("``", "").replace("::", ":"),
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--runs", default="10", metavar="N", help="seeded runs per case, pair and point (default 10)")
    p.add_argument("--seed", default="1", metavar="S", help="campaign seed >= 1 (default 1)")
    p.add_argument("--workers", default=None, metavar="W", help="local worker processes (default: all cores)")
    p.add_argument("--out", default="results/campaign-paper", metavar="DIR",
                   help="output directory: DIR/single, DIR/dual, DIR/envelope (default results/campaign-paper)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.add_argument("--check", action="store_true", help="exit 1 when a goal of any of the three is not met")
    p.set_defaults(func=_paper)


def part_arguments(name: str, module, extra: tuple[str, ...], args, out: Path) -> argparse.Namespace:
    """What the part's own command line parses for this part (``argv`` included, for its record)."""
    parser = argparse.ArgumentParser(prog="f16mmae campaign")
    module.register(parser.add_subparsers(dest="kind"))
    argv = [name, "--runs", str(args.runs), "--seed", str(args.seed), *extra, "--out", str(out)]
    argv += ["--quiet"] * args.quiet + ["--check"] * args.check
    ns = parser.parse_args(argv)
    ns.argv = ["campaign", *argv]
    return ns


def _paper(args) -> int:
    number("--runs", args.runs, integer=True, minimum=1, maximum=RUNS_MAX)
    seed("--seed", args.seed)
    workers = (number("--workers", args.workers, integer=True, minimum=1, maximum=WORKERS_MAX)
               if args.workers is not None else None)
    root = Path(args.out)
    parts = [(name, part_arguments(name, module, extra, args, root / name)) for name, module, extra in PARTS]
    for _, ns in parts:  # every output checked before the first flight
        writable_dir(ns.out)
    status = 0
    # each part's figures are drawn by the pool's processes (queued before the next part's
    # flights) and its report page on a background thread (report.drawing); all are written
    # when the command returns. The local pool forks all its workers at its first flight,
    # before that thread exists.
    with make_executor(workers=workers) as ex, \
            drawing_in_background(processes=ex if isinstance(ex, ProcessPoolExecutor) else None), \
            shared_flights.sharing():
        for name, ns in parts:
            ns.executor, ns.executor_label = ex, f"{workers or default_workers()} local process(es), shared"
            print(f"=== campaign {name} ({ns.out}) ===", flush=True)
            status = max(status, ns.func(ns))
            print(flush=True)
    return status
