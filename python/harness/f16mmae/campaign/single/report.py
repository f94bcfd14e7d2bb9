"""The HTML page of a single-failure campaign directory (``summary.json`` of kind "single"):
the runs that went wrong (each with its reproduce command), the evidence of the bank under
test (rates with 95 % intervals and verdicts), its parameters, the baseline bank's table, the
figures (embedded) and the scoring definitions; registered with ``report.page`` on import."""
from __future__ import annotations

import html
from pathlib import Path

from ...report.figures import img_tag
from ...report.markdown import case_rows, header, not_clean, register_markdown
from ...report.page import param_table, register_page
from ...report import evidence
from ..engine.scoring import GOALS


_DEFINITIONS = f"""
<h2>Definitions</h2><dl>
<dt>correct isolation</dt><dd>the run's final declaration is the injected hypothesis (no-failure runs: the run ends believing NONE)</dd>
<dt>missed</dt><dd>a failure was injected and the run ends with no failure declared (never declared, or backed out to NONE)</dd>
<dt>wrong isolation</dt><dd>the run ends with another failure declared than the injected one</dd>
<dt>false alarm</dt><dd>a failure declared before the failure time; in a no-failure run, any failure declaration</dd>
<dt>detection latency</dt><dd>first declaration of the injected hypothesis at or after the failure time, minus the failure time; median and 95th percentile (linear interpolation) over the runs that have one</dd>
<dt>transient-wrong</dt><dd>a failure other than the injected one declared at or after the failure time, even if the run recovers and ends correct (goal: none)</dd>
<dt>first declaration correct</dt><dd>runs whose first failure declaration at or after the failure time names the injected failure, whatever is declared after it; reported beside the score (the last declaration), never in its place</dd>
<dt>intervals</dt><dd>95 % Clopper-Pearson (exact) intervals of every rate, in brackets; summary.json also holds the Wilson intervals</dd>
<dt>verdicts</dt><dd><em>demonstrated</em>: the interval clears the goal; <em>consistent</em>: the point estimate meets it, the interval does not; <em>not met</em>: the point estimate misses it. A goal of zero (false alarms, transient-wrong) can never be demonstrated by finitely many runs</dd>
<dt>detected within 0.5 / 1 / 2 s / in flight</dt><dd>fractions of all runs of a case, a missed run counting as never detected. The latency goals are judged in this form: median &le; {GOALS['latency_median_s_max']} s as &ge; 50 % detected within 1 s, p95 &le; {GOALS['latency_p95_s_max']} s as &ge; 95 % within 2 s</dd>
<dt>false declarations per flight hour</dt><dd>failure declarations before the failure (all of them in no-failure runs) over the failure-free flying time (before each failure, all of each no-failure run), exact Poisson interval</dd>
<dt>goals</dt><dd>correct &ge; {100 * GOALS['correct_fraction_min']:.0f}%, false alarms = {GOALS['false_alarms_max']}, no transient-wrong, latency median &le; {GOALS['latency_median_s_max']} s, p95 &le; {GOALS['latency_p95_s_max']} s</dd>
<dt>seeds</dt><dd>campaigns fly evaluation seeds; the tuning (calibration, convergence, the choice of the shipped bank's settings) flew other seeds, never these</dd>
</dl>"""


def _first_declared(cases: list[dict]) -> str:
    """A line naming the cases whose first declaration was right more often than their last."""
    moved = [f"{html.escape(c['case'])} {c['first_declared_correct']}/{c['runs']} (score {c['correct']})"
             for c in cases if c.get("first_declared_correct", c["correct"]) > c["correct"]]
    if not moved:
        return ""
    return "<p>First declaration correct, where more runs than the score: " + "; ".join(moved) + "</p>"


def single_page(d: Path, s: dict) -> str:
    """The body of the page for a single-failure summary ``s`` in directory ``d``."""
    t = s.get("timing", {})
    params = [
        ("kind", s.get("kind")), ("runs per case", s.get("runs_per_case")), ("campaign seed", s.get("seed")),
        ("flight condition", f"Mach {s.get('mach')}, {s.get('alt_ft')} ft"),
        ("turbulence", s.get("turbulence")), ("FCS feedback", s.get("feedback")),
        ("failure time / duration (s)", evidence.failure_instant_text(s)),
        ("failure mode", s.get("mode")),
        ("dither", f"truth defaults x {s.get('dither_scale', 1.0)}"),
        ("estimator settings", evidence.settings_text(s)),
        ("bank (tuning, hash)", f"{s.get('tuning')}, {s.get('bank_hash')}"),
        ("code", f"{s.get('version')}, {(s.get('code') or {}).get('code', 'unrecorded')}"),
        ("wall time", f"{t.get('wall_s', 0):.1f} s for {t.get('runs_executed', '?')} runs "
                      f"({t.get('runs_resumed', 0)} resumed) on {t.get('executor', '?')}"),
    ]
    ov = t.get("overhead")
    if ov:
        params.append(("one flight: closed loop / truth model alone",
                       f"{ov['closed_loop_s'] * 1e3:.0f} ms / {ov['truth_only_s'] * 1e3:.0f} ms "
                       f"= {ov['ratio']:.2f} (one {ov['duration_s']:g}-s flight, this process)"))
    parts = [
        "<h1>f16mmae single-failure campaign</h1>",
        evidence.drilldown_section(s.get("not_clean", []), ("tuning", "case")),
        f"<h2>Evidence, {html.escape(str(s.get('tuning')))} bank</h2>",
        evidence.campaign_evidence(s),
        evidence.evidence_table(s["cases"]),
        _first_declared(s["cases"]),
        "<h2>Campaign</h2>",
        param_table(params),
    ]
    base = s.get("baseline")
    if base:
        parts += [f"<h2>Results, {html.escape(base['tuning'])} bank (baseline, bank {html.escape(base['bank_hash'])})</h2>",
                  evidence.evidence_table(base["cases"])]
    figs = s.get("figures", {})
    parts.append("<h2>Figures</h2>")
    if "strips" in figs:
        parts.append(img_tag(d / figs["strips"], "Mean probability of the injected hypothesis (paper Figs. 3 and 6)"))
    if "latency" in figs:
        parts.append(img_tag(d / figs["latency"], "Detection latency per case"))
    parts.append(_DEFINITIONS)
    return "".join(parts)



def single_markdown(s: dict) -> str:
    out = header(s, f"Single failures at Mach {s['mach']:g}, {s['alt_ft']:.0f} ft, "
                     f"{s['runs_per_case']} runs per case")
    out += ["## Cases", ""] + case_rows(s["cases"])
    out += not_clean(s, lambda r: f"{r.get('tuning')} {r['case']}")
    return "\n".join(out)

register_page("single", single_page)
register_markdown("single", single_markdown)
