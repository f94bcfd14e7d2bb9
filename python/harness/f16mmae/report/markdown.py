"""A campaign's results as Markdown (``f16mmae report DIR --markdown FILE``), generated from its
``summary.json`` so that a results page cannot drift from what the code measured.

The page states the command that made the campaign (``summary["command"]``, recorded by the
command line), the code identity, that the seeds are evaluation seeds, the pooled totals and
false declarations per flight hour with 95 % intervals, one table per kind, and the runs that
went wrong with their reproduce commands (the first :data:`MAX_LISTED`; all are in
summary.json).  Rates read ``k/n [lo-hi %]``: Clopper-Pearson 95 % intervals.
"""
from __future__ import annotations

from collections.abc import Callable

from .evidence import VARIANT_COLUMNS, describe_rate, variant_cells

MAX_LISTED = 25
#: The declarations listed per run that went wrong (all are in summary.json).
MAX_DECLARATIONS = 8


def rate(r: dict | None) -> str:
    return describe_rate(r, digits=1, unit=" %")


def num(x) -> str:
    return "-" if x is None else f"{x:.2f}"


def _pct(x) -> str:
    return "-" if x is None else f"{100 * x:.0f}"


def _setting(v) -> str:
    """An estimator setting as text: a number in %g, a table {name: N} as "(LS 32, ...)"."""
    if isinstance(v, dict):
        return "(" + ", ".join(f"{k} {_setting(x)}" for k, x in v.items()) + ")"
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return f"{v:g}"
    return str(v)


def header(s: dict, title: str) -> list[str]:
    code = s.get("code") or {}
    cmd = s.get("command") or "(not recorded: made through the Python API)"
    settings = ", ".join(f"{k} {_setting(v)}" for k, v in (s.get("estimator_settings") or {}).items()) or "core defaults"
    out = [f"# {title}", "", "Generated from `summary.json` by `f16mmae report DIR --markdown FILE`.", "",
           "```", cmd, "```", "",
           f"- code {code.get('code', 'unrecorded')}, JSBSim {code.get('jsbsim')}, LCM {code.get('lcm')}",
           f"- bank `{s.get('tuning')}` {str(s.get('bank_hash'))[:12]}, estimator settings in force: {settings}",
           f"- {s.get('turbulence')} turbulence, "
           + (f"failure mode `{s['mode']}`, " if s.get("mode") else "")
           + f"campaign seed {s.get('seed')}: evaluation seeds, which the tuning never flew"]
    t = s.get("totals") or {}
    if t:
        out.append(f"- pooled: correct {rate(t['correct'])}, runs with a false alarm {rate(t['false_alarm'])}, "
                   f"transient-wrong runs {rate(t['transient_wrong'])}")
    fd = s.get("false_declarations_per_hour") or {}
    if fd.get("rate") is not None:
        lo, hi = fd["ci95"]
        out.append(f"- false declarations: {fd['events']} in {fd['exposure']:.3f} failure-free flight hours = "
                   f"{fd['rate']:.2f} per hour (95 %: {lo:.2f}-{hi:.2f})")
    vc = s.get("verdict_counts") or {}
    if vc:
        out.append("- case verdicts: " + ", ".join(f"{k} {v}" for k, v in vc.items())
                   + f"; goals met (no verdict *not met*): {'yes' if s.get('goals_met') else 'no'}")
    dem = s.get("demonstration") or {}
    if dem:
        out.append(f"- to demonstrate >= {100 * dem['goal']:.0f} % correct a case needs {dem['runs_all_correct']} "
                   f"runs all correct ({dem['runs_one_failure']} with one failure)")
    return out + [""]


def case_rows(cases: list[dict], label: str = "case") -> list[str]:
    out = [f"| {label} | correct [95 %] | verdict | missed | wrong | transient-wrong | runs with FA | "
           "detected <= 0.5 / 1 / 2 s / in flight (%) | latency median / p95, detected runs (n) | case verdict |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        ev = c.get("evidence") or {}
        r = ev.get("rates") or {}
        if not r:
            continue
        det = ev.get("detection")
        fr = "-" if not det else " / ".join(_pct(det["within_s"][k]) for k in ("0.5", "1", "2")) + \
            f" / {_pct(det['in_flight'])}"
        lat = c.get("latency_s") or {}
        out.append(f"| {c['case']} | {rate(r['correct'])} | {r['correct'].get('verdict', '-')} | "
                   f"{r['missed']['count']} | {r['wrong']['count']} | {r['transient_wrong']['count']} | "
                   f"{r['false_alarm']['count']} | {fr} | {num(lat.get('median'))} / {num(lat.get('p95'))} "
                   f"({c.get('latency_detected_runs', '?')}) | {ev.get('verdict') or '-'} |")
    return out + [""]


def not_clean(s: dict, label: Callable[[dict], str]) -> list[str]:
    bad = s.get("not_clean") or []
    out = [f"## Runs that went wrong ({len(bad)})", ""]
    if not bad:
        return out + ["None.", ""]
    for r in bad[:MAX_LISTED]:
        flags = "+".join([r["outcome"]] + r["flags"])
        decl = ", ".join(f"{d['hypothesis']}@{d['time_s']:.2f}" for d in r["declarations"][:MAX_DECLARATIONS]) or "none"
        if len(r["declarations"]) > MAX_DECLARATIONS:
            decl += f", ... {len(r['declarations']) - MAX_DECLARATIONS} more"
        out.append(f"- {label(r)} run {r['run_index']} ({flags}; {decl}): `{r['command']}`")
    if len(bad) > MAX_LISTED:
        out.append(f"- ... {len(bad) - MAX_LISTED} more in summary.json (`not_clean`)")
    return out + [""]







def variants_markdown(s: dict) -> str:
    columns = tuple(s["axes"]) + VARIANT_COLUMNS
    out = header(s, f"The {s['campaign']} campaign in {len(s['variants'])} variants of "
                     f"{' and '.join(s['axes'])} (common seeds)")
    out += ["## Side by side (the bank under test)", "",
            "| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    out += ["| " + " | ".join(variant_cells(row, s["axes"])) + " |" for row in s["variants"]]
    out += ["", "Each variant's full results: `f16mmae report DIR/<variant> --markdown FILE`.", ""]
    out += not_clean(s, lambda r: " ".join(str(r[k]) for k in ("variant", "tuning", "case", "pair", "point") if k in r))
    return "\n".join(out)


#: Each campaign kind registers its page on import (``register_markdown``); the variants page
#: (any kind flown in several variants) is the report's own.
MARKDOWN: dict[str, Callable[[dict], str]] = {"variants": variants_markdown}


def register_markdown(kind: str, render: Callable[[dict], str]) -> None:
    """Register the Markdown page of a campaign kind (a kind registers it on import, as it
    registers its HTML page)."""
    MARKDOWN[kind] = render


def summary_markdown(summary: dict) -> str:
    """The Markdown page of a campaign summary, by its kind (ValueError for another kind)."""
    kind = summary.get("kind")
    if kind not in MARKDOWN:
        raise ValueError(f"no Markdown page for campaign kind {kind!r}; valid: {', '.join(MARKDOWN)}")
    return MARKDOWN[kind](summary) + "\n"
