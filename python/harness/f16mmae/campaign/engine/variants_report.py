"""The HTML page of a campaign flown at several turbulence levels or failure modes
(``summary.json`` of kind "variants", :mod:`.variants`): the variants side by side (correct
fraction, false declarations per flight hour, latency, goals, cases skipped), each variant's
own page, the runs that went wrong in every variant with their reproduce commands, and the
figure against the variant; registered on import."""
from __future__ import annotations

import html
from pathlib import Path

from ...report import evidence
from ...report.figures import img_tag
from ...report.page import register_page

#: The kind of the summary this page renders.
KIND = "variants"


def variants_page(d: Path, s: dict) -> str:
    """The body of the page for a summary ``s`` of kind "variants" in directory ``d``."""
    axes = s["axes"]
    head = "".join(f"<th>{html.escape(c)}</th>" for c in tuple(axes) + evidence.VARIANT_COLUMNS) + "<th>page</th>"
    rows = []
    for row in s["variants"]:
        cls = "ok" if row["goals_met"] else "bad"
        cells = "".join(f"<td>{html.escape(c)}</td>" for c in evidence.variant_cells(row, axes))
        link = html.escape(f"{row['directory']}/report.html")
        rows.append(f"<tr class='{cls}'>{cells}<td><a href='{link}'>{html.escape(row['label'])}</a></td></tr>")
    bad = s.get("not_clean", [])
    keys = ("variant",) + tuple(k for k in ("tuning", "case", "pair", "point") if bad and k in bad[0])
    parts = [f"<h1>f16mmae {html.escape(s['campaign'])} campaign in {len(s['variants'])} variants of "
             f"{html.escape(' and '.join(axes))}</h1>",
             f"<p>Common seeds: run n of each case flies the same seed in every variant. Turbulence "
             f"{html.escape(s['turbulence'])}; failure mode {html.escape(s['mode'])}. Bank under test "
             f"{html.escape(str(s.get('tuning')))} ({html.escape(str(s.get('bank_hash')))}); campaign seed "
             f"{html.escape(str(s.get('seed')))}. Goals met in every variant: "
             f"<strong>{'yes' if s.get('goals_met') else 'no'}</strong>.</p>",
             "<table><tr>" + head + "</tr>" + "".join(rows) + "</table>",
             evidence.drilldown_section(bad, keys), "<h2>Figures</h2>"]
    figs = s.get("figures", {})
    if "variants" in figs:
        parts.append(img_tag(d / figs["variants"], "Correct fraction, false declarations per flight hour and "
                                                   "detection latency against the variant (95 % intervals)"))
    return "".join(parts)


register_page(KIND, variants_page)
