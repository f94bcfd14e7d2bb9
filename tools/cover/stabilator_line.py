"""The stabilator dither line moved to other frequencies within the subliminal budget, and what
it does to a campaign's PIT, LS, RS and NONE flights.

For each frequency f of the stabilator pair's line (LS and RS in phase, the flaperon and rudder
lines as shipped), the stabilator amplitude a(f) is the largest (bisection, 12 steps, up to
``MAX_AMPLITUDE_DEG``) whose closed-loop flight (calm air, no sensor noise, FCS on raw feedback,
the nominal point, 8 s: ``truth.fly_raw``, as tests/python/test_truth_dither.py measures the
default) keeps the peak |Delta n_z| at most the shipped dither's and every peak body rate
below ``--rate-budget`` (default: the criterion's 1 deg/s).  Printed: f, a(f), the peaks.  With ``--runs N`` the
single campaign's flights of the cases PIT, LS, RS (those ``--mode`` applies to) and NONE at
campaign seed ``--seed`` (``failure_runs.run_seed``: the same flights as
``f16mmae campaign single --seed S --runs N``) are flown again with that dither
(``loop.flight.fly``, the bank's recommended settings) and the runs that end on the injected
case counted, with the runs whose first declaration after the onset was another failure.

Run: .venv/bin/python tools/cover/stabilator_line.py --bank results/cover.f16bank --freqs 1.7,2.5 [--runs 10 --seed 7]
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core
from f16mmae.campaign.engine.failure_runs import run_seed
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario, fly_raw
from f16mmae.truth.dither import CRITERION, DEFAULT_AMPLITUDE_DEG, DEFAULT_FREQUENCY_HZ, MAX_AMPLITUDE_DEG, DitherSpec
from f16mmae.campaign.engine.config import split_mode
from f16mmae.truth.failures import make_failure

RATES = [2, 4, 5]  # PIT, ROL, YAW
AZ = 3


def peaks(spec: DitherSpec) -> np.ndarray:
    sc = Scenario(mach=0.4, alt_ft=20_000.0, duration_s=8.0, noise=False, feedback="raw", dither=spec)
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    return np.abs(log["z_ideal"] - truth.trim.z).max(axis=0)


def line(f_hz: float, amp_deg: float) -> DitherSpec:
    a = list(DEFAULT_AMPLITUDE_DEG)
    fr = list(DEFAULT_FREQUENCY_HZ)
    a[0] = a[1] = amp_deg
    fr[0] = fr[1] = f_hz
    return DitherSpec(amplitude_deg=tuple(a), frequency_hz=tuple(fr))


def largest_amplitude(f_hz: float, nz_budget: float, rate_budget: float) -> tuple[float, np.ndarray]:
    def ok(a):
        pk = peaks(line(f_hz, a))
        return pk[AZ] <= nz_budget and np.degrees(pk[RATES]).max() < rate_budget, pk
    lo, hi = 0.0, MAX_AMPLITUDE_DEG
    best = peaks(line(f_hz, 0.0))
    for _ in range(12):
        mid = 0.5 * (lo + hi)
        good, pk = ok(mid)
        if good:
            lo, best = mid, pk
        else:
            hi = mid
    return lo, best


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--freqs", default="1.7")
    ap.add_argument("--runs", type=int, default=0)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--mode", default="complete")
    ap.add_argument("--rate-budget", type=float, default=CRITERION["rate_deg_s"],
                    help="peak body rate the dither may reach (deg/s; default the criterion)")
    args = ap.parse_args(argv)
    shipped = peaks(DitherSpec())
    print(f"shipped dither: n_z {shipped[AZ]:.4f} g, q/p/r {np.degrees(shipped[RATES]).round(3).tolist()} deg/s")
    mb = core.load_bank(args.bank) if args.runs else None
    for f in (float(x) for x in args.freqs.split(",")):
        amp, pk = largest_amplitude(f, shipped[AZ], args.rate_budget)
        print(f"stabilator line {f:g} Hz: amplitude {amp:.2f} deg, n_z {pk[AZ]:.4f} g, "
              f"q/p/r {np.degrees(pk[RATES]).round(3).tolist()} deg/s", flush=True)
        if not args.runs:
            continue
        spec = line(f, amp)
        out = []
        for case in ("PIT", "LS", "RS", "NONE"):
            try:
                failures = () if case == "NONE" else (make_failure(case, 3.0, *split_mode(args.mode)),)
            except ValueError:
                continue  # the mode does not apply to this component
            ok = first_wrong = 0
            for n in range(args.runs):
                sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence="light", seed=run_seed(args.seed, case, n),
                              duration_s=8.0, failures=failures, dither=spec)
                res = fly(sc, mb, record_probabilities=False)
                ok += res.final_hypothesis == case
                first = next((d["hypothesis"] for d in res.declarations
                              if d["hypothesis"] != "NONE" and (case == "NONE" or d["time_s"] >= 3.0)), "NONE")
                first_wrong += first not in (case, "NONE")
            out.append(f"{case} {ok}/{args.runs} (first declaration wrong {first_wrong})")
        print("    " + ", ".join(out), flush=True)


if __name__ == "__main__":
    main()
