"""Would a modelled throttle dither detect a complete VEL or AOA failure in calm air?  An
offline check on the nonlinear truth, before the sixth input is built into the core.

Each flight is the JSBSim truth (cpp engine) with the FCS on RAW sensor feedback (the
estimator is not in the loop), calm air by default, a complete failure at 3 s of 8 s (or none),
the default surface dither and optionally the truth's throttle dither (truth/dither.py).  The
recorded frames are then run through a level-0 bank of the 13 single hypotheses in the core's
dynamic-size ``core.FilterBank`` with a ``core.Declarer`` (the tuning's p_min, threshold and
dwell):

  ``light``         the shipped design (tuning ``tuned``, light turbulence), 5 inputs;
  ``light+thr``     the shipped design with a sixth input: every filter's B_d gets the
                    throttle column (design/excitation.py), u_6 = the throttle dither's
                    perturbation a sin(2 pi f t_i) of frame i;
  ``calm+thr``      the same with the tuning designed for calm air (no gust model).

Per case it prints the first declaration after the failure (name@latency s), any declaration
before it ("FA" = false alarm), and "-" when nothing is declared.  Seeds are TUNING seeds
(f16mmae/seeds.py TUNING_FLIGHT_SEEDS).  Example:

    .venv/bin/python tools/excitation/excitation_offline.py --cases VEL,AOA,NONE --seeds 1,2,3,4,5
"""
from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from f16mmae import core, names
from f16mmae.design import excitation
from f16mmae.design.bank import design_bank
from f16mmae.design.tuning import load_tuning
from f16mmae.names import FAILURE_TIME_S, FLIGHT_S, FRAME_RATE_HZ
from f16mmae.seeds import evaluation_seed
from f16mmae.truth import Scenario, aircraft, fly_raw
from f16mmae.truth.dither import DitherSpec, throttle_terms
from f16mmae.truth.failures import make_failure


def bank_models(design, bd_throttle=None):
    """core.FilterModels of ``design``'s filters, B_d widened by ``bd_throttle`` (13, 1) if given."""
    out = []
    for f in design.filters:
        bd = f.model.bd if bd_throttle is None else np.hstack([f.model.bd, bd_throttle])
        out.append(core.FilterModel(phi=f.model.phi, bd=bd, h=f.model.h, k=f.gains.k, a=f.gains.a,
                                    uninformative_width=f.model.uninformative_width,
                                    uninformative_level_q=f.model.uninformative_level_q))
    return out


def run_bank(models, est: dict, z: np.ndarray, u: np.ndarray, hyps: tuple[str, ...]) -> list[tuple[float, str]]:
    """Declarations (time_s, name) of a level-0 bank over the frames (z, u perturbations)."""
    bank = core.FilterBank(models, p_min=est["p_min"])
    dec = core.Declarer(threshold=est["threshold"], dwell_s=est["dwell_s"], frame_rate_hz=FRAME_RATE_HZ)
    probs = bank.step_frames(z, u)
    out = []
    for i, p in enumerate(probs):
        k = dec.update(p)
        if k is not None:
            out.append((i / FRAME_RATE_HZ, hyps[k]))
    return out


def describe(decls: list[tuple[float, str]], case: str) -> str:
    """"NAME@latency" of the first declaration at or after the failure ("-": none), then any
    false alarm "(FA NAME@t, ...)": a declaration before the failure, or in a NONE flight any
    declaration of a failure."""
    if case == "NONE":
        fa = [f"{n}@{t:.2f}" for t, n in decls if n != "NONE"]
        return "-" if not fa else f"FA {','.join(fa)}"
    fa = [f"{n}@{t:.2f}" for t, n in decls if t < FAILURE_TIME_S]
    after = [(t, n) for t, n in decls if t >= FAILURE_TIME_S]
    first = f"{after[0][1]}@{after[0][0] - FAILURE_TIME_S:.2f}" if after else "-"
    return first + (f" (FA {','.join(fa)})" if fa else "")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--cases", default="VEL,AOA,NONE")
    p.add_argument("--seeds", default="1,2,3,4,5", help="tuning seeds (explore with these)")
    p.add_argument("--evaluation", type=int, default=0,
                   help="instead of --seeds: N evaluation seeds per case (f16mmae.seeds.evaluation_seed), "
                        "and a summary with 95 %% intervals")
    p.add_argument("--turbulence", default="none")
    p.add_argument("--frequencies", default="0.1,0.2", help="throttle dither frequencies (Hz)")
    p.add_argument("--amplitude", type=float, default=excitation.PEAK_AMPLITUDE)
    p.add_argument("--duration", type=float, default=FLIGHT_S, help="flight length (s)")
    args = p.parse_args(argv)
    hyps = names.SINGLE_HYPOTHESES
    tuning = load_tuning("tuned")
    est = {k: tuning.estimator[k] for k in ("p_min", "threshold", "dwell_s")}
    light = design_bank(tuning=tuning, hypotheses=hyps)
    calm = design_bank(tuning=dataclasses.replace(tuning, turbulence="none"), hypotheses=hyps)
    fdm, _ = aircraft.trimmed_fdm()
    bd_th = excitation.discrete_throttle_column(calm, excitation.throttle_column(fdm))
    banks = {"light": bank_models(light), "light+thr": bank_models(light, bd_th),
             "calm+thr": bank_models(calm, bd_th)}
    freqs = [float(f) for f in args.frequencies.split(",")]
    print(f"turbulence {args.turbulence}; failure at {FAILURE_TIME_S} s of {args.duration:g} s; "
          f"throttle dither a = {args.amplitude} at {freqs} Hz; FCS on raw feedback; p_min {est['p_min']:g}")
    print("| case | seed | light, no throttle | "
          + " | ".join(f"light+thr, {f:g} Hz | calm+thr, {f:g} Hz" for f in freqs) + " |")
    print("|---|---|---|" + "---|---|" * len(freqs))
    summary = {}
    for case in args.cases.split(","):
        seeds = ([evaluation_seed("excitation_offline", 1, case, n) for n in range(args.evaluation)]
                 if args.evaluation else [int(s) for s in args.seeds.split(",")])
        for seed in seeds:
            fails = () if case == "NONE" else (make_failure(case, FAILURE_TIME_S, "complete"),)
            cells = []
            for f_hz in [None] + freqs:
                spec = DitherSpec() if f_hz is None else DitherSpec(throttle_amplitude=args.amplitude,
                                                                   throttle_frequency_hz=f_hz)
                sc = Scenario(duration_s=args.duration, seed=seed, turbulence=args.turbulence, feedback="raw",
                              dither=spec, failures=fails)
                truth, _ = fly_raw(sc)
                log = truth.truth_log
                n = len(log["u_cmd_rad"])
                z = log["z"][:n] - truth.trim.z
                u = log["u_cmd_rad"] - truth.trim.u_rad
                a, w = throttle_terms(spec)
                th = a * np.sin(w * (np.arange(n) / FRAME_RATE_HZ))
                if f_hz is None:
                    cells.append(describe(run_bank(banks["light"], est, z, u, hyps), case))
                    continue
                for b in ("light+thr", "calm+thr"):
                    cells.append(describe(run_bank(banks[b], est, z, np.column_stack([u, th]), hyps), case))
            print(f"| {case} | {seed} | " + " | ".join(cells) + " |", flush=True)
            for j, c in enumerate(cells):
                summary.setdefault((case, j), []).append(c)
    if args.evaluation:
        print_summary(summary, ["light, no throttle"] + [f"{b}, {f:g} Hz" for f in freqs
                                                         for b in ("light+thr", "calm+thr")])
    return 0


def print_summary(summary: dict, columns: list[str]) -> None:
    """Per case and bank: correct declarations (the failure itself first, no false alarm; for
    NONE: nothing declared) with the Wilson 95 % interval, and the latency median / p95 / max."""
    from f16mmae.campaign.engine.intervals import wilson

    print("\n| case | bank | correct | 95 % interval | latency median / p95 / max (s) |")
    print("|---|---|---|---|---|")
    for (case, j), cells in summary.items():
        lat = []
        for c in cells:
            if case != "NONE" and c.startswith(f"{case}@") and "FA" not in c:
                lat.append(float(c.split("@")[1]))
        k = sum(1 for c in cells if c == "-") if case == "NONE" else len(lat)
        lo, hi = wilson(k, len(cells))
        stats = (f"{np.median(lat):.2f} / {np.percentile(lat, 95):.2f} / {max(lat):.2f}" if lat else "-")
        print(f"| {case} | {columns[j]} | {k}/{len(cells)} | {100 * lo:.1f}-{100 * hi:.1f} % | {stats} |")


if __name__ == "__main__":
    raise SystemExit(main())
