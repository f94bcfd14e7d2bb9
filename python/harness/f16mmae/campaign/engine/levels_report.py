"""The HTML page of a campaign flown at several turbulence levels (``summary.json`` of kind
"levels", :mod:`.levels`): the levels side by side (correct fraction, false declarations per
flight hour, latency, goals), each level's own page, the runs that went wrong at every level
with their reproduce commands, and the figure against the level; registered on import."""
from __future__ import annotations

import html
from pathlib import Path

from ...report import evidence
from ...report.figures import img_tag
from ...report.page import register_page

#: The kind of the summary this page renders.
KIND = "levels"


def levels_page(d: Path, s: dict) -> str:
    """The body of the page for a summary ``s`` of kind "levels" in directory ``d``."""
    head = "".join(f"<th>{html.escape(c)}</th>" for c in evidence.LEVEL_COLUMNS) + "<th>page</th>"
    rows = []
    for row in s["levels"]:
        cls = "ok" if row["goals_met"] else "bad"
        cells = "".join(f"<td>{html.escape(c)}</td>" for c in evidence.level_cells(row))
        link = html.escape(f"{row['directory']}/report.html")
        rows.append(f"<tr class='{cls}'>{cells}<td><a href='{link}'>{html.escape(row['level'])}</a></td></tr>")
    bad = s.get("not_clean", [])
    keys = ("level",) + tuple(k for k in ("tuning", "case", "pair", "point") if bad and k in bad[0])
    parts = [f"<h1>f16mmae {html.escape(s['campaign'])} campaign at {len(s['levels'])} turbulence levels</h1>",
             f"<p>Common seeds: run n of each case flies the same seed at every level. Bank under test "
             f"{html.escape(str(s.get('tuning')))} ({html.escape(str(s.get('bank_hash')))}); campaign seed "
             f"{html.escape(str(s.get('seed')))}. Goals met at every level: "
             f"<strong>{'yes' if s.get('goals_met') else 'no'}</strong>.</p>",
             "<table><tr>" + head + "</tr>" + "".join(rows) + "</table>",
             evidence.drilldown_section(bad, keys), "<h2>Figures</h2>"]
    figs = s.get("figures", {})
    if "levels" in figs:
        parts.append(img_tag(d / figs["levels"], "Correct fraction, false declarations per flight hour and "
                                                 "detection latency against turbulence level (95 % intervals)"))
    return "".join(parts)


register_page(KIND, levels_page)
