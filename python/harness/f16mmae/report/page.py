"""``f16mmae report DIR``: one self-contained HTML page from a campaign or run directory.

A campaign directory holds ``summary.json`` (see ``f16mmae.campaign.single``) and its
figures; a run directory holds ``run.json`` and ``probabilities.png``.  Figures are
embedded as base64 data URIs so the page can be mailed or archived as one file.
"""
from __future__ import annotations

import base64
import html
import json
from pathlib import Path

from .scoring import GOALS, check_goals


class ReportError(Exception):
    """The directory holds nothing a report can be made from."""


def img_tag(path: Path, alt: str) -> str:
    if not path.exists():
        return f"<p><em>figure {html.escape(path.name)} missing</em></p>"
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<figure><img alt="{html.escape(alt)}" src="data:image/png;base64,{data}"><figcaption>{html.escape(alt)}</figcaption></figure>'


def _fmt_s(x) -> str:
    return "&ndash;" if x is None else f"{x:.3f}"


def _case_table(cases: list[dict]) -> str:
    head = ("<tr><th>case</th><th>runs</th><th>correct</th><th>missed</th><th>wrong</th>"
            "<th>false alarms</th><th>latency median (s)</th><th>latency p95 (s)</th>"
            "<th>goals</th></tr>")
    rows = []
    for c in cases:
        g = check_goals(c)
        pct = 100.0 * c["correct"] / c["runs"] if c["runs"] else 0.0
        unmet = [k for k, ok in g.items() if k != "all" and not ok]
        verdict = "met" if g["all"] else "not met: " + ", ".join(unmet)
        cls = "ok" if g["all"] else "bad"
        rows.append(
            f"<tr class='{cls}'><td>{html.escape(c['case'])}</td><td>{c['runs']}</td>"
            f"<td>{c['correct']} ({pct:.0f}%)</td><td>{c['missed']}</td><td>{c['wrong']}</td>"
            f"<td>{c['false_alarms']}</td><td>{_fmt_s(c['latency_s']['median'])}</td>"
            f"<td>{_fmt_s(c['latency_s']['p95'])}</td><td>{verdict}</td></tr>"
        )
    return "<table>" + head + "".join(rows) + "</table>"


_CSS = """
body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;margin:0.8em 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}
th{background:#f3f3f3}td:first-child{text-align:left;font-weight:600}
tr.bad td{background:#fff1f0}tr.ok td{background:#f4fbf4}tr.fair td{background:#fffbe6}
img{max-width:100%}figure{margin:1em 0}figcaption{font-size:0.85em;color:#555}
code{background:#f5f5f5;padding:0 3px}dt{font-weight:600}dd{margin:0 0 0.5em 1.5em}
"""

_DEFINITIONS = f"""
<h2>Definitions</h2><dl>
<dt>correct isolation</dt><dd>the run's final declaration is the injected hypothesis (no-failure runs: the run ends believing NONE)</dd>
<dt>missed</dt><dd>a failure was injected and the run ends with no failure declared (never declared, or backed out to NONE)</dd>
<dt>wrong isolation</dt><dd>the run ends with another failure declared than the injected one</dd>
<dt>false alarm</dt><dd>a failure declared before the failure time; in a no-failure run, any failure declaration</dd>
<dt>detection latency</dt><dd>first declaration of the injected hypothesis at or after the failure time, minus the failure time; median and 95th percentile (linear interpolation) over the runs that have one</dd>
<dt>goals</dt><dd>correct &ge; {100 * GOALS['correct_fraction_min']:.0f}%, false alarms = {GOALS['false_alarms_max']}, latency median &le; {GOALS['latency_median_s_max']} s, p95 &le; {GOALS['latency_p95_s_max']} s</dd>
</dl>"""


def _campaign_page(d: Path, s: dict) -> str:
    t = s.get("timing", {})
    params = [
        ("kind", s.get("kind")), ("runs per case", s.get("runs_per_case")), ("campaign seed", s.get("seed")),
        ("flight condition", f"Mach {s.get('mach')}, {s.get('alt_ft')} ft"),
        ("turbulence", s.get("turbulence")), ("FCS feedback", s.get("feedback")),
        ("failure time / duration (s)", f"{s.get('failure_time_s')} / {s.get('duration_s')}"),
        ("failure mode", s.get("mode")),
        ("dither", f"truth defaults x {s.get('dither_scale', 1.0)}"),
        ("estimator settings", ", ".join(f"{k}={v}" for k, v in (s.get("estimator") or {}).items())
         or "core defaults"),
        ("bank (tuning, hash)", f"{s.get('tuning')}, {s.get('bank_hash')}"),
        ("code version", s.get("version")),
        ("wall time", f"{t.get('wall_s', 0):.1f} s for {t.get('runs_executed', '?')} runs "
                      f"({t.get('runs_resumed', 0)} resumed) on {t.get('executor', '?')}"),
    ]
    ov = t.get("overhead")
    if ov:
        params.append(("one flight: closed loop / truth model alone",
                       f"{ov['closed_loop_s'] * 1e3:.0f} ms / {ov['truth_only_s'] * 1e3:.0f} ms "
                       f"= {ov['ratio']:.2f} (one {ov['duration_s']:g}-s flight, this process)"))
    parts = [
        f"<h1>f16mmae single-failure campaign</h1>",
        "<table>" + "".join(f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                            for k, v in params) + "</table>",
        f"<h2>Results, {html.escape(str(s.get('tuning')))} bank</h2>",
        _case_table(s["cases"]),
    ]
    base = s.get("baseline")
    if base:
        parts += [f"<h2>Results, {html.escape(base['tuning'])} bank (baseline, bank {html.escape(base['bank_hash'])})</h2>",
                  _case_table(base["cases"])]
    figs = s.get("figures", {})
    parts.append("<h2>Figures</h2>")
    if "strips" in figs:
        parts.append(img_tag(d / figs["strips"], "Mean probability of the injected hypothesis (paper Figs. 3 and 6)"))
    if "latency" in figs:
        parts.append(img_tag(d / figs["latency"], "Detection latency per case"))
    parts.append(_DEFINITIONS)
    return "".join(parts)


def _run_page(d: Path, r: dict) -> str:
    fails = ", ".join(f"{f['name']}@{f['time_s']}:{f['mode']}" for f in r.get("failures", [])) or "none"
    decl = "".join(f"<tr><td>{html.escape(x['hypothesis'])}</td><td>{x['time_s']:.3f}</td></tr>"
                   for x in r.get("declarations", [])) or "<tr><td colspan=2>no declaration</td></tr>"
    return (
        "<h1>f16mmae run</h1><table>"
        f"<tr><th>failures injected</th><td>{html.escape(fails)}</td></tr>"
        f"<tr><th>final hypothesis</th><td>{html.escape(r.get('final_hypothesis', ''))}</td></tr>"
        f"<tr><th>outcome</th><td>{html.escape(str(r.get('outcome')))}</td></tr>"
        f"<tr><th>seed / bank / version</th><td>{r.get('seed')} / {html.escape(str(r.get('bank_hash')))} / {html.escape(str(r.get('version')))}</td></tr>"
        "</table><h2>Declarations</h2><table><tr><th>hypothesis</th><th>time (s)</th></tr>"
        + decl + "</table>" + img_tag(d / "probabilities.png", "Hypothesis probabilities")
    )


def _summary_page(d: Path, summary: dict) -> str:
    """The page of a campaign directory, by the kind of its summary."""
    kind = summary.get("kind", "single")
    if kind == "single":
        return _campaign_page(d, summary)
    if kind == "dual":
        from .dual_report import dual_page

        return dual_page(d, summary)
    if kind == "envelope":
        from .envelope_report import envelope_page

        return envelope_page(d, summary)
    raise ReportError(f"{d / 'summary.json'} is of an unknown campaign kind {kind!r}; "
                      f"this version reports single, dual and envelope campaigns")


def render_report(directory: str | Path) -> Path:
    """Write ``DIR/report.html`` and return its path."""
    d = Path(directory)
    if not d.is_dir():
        raise ReportError(f"{d} is not a directory")
    if (d / "summary.json").exists():
        body = _summary_page(d, json.loads((d / "summary.json").read_text()))
    elif (d / "run.json").exists():
        body = _run_page(d, json.loads((d / "run.json").read_text()))
    else:
        raise ReportError(
            f"{d} holds neither summary.json (from 'f16mmae campaign single|dual|envelope --out DIR') "
            f"nor run.json (from 'f16mmae run --out DIR')"
        )
    out = d / "report.html"
    out.write_text(
        "<!doctype html><html><head><meta charset='utf-8'><title>f16mmae report</title>"
        f"<style>{_CSS}</style></head><body>{body}</body></html>\n",
        encoding="utf-8",
    )
    return out
