"""The HTML page of an off-nominal campaign directory (``summary.json`` of kind "envelope").

``envelope_page(d, summary)`` is the page body: the runs that went wrong (each with its
reproduce command), the campaign's evidence, the settings, the per-point table (Mach,
altitude, q̄, correct and false-alarm runs with 95 % intervals, transient-wrong runs, median
latency, acceptable, verdict, truth trim
minus design trim) and both figures embedded as base64 PNGs (``report.figures.img_tag``), so the page
is one self-contained file; ``report.page.render_report(d)`` writes it to ``DIR/report.html``.
"""
from __future__ import annotations

import html
from pathlib import Path

from ...report import evidence
from ...report.figures import img_tag
from ...report.markdown import header, not_clean, num, rate, register_markdown
from ...report.page import param_table, register_page


def _f(x, fmt: str) -> str:
    return "&ndash;" if x is None else format(x, fmt)


def envelope_page(d: Path, s: dict) -> str:
    rule = s["acceptable_rule"]
    dp = s["design_point"]
    settings = (
        ("kind", s["kind"]), ("bank", f"{s['tuning']} ({s['bank_hash']})"),
        ("design point", f"Mach {dp['mach']:g}, {dp['alt_ft']:.0f} ft, q̄ {dp['qbar_psf']:.1f} lbf/ft²"),
        ("runs per case and point", s["runs_per_case"]), ("campaign seed", s["seed"]),
        ("cases", ", ".join(s["cases"])), ("turbulence", s["turbulence"]), ("failure mode", s["mode"]),
        ("failure time / duration (s)", evidence.failure_instant_text(s)),
        ("estimator settings", evidence.settings_text(s)),
        ("code", f"{s['version']}, {(s.get('code') or {}).get('code', 'unrecorded')}"),
    )
    head = ("<tr><th>point</th><th>Mach</th><th>alt (ft)</th><th>q̄ (lbf/ft²)</th><th>correct [95 %]</th>"
            "<th>false-alarm runs [95 %]</th><th>transient-wrong runs</th><th>latency median (s)</th><th>acceptable</th>"
            "<th>verdict</th>"
            "<th>Δ stab (deg)</th><th>Δ VEL (ft/s)</th><th>Δ AOA (deg)</th></tr>")
    rows = []
    for p in s["points"]:
        rates = p.get("evidence", {}).get("rates", {})
        t = p["trim_offset"]
        rows.append(
            f"<tr class='{'ok' if p['acceptable'] else 'bad'}'><td>{html.escape(p['label'])}</td>"
            f"<td>{p['mach']:.3f}</td><td>{p['alt_ft']:.0f}</td><td>{p['qbar_psf']:.1f}</td>"
            f"<td>{evidence.rate_cell(rates.get('correct'))}</td><td>{evidence.rate_cell(rates.get('false_alarm'))}</td>"
            f"<td>{rates.get('transient_wrong', {}).get('count', '&ndash;')}</td>"
            f"<td>{_f(p['latency_median_s'], '.2f')}</td>"
            f"<td>{'yes' if p['acceptable'] else 'no'}</td><td>{html.escape(str(p.get('evidence', {}).get('verdict')))}</td>"
            f"<td>{t['stab_deg']:+.3f}</td>"
            f"<td>{t['vel_fps']:+.2f}</td><td>{t['aoa_deg']:+.3f}</td></tr>")
    figs = s.get("figures", {})
    parts = [
        "<h1>f16mmae off-nominal campaign (paper Fig. 9)</h1>",
        evidence.drilldown_section(s.get("not_clean", []), ("point", "case")),
        "<h2>Evidence</h2>", evidence.campaign_evidence(s),
        param_table(settings),
        "<h2>Points</h2>",
        f"<p>Acceptable: at least {100 * rule['correct_fraction_min']:.0f}% of the failure-case runs end "
        f"with the injected failure declared, and at most {rule['false_alarm_runs_max']} runs (NONE runs "
        "included) have a false alarm. Δ columns: the truth model's own trim at the point minus the "
        "bank's design trim (the estimator never sees them).</p>",
        "<table>" + head + "".join(rows) + "</table><h2>Figures</h2>",
    ]
    if "map" in figs:
        parts.append(img_tag(d / figs["map"], "Points on Mach-altitude axes, coloured by correct fraction; lines of constant q̄"))
    if "cases" in figs:
        parts.append(img_tag(d / figs["cases"], "Correct runs per point and case"))
    return "".join(parts)



def envelope_markdown(s: dict) -> str:
    out = header(s, f"Off the design point: {len(s['points'])} points, {s['runs_per_case']} runs per case "
                     f"and point")
    out += ["## Points", "",
            "| point | Mach | alt (ft) | correct [95 %] | runs with FA [95 %] | transient-wrong | "
            "latency median (s) | acceptable | verdict |", "|---|---|---|---|---|---|---|---|---|"]
    for p in s["points"]:
        r = p["evidence"]["rates"]
        out.append(f"| {p['label']} | {p['mach']:.3f} | {p['alt_ft']:.0f} | {rate(r.get('correct'))} | "
                   f"{rate(r.get('false_alarm'))} | {r.get('transient_wrong', {}).get('count', '-')} | "
                   f"{num(p['latency_median_s'])} | {'yes' if p['acceptable'] else 'no'} | {p['evidence']['verdict']} |")
    out += [""] + not_clean(s, lambda r: f"point {r['point']} {r['case']}")
    return "\n".join(out)

register_page("envelope", envelope_page)
register_markdown("envelope", envelope_markdown)
