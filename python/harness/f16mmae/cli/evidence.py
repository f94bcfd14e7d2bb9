"""The console's evidence table of a campaign: every rate with its 95 % interval and
verdict, the censored detection fractions, the runs needed, false declarations per flight
hour and the runs that went wrong with their reproduce commands (the first few; all of them
are in summary.json and report.html)."""
from __future__ import annotations

from ..report.evidence import VARIANT_COLUMNS, describe_rate, variant_cells

SHOW_COMMANDS = 5
_SHORT = {"demonstrated": "demo", "consistent": "cons", "not met": "NOT"}


def _pct(x) -> str:
    return "-" if x is None else f"{100 * x:.0f}"


def print_cases(cases: list[dict], stream, label: str = "case") -> None:
    """One line per case (intervals are Clopper-Pearson 95 %, in %)."""
    width = max([len(label)] + [len(c["case"]) for c in cases])
    print(f"  {label:<{width}} {'correct [95% CI]':>17} {'v':>4} {'miss':>4} {'wrong':>5} {'TW':>3} "
          f"{'FA':>3} {'<=0.5/1/2 s/flight %':>21} {'med/p95 det (n)':>18} verdict", file=stream)
    for c in cases:
        ev = c.get("evidence", {})
        rates = ev.get("rates", {})
        if not rates:
            continue
        det = ev.get("detection")
        fr = "-" if not det else "/".join(_pct(det["within_s"][k]) for k in ("0.5", "1", "2")) + \
            f"/{_pct(det['in_flight'])}"
        lat = c.get("latency_s", {})
        med = "-" if lat.get("median") is None else f"{lat['median']:.2f}"
        p95 = "-" if lat.get("p95") is None else f"{lat['p95']:.2f}"
        print(f"  {c['case']:<{width}} {describe_rate(rates['correct']):>17} {_SHORT[rates['correct']['verdict']]:>4} "
              f"{rates['missed']['count']:>4} {rates['wrong']['count']:>5} {rates['transient_wrong']['count']:>3} "
              f"{rates['false_alarm']['count']:>3} {fr:>21} {med + '/' + p95 + ' (' + str(c.get('latency_detected_runs', '?')) + ')':>18} "
              f"{ev.get('verdict') or '-'}", file=stream)


def print_campaign(summary: dict, stream) -> None:
    """The campaign-wide lines: false declarations per hour, runs needed, verdicts, bad runs."""
    fd = summary.get("false_declarations_per_hour") or {}
    if fd.get("rate") is not None:
        lo, hi = fd["ci95"]
        print(f"\nfalse declarations: {fd['events']} in {fd['exposure']:.3f} failure-free flight hours = "
              f"{fd['rate']:.2f}/h (95% {lo:.2f}-{hi:.2f})", file=stream)
    med, n = summary.get("latency_median_s"), summary.get("latency_median_runs")
    if med and n:
        print("median latency over the detected runs: " + ", ".join(
            f"{label} {'-' if med[k] is None else format(med[k], '.2f') + ' s'} ({n[k]})"
            for k, label in (("all", "all"), ("except_vel", "VEL excepted"), ("vel", "VEL"))), file=stream)
    dem = summary.get("demonstration")
    if dem:
        print(f"to demonstrate >= {100 * dem['goal']:.0f}% correct, a case needs {dem['runs_all_correct']} runs "
              f"all correct ({dem['runs_one_failure']} with one failure)", file=stream)
    vc = summary.get("verdict_counts")
    if vc:
        print("verdicts: " + ", ".join(f"{k} {v}" for k, v in vc.items()) + " (demonstrated: the 95% "
              "interval clears the goal; consistent: the point estimate meets it, the interval does not)",
              file=stream)
    bad = summary.get("not_clean") or []
    print(f"runs that went wrong: {len(bad)}", file=stream)
    for r in bad[:SHOW_COMMANDS]:
        print(f"  {r['outcome']}{'+' + '+'.join(r['flags']) if r['flags'] else ''}: {r['command']}", file=stream)
    if len(bad) > SHOW_COMMANDS:
        print(f"  ... {len(bad) - SHOW_COMMANDS} more in summary.json (not_clean) and report.html", file=stream)


def print_variants(summary: dict, stream) -> None:
    """The variants of a campaign flown at several levels or modes, side by side (the bank under test)."""
    axes = summary["axes"]
    cells = [tuple(axes) + VARIANT_COLUMNS] + [variant_cells(r, axes) for r in summary["variants"]]
    widths = [max(len(c[i]) for c in cells) for i in range(len(cells[0]))]
    print(f"{' x '.join(axes)} side by side (common seeds; 95% intervals):", file=stream)
    for c in cells:
        print("  " + "  ".join(f"{x:<{w}}" for x, w in zip(c, widths)), file=stream)
