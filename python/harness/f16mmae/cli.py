"""The ``f16mmae`` command line: one subcommand per module in ``f16mmae.commands``."""
from __future__ import annotations

import argparse
import importlib
import sys

from . import __version__

#: Subcommands in the order ``--help`` lists them.
SUBCOMMANDS = ("run", "campaign", "design", "report", "bench", "hil", "replay")


class CliError(Exception):
    """A bad argument: the message names the bad value and the valid choices."""


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
    for name in SUBCOMMANDS:
        try:
            module = importlib.import_module(f"f16mmae.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"f16mmae.commands.{name}":
                continue  # subcommand not built yet
            raise
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
    except CliError as exc:
        print(f"f16mmae {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"f16mmae {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
