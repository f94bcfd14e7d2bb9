"""One campaign flown at several turbulence levels and/or failure modes, side by side.

``--turbulence none,light,moderate,severe`` (``CampaignConfig.levels``) and, for the kinds
that take it, ``--mode complete,stuck,loss=0.5`` (``CampaignConfig.modes``): :func:`fly_variants`
plans the kind's runs once per variant -- each (level, mode) pair, the config with ``turbulence``
and ``mode`` set to it, narrowed by the kind's ``variant`` hook (the single campaign drops the
cases a mode does not apply to) -- and flies them all through one ``execute`` (one store, one
progress bar, one resume; a run planned by two variants, e.g. NONE in every mode, flies once).
The seeds depend on neither the level nor the mode, so run n of case c flies the same seed in
every variant: common random numbers.  Each variant is summarized as the kind does for one.

* One variant: the kind's summary and figures in ``DIR``, exactly as without this module.
* Several: each variant's summary and figures in ``DIR/<variant>/`` (``light``, ``stuck``,
  ``light-stuck``; a campaign directory of its own for ``f16mmae report DIR/<variant>``, its
  records staying in ``DIR/runs.jsonl``), and in ``DIR/summary.json`` a summary of kind
  ``"variants"`` (:func:`combine`): the axes that vary, and per variant the bank under test's
  correct fraction, false declarations per flight hour and detection latency (median and p95
  over detected failure runs) with their intervals, the variant's goals verdict and the cases it
  skipped; the runs that went wrong in every variant (labelled with it); ``goals_met`` when
  every variant's is.  The figure ``variants.png`` draws the three against the variant.

The correct fraction of a variant carries the isolation goal of its turbulence level
(:data:`LEVEL_CORRECT_GOALS`: at least 99 % correct in calm air, light and moderate turbulence,
95 % in severe) and its verdict; the kind's own per-case goals stay in ``goals_met``.
"""
from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ...report.figures import pyplot, save_figure
from . import evidence, intervals, variants_report
from .runner import Execution
from .store import write_summary

VARIANTS_KIND = variants_report.KIND
AXES: tuple[str, ...] = ("turbulence", "mode")
#: The fraction of a variant's runs that must end correct, by turbulence level.
LEVEL_CORRECT_GOALS: dict[str, float] = {"none": 0.99, "light": 0.99, "moderate": 0.99, "severe": 0.95}


def same_cases(cfg) -> tuple[object, list[str]]:
    """The default ``variant`` hook: the variant's config as it is, no case skipped."""
    return cfg, []


def fly_variants(cfg, out: Path, plan: Callable[[object], list[dict]],
                 execute: Callable[[list[dict]], Execution],
                 summarize: Callable[[object, list[dict], Path], dict],
                 under_test: Callable[[dict], bool] = lambda r: True,
                 variant: Callable[[object], tuple[object, list[str]]] = same_cases) -> tuple[dict, Execution]:
    """Plan, fly and summarize ``cfg`` in each of its variants (module docstring).
    ``plan(cfg_v)``: the variant's specs; ``execute(specs)``: ``runner.execute`` with the kind's
    arguments; ``summarize(cfg_v, records, directory)``: the variant's summary with its figures
    written into ``directory``; ``under_test(record)``: the records of the bank under test;
    ``variant(cfg_v)``: the config to fly and the cases skipped (``same_cases`` by default)."""
    levels, modes = cfg.levels(), cfg.modes()
    axes = [a for a, values in zip(AXES, (levels, modes)) if len(values) > 1]
    variants = []
    for lvl in levels:
        for mode in modes:
            c, skipped = variant(dataclasses.replace(cfg, turbulence=lvl, mode=mode))
            name = "-".join(v for a, v in zip(AXES, (lvl, mode)) if a in axes)
            variants.append((name, {"turbulence": lvl, "mode": mode}, c, skipped))
    keys: dict[str, set[str]] = {}
    specs: dict[str, dict] = {}
    for name, _, c, _ in variants:
        planned = plan(c)
        keys[name] = {s["run_key"] for s in planned}
        specs.update((s["run_key"], s) for s in planned if s["run_key"] not in specs)
    done = execute(list(specs.values()))
    if not axes:
        _, _, c, skipped = variants[0]
        summary = summarize(c, done.records, out)
        if skipped:
            summary["cases_skipped"] = skipped
        return summary, done
    rows, summaries = [], []
    for name, values, c, skipped in variants:
        d = out / name
        d.mkdir(exist_ok=True)
        records = [r for r in done.records if r["run_key"] in keys[name]]
        summary = summarize(c, records, d)
        if skipped:
            summary["cases_skipped"] = skipped
        write_summary(d / "summary.json", summary)
        rows.append({**values, **variant_row(name, summary, [r for r in records if under_test(r)],
                                             LEVEL_CORRECT_GOALS.get(values["turbulence"])),
                     "cases_skipped": skipped})
        summaries.append((name, summary))
    combined = combine(axes, levels, modes, rows, summaries)
    combined["figures"] = {"variants": against_variant(rows, out / "variants.png").name}
    return combined, done


def variant_row(name: str, summary: dict, records: list[dict], correct_goal: float | None = None) -> dict:
    """One variant's row: correct (with ``correct_goal`` and its verdict when given), false
    declarations per hour, latency, goals (module docstring)."""
    n = len(records)
    lat = sorted(float(r["latency_s"]) for r in records if r.get("latency_s") is not None)
    return {
        "label": name, "directory": name, "runs": n,
        "correct": intervals.rate(sum(r["outcome"] == "correct" for r in records), n, goal=correct_goal)
        if n else None,
        "false_declarations_per_hour": evidence.false_declaration_rate(records),
        "latency_s": {"median": round(float(np.median(lat)), 6) if lat else None,
                      "p95": round(float(np.percentile(lat, 95)), 6) if lat else None,
                      "detected_runs": len(lat), "failure_runs": sum(1 for r in records if r["scenario"]["failures"])},
        "goals_met": bool(summary.get("goals_met")),
    }


def combine(axes: list[str], levels: tuple[str, ...], modes: tuple[str, ...], rows: list[dict],
            summaries: list[tuple[str, dict]]) -> dict:
    """The summary of kind ``"variants"`` (module docstring)."""
    first = summaries[0][1]
    shared = {k: first.get(k) for k in ("seed", "tuning", "bank_hash", "version", "code", "estimator_settings")}
    return {
        "kind": VARIANTS_KIND, "campaign": first["kind"], **shared, "axes": axes,
        "turbulence": ",".join(levels), "mode": ",".join(modes), "variants": rows,
        "goals_met": all(s.get("goals_met") for _, s in summaries),
        "not_clean": [{"variant": name, **e} for name, s in summaries for e in s.get("not_clean", [])],
    }


def against_variant(rows: list[dict], path: Path) -> Path:
    """Correct fraction, false declarations per hour and latency against the variant, with
    95 % intervals (latency: median, and p95 as the bar's top)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
    xs = np.arange(len(rows))
    names = [r["label"] for r in rows]

    def bars(ax, values, lo, hi, ylabel):
        v = np.array([np.nan if x is None else x for x in values], dtype=float)
        ax.errorbar(xs, v, yerr=[np.nan_to_num(v - lo), np.nan_to_num(hi - v)], fmt="o", capsize=4)
        ax.set_xticks(xs, names)
        ax.set_xlabel("variant")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.tick_params(axis="x", labelrotation=30 if len(rows) > 4 else 0)

    c = [r["correct"] for r in rows]
    bars(axes[0], [x and x["fraction"] for x in c], np.array([x["ci95"]["clopper_pearson"][0] if x else np.nan for x in c]),
         np.array([x["ci95"]["clopper_pearson"][1] if x else np.nan for x in c]), "runs correct (95 % CP)")
    f = [r["false_declarations_per_hour"] for r in rows]
    bars(axes[1], [x["rate"] for x in f], np.array([x["ci95"][0] if x["ci95"] else np.nan for x in f]),
         np.array([x["ci95"][1] if x["ci95"] else np.nan for x in f]), "false declarations / flight h (95 %)")
    med = [r["latency_s"]["median"] for r in rows]
    p95 = np.array([np.nan if r["latency_s"]["p95"] is None else r["latency_s"]["p95"] for r in rows])
    bars(axes[2], med, np.array([np.nan if m is None else m for m in med]), p95, "latency (s): median, bar to p95")
    return save_figure(fig, path)
