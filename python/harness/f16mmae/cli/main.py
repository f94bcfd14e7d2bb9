"""The ``f16mmae`` command line: one subcommand per module of ``f16mmae.cli``."""
from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..errors import F16mmaeError
from . import bench, campaign, design, hil, replay, report, run


#: Subcommands in the order ``--help`` lists them.
SUBCOMMANDS = (run, campaign, design, report, bench, hil, replay)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="f16mmae",
        description=(
            "MMAE failure detection for the F-16 (Eide & Maybeck): fly the nonlinear JSBSim "
            "F-16 with failures injected, run Monte Carlo campaigns, design model banks, "
            "benchmark the C++ estimator."
        ),
        epilog="Run 'f16mmae COMMAND --help' for the options of each command.",
    )
    parser.add_argument("--version", action="version", version=f"f16mmae {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in SUBCOMMANDS:
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except F16mmaeError as exc:
        print(f"f16mmae {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"f16mmae {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
