"""The ``f16mmae`` command line: one subcommand per module in ``f16mmae.commands``."""
from __future__ import annotations

import argparse
import importlib
import math
import sys

from . import __version__

#: Subcommands in the order ``--help`` lists them.
SUBCOMMANDS = ("run", "campaign", "design", "report", "bench", "hil", "replay")


class CliError(Exception):
    """A bad argument: the message names the bad value and the valid choices."""


def number(option: str, value, *, integer: bool = False, minimum=None, exclusive: bool = False,
           below=None):
    """``value`` of ``option`` as an int (``integer``) or a finite float, at least ``minimum``
    (above it if ``exclusive``) and below ``below``; CliError naming the option, the value
    and the valid range otherwise."""
    try:
        x = int(value) if integer else float(value)
    except (TypeError, ValueError):
        kind = "an integer" if integer else "a number"
        raise CliError(f"{option} {value!r} is not {kind}") from None
    if not integer and not math.isfinite(x):
        raise CliError(f"{option} {value!r} must be finite")
    if minimum is not None and (x <= minimum if exclusive else x < minimum):
        raise CliError(f"{option} {value!r} must be {'>' if exclusive else '>='} {minimum}")
    if below is not None and not x < below:
        raise CliError(f"{option} {value!r} must be < {below}")
    return x


def choice(option: str, value: str, valid) -> str:
    """``value`` of ``option`` lower-cased if it is one of ``valid``; CliError listing them."""
    v = value.lower()
    if v not in valid:
        raise CliError(f"{option} {value!r} is unknown; valid: {', '.join(valid)}")
    return v


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
