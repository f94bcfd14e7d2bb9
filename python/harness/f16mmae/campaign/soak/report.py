"""The HTML page of a soak directory (``summary.json`` of kind "soak"): false declarations
per flight hour per turbulence level with their intervals and verdicts (pooled over the points),
the hypotheses involved and how long the declarations lasted, with two or more points the same
per point, the flights with one (each with its reproduce command), the parameters and the
figures; and its Markdown page; registered with ``report.page`` and ``report.markdown`` on import."""
from __future__ import annotations

import html
from pathlib import Path

from ...report import evidence
from ...report.figures import img_tag
from ...report.markdown import header, not_clean, num, register_markdown
from ...report.page import param_table, register_page

_DEFINITIONS = """
<h2>Definitions</h2><dl>
<dt>false declaration</dt><dd>any failure declaration in a failure-free flight</dd>
<dt>how long it lasted</dt><dd>from the declaration to the next declaration of the flight: a back-out to NONE, or another hypothesis replacing it; a declaration still standing at the flight's end lasts until the end</dd>
<dt>per flight hour</dt><dd>false declarations over the hours flown at the level, with the exact (Garwood) Poisson 95 % interval</dd>
<dt>left the flight condition</dt><dd>in level flight, the truth's Mach or altitude more than 0.1 or 2,000 ft from the trim's (with maneuvers: non-finite), at a whole second of the flight: its hours and declarations from then on are not counted, and the flight is listed with its command</dd>
<dt>verdicts</dt><dd><em>demonstrated</em>: the interval's upper bound is within the goal; <em>consistent</em>: the rate is, the bound is not; <em>not met</em>: the rate exceeds the goal. A goal of zero can at best be consistent</dd>
<dt>seeds</dt><dd>evaluation seeds, flight n the same at every level (common random numbers); the tuning never flew them</dd>
</dl>"""


def _level_rows(levels: list[dict]) -> str:
    head = ("<tr><th>turbulence</th><th>flights</th><th>hours</th><th>false declarations per hour [95 %], verdict</th>"
            "<th>flights with one</th><th>first in its flight, median / earliest (s)</th><th>hypotheses involved</th><th>lasted median / max (s)</th>"
            "<th>backed out / replaced / flight end</th><th>flights that left the condition (declarations after)</th></tr>")
    rows = []
    for lv in levels:
        verdict = lv["per_hour"].get("verdict")
        cls = {"not met": "bad", "consistent": "fair", "demonstrated": "ok"}.get(verdict, "")
        hyps = evidence.describe_counts(lv["hypotheses"], top=12)
        d = lv["duration_s"]
        lasted = "-" if d["median"] is None else f"{d['median']:.2f} / {d['max']:.2f}"
        f = lv["first_declaration_s"]
        first = "-" if f["median"] is None else f"{f['median']:.1f} / {f['min']:.1f}"
        ends = " / ".join(str(lv["episodes_by_end"][k]) for k in ("backed out", "replaced", "flight end"))
        rows.append(f"<tr class='{cls}'><td>{html.escape(lv['level'])}</td><td>{lv['flights']}</td>"
                    f"<td>{lv['hours']:.3f}</td><td>{html.escape(evidence.describe_per_hour(lv['per_hour']))}</td>"
                    f"<td>{lv['flights_with_false_declaration']}</td><td>{first}</td><td>{html.escape(hyps)}</td>"
                    f"<td>{lasted}</td>"
                    f"<td>{ends}</td><td>{_left(lv)}</td></tr>")
    return "<table>" + head + "".join(rows) + "</table>"


def several_points(s: dict) -> bool:
    """Whether soak summary ``s`` flew two or more points (a summary from before there were
    points flew one)."""
    return len(s.get("points") or ()) > 1


def points_text(s: dict, listed: int = 12) -> str:
    """The labels of the soak's points in order, the middle ones elided past ``listed``."""
    labels = [p["label"] for p in s.get("points") or ()]
    if len(labels) > listed:
        labels = labels[:listed - 2] + ["...", labels[-1]]
    return ", ".join(labels)


def _point_rate(level: dict) -> str:
    """A point's false declarations per hour at a level: ``rate [lo-hi] (count)``, ``-`` unflown."""
    ph = level["per_hour"]
    if ph.get("rate") is None:
        return "-"
    lo, hi = ph["ci95"]
    return f"{ph['rate']:.2f} [{lo:.2f}-{hi:.2f}] ({ph['events']})"


def _point_rows(s: dict) -> str:
    """The table of the points: per level, false declarations per hour, flights with one and
    the hypotheses; a row coloured by its worst verdict."""
    levels = [lv["level"] for lv in s["levels"]]
    head = ("<tr><th>point</th><th>Mach</th><th>altitude (ft)</th>"
            + "".join(f"<th>{html.escape(lvl)}: false declarations per hour [95 %] (count)</th>"
                      f"<th>{html.escape(lvl)}: flights with one</th><th>{html.escape(lvl)}: hypotheses</th>"
                      for lvl in levels) + "</tr>")
    rows = []
    for p in s["points"]:
        verdicts = {q["per_hour"].get("verdict") for q in p["levels"]}
        cls = ("bad" if "not met" in verdicts else "fair" if "consistent" in verdicts
               else "ok" if verdicts == {"demonstrated"} else "")
        cells = "".join(f"<td>{_point_rate(q)}</td><td>{q['flights_with_false_declaration']}/{q['flights']}</td>"
                        f"<td>{html.escape(evidence.describe_counts(q['hypotheses'], top=4))}</td>"
                        for q in p["levels"])
        rows.append(f"<tr class='{cls}'><td>{html.escape(p['label'])}</td><td>{p['mach']:.3f}</td>"
                    f"<td>{p['alt_ft']:.0f}</td>{cells}</tr>")
    return ("<h2>Per point</h2><p>Each point's flights alone (the same seeds at every point); the table above "
            "pools them.</p><table>" + head + "".join(rows) + "</table>")


def _left(level: dict) -> str:
    """Flights of a level that left the flight condition, and their failure declarations after."""
    return f"{level.get('flights_left_condition', 0)} ({level.get('declarations_after_leaving', 0)})"


def _left_section(flights: list[dict]) -> str:
    """The flights that left the flight condition, each with its command."""
    if not flights:
        return ""
    pointed = any("point" in f for f in flights)
    rows = "".join(
        "<tr>" + (f"<td>{html.escape(str(f.get('point')))}</td>" if pointed else "")
        + f"<td>{html.escape(f['level'])}</td><td>{f['run_index']}</td><td>{f['left_condition_s']:.0f}</td>"
        f"<td>{html.escape(', '.join(d['hypothesis'] + ' ' + format(d['time_s'], '.1f') for d in f['declarations_after_leaving']) or '-')}</td>"
        f"<td><code>{html.escape(f['command'])}</code></td></tr>" for f in flights)
    return ("<h2>Flights that left the flight condition</h2><table><tr>" + ("<th>point</th>" if pointed else "")
            + "<th>turbulence</th><th>flight</th>"
            "<th>left at (s)</th><th>declarations after (not counted)</th><th>command</th></tr>" + rows + "</table>")


def _flown(s: dict) -> str:
    """What the flights flew: the profile, the maneuvers (each point's own from a profile over
    several points) or trim."""
    text = f"profile {s['profile']}: " if s.get("profile") else ""
    if s.get("maneuvers"):
        return text + "maneuvering: " + ", ".join(s["maneuvers"])
    if s.get("profile"):
        return text + "maneuvering, each point from its own flight condition"
    return text + "trim, no pilot (no maneuvers)"


def soak_page(d: Path, s: dict) -> str:
    """The body of the page for a soak summary ``s`` in directory ``d``."""
    t = s.get("timing", {})
    params = [
        ("kind", "soak: failure-free flights, " + _flown(s)),
        ("flights per level" + (" and point" if several_points(s) else ""),
         f"{s['flights_per_level']} of {s['flight_s']:g} s (asked {s['hours']:g} h)"),
        ("turbulence", s.get("turbulence")), ("campaign seed", s.get("seed")),
        ("flight condition", f"{len(s['points'])} points: {points_text(s)}" if several_points(s)
         else f"Mach {s.get('mach')}, {s.get('alt_ft')} ft"),
        ("FCS feedback", s.get("feedback")),
        ("dither", f"truth defaults x {s.get('dither_scale', 1.0)}" if s.get("dither", True) else "off"),
        ("estimator settings", evidence.settings_text(s)),
        ("bank (tuning, hash)", f"{s.get('tuning')}, {s.get('bank_hash')}"),
        ("code", f"{s.get('version')}, {(s.get('code') or {}).get('code', 'unrecorded')}"),
        ("wall time", f"{t.get('wall_s', 0):.1f} s for {t.get('runs_executed', '?')} flights "
                      f"({t.get('runs_resumed', 0)} resumed) on {t.get('executor', '?')}"),
    ]
    figs = s.get("figures", {})
    several = several_points(s)
    parts = ["<h1>f16mmae soak campaign</h1>",
             f"<p>Goals met (no level <em>not met</em>"
             + (f", pooled over {len(s['points'])} points" if several else "")
             + f"): <strong>{'yes' if s.get('goals_met') else 'no'}</strong></p>",
             _level_rows(s["levels"]),
             _point_rows(s) if several else "",
             evidence.drilldown_section(s.get("not_clean", []),
                                        ("point",) * several + ("level", "false_declarations")),
             _left_section(s.get("left_condition", [])),
             "<h2>Campaign</h2>", param_table(params), "<h2>Figures</h2>"]
    captions = {"rate_by_level": "False declarations per flight hour against turbulence level (95 % intervals)",
                "map": "The points coloured by their false declarations per flight hour, per turbulence level "
                       "(green: none), each with its count; the star: the bank's design point",
                "timeline": "False declarations on a timeline per flight" + (" (a block of rows per point)"
                                                                              if several else ""),
                "durations": "How long the false declarations lasted"}
    parts += [img_tag(d / figs[k], cap) for k, cap in captions.items() if k in figs]
    parts.append(_DEFINITIONS)
    return "".join(parts)



def soak_markdown(s: dict) -> str:
    several = several_points(s)
    where = (f"level and point at {len(s['points'])} points ({points_text(s)})" if several
             else f"level from Mach {s['mach']:g}, {s['alt_ft']:.0f} ft")
    if s.get("maneuvers"):
        flown = "maneuvering: " + ", ".join(f"`{m}`" for m in s["maneuvers"])
    elif s.get("profile"):
        flown = f"maneuvering: profile `{s['profile']}` from each point's flight condition"
    else:
        flown = "trim (no maneuvers)"
    out = header(s, f"Soak: {s['flights_per_level']} failure-free flights of {s['flight_s']:g} s per turbulence "
                     f"{where}, {flown}")
    out += ["## False declarations per flight hour" + (", pooled over the points" if several else ""), "",
            "| turbulence | flights | hours | false declarations per hour [95 %], goal: verdict | "
            "flights with one | first in its flight, median / earliest (s) | hypotheses involved | "
            "lasted median / max (s) | ended: backed out / replaced / flight end | "
            "flights that left the condition (declarations after) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for lv in s["levels"]:
        hyps = evidence.describe_counts(lv["hypotheses"])
        ends = " / ".join(str(lv["episodes_by_end"][k]) for k in ("backed out", "replaced", "flight end"))
        out.append(f"| {lv['level']} | {lv['flights']} | {lv['hours']:.3f} | {evidence.describe_per_hour(lv['per_hour'])} | "
                   f"{lv['flights_with_false_declaration']} | {num(lv['first_declaration_s']['median'])} / "
                   f"{num(lv['first_declaration_s']['min'])} | {hyps} | {num(lv['duration_s']['median'])} / "
                   f"{num(lv['duration_s']['max'])} | {ends} | {_left(lv)} |")
    out += ["", f"Goals met (no level *not met*): {'yes' if s.get('goals_met') else 'no'}", ""]
    if several:
        out += _point_markdown(s)
    out += not_clean(s, lambda r: (f"point {r['point']}, " if "point" in r else "") + f"{r['level']} flight")
    if s.get("left_condition"):
        out += ["## Flights that left the flight condition (hours and declarations after not counted)", ""]
        out += [f"- {'point ' + f['point'] + ', ' if 'point' in f else ''}{f['level']} flight {f['run_index']}, "
                f"left at {f['left_condition_s']:.0f} s, declarations after: "
                + (", ".join(f"{d['hypothesis']} {d['time_s']:.1f} s" for d in f["declarations_after_leaving"]) or "none")
                + f": `{f['command']}`" for f in s["left_condition"]]
        out.append("")
    return "\n".join(out)


def _point_markdown(s: dict) -> list[str]:
    """The per-point table of a soak over several points (as :func:`_point_rows`)."""
    levels = [lv["level"] for lv in s["levels"]]
    out = ["## Per point", "", "Each point's flights alone (the same seeds at every point).", "",
           "| point | Mach | altitude (ft) | "
           + " | ".join(f"{lvl}: false declarations per hour [95 %] (count) | {lvl}: flights with one | "
                        f"{lvl}: hypotheses" for lvl in levels) + " |",
           "|---|---|---|" + "---|---|---|" * len(levels)]
    for p in s["points"]:
        cells = " | ".join(f"{_point_rate(q)} | {q['flights_with_false_declaration']}/{q['flights']} | "
                           f"{evidence.describe_counts(q['hypotheses'], top=4)}" for q in p["levels"])
        out.append(f"| {p['label']} | {p['mach']:.3f} | {p['alt_ft']:.0f} | {cells} |")
    return out + [""]

register_page("soak", soak_page)
register_markdown("soak", soak_markdown)
