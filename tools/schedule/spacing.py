"""Lab driver (not in the wheel): how acceptable is a bank away from its design point, with and
without its trim scheduled, and how do the two ways of scheduling compare off the grid.

    python tools/schedule/spacing.py --points 0.45:20000,0.4:25000 --banks nominal,trim,local \
        --runs 3 --out results/spacing.json
    python tools/schedule/spacing.py --points 0.35:17500 --banks interpolate,nearest \
        --schedule FILE --runs 3 --out results/modes.json
    python tools/schedule/spacing.py --points random:20:seed=2 --banks interpolate --schedule FILE \
        --seeds tuning --adapt-turbulence --runs 2 --out results/tune.json

--points: MACH:ALT_FT,..., random:N[:seed=S] (campaign envelope's Latin hypercube) or a
selection of the paper's Fig. 9 points (all, local, extrema, ...).
--seeds: ``evaluation`` (default; those of ``campaign single`` at campaign seed 1) or
``tuning`` (the tuning campaign's: ``derived_seed("single", 1, case, n)``, n < 20, the seeds
the shipped tuned bank's settings were chosen on; f16mmae.seeds) -- tune on these, never on
evaluation seeds.

Banks (each flown at every point, the single-failure cases NONE + 12, ``--runs`` evaluation
seeds each, 8-s flights, failure at 3 s, light turbulence, the seeds of ``campaign single``):
  nominal      the shipped tuned bank (designed at Mach 0.4, 20,000 ft), its own trim
  trim         the nominal bank's filters with the trim designed at the flight point (what a
               schedule of trims alone would give)
  local        the bank designed at the flight point (a schedule at one of its nodes)
  interpolate  the scheduled bank FILE, bilinear
  nearest      the scheduled bank FILE, nearest node with hysteresis
The closed loop feeds the estimator the truth's measured air data every frame (loop/flight.py);
a bank designed at one point ignores it.
Acceptable: >= 90 % of failure runs correct and no false-alarm run (campaign envelope's rule).
"""
from __future__ import annotations

import argparse
import functools
import json
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.campaign.engine.scoring import score_run
from f16mmae.design.bank import design_bank, to_model_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import COMPONENTS, FAILURE_TIME_S, NONE
from f16mmae.campaign.envelope.points import dynamic_pressure_psf, select_points
from f16mmae.seeds import TUNING_CAMPAIGN, derived_seed, evaluation_seed
from f16mmae.truth.failures import make_failure
from f16mmae.truth.scenario import Scenario

CASES = (NONE,) + COMPONENTS


def trim_bank(mach: float, alt_ft: float, path: Path) -> str:
    """The nominal bank's filters with the trim designed at (mach, alt_ft), written to path."""
    _, _, nominal = load_bank("tuned")
    local = design_bank(mach, alt_ft, "tuned")
    b = core.ModelBank(nominal.hypotheses, state_names=list(nominal.state_names),
                       input_names=list(nominal.input_names), measurement_names=list(nominal.measurement_names),
                       frame_rate_hz=nominal.frame_rate_hz, u_trim=local.u_trim, z_trim=local.z_trim,
                       h_output=nominal.h_output, mach=mach, alt_ft=alt_ft, tuning=nominal.tuning,
                       **nominal.estimator_settings, metadata="{}")
    b.save(str(path))
    return str(path)


def local_bank(mach: float, alt_ft: float, path: Path) -> str:
    core.save_bank(to_model_bank(design_bank(mach, alt_ft, "tuned")), str(path))
    return str(path)


@functools.lru_cache(maxsize=16)
def _bank(path: str):
    return load_bank(path)[2]


def run_seed(seeds: str, case: str, n: int) -> int:
    """The seed of run n of a case in the namespace ``seeds`` (module docstring)."""
    if seeds == "tuning":
        kind, campaign_seed, runs = TUNING_CAMPAIGN
        if n >= runs:
            raise SystemExit(f"--seeds tuning has {runs} runs per case; --runs {n + 1} is too many")
        return derived_seed(kind, campaign_seed, case, n)
    return evaluation_seed("single", 1, case, n)


def fly_one(task) -> dict:
    bank_label, bank_path, mode, mach, alt_ft, case, n, seeds, adapt, extra = task
    bank = _bank(bank_path)
    seed = run_seed(seeds, case, n)
    failures = () if case == NONE else (make_failure(case, FAILURE_TIME_S),)
    scenario = Scenario(mach=mach, alt_ft=alt_ft, turbulence="light", failures=failures, duration_s=8.0, seed=seed)
    options = {"schedule_mode": mode} if mode else {}
    if adapt:
        options["adapt_turbulence"] = True
    options.update(extra)
    est = Estimator.fresh(bank, **options)   # one per process and bank, reset per flight
    result = fly(scenario, bank, estimator=est)
    scored = score_run(case, FAILURE_TIME_S if case != NONE else None, result.declarations)
    declared = [d["hypothesis"] if isinstance(d, dict) else str(d) for d in result.declarations]
    declared_at = [round(float(d["time_s"]), 2) for d in result.declarations if isinstance(d, dict)]
    return {"bank": bank_label, "mach": mach, "alt_ft": alt_ft, "case": case, "run": n, "seed": seed,
            "declared": declared, "declared_at_s": declared_at, **scored}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", required=True, help="MACH:ALT_FT,... flight points")
    ap.add_argument("--banks", default="nominal,trim,local")
    ap.add_argument("--schedule", default=None, help="scheduled bank file (interpolate, nearest)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", required=True)
    ap.add_argument("--seeds", choices=("evaluation", "tuning"), default="evaluation")
    ap.add_argument("--adapt-turbulence", action="store_true", help="the estimator's turbulence adaptation on")
    ap.add_argument("--option", action="append", default=[], metavar="NAME=VALUE",
                    help="a core.HierarchicalBank setting (number), e.g. adapt_reference=0.76; repeatable")
    args = ap.parse_args()
    extra = tuple((k, float(v)) for k, v in (o.split("=", 1) for o in args.option))
    if args.points.startswith("random") or ":" not in args.points:  # campaign envelope's selections
        points = [(p.mach, p.alt_ft) for p in select_points(args.points)]
    else:
        points = [tuple(float(x) for x in p.split(":")) for p in args.points.split(",")]
    labels = args.banks.split(",")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix="spacing-"))
    tasks = []
    for mach, alt in points:
        for label in labels:
            mode = label if label in ("interpolate", "nearest") else None
            if label == "nominal":
                path = str(load_bank("tuned")[1])
            elif label == "trim":
                path = trim_bank(mach, alt, tmp / f"trim_{mach}_{alt}.f16bank")
            elif label == "local":
                path = local_bank(mach, alt, tmp / f"local_{mach}_{alt}.f16bank")
            else:
                path = args.schedule
            tasks += [(label, path, mode, mach, alt, c, n, args.seeds, args.adapt_turbulence, dict(extra))
                      for c in CASES for n in range(args.runs)]
    with ProcessPoolExecutor(args.workers) as pool:
        records = list(pool.map(fly_one, tasks, chunksize=4))
    rows = []
    for mach, alt in points:
        for label in labels:
            rs = [r for r in records if r["bank"] == label and r["mach"] == mach and r["alt_ft"] == alt]
            fail = [r for r in rs if r["case"] != NONE]
            correct = sum(r["outcome"] == "correct" for r in fail) / len(fail)
            fa = sum(r["false_alarm"] for r in rs)
            rows.append({"mach": mach, "alt_ft": alt, "bank": label, "correct": correct, "false_alarm_runs": fa,
                         "runs": len(rs), "acceptable": correct >= 0.9 and fa == 0})
            wrong = " ".join(f"{r['case']}:{r['outcome'][:4]}{'+FA' if r['false_alarm'] else ''}"
                             f"({','.join(r['declared'][:3])})"
                             for r in rs if r["outcome"] != "correct" or r["false_alarm"])
            print(f"Mach {mach:.3f} {alt:7.0f} ft q {dynamic_pressure_psf(mach, alt):4.0f}  {label:11s}  "
                  f"correct {correct:5.1%}  false-alarm runs {fa:2d}/{len(rs)}  "
                  f"{'ACCEPTABLE' if rows[-1]['acceptable'] else ''}  {wrong}", flush=True)
    acceptable = sum(r["acceptable"] for r in rows)
    print(f"acceptable {acceptable}/{len(rows)}; failure runs correct "
          f"{sum(r['outcome'] == 'correct' for r in records if r['case'] != NONE)}/"
          f"{sum(r['case'] != NONE for r in records)}; false-alarm runs {sum(r['false_alarm'] for r in records)}/"
          f"{len(records)}", flush=True)
    out.write_text(json.dumps({"rows": rows, "records": records}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
