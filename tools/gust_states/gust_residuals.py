"""Residual consistency of the no-failure filter with and without Dryden gust states, on
TUNING flight seeds only (f16mmae/seeds.py): the measurement that chose the gust-state size.

For each design (a tuning name or file, with ``+gust`` for ``--gust-states`` -- the six
Dryden gust states, ``+uvw`` for the three translational ones only -- and ``@LEVEL`` for
``--gust-level``) and each turbulence level flown, it flies the truth model with no
failure on raw feedback (design/flights.py fly_closed_loop; the first second dropped), runs
the design's NONE filter over the records (design/residuals.py) and prints per channel
var(r)/A (1 = matched) and the lag-1 autocorrelation (0 = white), and the NIS mean (7 =
matched).  With ``--evidence`` it prints instead, per design, the expected evidence per frame
for each single failure against NONE (design/distinguish.py ``evidence_rates``: the dither,
open loop, the design's own gusts and noise).  Example:

    .venv/bin/python tools/gust_states/gust_residuals.py --designs tuned tuned@severe tuned+gust@severe \
        --levels moderate,severe --seconds 30 --seeds 4
"""
from __future__ import annotations

import argparse
import dataclasses

from f16mmae import names
from f16mmae.design.bank import design_bank
from f16mmae.design.distinguish import evidence_rates
from f16mmae.design.flights import fly_closed_loop
from f16mmae.design.model import linearize_truth
from f16mmae.design.residuals import filter_residuals, residual_stats
from f16mmae.design.tuning import load_tuning
from f16mmae.seeds import TUNING_FLIGHT_SEEDS


def tuning_of(spec: str):
    """``NAME[+gust|+uvw][@LEVEL]`` -> Tuning."""
    base, _, level = spec.partition("@")
    base, _, gust = base.partition("+")
    tun = load_tuning(base)
    if level:
        tun = dataclasses.replace(tun, turbulence=level)
    if gust:
        tun = dataclasses.replace(tun, gust_model={"gust": "dryden_states", "uvw": "dryden_translational"}[gust])
    return dataclasses.replace(tun, name=spec)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--designs", nargs="+", default=["tuned", "tuned+gust"])
    p.add_argument("--levels", default="moderate,severe")
    p.add_argument("--seconds", type=float, default=30.0)
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--evidence", action="store_true")
    a = p.parse_args()
    lin = linearize_truth(0.4, 20_000.0)
    if a.evidence:
        singles = names.SINGLE_HYPOTHESES[1:]
        print("design " + " ".join(singles))
        for spec in a.designs:
            d = design_bank(tuning=tuning_of(spec), linearized=lin, hypotheses=names.SINGLE_HYPOTHESES)
            rates = [evidence_rates(d, s, [names.NONE])[names.NONE] for s in singles]
            print(f"{spec} " + " ".join(f"{x:.3g}" for x in rates), flush=True)
        return
    flights = {lv: [fly_closed_loop(0.4, 20_000.0, seed=s, turbulence_level=lv, duration_s=a.seconds)
                    for s in TUNING_FLIGHT_SEEDS[:a.seeds]] for lv in a.levels.split(",")}
    print("channels " + " ".join(f"{c:>6}" for c in names.SENSORS))
    for spec in a.designs:
        d = design_bank(tuning=tuning_of(spec), linearized=lin, hypotheses=(names.NONE,))
        f = d.filters[0]
        for lv, fls in flights.items():
            res = [filter_residuals(f.model.phi, f.model.bd, f.model.h, f.gains.k, fl.u, fl.z)
                   [names.FRAME_RATE_HZ:] for fl in fls]
            st = residual_stats(res, f.gains.a)
            print(f"{spec} (nx {f.model.phi.shape[0]}) flown in {lv}: NIS mean {st.nis_mean:.1f}")
            print("  var/A  " + " ".join(f"{v:6.2f}" for v in st.var_over_a))
            print("  rho(1) " + " ".join(f"{v:6.2f}" for v in st.lag1_autocorr), flush=True)


if __name__ == "__main__":
    main()
