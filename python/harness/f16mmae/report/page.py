"""``f16mmae report DIR``: one self-contained HTML page from a campaign or run directory.

A campaign directory holds ``summary.json`` and its figures; its ``"kind"`` chooses the page,
from a registry that each campaign kind fills when it is imported (:func:`register_page`), so
this module knows no kind.  A run directory holds ``run.json`` and ``probabilities.png``
(:mod:`.flight`).  Figures are embedded as base64 data URIs so the page can be mailed or
archived as one file.
"""
from __future__ import annotations

import html
import json
from collections.abc import Callable
from pathlib import Path

from ..errors import F16mmaeError
from ..outputs import writable_file
from .drawing import deferrable
from .flight import run_page

#: A page body from a campaign directory and its summary.
PageRenderer = Callable[[Path, dict], str]
_PAGES: dict[str, PageRenderer] = {}


class ReportError(F16mmaeError):
    """The directory holds nothing a report can be made from."""


def register_page(kind: str, render: PageRenderer) -> None:
    """Make ``render(directory, summary)`` the page of campaign summaries of ``kind``."""
    _PAGES[kind] = render


def param_table(rows) -> str:
    """A two-column table of (name, value) pairs, both escaped."""
    return "<table>" + "".join(f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                               for k, v in rows) + "</table>"


_CSS = """
body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;margin:0.8em 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}
th{background:#f3f3f3}td:first-child{text-align:left;font-weight:600}
tr.bad td{background:#fff1f0}tr.ok td{background:#f4fbf4}tr.fair td{background:#fffbe6}
img{max-width:100%}figure{margin:1em 0}figcaption{font-size:0.85em;color:#555}
code{background:#f5f5f5;padding:0 3px}dt{font-weight:600}dd{margin:0 0 0.5em 1.5em}
"""


def _read_record(path: Path, what: str) -> dict:
    """The JSON object in ``path``; ReportError naming the file when it is not one."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        raise ReportError(f"{path} cannot be read: {exc}") from None
    except json.JSONDecodeError as exc:
        raise ReportError(f"{path} is not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno}); "
                          f"write it again with the command that made it") from None
    if not isinstance(data, dict):
        raise ReportError(f"{path} holds a JSON {type(data).__name__}, not an object: it is not {what}")
    return data


def _rendered(path: Path, what: str, render: PageRenderer, record: dict) -> str:
    """``render(path.parent, record)``; ReportError naming the file and the field it lacks
    when the record is not the one the page reads."""
    try:
        return render(path.parent, record)
    except KeyError as exc:
        raise ReportError(f"{path} is not {what}: its field {exc.args[0]!r} is missing") from None
    except (TypeError, ValueError, AttributeError) as exc:
        raise ReportError(f"{path} is not {what}: {exc}") from None


def _summary_page(d: Path, summary: dict) -> str:
    """The page of a campaign directory, by the kind of its summary."""
    kind = summary.get("kind", "single")
    render = _PAGES.get(kind)
    if render is None:
        raise ReportError(f"{d / 'summary.json'} is of an unknown campaign kind {kind!r}; "
                          f"this version reports {', '.join(sorted(_PAGES)) or 'no kind (none imported)'}")
    return _rendered(d / "summary.json", f"a {kind} campaign summary", render, summary)


@deferrable(lambda a: Path(a["directory"]) / "report.html")
def render_report(directory: str | Path) -> Path:
    """Write ``DIR/report.html`` and return its path (deferrable: ``report.drawing``)."""
    d = Path(directory)
    if not d.is_dir():
        raise ReportError(f"{d} is not a directory")
    if (d / "summary.json").exists():
        body = _summary_page(d, _read_record(d / "summary.json", "a campaign summary"))
    elif (d / "run.json").exists():
        path = d / "run.json"
        body = _rendered(path, "a run record", run_page, _read_record(path, "a run record"))
    else:
        raise ReportError(
            f"{d} holds neither summary.json (from 'f16mmae campaign single|dual|envelope|soak --out DIR') "
            f"nor run.json (from 'f16mmae run --out DIR')"
        )
    out = writable_file(d / "report.html", "report")
    out.write_text(
        "<!doctype html><html><head><meta charset='utf-8'><title>f16mmae report</title>"
        f"<style>{_CSS}</style></head><body>{body}</body></html>\n",
        encoding="utf-8",
    )
    return out
