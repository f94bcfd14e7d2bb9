"""The HTML page of a maneuver campaign directory (``summary.json`` of kind "maneuver"): the runs
that went wrong (each with its reproduce command), the evidence, the settings, the table per
maneuver and per point and maneuver, and both figures embedded; registered on import."""
from __future__ import annotations

import html
from pathlib import Path

from ...report import evidence
from ...report.figures import img_tag
from ...report.markdown import header, not_clean, num, rate, register_markdown
from ...report.page import param_table, register_page


def _f(x) -> str:
    return "&ndash;" if x is None else f"{x:.2f}"


def maneuver_page(d: Path, s: dict) -> str:
    settings = (
        ("kind", s["kind"]), ("bank", f"{s['tuning']} ({s['bank_hash']})"),
        ("points", ", ".join(f"{p['label']} (Mach {p['mach']:.3f}, {p['alt_ft']:.0f} ft)" for p in s["points"])),
        ("maneuvers", ", ".join(s["maneuvers"])), ("runs per case", s["runs_per_case"]),
        ("campaign seed", s["seed"]), ("cases", ", ".join(s["cases"])), ("turbulence", s["turbulence"]),
        ("failure mode", s["mode"]),
        ("maneuver / failure time / duration (s)", f"{s['maneuver_time_s']} / {evidence.failure_instant_text(s)}"),
        ("estimator settings", evidence.settings_text(s)),
    )
    rows = []
    for r in s["by_maneuver"] + [{"maneuver": "all", **s["overall"]}]:
        rates = r["rates"]
        rows.append(f"<tr><td>{html.escape(r['maneuver'])}</td><td>{evidence.rate_cell(rates.get('correct'))}</td>"
                    f"<td>{evidence.rate_cell(rates.get('false_alarm'))}</td>"
                    f"<td>{html.escape(evidence.describe_per_hour(r['per_hour']))}</td>"
                    f"<td>{_f(r['latency_median_s'])}</td><td>{_f(r['vel_latency_median_s'])}</td>"
                    f"<td>{html.escape(str(r.get('verdict')))}</td></tr>")
    cells = [f"<tr><td>{html.escape(c['point'])}</td><td>{c['mach']:.3f}</td><td>{c['alt_ft']:.0f}</td>"
             f"<td><code>{html.escape(c['maneuver_spec'])}</code></td>"
             f"<td>{evidence.rate_cell(c['rates'].get('correct'))}</td><td>{c['false_alarm_runs']}/{c['runs']}</td>"
             f"<td>{_f(c['latency_median_s'])}</td></tr>" for c in s["by_point"]]
    figs = s.get("figures", {})
    parts = [
        "<h1>f16mmae maneuver campaign</h1>",
        evidence.drilldown_section(s.get("not_clean", []), ("point", "maneuver", "case")),
        "<h2>Evidence</h2>", evidence.campaign_evidence(s), param_table(settings),
        "<h2>Per maneuver</h2><table><tr><th>maneuver</th><th>correct [95 %]</th><th>false-alarm runs [95 %]</th>"
        "<th>false declarations per maneuvering hour</th><th>latency median (s, VEL apart)</th>"
        "<th>VEL latency median (s)</th><th>verdict</th></tr>" + "".join(rows) + "</table>",
        "<h2>Per point and maneuver</h2><table><tr><th>point</th><th>Mach</th><th>alt (ft)</th><th>maneuver</th>"
        "<th>correct [95 %]</th><th>false-alarm runs</th><th>latency median (s)</th></tr>" + "".join(cells) + "</table>",
        "<h2>Figures</h2>",
    ]
    if "map" in figs:
        parts.append(img_tag(d / figs["map"], "Points coloured by correct fraction, per maneuver"))
    if "strips" in figs:
        parts.append(img_tag(d / figs["strips"], "Mean probability of the injected failure, per maneuver and case"))
    return "".join(parts)



def maneuver_markdown(s: dict) -> str:
    out = header(s, f"Maneuvers: {', '.join(s['maneuvers'])} at {len(s['points'])} point(s), "
                     f"{s['runs_per_case']} run(s) per case, failure at {s['failure_time_s']:g} s into a "
                     f"maneuver begun at {s['maneuver_time_s']:g} s of a {s['duration_s']:g}-s flight")
    out += ["## Per maneuver", "",
            "| maneuver | correct [95 %] | runs with FA [95 %] | false declarations per maneuvering hour "
            "[95 %] | latency median (s, VEL apart) | VEL latency median (s) | verdict |",
            "|---|---|---|---|---|---|---|"]
    for r in s["by_maneuver"] + [{"maneuver": "all", **s["overall"]}]:
        out.append(f"| {r['maneuver']} | {rate(r['rates'].get('correct'))} | {rate(r['rates'].get('false_alarm'))} | "
                   f"{evidence.describe_per_hour(r['per_hour'])} | {num(r['latency_median_s'])} | "
                   f"{num(r['vel_latency_median_s'])} | {r.get('verdict')} |")
    out += ["", "## Per point and maneuver", "",
            "| point | Mach | alt (ft) | maneuver flown | correct [95 %] | runs with FA | latency median (s) |",
            "|---|---|---|---|---|---|---|"]
    for c in s["by_point"]:
        out.append(f"| {c['point']} | {c['mach']:.3f} | {c['alt_ft']:.0f} | `{c['maneuver_spec']}` | "
                   f"{rate(c['rates'].get('correct'))} | {c['false_alarm_runs']}/{c['runs']} | "
                   f"{num(c['latency_median_s'])} |")
    out += [""] + not_clean(s, lambda r: f"point {r['point']} {r['maneuver']} {r['case']}")
    return "\n".join(out)

register_page("maneuver", maneuver_page)
register_markdown("maneuver", maneuver_markdown)
