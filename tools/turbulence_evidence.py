"""The per-frame evidence a failure gives the turbulence bank set's member in force, before and
after its tempering (docs/results/turbulence_banks.md, issue 14's severe flaperons).

For each flight (a complete failure of CASE at 3 s of an 8-s flight, the single campaign's; the
tuning campaign's seeds, derived_seed("single", 1, CASE, n)) it records, every frame after the
failure while NONE and CASE are on line (until a declaration moves the level), the member in force's quadratic forms q_k = r_k' A_k^-1 r_k of NONE and of CASE
(its filters' residuals and the member bank's residual covariances) and the adaptation's scale s
in force and which member is in force, and prints per level:
    e    = (q_NONE - q_CASE) / 2        the untempered evidence for CASE against NONE, nats/frame
    e/s  = l_CASE - l_NONE              after the tempering: the bank's own log-likelihoods
                                        (the adaptation's scale s, or its per-channel scales,
                                        and the load-factor tempering s_m)
the means over the 5 s after the failure and over its first second, the median s, and the
sum of e/s over the 5 s against ln(1 / p_min) (what lifts CASE from the floor).

With ``--per-flight``, each flight's sums over the 5 s per measurement, and the leading term of
eq. 2 that the bank strips, (ln |A_NONE| - ln |A_CASE|) / 2 per frame of the member in force
(what the full Gaussian likelihood would add to e every frame, untempered).

    .venv/bin/python tools/turbulence_evidence.py --cases LF,RF,LS --levels light,moderate,severe --runs 3
    .venv/bin/python tools/turbulence_evidence.py --cases VEL --levels light --runs 10 --per-flight
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import math

import numpy as np

import f16mmae.design.turbulence_banks  # noqa: F401  (registers the set)
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import FAILURE_TIME_S, FLIGHT_S, SENSORS as MEASUREMENTS
from f16mmae.seeds import derived_seed, tuning_seeds
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure


def flight(job):
    level, case, n, feedback, options, quiet = job
    bank = load_bank("turbulence")[2]
    est = Estimator(bank, turbulence_banks=True, **options)
    banks = f16mmae.design.turbulence_banks.load_set().banks
    inverse = [{h.name: np.linalg.inv(np.asarray(h.a)) for h in b.hypotheses} for b in banks]
    rows = []

    def frame(t, u, z, air_data):
        if t < FAILURE_TIME_S:
            return
        a = est.core_bank.active
        m = est.core_bank   # the member in force's outputs
        names = list(m.hypotheses)
        if case not in names or "NONE" not in names:
            return
        r = np.asarray(m.residuals)
        # per measurement j: r_j (A^-1 r)_j, which sums to q over j
        c = {k: r[names.index(k)] * (inverse[a][k] @ r[names.index(k)]) for k in ("NONE", case)}
        e = (c["NONE"] - c[case]) / 2.0
        ll = np.asarray(m.log_likelihoods)
        tempered = float(ll[names.index(case)] - ll[names.index("NONE")])
        rows.append((t, float(e.sum()), m.turbulence_scale, a, tempered, *e))

    seed = derived_seed("single", 1, case, n)
    assert seed in tuning_seeds()
    sc = Scenario(turbulence=level, duration_s=FLIGHT_S, seed=seed, feedback=feedback,
                  failures=() if quiet else (make_failure(case, FAILURE_TIME_S, "complete", None),))
    r = fly(sc, load_bank("turbulence")[2], estimator=est, on_frame=frame)
    first = next((d["time_s"] - FAILURE_TIME_S for d in r.declarations if d["hypothesis"] == case), None)
    return level, case, np.array(rows), first


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", default="LF,RF")
    p.add_argument("--levels", default="light,moderate,severe")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--feedback", default="reconfigure")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--per-flight", action="store_true",
                   help="each flight's evidence sums per measurement and the stripped leading term")
    p.add_argument("--quiet", action="store_true",
                   help="the same flights without the failure: the evidence for CASE the turbulence alone gives")
    p.add_argument("--option", action="append", default=[], metavar="KEY=VALUE",
                   help="a further estimator setting (core keyword, a number or true), e.g. maneuver_tempering_g=4, "
                        "adapt_channel_weight=0.5")
    a = p.parse_args()
    options = {k: True if v == "true" else float(v) for k, _, v in (o.partition("=") for o in a.option)}
    jobs = [(lv, c, n, a.feedback, options, a.quiet) for lv in a.levels.split(",") for c in a.cases.split(",")
            for n in range(a.runs)]
    out: dict = {}
    with cf.ProcessPoolExecutor(a.workers) as ex:
        for level, case, rows, first in ex.map(flight, jobs):
            out.setdefault((level, case), []).append((rows, first))
    floor = math.log(1.0 / load_bank("turbulence")[2].estimator_settings["p_min"])
    print(f"{'level':9s} {'case':4s} {'e, 5 s':>8s} {'e/s, 5 s':>9s} {'e/s, 1st s':>10s} {'median s':>9s} "
          f"{'sum e/s':>8s} (ln 1/p_min = {floor:.1f})  member in force (frames)  per flight: first correct declaration, s (sum e/s)")
    for (level, case), flights in out.items():
        rows = np.vstack([f[0] for f in flights if len(f[0])])
        t, e, s = rows[:, 0] - FAILURE_TIME_S, rows[:, 1], rows[:, 2]
        es = rows[:, 4]
        sums = [float(np.sum(f[0][:, 4])) for f in flights if len(f[0])]
        firsts = ", ".join(("-" if f[1] is None else f"{f[1]:.2f}") + f" ({np.sum(f[0][:, 4]):.0f})"
                           for f in flights if len(f[0]))
        members = ", ".join(f"{int(m)}: {int(np.sum(rows[:, 3] == m))}" for m in np.unique(rows[:, 3]))
        print(f"{level:9s} {case:4s} {e.mean():8.3f} {es.mean():9.4f} {es[t < 1.0].mean():10.4f} "
              f"{np.median(s):9.1f} {np.median(sums):8.1f}  {members}  {firsts}", flush=True)
        ej = rows[:, 5:]
        channels = " ".join(f"{name} {m:+.3f}/{sd:.3f}" for name, m, sd in zip(MEASUREMENTS, ej.mean(axis=0), ej.std(axis=0)))
        print(f"{'':14s} untempered e_j per frame, mean/std: {channels}; e: {e.mean():+.3f}/{e.std():.3f}", flush=True)
        if a.per_flight:
            banks = f16mmae.design.turbulence_banks.load_set().banks
            for n, (rows_n, first) in enumerate(flights):
                if not len(rows_n):
                    continue
                member = int(np.bincount(rows_n[:, 3].astype(int)).argmax())
                log_det = {h.name: np.linalg.slogdet(np.asarray(h.a))[1] for h in banks[member].hypotheses}
                sums = " ".join(f"{name} {v:+.1f}" for name, v in zip(MEASUREMENTS, rows_n[:, 5:].sum(axis=0)))
                print(f"{'':14s} flight {n}: first correct {'-' if first is None else f'{first:.2f} s'}, "
                      f"e summed {rows_n[:, 1].sum():+.1f} ({sums}), stripped leading term "
                      f"{(log_det['NONE'] - log_det[case]) / 2:+.3f} per frame of member {member}", flush=True)


if __name__ == "__main__":
    main()
