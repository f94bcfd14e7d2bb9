"""Can a bank's own residual power tell calm air from light turbulence?  The turbulence
adaptation's intensity measure rho (cpp/f16mmae/turbulence_adaptation.h: the average over its
time constant of min_k q_k / nz) of each bank named, measured on no-failure closed-loop flights
at each level, with the adaptation's scale held at 1 (``adapt_scale_max=1``: the bank flies as
designed, rho is only read).  Evaluation seeds of kind ``turbulence_rho`` at campaign seed 7.

    .venv/bin/python tools/turbulence_rho.py --banks tuned,FILE --runs 10
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import FRAME_RATE_HZ
from f16mmae.seeds import evaluation_seed
from f16mmae.truth import Scenario


def rho_history(model_bank, level: str, seed: int, duration_s: float) -> np.ndarray:
    """rho after each frame of one no-failure flight at ``level``."""
    est = Estimator(model_bank, adapt_turbulence=True, adapt_scale_max=1.0)
    rho: list[float] = []
    fly(Scenario(turbulence=level, duration_s=duration_s, seed=seed), model_bank, estimator=est,
        on_frame=lambda t, u, z, a: rho.append(est.core_bank.turbulence_power_ratio))
    return np.array(rho)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--banks", default="tuned", help="comma list of banks (tuned, untuned, FILE)")
    p.add_argument("--levels", default="none,light")
    p.add_argument("--runs", type=int, default=10)
    p.add_argument("--duration", type=float, default=8.0)
    args = p.parse_args(argv)
    at = [1.0, 3.0, args.duration]
    print("| bank | turbulence | rho min-max over 1 s - end | " + " | ".join(f"rho at {t:g} s, min-max" for t in at) + " |")
    print("|---|---|---|" + "---|" * len(at))
    for name in args.banks.split(","):
        _, path, mb = load_bank(name)
        label = name if path.suffix != ".f16bank" or name in ("tuned", "untuned") else path.name
        for level in args.levels.split(","):
            runs = np.array([rho_history(mb, level, evaluation_seed("turbulence_rho", 7, level, n), args.duration)
                             for n in range(args.runs)])
            tail = runs[:, int(FRAME_RATE_HZ):]
            cols = [runs[:, min(int(t * FRAME_RATE_HZ), runs.shape[1] - 1)] for t in at]
            print(f"| {label} | {level} | {tail.min():.3f}-{tail.max():.3f} | "
                  + " | ".join(f"{c.min():.3f}-{c.max():.3f}" for c in cols) + " |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
