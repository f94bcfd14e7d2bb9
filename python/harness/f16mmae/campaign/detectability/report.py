"""The table of a detectability campaign (``summary.json`` of kind "detectability"), once, and
its three renderings: console lines, the HTML report page and the Markdown results page, both
registered with the report on import.

One row per (family, component, size): the size in its unit and in the truth's unit, P(detect)
``k/n [lo-hi %]`` (95 % Clopper-Pearson), P(any failure declared after the onset), runs with a
false alarm, the median latency of the detected runs, and the hypotheses most often declared
instead of the failed component (each run's first other declaration after the onset)."""
from __future__ import annotations

import html
from pathlib import Path

from ...report.evidence import describe_rate, drilldown_section
from ...report.figures import img_tag
from ...report.markdown import _setting, register_markdown
from ...report.page import param_table, register_page

COLUMNS = ("family", "component", "size", "truth value", "P(detect) [95 %]", "P(any declared) [95 %]",
           "runs with FA", "latency median (s)", "declared instead (runs)")

DEFINITIONS = (
    ("sizes", "bias: multiples of the sensor's white-noise sigma (the truth model's NOISE_SIGMA: "
              "0.5 ft/s, 0.1 deg, 0.1 deg/s, 0.01 g, 0.1 deg/s, 0.1 deg/s, 0.005 g for VEL AOA PIT AZ ROL YAW AY); "
              "drift: sigma per second from the onset; loss: fraction of the surface's effectiveness lost "
              "(1 = none left)"),
    ("detected", "the failed component's hypothesis declared at or after the onset within the flight "
                 "(not necessarily the final declaration)"),
    ("any declared", "some failure hypothesis declared at or after the onset; above P(detect) it is mis-isolation"),
    ("false alarm", "a failure declared before the onset"),
    ("runs that went wrong", "runs that declared a wrong failure: a false alarm, or another failure after the "
                             "onset; a run that merely missed a small failure is a point of the curve"),
    ("intervals", "95 % Clopper-Pearson; summary.json also holds the Wilson intervals"),
    ("seeds", "evaluation seeds, run n of a component flies the same seed at every size and family"),
)


def _lat(x) -> str:
    return "-" if x is None else f"{x:.2f}"


def table_rows(s: dict) -> list[tuple[str, ...]]:
    """The rows of the table, in :data:`COLUMNS` order."""
    rows = []
    for family, fam in s["families"].items():
        for comp in fam["components"]:
            for p in comp["points"]:
                if not p["runs"]:
                    continue
                rows.append((family, comp["component"], f"{p['size']:g} {fam['unit']}", f"{p['value']:.4g}",
                             describe_rate(p["detected"], unit=" %"), describe_rate(p["any_declared"], unit=" %"),
                             str(p["false_alarm"]["count"]), _lat(p["latency_median_s"]),
                             " ".join(f"{h} {k}" for h, k in p["declared_instead"].items()) or "-"))
    return rows


def _setting_lines(s: dict) -> list[tuple[str, str]]:
    t = s.get("timing", {})
    code = s.get("code") or {}
    return [("runs per size", str(s["runs_per_size"])), ("campaign seed", str(s["seed"])),
            ("flight condition", f"Mach {s['mach']}, {s['alt_ft']:.0f} ft"), ("turbulence", s["turbulence"]),
            ("failure time / duration (s)", f"{s['failure_time_s']} / {s['duration_s']}"
             + (f", each run's failure and end up to {s['failure_jitter_s']:g} s later (its seed)"
                if s.get("failure_jitter_s") else "")),
            ("bank (tuning, hash)", f"{s['tuning']}, {s['bank_hash']}"),
            ("estimator settings", ", ".join(f"{k} {_setting(v)}" for k, v in s["estimator_settings"].items())),
            ("code", f"{s['version']}, {code.get('code', 'unrecorded')}"),
            ("wall time", f"{t.get('wall_s', 0):.1f} s for {t.get('runs_executed', '?')} runs "
                          f"({t.get('runs_resumed', 0)} resumed) on {t.get('executor', '?')}")]


def print_table(s: dict, stream) -> None:
    """The table on the console."""
    rows = [COLUMNS] + table_rows(s)
    widths = [max(len(r[i]) for r in rows) for i in range(len(COLUMNS))]
    for r in rows:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip(), file=stream)


def detectability_page(d: Path, s: dict) -> str:
    parts = ["<h1>f16mmae detectability curves</h1>", "<h2>Campaign</h2>", param_table(_setting_lines(s)),
             "<h2>Figures</h2>"]
    for family, name in (s.get("figures") or {}).items():
        parts.append(img_tag(d / name, f"Detection probability against {family} size"))
    head = "".join(f"<th>{html.escape(c)}</th>" for c in COLUMNS)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in table_rows(s))
    parts += ["<h2>Table</h2>", f"<table><tr>{head}</tr>{body}</table>", "<h2>Definitions</h2><dl>"]
    parts += [f"<dt>{html.escape(k)}</dt><dd>{html.escape(v)}</dd>" for k, v in DEFINITIONS]
    parts.append("</dl>")
    parts.append(drilldown_section(s.get("not_clean", []), ("family", "component", "size")))
    return "".join(parts)


def detectability_markdown(s: dict) -> str:
    cmd = s.get("command") or "(not recorded: made through the Python API)"
    out = [f"# Detectability curves at Mach {s['mach']:g}, {s['alt_ft']:.0f} ft, {s['runs_per_size']} runs "
           "per size", "", "Generated from `summary.json` by `f16mmae report DIR --markdown FILE`.", "",
           "```", cmd, "```", ""]
    out += [f"- {k}: {v}" for k, v in _setting_lines(s)]
    out += [f"- {k}: {v}" for k, v in DEFINITIONS]
    fd = s.get("false_declarations_per_hour") or {}
    if fd.get("rate") is not None:
        out.append(f"- false declarations: {fd['events']} in {fd['exposure']:.3f} failure-free flight hours "
                   f"(95 %: {fd['ci95'][0]:.2f}-{fd['ci95'][1]:.2f} per hour)")
    bad = s.get("not_clean") or []
    out.append(f"- runs that declared a wrong failure (a false alarm, or another failure after the onset): "
               f"{len(bad)}, each with the `f16mmae run` command that flies it again in summary.json (`not_clean`)")
    out += ["", "Figures (in the campaign directory): "
            + ", ".join(f"`{n}`" for n in (s.get("figures") or {}).values()), "",
            "| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    out += ["| " + " | ".join(r) + " |" for r in table_rows(s)]
    return "\n".join(out) + "\n"


register_page("detectability", detectability_page)
register_markdown("detectability", detectability_markdown)
