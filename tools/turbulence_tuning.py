"""Choose the turbulence adaptation's settings on TUNING seeds only (f16mmae/seeds.py).

For each candidate (adapt on/off, time constant, scale floor, ..., dwell) and turbulence level
it flies
  - failure-free flights of --quiet-s seconds on the tuning flight seeds (1-8), counting the
    false declarations (any hypothesis other than NONE declared);
  - the single-failure cases (failure at 3 s of an 8-s flight) on the tuning campaign's seeds
    derived_seed("single", 1, case, n), n < --runs, counting correct final answers, false
    alarms (a declaration before the failure), the runs with a wrong declaration after the
    failure (any hypothesis other than NONE and the case), the median and p95 latency of the
    first correct declaration (every case, actuators and sensors apart) and the cases missed.
A candidate is "off", "on:TAU:SMIN[:SMAX[:GAIN[:REFERENCE]]]" (the adaptation) or any
estimator settings as "KEY=VALUE[,KEY=VALUE...]" (core.HierarchicalBank keywords, e.g.
"p_min=1e-6,dwell_s=0.1", "strip_leading_term=false"), either followed by "@DWELL_S" (the declaration dwell).  Prints one
line per (candidate, level).  Example:

    .venv/bin/python tools/turbulence_tuning.py --levels none,light,moderate,severe \
        --candidates off on:5:1 on:10:1 --quiet-s 300 --runs 2 --workers 2
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf

import numpy as np

from f16mmae import banks
from f16mmae.banks import load_bank
from f16mmae.design import turbulence_banks  # --bank turbulence: registers the set
from f16mmae.loop.flight import fly
from f16mmae.campaign.soak.campaign import PROFILES, profile
from f16mmae.names import ACTUATORS, COMPONENTS, FAILURE_TIME_S, FEEDBACK_MODES, FLIGHT_S, SENSORS
from f16mmae.seeds import TUNING_FLIGHT_SEEDS, derived_seed, tuning_seeds
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure


def options(candidate: str) -> dict:
    """"off" or "on:TAU:SMIN[:SMAX[:GAIN[:REFERENCE]]]", either followed by "@DWELL_S" (the
    declaration dwell) -> core.HierarchicalBank keyword arguments."""
    candidate, _, dwell = candidate.partition("@")
    out = {"dwell_s": float(dwell)} if dwell else {}
    if candidate == "off":
        return out
    if "=" in candidate:
        for item in candidate.split(","):
            key, _, value = item.partition("=")
            out[key] = True if value == "true" else False if value == "false" else float(value)
        return out
    parts = candidate.split(":")
    out.update({"adapt_turbulence": True, "adapt_time_constant_s": float(parts[1]),
                "adapt_scale_min": float(parts[2])})
    if len(parts) > 3:
        out["adapt_scale_max"] = float(parts[3])
    if len(parts) > 4:
        out["adapt_gain"] = float(parts[4])
    if len(parts) > 5:
        out["adapt_reference"] = float(parts[5])
    return out


def flight(job):
    candidate, level, seed, case, duration, bank_name, feedback, maneuvers = job
    _, _, bank = load_bank(bank_name)
    fails = () if case == "NONE" else (make_failure(case, FAILURE_TIME_S, "complete", None),)
    sc = Scenario(mach=bank.mach, alt_ft=bank.alt_ft, turbulence=level, duration_s=duration, seed=seed,
                  failures=fails, feedback=feedback, maneuvers=maneuvers)
    r = fly(sc, bank, estimator_options=options(candidate), record_probabilities=True)
    decl = r.declarations
    s = r.turbulence_scale
    if case == "NONE":
        return (candidate, level, case, sum(d["hypothesis"] != "NONE" for d in decl), 0, float(s.mean()),
                float(s.max()), None, 0)
    early = any(d["time_s"] < FAILURE_TIME_S and d["hypothesis"] != "NONE" for d in decl)
    first = next((d["time_s"] - FAILURE_TIME_S for d in decl
                  if d["hypothesis"] == case and d["time_s"] >= FAILURE_TIME_S), None)
    wrong = any(d["time_s"] >= FAILURE_TIME_S and d["hypothesis"] not in ("NONE", case) for d in decl)
    return (candidate, level, case, int(r.final_hypothesis == case), int(early), float(s.mean()), float(s.max()),
            first, int(wrong))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--levels", default="none,light,moderate,severe")
    p.add_argument("--candidates", nargs="+", default=["off", "on:5:1"])
    p.add_argument("--quiet-s", type=float, default=300.0)
    p.add_argument("--quiet-seeds", type=int, default=len(TUNING_FLIGHT_SEEDS))
    p.add_argument("--runs", type=int, default=2)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--bank", default="tuned", help="tuned | untuned | a bank file")
    p.add_argument("--feedback", default="mmae", choices=FEEDBACK_MODES)
    p.add_argument("--quiet-profile", default=None, choices=PROFILES,
                   help="the failure-free flights fly this soak profile (hold: the pilot holds the trim)")
    p.add_argument("--set", default=None, metavar="FILE",
                   help="--bank turbulence flies this turbulence bank set file (f16mmae design "
                        "--turbulence-banks --out FILE), not the one the design module names")
    a = p.parse_args()
    if a.set:
        given = turbulence_banks.load_set(a.set)   # checked now; the workers inherit the registration
        banks.register_turbulence_set(lambda: given, lambda: (given.path, given.banks[given.selector["start"]]))
    quiet_maneuvers = () if a.quiet_profile is None else profile(a.quiet_profile, 0.4, 20_000.0)[0]
    tuning = tuning_seeds()
    jobs = []
    for c in a.candidates:
        for lv in a.levels.split(","):
            jobs += [(c, lv, s, "NONE", a.quiet_s, a.bank, a.feedback, quiet_maneuvers)
                     for s in TUNING_FLIGHT_SEEDS[: a.quiet_seeds]]
            for case in COMPONENTS:
                for n in range(a.runs):
                    seed = derived_seed("single", 1, case, n)
                    assert seed in tuning
                    jobs.append((c, lv, seed, case, FLIGHT_S, a.bank, a.feedback, ()))
    rows: dict = {}
    with cf.ProcessPoolExecutor(a.workers) as ex:
        for out in ex.map(flight, jobs, chunksize=4):
            rows.setdefault(out[:2], []).append(out[2:])
    for (c, lv), rs in rows.items():
        quiet = [r for r in rs if r[0] == "NONE"]
        fail = [r for r in rs if r[0] != "NONE"]
        missed = {}
        for r in fail:
            if not r[1]:
                missed[r[0]] = missed.get(r[0], 0) + 1
        quiet_text = (f"quiet: {sum(r[1] for r in quiet):4d} false decl in {len(quiet) * a.quiet_s / 3600:.2f} h"
                      f" (s mean {sum(r[3] for r in quiet) / len(quiet):.2f}, max {max(r[4] for r in quiet):.2f})"
                      if quiet else "quiet: -")
        print(f"{c:14s} {lv:9s} {quiet_text}"
              f" | failures correct {sum(r[1] for r in fail)}/{len(fail)}, early FA {sum(r[2] for r in fail)}"
              f", wrong after the failure {sum(r[6] for r in fail)}, latency {_latency(fail, COMPONENTS)} all"
              f", latency {_latency(fail, ACTUATORS)} actuators, {_latency(fail, SENSORS)} sensors"
              f", missed {' '.join(f'{k} {v}' for k, v in missed.items()) or '-'}", flush=True)



def _latency(rows, components) -> str:
    """Median / p95 latency (s) of the first correct declaration in the runs of ``components``."""
    lat = [r[5] for r in rows if r[0] in components and r[5] is not None]
    if not lat:
        return "- / -"
    return f"{float(np.median(lat)):.2f} / {float(np.percentile(lat, 95)):.2f} s"


if __name__ == "__main__":
    main()
