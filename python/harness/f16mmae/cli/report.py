"""``f16mmae report DIR``: render a campaign or run directory as one HTML page."""
from __future__ import annotations

import argparse

from ..campaign import dual, envelope, single  # noqa: F401 -- each registers its report page
from ..report.page import render_report

EXAMPLES = """\
examples:
  f16mmae campaign single --out results/single   # writes results/single/report.html too
  f16mmae report results/single                  # re-render it (e.g. after a resume)
  f16mmae run --fail PIT@3.0 --out results/pit
  f16mmae report results/pit                     # one run's page
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "report",
        help="render a campaign or run directory as one HTML page",
        description=(
            "Render DIR/summary.json (from 'f16mmae campaign single --out DIR') or "
            "DIR/run.json (from 'f16mmae run --out DIR') with its figures as one "
            "self-contained HTML page, DIR/report.html (figures embedded)."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("directory", metavar="DIR", help="a campaign or run output directory")
    p.set_defaults(func=_report)


def _report(args) -> int:
    path = render_report(args.directory)
    print(f"report: {path}")
    return 0
