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

from .evidence import VARIANT_COLUMNS, describe_counts, describe_per_hour, describe_rate, variant_cells

MAX_LISTED = 25
#: The declarations listed per run that went wrong (all are in summary.json).
MAX_DECLARATIONS = 8


def _rate(r: dict | None) -> str:
    return describe_rate(r, digits=1, unit=" %")


def _s(x) -> str:
    return "-" if x is None else f"{x:.2f}"


def _pct(x) -> str:
    return "-" if x is None else f"{100 * x:.0f}"


def _header(s: dict, title: str) -> list[str]:
    code = s.get("code") or {}
    cmd = s.get("command") or "(not recorded: made through the Python API)"
    settings = ", ".join(f"{k} {v:g}" for k, v in (s.get("estimator_settings") or {}).items()) or "core defaults"
    out = [f"# {title}", "", "Generated from `summary.json` by `f16mmae report DIR --markdown FILE`.", "",
           "```", cmd, "```", "",
           f"- code {code.get('code', 'unrecorded')}, JSBSim {code.get('jsbsim')}, LCM {code.get('lcm')}",
           f"- bank `{s.get('tuning')}` {str(s.get('bank_hash'))[:12]}, estimator settings in force: {settings}",
           f"- {s.get('turbulence')} turbulence, "
           + (f"failure mode `{s['mode']}`, " if s.get("mode") else "")
           + f"campaign seed {s.get('seed')}: evaluation seeds, which the tuning never flew"]
    t = s.get("totals") or {}
    if t:
        out.append(f"- pooled: correct {_rate(t['correct'])}, runs with a false alarm {_rate(t['false_alarm'])}, "
                   f"transient-wrong runs {_rate(t['transient_wrong'])}")
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


def _case_rows(cases: list[dict], label: str = "case") -> list[str]:
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
        out.append(f"| {c['case']} | {_rate(r['correct'])} | {r['correct'].get('verdict', '-')} | "
                   f"{r['missed']['count']} | {r['wrong']['count']} | {r['transient_wrong']['count']} | "
                   f"{r['false_alarm']['count']} | {fr} | {_s(lat.get('median'))} / {_s(lat.get('p95'))} "
                   f"({c.get('latency_detected_runs', '?')}) | {ev.get('verdict') or '-'} |")
    return out + [""]


def _not_clean(s: dict, label: Callable[[dict], str]) -> list[str]:
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


def single_markdown(s: dict) -> str:
    out = _header(s, f"Single failures at Mach {s['mach']:g}, {s['alt_ft']:.0f} ft, "
                     f"{s['runs_per_case']} runs per case")
    out += ["## Cases", ""] + _case_rows(s["cases"])
    out += _not_clean(s, lambda r: f"{r.get('tuning')} {r['case']}")
    return "\n".join(out)


def dual_markdown(s: dict) -> str:
    out = _header(s, f"Dual failures, {s['runs_per_pair']} runs per ordered pair "
                     f"(first at {s['first_time_s']:g} s, second at {s['second_time_s']:g} s)")
    cmp_ = s.get("paper_comparison") or {}
    out += ["## Ratings", "",
            "- relative to the lone second failure (paper's Fig. 7 rule): "
            + ", ".join(f"{k} {v}" for k, v in s["ratings"].items()),
            "- absolute (>= 90 % correct, no false alarm, no transient-wrong, median latency <= 1.5 s): "
            + ", ".join(f"{k} {v}" for k, v in (s.get("absolute_ratings") or {}).items()),
            f"- same rating as the paper in {cmp_.get('equal', '?')} of {cmp_.get('cells', '?')} comparable cells", ""]
    worse = [p for p in s["pairs"] if p["rating"] != "Good" or p.get("absolute_rating") != "Good"]
    out += [f"## Pairs not Good on either rating ({len(worse)})", "",
            "| pair | correct [95 %] | transient-wrong | runs with FA | latency median (s) | relative | absolute: why |",
            "|---|---|---|---|---|---|---|"]
    for p in worse:
        r = p["evidence"]["rates"]
        out.append(f"| {p['case']} | {_rate(r['correct'])} | {r['transient_wrong']['count']} | "
                   f"{r['false_alarm']['count']} | {_s(p['latency_s']['median'])} | {p['rating']} | "
                   f"{p.get('absolute_rating')}: {p.get('absolute_rating_reason', '')} |")
    out += ["", "## Baselines (each second failure alone)", ""] + _case_rows(s["baselines"], "failure")
    out += _not_clean(s, lambda r: r["pair"])
    return "\n".join(out)


def envelope_markdown(s: dict) -> str:
    out = _header(s, f"Off the design point: {len(s['points'])} points, {s['runs_per_case']} runs per case "
                     f"and point")
    out += ["## Points", "",
            "| point | Mach | alt (ft) | correct [95 %] | runs with FA [95 %] | transient-wrong | "
            "latency median (s) | acceptable | verdict |", "|---|---|---|---|---|---|---|---|---|"]
    for p in s["points"]:
        r = p["evidence"]["rates"]
        out.append(f"| {p['label']} | {p['mach']:.3f} | {p['alt_ft']:.0f} | {_rate(r.get('correct'))} | "
                   f"{_rate(r.get('false_alarm'))} | {r.get('transient_wrong', {}).get('count', '-')} | "
                   f"{_s(p['latency_median_s'])} | {'yes' if p['acceptable'] else 'no'} | {p['evidence']['verdict']} |")
    out += [""] + _not_clean(s, lambda r: f"point {r['point']} {r['case']}")
    return "\n".join(out)


def soak_markdown(s: dict) -> str:
    out = _header(s, f"Soak: {s['flights_per_level']} failure-free flights of {s['flight_s']:g} s per turbulence "
                     f"level from Mach {s['mach']:g}, {s['alt_ft']:.0f} ft, "
                     + ("maneuvering: " + ", ".join(f"`{m}`" for m in s["maneuvers"]) if s.get("maneuvers")
                        else "trim (no maneuvers)"))
    out += ["## False declarations per flight hour", "",
            "| turbulence | flights | hours | false declarations per hour [95 %], goal: verdict | "
            "flights with one | first in its flight, median / earliest (s) | hypotheses involved | "
            "lasted median / max (s) | ended: backed out / replaced / flight end |", "|---|---|---|---|---|---|---|---|---|"]
    for lv in s["levels"]:
        hyps = describe_counts(lv["hypotheses"])
        ends = " / ".join(str(lv["episodes_by_end"][k]) for k in ("backed out", "replaced", "flight end"))
        out.append(f"| {lv['level']} | {lv['flights']} | {lv['hours']:.3f} | {describe_per_hour(lv['per_hour'])} | "
                   f"{lv['flights_with_false_declaration']} | {_s(lv['first_declaration_s']['median'])} / "
                   f"{_s(lv['first_declaration_s']['min'])} | {hyps} | {_s(lv['duration_s']['median'])} / "
                   f"{_s(lv['duration_s']['max'])} | {ends} |")
    out += ["", f"Goals met (no level *not met*): {'yes' if s.get('goals_met') else 'no'}", ""]
    out += _not_clean(s, lambda r: f"{r['level']} flight")
    return "\n".join(out)


def maneuver_markdown(s: dict) -> str:
    out = _header(s, f"Maneuvers: {', '.join(s['maneuvers'])} at {len(s['points'])} point(s), "
                     f"{s['runs_per_case']} run(s) per case, failure at {s['failure_time_s']:g} s into a "
                     f"maneuver begun at {s['maneuver_time_s']:g} s of a {s['duration_s']:g}-s flight")
    out += ["## Per maneuver", "",
            "| maneuver | correct [95 %] | runs with FA [95 %] | false declarations per maneuvering hour "
            "[95 %] | latency median (s, VEL apart) | VEL latency median (s) | verdict |",
            "|---|---|---|---|---|---|---|"]
    for r in s["by_maneuver"] + [{"maneuver": "all", **s["overall"]}]:
        out.append(f"| {r['maneuver']} | {_rate(r['rates'].get('correct'))} | {_rate(r['rates'].get('false_alarm'))} | "
                   f"{describe_per_hour(r['per_hour'])} | {_s(r['latency_median_s'])} | "
                   f"{_s(r['vel_latency_median_s'])} | {r.get('verdict')} |")
    out += ["", "## Per point and maneuver", "",
            "| point | Mach | alt (ft) | maneuver flown | correct [95 %] | runs with FA | latency median (s) |",
            "|---|---|---|---|---|---|---|"]
    for c in s["by_point"]:
        out.append(f"| {c['point']} | {c['mach']:.3f} | {c['alt_ft']:.0f} | `{c['maneuver_spec']}` | "
                   f"{_rate(c['rates'].get('correct'))} | {c['false_alarm_runs']}/{c['runs']} | "
                   f"{_s(c['latency_median_s'])} |")
    out += [""] + _not_clean(s, lambda r: f"point {r['point']} {r['maneuver']} {r['case']}")
    return "\n".join(out)


def variants_markdown(s: dict) -> str:
    columns = tuple(s["axes"]) + VARIANT_COLUMNS
    out = _header(s, f"The {s['campaign']} campaign in {len(s['variants'])} variants of "
                     f"{' and '.join(s['axes'])} (common seeds)")
    out += ["## Side by side (the bank under test)", "",
            "| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    out += ["| " + " | ".join(variant_cells(row, s["axes"])) + " |" for row in s["variants"]]
    out += ["", "Each variant's full results: `f16mmae report DIR/<variant> --markdown FILE`.", ""]
    out += _not_clean(s, lambda r: " ".join(str(r[k]) for k in ("variant", "tuning", "case", "pair", "point") if k in r))
    return "\n".join(out)


MARKDOWN: dict[str, Callable[[dict], str]] = {
    "single": single_markdown, "dual": dual_markdown, "envelope": envelope_markdown, "soak": soak_markdown,
    "maneuver": maneuver_markdown, "variants": variants_markdown}


def register_markdown(kind: str, render: Callable[[dict], str]) -> None:
    """Register the Markdown page of a campaign kind that lives outside this module (a kind
    registers it on import, as it registers its HTML page)."""
    MARKDOWN[kind] = render


def summary_markdown(summary: dict) -> str:
    """The Markdown page of a campaign summary, by its kind (ValueError for another kind)."""
    kind = summary.get("kind")
    if kind not in MARKDOWN:
        raise ValueError(f"no Markdown page for campaign kind {kind!r}; valid: {', '.join(MARKDOWN)}")
    return MARKDOWN[kind](summary) + "\n"
