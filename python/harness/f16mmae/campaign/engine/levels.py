"""One campaign flown at several turbulence levels, the levels side by side.

``--turbulence none,light,moderate,severe`` (``CampaignConfig.levels``): :func:`fly_levels`
plans the kind's runs once per level (the config with ``turbulence`` set to that level; the
seeds do not depend on the level, so run n of case c flies the same seed at every level:
common random numbers), flies them all through one ``execute`` (one store, one progress
bar, one resume), then summarizes each level as the kind does for one level.

* One level: the kind's summary and figures in ``DIR``, exactly as without this module.
* Several: each level's summary and figures in ``DIR/<level>/`` (a campaign directory of its
  own for ``f16mmae report DIR/<level>``; its records stay in ``DIR/runs.jsonl``), and in
  ``DIR/summary.json`` a summary of kind ``"levels"`` (:func:`combine`): the kind, the levels,
  per level the bank under test's correct fraction, false declarations per flight hour and
  detection latency (median and p95 over detected failure runs) with their intervals, the
  level's goals verdict, and the runs that went wrong of every level (labelled with it);
  ``goals_met`` when every level's is.  The figure ``levels.png`` draws the three against the
  level.
"""
from __future__ import annotations

import dataclasses
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ...report.figures import pyplot, save_figure
from . import evidence, intervals, levels_report  # noqa: F401 -- levels_report registers the page
from .runner import Execution

LEVELS_KIND = levels_report.KIND


def fly_levels(cfg, out: Path, plan: Callable[[object], list[dict]],
               execute: Callable[[list[dict]], Execution],
               summarize: Callable[[object, list[dict], Path], dict],
               under_test: Callable[[dict], bool] = lambda r: True) -> tuple[dict, Execution]:
    """Plan, fly and summarize ``cfg`` at each of its levels (module docstring).
    ``plan(cfg_level)``: the level's specs; ``execute(specs)``: ``runner.execute`` with the kind's
    arguments; ``summarize(cfg_level, records, directory)``: the level's summary with its figures
    written into ``directory``; ``under_test(record)``: the records of the bank under test."""
    levels = cfg.levels()
    configs = {lvl: dataclasses.replace(cfg, turbulence=lvl) for lvl in levels}
    keys: dict[str, set[str]] = {}
    specs: list[dict] = []
    for lvl, c in configs.items():
        planned = plan(c)
        keys[lvl] = {s["run_key"] for s in planned}
        specs += planned
    done = execute(specs)
    if len(levels) == 1:
        return summarize(cfg, done.records, out), done
    per_level = []
    for lvl, c in configs.items():
        d = out / lvl
        d.mkdir(exist_ok=True)
        records = [r for r in done.records if r["run_key"] in keys[lvl]]
        summary = summarize(c, records, d)
        (d / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
        per_level.append((lvl, summary, [r for r in records if under_test(r)]))
    combined = combine(per_level)
    combined["figures"] = {"levels": against_level(combined["levels"], out / "levels.png").name}
    return combined, done


def level_row(level: str, summary: dict, records: list[dict]) -> dict:
    """One level's row: correct, false declarations per hour, latency, goals (module docstring)."""
    n = len(records)
    lat = sorted(float(r["latency_s"]) for r in records if r.get("latency_s") is not None)
    failure_runs = sum(1 for r in records if r["scenario"]["failures"])
    return {
        "level": level, "directory": level, "runs": n,
        "correct": intervals.rate(sum(r["outcome"] == "correct" for r in records), n) if n else None,
        "false_declarations_per_hour": evidence.false_declaration_rate(records),
        "latency_s": {"median": round(float(np.median(lat)), 6) if lat else None,
                      "p95": round(float(np.percentile(lat, 95)), 6) if lat else None,
                      "detected_runs": len(lat), "failure_runs": failure_runs},
        "goals_met": bool(summary.get("goals_met")),
    }


def combine(per_level: list[tuple[str, dict, list[dict]]]) -> dict:
    """The summary of kind ``"levels"`` from (level, the kind's summary, records under test)."""
    first = per_level[0][1]
    shared = {k: first.get(k) for k in ("seed", "tuning", "bank_hash", "version", "code", "estimator_settings")}
    return {
        "kind": LEVELS_KIND, "campaign": first["kind"], **shared,
        "turbulence": ",".join(lvl for lvl, _, _ in per_level),
        "levels": [level_row(lvl, s, rs) for lvl, s, rs in per_level],
        "goals_met": all(s.get("goals_met") for _, s, _ in per_level),
        "not_clean": [{"level": lvl, **e} for lvl, s, _ in per_level for e in s.get("not_clean", [])],
    }


def against_level(rows: list[dict], path: Path) -> Path:
    """Correct fraction, false declarations per hour and latency against the level, with
    95 % intervals (latency: median, and p95 as the bar's top)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
    xs = np.arange(len(rows))
    names = [r["level"] for r in rows]

    def bars(ax, values, lo, hi, ylabel):
        v = np.array([np.nan if x is None else x for x in values], dtype=float)
        ax.errorbar(xs, v, yerr=[np.nan_to_num(v - lo), np.nan_to_num(hi - v)], fmt="o", capsize=4)
        ax.set_xticks(xs, names)
        ax.set_xlabel("turbulence")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)

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
