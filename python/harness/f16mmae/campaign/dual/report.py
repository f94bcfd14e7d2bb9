"""The HTML page of a dual-failure campaign directory (``summary.json`` of kind ``dual``).

``dual_page(d, summary)`` is the body of the page ``report.page.render_report`` writes for a dual
campaign directory (figures embedded): the runs that went wrong (each with its reproduce
command), the campaign's evidence and parameters, the rating counts (relative and absolute) and their agreement with the paper's Fig. 7, the two figures,
the rating definitions with their thresholds (``scoring.RATING_RULES``), the baselines
and every pair that is not Good with the reason of its rating, then all pairs.
"""
from __future__ import annotations

import html
from pathlib import Path

from ...report import evidence
from ...report.figures import img_tag
from ...report.markdown import case_rows, header, not_clean, num, rate, register_markdown
from ...report.page import param_table, register_page
from ..engine.outcomes import ABSOLUTE_DUAL_RULES
from .scoring import RATING_RULES, RATINGS

_ROW_CLASS = {"Good": "ok", "Fair": "fair", "Poor": "bad", "ND": "bad", "Indistinguishable": "fair"}


def _s(x) -> str:
    return "&ndash;" if x is None else f"{x:.2f}"


def _table(rows: list[dict], rated: bool) -> str:
    head = ("<tr><th>case</th><th>runs</th><th>correct [95 %]</th><th>missed</th><th>wrong</th>"
            "<th>transient-wrong</th><th>false alarms</th><th>latency median (s)</th><th>latency p95 (s)</th>"
            "<th>hold</th><th>peak p</th>" + ("<th>rating</th><th>why</th><th>absolute</th><th>why</th>"
                                              if rated else "") + "</tr>")
    body = []
    for r in rows:
        hold = "&ndash;" if r.get("hold_mean") is None else f"{100 * r['hold_mean']:.0f}%"
        rates = r.get("evidence", {}).get("rates", {})
        tw = rates.get("transient_wrong", {}).get("count", "&ndash;")
        cells = (f"<td>{html.escape(r['case'])}</td><td>{r['runs']}</td><td>{evidence.rate_cell(rates.get('correct'))}</td>"
                 f"<td>{r['missed']}</td><td>{r['wrong']}</td><td>{tw}</td><td>{r['false_alarms']}</td>"
                 f"<td>{_s(r['latency_s']['median'])}</td><td>{_s(r['latency_s']['p95'])}</td>"
                 f"<td>{hold}</td><td>{_s(r.get('p_max'))}</td>")
        if rated:
            cells += (f"<td>{r['rating']}</td><td style='text-align:left'>{html.escape(r['rating_reason'])}</td>"
                      f"<td>{html.escape(str(r.get('absolute_rating', '-')))}</td>"
                      f"<td style='text-align:left'>{html.escape(r.get('absolute_rating_reason', ''))}</td>")
        body.append(f"<tr class='{_ROW_CLASS.get(r.get('rating'), '')}'>{cells}</tr>")
    return "<table>" + head + "".join(body) + "</table>"


def dual_page(d: Path, s: dict) -> str:
    """The body of the page for a dual summary ``s`` in directory ``d``."""
    t = s.get("timing", {})
    R = RATING_RULES
    A = s.get("absolute_rules") or ABSOLUTE_DUAL_RULES
    params = [
        ("runs per pair / campaign seed", f"{s['runs_per_pair']} / {s['seed']}"),
        ("flight condition", f"Mach {s['mach']}, {s['alt_ft']:.0f} ft, {s['turbulence']} turbulence"),
        ("failures", f"first at {s['first_time_s']} s, second at {s['second_time_s']} s "
                     f"(mode {s['mode']}), flight {s['duration_s']} s"
                     + (f"; each run's two failures and its end up to {s['failure_jitter_s']:g} s later (its seed)"
                        if s.get("failure_jitter_s") else "")),
        ("FCS feedback / dither", f"{s['feedback']} / {'on' if s.get('dither', True) else 'off'} "
                                  f"x {s.get('dither_scale', 1.0)}"),
        ("estimator settings", evidence.settings_text(s)),
        ("bank (tuning, hash) / code", f"{s['tuning']}, {s['bank_hash']} / {s['version']}, "
                                       f"{(s.get('code') or {}).get('code', 'unrecorded')}"),
        ("wall time", f"{t.get('wall_s', 0):.1f} s for {t.get('runs_executed', '?')} runs "
                      f"({t.get('runs_resumed', 0)} resumed) on {t.get('executor', '?')}"),
    ]
    counts = ", ".join(f"{k} {s['ratings'].get(k, 0)}" for k in RATINGS)
    cmp_ = s.get("paper_comparison", {})
    figs = s.get("figures", {})
    defs = (
        "<h2>Rating (against the lone second failure, flown on the same seeds)</h2><dl>"
        f"<dt>Good</dt><dd>correct &ge; baseline's &minus; {100 * R['good_correct_margin']:.0f} points, "
        f"median latency after the second failure &le; baseline's + {R['good_latency_margin_s']} s "
        f"({R['reference_latency_s']} s if the baseline never detects), mean hold &ge; baseline's "
        f"&minus; {100 * R['good_hold_margin']:.0f} points</dd>"
        f"<dt>Fair</dt><dd>not Good, some run correct, and correct &ge; {100 * R['fair_correct_min']:.0f}% "
        "or &ge; baseline's &minus; the Good margin</dd>"
        f"<dt>Poor</dt><dd>neither, but the dual was declared in some run or its probability reached "
        f"{R['poor_probability']}</dd>"
        "<dt>ND</dt><dd>the dual never declared and its probability never reached that</dd>"
        "<dt>Indistinguishable</dt><dd>not Good, and the models show the dual indistinguishable: its "
        "expected evidence per frame against a rival of the first failure's level-1 bank is &le; 0 "
        "(design.distinguish on the bank's own design; the measured rating is kept beside it)</dd>"
        "<dt>correct / missed / wrong</dt><dd>the run ends declaring the dual / NONE or one of the two "
        "failures alone / a hypothesis naming a component that has not failed</dd>"
        "<dt>latency, hold</dt><dd>first declaration of the dual after the second failure minus its "
        "time; the fraction of the flight after that declaration during which the dual stays declared</dd>"
        "<dt>false alarm</dt><dd>before the second failure, a hypothesis other than NONE and the first "
        "failure declared</dd>"
        "<dt>transient-wrong</dt><dd>from the first failure on, a hypothesis declared that names a component "
        "not failed (in truth) by its time, even if the run recovers; a declaration naming only failed "
        "components is true if incomplete (the former rule, which also counted the lone second failure, is "
        "kept beside it: transient_wrong_strict)</dd>"
        f"<dt>absolute rating</dt><dd>Good when &ge; {100 * A['correct_fraction_min']:.0f}% of the runs are "
        f"correct, no run has a false alarm, no run is transient-wrong and the median latency after the "
        f"second failure is &le; {A['latency_median_s_max']} s, whatever the baseline did; else Not good "
        "(the matrix figure marks absolutely Good cells with a black square)</dd></dl>")
    not_good = [p for p in s["pairs"] if p["rating"] != "Good"]
    absolute = ", ".join(f"{k} {v}" for k, v in (s.get("absolute_ratings") or {}).items())
    return "".join([
        "<h1>f16mmae dual-failure campaign (paper Fig. 7)</h1>",
        evidence.drilldown_section(s.get("not_clean", []), ("pair",)),
        "<h2>Evidence</h2>", evidence.campaign_evidence(s),
        param_table(params),
        f"<p><b>{len(s['pairs'])} pairs: {counts}; absolute: {absolute}.</b> Same rating as the paper's Fig. 7 in "
        f"{cmp_.get('equal', '?')} of {cmp_.get('cells', '?')} comparable cells; same Good / not Good "
        f"in {cmp_.get('good_vs_not_good_equal', '?')}.</p>",
        img_tag(d / figs["matrix"], "Rating matrix (rows: first failure, columns: second) beside the "
                                 "paper's Fig. 7") if "matrix" in figs else "",
        img_tag(d / figs["probabilities"], "Mean probability of each dual against time") if "probabilities" in figs else "",
        defs,
        "<h2>Baselines: each second failure alone</h2>", _table(s["baselines"], rated=False),
        f"<h2>Pairs not rated Good ({len(not_good)})</h2>", _table(not_good, rated=True),
        "<h2>All pairs</h2>", _table(s["pairs"], rated=True),
    ])



def dual_markdown(s: dict) -> str:
    out = header(s, f"Dual failures, {s['runs_per_pair']} runs per ordered pair "
                     f"(first at {s['first_time_s']:g} s, second at {s['second_time_s']:g} s)")
    cmp_ = s.get("paper_comparison") or {}
    out += ["## Ratings", "",
            "- relative to the lone second failure (paper's Fig. 7 rule): "
            + ", ".join(f"{k} {v}" for k, v in s["ratings"].items()),
            "- absolute (>= 90 % correct, no false alarm, no transient-wrong, median latency <= 1.5 s): "
            + ", ".join(f"{k} {v}" for k, v in (s.get("absolute_ratings") or {}).items()),
            *([f"- absolute with the former transient-wrong rule (the lone second failure counted wrong): "
               + ", ".join(f"{k} {v}" for k, v in s["strict_rule"]["absolute_ratings"].items())
               + f"; transient-wrong runs {s['strict_rule']['transient_wrong_runs']}"] if "strict_rule" in s else []),
            f"- same rating as the paper in {cmp_.get('equal', '?')} of {cmp_.get('cells', '?')} comparable cells", ""]
    worse = [p for p in s["pairs"] if p["rating"] != "Good" or p.get("absolute_rating") != "Good"]
    out += [f"## Pairs not Good on either rating ({len(worse)})", "",
            "| pair | correct [95 %] | transient-wrong | runs with FA | latency median (s) | relative | absolute: why |",
            "|---|---|---|---|---|---|---|"]
    for p in worse:
        r = p["evidence"]["rates"]
        out.append(f"| {p['case']} | {rate(r['correct'])} | {r['transient_wrong']['count']} | "
                   f"{r['false_alarm']['count']} | {num(p['latency_s']['median'])} | {p['rating']} | "
                   f"{p.get('absolute_rating')}: {p.get('absolute_rating_reason', '')} |")
    out += ["", "## Baselines (each second failure alone)", ""] + case_rows(s["baselines"], "failure")
    out += not_clean(s, lambda r: r["pair"])
    return "\n".join(out)

register_page("dual", dual_page)
register_markdown("dual", dual_markdown)
