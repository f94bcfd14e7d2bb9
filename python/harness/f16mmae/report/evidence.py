"""HTML sections every campaign page shares: the runs that went wrong (first), the case table
with 95 % intervals and verdicts, and the campaign-wide evidence (false declarations per
flight hour, runs needed, code identity).  Input: the ``summary.json`` fields documented in
docs/INTERFACES.md ("Campaign records and summary.json")."""
from __future__ import annotations

import html

_VERDICT_CLASS = {"demonstrated": "ok", "consistent": "fair", "not met": "bad"}


def failure_instant_text(s: dict) -> str:
    """A summary's failure time and flight duration, with its failure jitter when it has one
    (campaign/engine/failure_runs.py)."""
    text = f"{s.get('failure_time_s')} / {s.get('duration_s')}"
    jitter = s.get("failure_jitter_s")
    return text + (f", each run's failure and end up to {jitter:g} s later (its seed)" if jitter else "")


def _e(x) -> str:
    return html.escape(str(x))


def _pct(x) -> str:
    return "&ndash;" if x is None else f"{100 * x:.0f}%"


def _s(x) -> str:
    return "&ndash;" if x is None else f"{x:.2f}"


def describe_rate(r: dict | None, digits: int = 0, unit: str = "") -> str:
    """An ``intervals.rate`` record as text, ``k/n [lo-hi<unit>]`` with its Clopper-Pearson bounds in
    percent to ``digits`` places (``-`` for None)."""
    if not r:
        return "-"
    lo, hi = r["ci95"]["clopper_pearson"]
    return f"{r['count']}/{r['runs']} [{100 * lo:.{digits}f}-{100 * hi:.{digits}f}{unit}]"


def describe_per_hour(per_hour: dict | None) -> str:
    """An ``intervals.poisson_rate`` record over flight hours as text: ``k in H h = r/h [lo-hi]``
    (95 % Poisson interval), with the verdict when it has a goal (``-`` for none)."""
    if not per_hour or per_hour.get("rate") is None:
        return "-"
    lo, hi = per_hour["ci95"]
    text = (f"{per_hour['events']} in {per_hour['exposure']:.3f} h = {per_hour['rate']:.2f}/h "
            f"[{lo:.2f}-{hi:.2f}]")
    if "verdict" in per_hour:
        text += f", goal <= {per_hour['goal']:g}/h: {per_hour['verdict']}"
    return text


#: The columns of :func:`variant_cells` after the varying axes (turbulence, mode).
VARIANT_COLUMNS = ("runs", "correct [95 %]", "false declarations per flight hour [95 %]",
                   "latency median / p95 (s), detected of failure runs", "goals met", "cases skipped")


def variant_cells(row: dict, axes: list[str]) -> tuple[str, ...]:
    """One variant of a campaign flown at several turbulence levels or failure modes (a row of a
    summary of kind "variants") as text cells: the values of ``axes``, then :data:`VARIANT_COLUMNS`."""
    lat = row["latency_s"]
    latency = ("-" if lat["median"] is None else f"{lat['median']:.2f} / {lat['p95']:.2f}") + \
        f" ({lat['detected_runs']} of {lat['failure_runs']})"
    correct = describe_rate(row["correct"], digits=1, unit=" %")
    if row["correct"] and "verdict" in row["correct"]:
        correct += f", goal >= {100 * row['correct']['goal']:g} %: {row['correct']['verdict']}"
    return tuple(row[a] for a in axes) + (
        str(row["runs"]), correct,
        describe_per_hour(row["false_declarations_per_hour"]), latency, "yes" if row["goals_met"] else "no",
        ",".join(row.get("cases_skipped") or []) or "-")


def describe_counts(counts: dict[str, int], top: int = 8) -> str:
    """``{name: count}`` (most first) as ``A 5, B 2, ... and N others (M)``, the first ``top``
    by name; ``none`` when empty."""
    items = list(counts.items())
    text = ", ".join(f"{k} {v}" for k, v in items[:top]) or "none"
    if len(items) > top:
        text += f" and {len(items) - top} others ({sum(v for _, v in items[top:])})"
    return text


def rate_cell(rate: dict | None) -> str:
    """``k/n`` with the Clopper-Pearson 95 % interval and, with a goal, the verdict."""
    if not rate:
        return "&ndash;"
    lo, hi = rate["ci95"]["clopper_pearson"]
    text = f"{rate['count']}/{rate['runs']} <small>[{100 * lo:.0f}&ndash;{100 * hi:.0f}%]</small>"
    if "verdict" in rate:
        text += f" <small class='{_VERDICT_CLASS[rate['verdict']]}'>{_e(rate['verdict'])}</small>"
    return text


def drilldown_section(entries: list[dict], label_keys: tuple[str, ...]) -> str:
    """The runs that were not clean, each with its reproduce command."""
    if not entries:
        return "<h2>Runs that went wrong</h2><p>None: every run ended correct, with no false alarm and no transient-wrong declaration.</p>"
    head = "".join(f"<th>{_e(k)}</th>" for k in label_keys) + (
        "<th>run</th><th>seed</th><th>outcome</th><th>flags</th><th>declarations</th><th>fly it again</th>")
    rows = []
    for r in entries:
        decl = ", ".join(f"{d['hypothesis']}@{d['time_s']:.3f}" for d in r["declarations"]) or "none"
        rows.append("<tr class='bad'>" + "".join(f"<td>{_e(r.get(k))}</td>" for k in label_keys)
                    + f"<td>{r['run_index']}</td><td>{r['seed']}</td><td>{_e(r['outcome'])}</td>"
                    f"<td>{_e(', '.join(r['flags']) or '-')}</td><td style='text-align:left'>{_e(decl)}</td>"
                    f"<td style='text-align:left'><code>{_e(r['command'])}</code></td></tr>")
    return (f"<h2>Runs that went wrong ({len(entries)})</h2><p>Missed, wrong, transient-wrong or with a "
            f"false alarm. Each command flies the run again with the same declarations.</p>"
            f"<table><tr>{head}</tr>{''.join(rows)}</table>")


def evidence_table(cases: list[dict], label: str = "case") -> str:
    """One row per case: every rate with its interval and verdict, the censored detection
    fractions, the latency over detected runs, and the case's overall verdict."""
    head = (f"<tr><th>{_e(label)}</th><th>correct</th><th>missed</th><th>wrong</th><th>transient-wrong</th>"
            "<th>runs with a false alarm</th><th>detected &le;0.5 / 1 / 2 s / in flight</th>"
            "<th>&le;1 s &ge; 50%</th><th>&le;2 s &ge; 95%</th>"
            "<th>latency median / p95, detected runs (n)</th><th>verdict</th></tr>")
    rows = []
    for c in cases:
        ev = c.get("evidence", {})
        rates = ev.get("rates", {})
        det = ev.get("detection")
        if det:
            w = det["within_s"]
            fr = f"{_pct(w.get('0.5'))} / {_pct(w.get('1'))} / {_pct(w.get('2'))} / {_pct(det['in_flight'])}"
            w1, w2 = rate_cell(det["within_1s"]), rate_cell(det["within_2s"])
        else:
            fr = w1 = w2 = "&ndash;"
        lat = c.get("latency_s", {})
        v = ev.get("verdict")
        rows.append(
            f"<tr class='{_VERDICT_CLASS.get(v, '')}'><td>{_e(c['case'])}</td>"
            + "".join(f"<td>{rate_cell(rates.get(k))}</td>"
                      for k in ("correct", "missed", "wrong", "transient_wrong", "false_alarm"))
            + f"<td>{fr}</td><td>{w1}</td><td>{w2}</td>"
            f"<td>{_s(lat.get('median'))} / {_s(lat.get('p95'))} ({c.get('latency_detected_runs', '?')})</td>"
            f"<td>{_e(v or '-')}</td></tr>")
    return "<table>" + head + "".join(rows) + "</table>"


def campaign_evidence(s: dict) -> str:
    """False declarations per flight hour, runs needed, verdict counts, code identity."""
    fd = s.get("false_declarations_per_hour") or {}
    dem = s.get("demonstration") or {}
    vc = s.get("verdict_counts") or {}
    code = s.get("code") or {}
    items = []
    if fd.get("rate") is not None:
        lo, hi = fd["ci95"]
        items.append(f"false declarations: {fd['events']} in {fd['exposure']:.3f} failure-free flight hours = "
                     f"{fd['rate']:.2f} per hour (95 % {lo:.2f}&ndash;{hi:.2f})")
    if dem:
        items.append(f"to demonstrate &ge; {100 * dem['goal']:.0f} % correct a case needs "
                     f"{dem['runs_all_correct']} runs all correct ({dem['runs_one_failure']} with one failure)")
    if vc:
        items.append("cases: " + ", ".join(f"{k} {v}" for k, v in vc.items()))
    if "goals_met" in s:
        items.append("goals: " + ("no goal is not met" if s["goals_met"] else "some goal is NOT met"))
    if code:
        items.append(f"code {_e(code.get('code'))}, JSBSim {_e(code.get('jsbsim'))}, LCM {_e(code.get('lcm'))}")
    mixed = s.get("codes_in_records") or {}
    if len(mixed) > 1:
        items.append("MIXED records: " + ", ".join(f"{_e(k)} ({v} runs)" for k, v in mixed.items()))
    seeds = "evaluation seeds (never used for tuning)"
    items.append(f"seeds: {seeds}, campaign seed {_e(s.get('seed'))}")
    return "<ul>" + "".join(f"<li>{x}</li>" for x in items) + "</ul>"


def settings_text(s: dict) -> str:
    """The estimator settings in force, and which came from the bank and which from options."""
    in_force = s.get("estimator_settings") or {}
    over = s.get("estimator") or {}
    if not in_force:
        return "core defaults (the bank recommends none)"
    from_bank = [k for k in in_force if k not in over]
    src = []
    if from_bank:
        src.append("bank: " + ", ".join(from_bank))
    if over:
        src.append("options: " + ", ".join(over))
    rest = "" if {"p_min", "threshold", "dwell_s"} <= in_force.keys() else "; others core defaults"
    return ", ".join(f"{k}={v}" for k, v in in_force.items()) + f" ({'; '.join(src)}{rest})"
