"""How much of a constant sensor bias the no-failure filter absorbs, and the bias it takes to
make the failed sensor's hypothesis win (a model computation; D0 from flights).

A bias b on sensor j (z = z_true + e_j b) moves the NONE filter's estimate: the deviation of
its prior estimate obeys dx_{i+1} = Phi (I - K H) dx_i + Phi K e_j b, so its residual's mean
at frame i is dr_i = e_j b - H dx_i (this script drives the filter with the bias alone,
noise-free), and in the steady state

    dr = g_j b,   g_j = e_j - H (I - Phi (I - K H))^-1 Phi K e_j.

The bias costs NONE  c_i = (1/2) dr_i^T A^-1 dr_i  nats at frame i on average (the cross term
with the zero-mean residual averages out).  The failed sensor's hypothesis does not pay for the
bias (its level follows the reading) but pays D0_j per frame for not using the sensor when it
is healthy: the mean of l_NONE - l_j over the no-failure tuning flights (design/calibrate.py
node_flights, first second dropped).  The hypothesis gains on NONE on average once the bias'
cost exceeds D0_j; from the cost 1 s after the onset (c_1s for a 10-sigma bias):

    b*_j = 10 sigma_j sqrt(D0_j / c_1s).

Printed per sensor: the cost of a 10-sigma bias at the first frame, 0.25, 1, 5 and 60 s,
D0_j and b*_j / sigma_j.
Run: .venv/bin/python tools/cover/bias_absorption.py --bank BANK
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.design.calibrate import node_flights
from f16mmae.truth import sensors

P_MIN = 1e-9
TIMES_S = (0.0, 0.25, 1.0, 5.0, 60.0)


def bias_costs(hyp, j: int, b: float, times_s=TIMES_S) -> list[float]:
    """NONE's mean cost (nats) of a bias b on sensor j at each of ``times_s`` after its onset."""
    phi, h, k, a = (np.asarray(x) for x in (hyp.phi, hyp.h, hyp.k, hyp.a))
    a_inv = np.linalg.inv(a)
    frames = [int(round(t * names.FRAME_RATE_HZ)) for t in times_s]
    x, out = np.zeros(phi.shape[0]), {}
    e = np.zeros(h.shape[0])
    e[j] = b
    for i in range(max(frames) + 1):
        r = e - h @ x
        out[i] = 0.5 * r @ a_inv @ r
        x = phi @ (x + k @ r)
    return [out[f] for f in frames]


def measured_d0(model_bank) -> np.ndarray:
    """(nz,) mean of l_NONE - l_sensor per frame over the no-failure tuning flights."""
    hyps = list(model_bank.hypotheses)[:names.K_BANK]
    models = [core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a, uninformative_width=h.uninformative_width,
                               uninformative_level_q=h.uninformative_level_q) for h in hyps]
    bank = core.FilterBank(models, p_min=P_MIN)
    diffs = []
    for fl in node_flights(float(model_bank.mach), float(model_bank.alt_ft), "light"):
        bank.reset()
        for i in range(len(fl.z)):
            bank.update(fl.z[i])
            if i >= names.FRAME_RATE_HZ:
                ll = np.asarray(bank.log_likelihoods)
                diffs.append(ll[0] - ll[1 + names.NU:])
            bank.propagate(fl.u[i, :model_bank.nu])
    return np.mean(diffs, axis=0)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bank", required=True)
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    sigma = np.asarray(sensors.NOISE_SIGMA, dtype=float)
    d0 = measured_d0(mb)
    print(f"{'sensor':<6} cost of a 10-sigma bias at " + " / ".join(f"{t:g} s" for t in TIMES_S)
          + "   D0   b*/sigma")
    for j, name in enumerate(names.SENSORS):
        c = bias_costs(mb.hypotheses[0], j, 10.0 * sigma[j])
        print(f"{name:<6} " + " / ".join(f"{v:.3g}" for v in c)
              + f"   {d0[j]:.3g}   {10.0 * np.sqrt(max(d0[j], 0.0) / c[2]):.1f}")


if __name__ == "__main__":
    main()
