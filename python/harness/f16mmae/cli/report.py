"""``f16mmae report DIR``: render a campaign or run directory as one HTML page."""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..campaign import import_kinds
from ..report.markdown import summary_markdown
from ..report.page import render_report
from .options import CliError

EXAMPLES = """\
examples:
  f16mmae campaign single --out results/single   # writes results/single/report.html too
  f16mmae report results/single                  # re-render it (e.g. after a resume)
  f16mmae run --fail PIT@3.0 --out results/pit
  f16mmae report results/pit                     # one run's page
  f16mmae report results/single --markdown docs/results/single.md   # results page from summary.json
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
    p.add_argument("--markdown", default=None, metavar="FILE",
                   help="also write the campaign's results as Markdown to FILE (e.g. docs/results/single.md)")
    p.set_defaults(func=_report)


def _report(args) -> int:
    import_kinds()  # each kind registers its report pages
    if args.markdown is not None:
        md = Path(args.markdown)
        if md.is_dir() or not md.parent.is_dir():
            raise CliError(f"--markdown {md}: need a file path in an existing directory")
    path = render_report(args.directory)
    print(f"report: {path}")
    if args.markdown is not None:
        summary_path = Path(args.directory) / "summary.json"
        if not summary_path.is_file():
            raise CliError(f"--markdown: {args.directory} holds no summary.json (a campaign directory is needed)")
        try:
            text = summary_markdown(json.loads(summary_path.read_text()))
        except ValueError as exc:
            raise CliError(f"--markdown: {summary_path}: {exc}") from None
        md.write_text(text, encoding="utf-8")
        print(f"markdown: {md}")
    return 0
