"""The HTML page of a single-failure campaign directory (``summary.json`` of kind "single"):
its parameters, the per-case tables of the bank under test and of the baseline bank, the
figures (embedded) and the scoring definitions; registered with ``report.page`` on import."""
from __future__ import annotations

import html
from pathlib import Path

from ...report.figures import img_tag
from ...report.page import param_table, register_page
from ..engine.scoring import GOALS, check_goals


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


_DEFINITIONS = f"""
<h2>Definitions</h2><dl>
<dt>correct isolation</dt><dd>the run's final declaration is the injected hypothesis (no-failure runs: the run ends believing NONE)</dd>
<dt>missed</dt><dd>a failure was injected and the run ends with no failure declared (never declared, or backed out to NONE)</dd>
<dt>wrong isolation</dt><dd>the run ends with another failure declared than the injected one</dd>
<dt>false alarm</dt><dd>a failure declared before the failure time; in a no-failure run, any failure declaration</dd>
<dt>detection latency</dt><dd>first declaration of the injected hypothesis at or after the failure time, minus the failure time; median and 95th percentile (linear interpolation) over the runs that have one</dd>
<dt>goals</dt><dd>correct &ge; {100 * GOALS['correct_fraction_min']:.0f}%, false alarms = {GOALS['false_alarms_max']}, latency median &le; {GOALS['latency_median_s_max']} s, p95 &le; {GOALS['latency_p95_s_max']} s</dd>
</dl>"""


def single_page(d: Path, s: dict) -> str:
    """The body of the page for a single-failure summary ``s`` in directory ``d``."""
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
        param_table(params),
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


register_page("single", single_page)
