"""Which hypothesis the per-hypothesis tempering spares around a failure's onset, frame by frame
(docs/results/turbulence_banks.md, round 17: the severe stabilator runs declared PIT or AOA first).

For each flight (a complete failure of CASE at 3 s of an 8-s flight in TURBULENCE, feedback
``reconfigure``, the single campaign's; the tuning campaign's seeds, derived_seed("single", 1,
CASE, n)) it flies the turbulence bank set in process with the given ``--set-tempering*`` options
and prints the first declarations; with ``--frames T0:T1`` it prints, for every frame from T0 to
T1 s while the member in force is at level 0, the quadratic forms q_k = r_k' A_k^-1 r_k of NONE,
LS, RS, AOA and PIT (its filters' residuals and the member bank's residual covariances), the scale s
in force, the member's measured rho-bar, the hypothesis of least q_k over the failure hypotheses (the
spared one unless it is fully tempered) and the probabilities. It ends with the count of flights
whose first declaration is not CASE and the median latency of CASE's first declaration.

    .venv/bin/python tools/turbulence_spared_trace.py --cases LS,RS --runs 20 --set-tempering 0.25 --set-tempering-rho 2.68
    .venv/bin/python tools/turbulence_spared_trace.py --cases LS --first-run 1 --runs 1 --frames 3.15:3.35 --set-tempering 0.25 --set-tempering-rho 2.68
"""
from __future__ import annotations

import argparse
import statistics

import numpy as np

import f16mmae.design.turbulence_banks as turbulence_banks
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import FAILURE_TIME_S, SINGLE_HYPOTHESES
from f16mmae.seeds import derived_seed, tuning_seeds
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure

SHOWN = ("NONE", "LS", "RS", "AOA", "PIT")


def flight(case: str, n: int, level: str, options: dict, frames: tuple[float, float] | None):
    """One flight's declarations [(name, time_s)], printing its frames in ``frames``."""
    bank = load_bank("turbulence")[2]
    inverses = [{h.name: np.linalg.inv(np.asarray(h.a)) for h in b.hypotheses}
                for b in turbulence_banks.load_set().banks]
    estimator = Estimator.fresh(bank, turbulence_banks=True, **options)
    seed = derived_seed("single", 1, case, n)
    if seed not in tuning_seeds():
        raise SystemExit(f"seed {seed} of {case} run {n} is not a tuning seed (runs 0-19 are)")
    scale = [1.0]   # the s in force for the next frame

    def on_frame(t, u, z, air):
        core = estimator.core_bank
        names = list(core.hypotheses)
        if frames is not None and frames[0] <= t <= frames[1] and core.level == 0 and names == list(SINGLE_HYPOTHESES):
            a_inv = inverses[core.active]
            r = np.asarray(core.residuals)
            q = np.array([r[k] @ a_inv[name] @ r[k] for k, name in enumerate(names)])
            p = np.asarray(core.probabilities)
            least = names[1 + int(np.argmin(q[1:]))]
            print(f"  {t:5.2f} s {scale[0]:5.1f} rho-bar {core.turbulence_power_ratio:5.2f} | q "
                  + " ".join(f"{name} {q[names.index(name)]:7.1f}" for name in SHOWN)
                  + f" | least {least:4s} | p " + " ".join(f"{name} {p[names.index(name)]:.3f}" for name in SHOWN[1:]))
        scale[0] = core.turbulence_scale

    scenario = Scenario(turbulence=level, duration_s=8.0, seed=seed, feedback="reconfigure",
                        failures=(make_failure(case, FAILURE_TIME_S, "complete", None),))
    result = fly(scenario, bank, estimator=estimator, on_frame=on_frame)
    return [(d["hypothesis"], round(d["time_s"], 2)) for d in result.declarations]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="LS,RS")
    ap.add_argument("--turbulence", default="severe")
    ap.add_argument("--first-run", type=int, default=0)
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--frames", default=None, help="T0:T1, seconds: print the frames between")
    ap.add_argument("--set-tempering", type=float, default=None)
    ap.add_argument("--set-tempering-rho", type=float, default=None)
    ap.add_argument("--set-tempering-margin", action="store_true")
    ap.add_argument("--set-tempering-margin-stabilators", action="store_true")
    args = ap.parse_args(argv)
    options = {}
    if args.set_tempering is not None:
        options["set_tempering"] = args.set_tempering
    if args.set_tempering_rho is not None:
        options["set_tempering_rho"] = args.set_tempering_rho
    if args.set_tempering_margin:
        options["set_tempering_margin"] = True
    if args.set_tempering_margin_stabilators:
        options["set_tempering_margin_stabilators"] = True
    frames = tuple(float(x) for x in args.frames.split(":")) if args.frames else None
    wrong, latency = [], []
    for case in args.cases.split(","):
        for n in range(args.first_run, args.first_run + args.runs):
            declared = flight(case, n, args.turbulence, options, frames)
            print(case, n, declared, flush=True)
            first = next((h for h, _ in declared if h != "NONE"), None)
            if first is not None and first != case:
                wrong.append(f"{case} {n}: {first}")
            found = next((t for h, t in declared if h == case), None)
            if found is not None:
                latency.append(found - FAILURE_TIME_S)
    median = f"{statistics.median(latency):.2f} s" if latency else "-"
    print(f"first declaration wrong: {len(wrong)} {wrong}; latency median {median} "
          f"({sum(x <= 0.5 for x in latency)} of {len(latency)} declared within 0.5 s)")


if __name__ == "__main__":
    main()
