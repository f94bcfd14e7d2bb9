"""One flight's files and page: ``run.json``, ``probabilities.csv``, ``probabilities.png``.

probabilities.csv: ``time_s``, then one column per hypothesis that was on line during the
flight (``FlightResult.hypotheses``: the union, in order of first appearance); a cell is
empty while its hypothesis is off line.  The probabilities on line sum to 1 per row.  With the
estimator's turbulence adaptation on, a last column ``turbulence_scale`` holds its scale s after
each frame (``FlightResult.turbulence_scale``).
"""
from __future__ import annotations

import csv
import html
import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..loop import timeseries
from .figures import img_tag, pyplot, save_figure


def write_flight(result, out_dir: str | Path, **extra) -> dict[str, Path]:
    """A flight's (``loop.flight.FlightResult``) run.json (its ``run_json(**extra)``),
    probabilities.csv and probabilities.png into ``out_dir``, and, when it was flown with
    ``record_series``, its table (``loop.timeseries``: flight.parquet or flight.csv)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"run": out / "run.json", "csv": out / "probabilities.csv", "png": out / "probabilities.png"}
    paths["run"].write_text(json.dumps(result.run_json(**extra), indent=1) + "\n")
    adaptive = bool(result.estimator_settings.get("adapt_turbulence"))
    with open(paths["csv"], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(("time_s",) + result.hypotheses + (("turbulence_scale",) if adaptive else ()))
        for i, (t, row) in enumerate(zip(result.time_s, result.probabilities)):
            w.writerow([f"{t:.6f}"] + ["" if np.isnan(p) else f"{p:.6g}" for p in row]
                       + ([f"{result.turbulence_scale[i]:.6g}"] if adaptive else []))
    probability_history(result.time_s, result.hypotheses, result.probabilities, result.failures,
                        result.declarations, paths["png"],
                        title=f"MMAE hypothesis probabilities, seed {result.scenario.get('seed')}, "
                              f"feedback {result.feedback}")
    if result.series is not None:
        sr = result.series
        table = timeseries.flight_table(result.time_s, sr["u"], sr["z"], sr["z_hat"], result.hypotheses,
                                        result.probabilities, sr["truth_log"])
        paths["table"] = timeseries.write_table(table, out / "flight")
    return paths


def probability_history(
    time_s: np.ndarray,
    hypotheses: Sequence[str],
    probabilities: np.ndarray,
    failures: Sequence[dict],
    declarations: Sequence[dict],
    path: str | Path,
    title: str = "",
) -> Path:
    """One run: every hypothesis's probability while on line (NaN = off line)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.6))
    probs = np.asarray(probabilities, dtype=float)
    top = set(np.nanargmax(np.nan_to_num(probs, nan=-1.0), axis=1)) if len(probs) else set()
    palette = plt.get_cmap("tab20").colors
    for k, name in enumerate(hypotheses):
        col = probs[:, k]
        if np.all(np.isnan(col)):
            continue
        highlight = k in top  # hypotheses that led at some frame get a legend entry
        ax.plot(time_s, col, color=palette[k % len(palette)], ls="--" if "+" in name else "-",
                lw=1.6 if highlight else 0.8, alpha=1.0 if highlight else 0.5,
                label=name if highlight else None)
    for f in failures:
        ax.axvline(f["time_s"], color="k", ls="--", lw=1)
        ax.text(f["time_s"], 1.02, f" {f['name']} fails", fontsize=8, va="bottom")
    for d in declarations:
        ax.plot([d["time_s"]], [1.0], "v", color="C3", ms=7)
        ax.text(d["time_s"], 0.93, f" {d['hypothesis']}", fontsize=7, color="C3")
    ax.set_ylim(-0.02, 1.08)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("hypothesis probability")
    ax.set_title(title or "MMAE hypothesis probabilities (triangles: declarations)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    return save_figure(fig, path)


def run_page(d: Path, r: dict) -> str:
    """The page body of a run directory from its ``run.json`` ``r``."""
    fails = ", ".join(f"{f['name']}@{f['time_s']}:{f['mode']}" for f in r.get("failures", [])) or "none"
    decl = "".join(f"<tr><td>{html.escape(x['hypothesis'])}</td><td>{x['time_s']:.3f}</td></tr>"
                   for x in r.get("declarations", [])) or "<tr><td colspan=2>no declaration</td></tr>"
    return (
        "<h1>f16mmae run</h1><table>"
        f"<tr><th>failures injected</th><td>{html.escape(fails)}</td></tr>"
        f"<tr><th>final hypothesis</th><td>{html.escape(r.get('final_hypothesis', ''))}</td></tr>"
        f"<tr><th>outcome</th><td>{html.escape(str(r.get('outcome')))}</td></tr>"
        f"<tr><th>seed / bank / version</th><td>{r.get('seed')} / {html.escape(str(r.get('bank_hash')))} / {html.escape(str(r.get('version')))}</td></tr>"
        "</table><h2>Declarations</h2><table><tr><th>hypothesis</th><th>time (s)</th></tr>"
        + decl + "</table>" + img_tag(d / "probabilities.png", "Hypothesis probabilities")
    )
