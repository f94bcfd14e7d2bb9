"""The ``f16mmae`` command line: one subcommand per module of ``f16mmae.cli``."""
from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..errors import F16mmaeError
from . import bench, campaign, design, hil, replay, report, run


#: Subcommands in the order ``--help`` lists them.
SUBCOMMANDS = (run, campaign, design, report, bench, hil, replay)


class Parser(argparse.ArgumentParser):
    """Every parser of the CLI, subcommands included (argparse gives nested subparsers their
    parent's class): options are never abbreviated, so a flag a command lacks is refused by
    its name (``--turbulence`` is not read as ``--turbulence-banks``)."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
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
    args, rest = parser.parse_known_args(argv)
    if rest and not getattr(args, "passes_on_arguments", False):
        parser.error(f"unrecognized arguments: {' '.join(rest)}")
    args.passed_on = rest  # a command that runs another program's options (bench lcm) gets them
    args.argv = list(sys.argv[1:] if argv is None else argv)  # the command line as given, for records
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
