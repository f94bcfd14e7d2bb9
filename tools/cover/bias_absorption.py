"""How much of a constant sensor bias the no-failure filter absorbs, and the bias it takes to
make the failed sensor's hypothesis win (a model computation, no flight).

A bias b on sensor j (z = z_true + e_j b) moves the NONE filter's steady-state estimate: the
deviation of its prior estimate obeys dx_{i+1} = Phi (I - K H) dx_i + Phi K e_j b, so in the
steady state dx = (I - Phi (I - K H))^-1 Phi K e_j b and the residual's mean is

    dr = g_j b,   g_j = e_j - H (I - Phi (I - K H))^-1 Phi K e_j      (the DC residual response).

The bias then costs NONE  c_j b^2 = (1/2) g_j^T A^-1 g_j b^2  nats per frame on average (the
cross term with the zero-mean residual averages out).  The failed sensor's hypothesis does not
pay for the bias (its level follows the reading) but pays D0_j per frame for not using the
sensor when it is healthy: the mean of l_NONE - l_j in the no-failure tuning flights
(``--d0``, from tools/cover/false_alarm_evidence.py, or measured here with ``--measure``).  On
average the hypothesis gains on NONE once c_j b^2 > D0_j, i.e. above

    b*_j = sqrt(D0_j / c_j)      (in units of the sensor's noise sigma below).

Printed per sensor: |g_jj| (the share of the bias left in its own residual; 1 - |g_jj| is
what the state estimate absorbs), the other channels' share, c_j per sigma^2, D0_j, b*_j/sigma.
Run: .venv/bin/python tools/cover/bias_absorption.py --bank BANK --measure
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.design.calibrate import node_flights
from f16mmae.truth import sensors

P_MIN = 1e-9


def dc_residual(hyp) -> np.ndarray:
    """(nz, nz) g: column j is the NONE filter's mean residual per unit bias on sensor j."""
    phi, h, k = np.asarray(hyp.phi), np.asarray(hyp.h), np.asarray(hyp.k)
    n = phi.shape[0]
    m = np.linalg.solve(np.eye(n) - phi @ (np.eye(n) - k @ h), phi @ k)
    return np.eye(h.shape[0]) - h @ m


def measured_d0(model_bank) -> np.ndarray:
    """(nz,) mean of l_NONE - l_sensor per frame over the no-failure tuning flights (first second dropped)."""
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
    ap.add_argument("--measure", action="store_true", help="measure D0 on the no-failure tuning flights")
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    none = mb.hypotheses[0]
    g = dc_residual(none)
    a_inv = np.linalg.inv(np.asarray(none.a))
    sigma = np.asarray(sensors.NOISE_SIGMA, dtype=float)
    d0 = measured_d0(mb) if args.measure else None
    print(f"{'sensor':<6} {'|g_jj|':>7} {'others':>7} {'c per sigma^2':>14} {'D0':>7} {'b*/sigma':>9}")
    for j, name in enumerate(names.SENSORS):
        col = g[:, j]
        c = 0.5 * col @ a_inv @ col * sigma[j] ** 2
        others = np.sqrt(sum((col[i] / sigma[i]) ** 2 for i in range(len(col)) if i != j)) * sigma[j]
        tail = f"{d0[j]:7.3f} {np.sqrt(max(d0[j], 0.0) / c):9.1f}" if d0 is not None else ""
        print(f"{name:<6} {abs(col[j]):7.3f} {others:7.3f} {c:14.4f} {tail}")


if __name__ == "__main__":
    main()
