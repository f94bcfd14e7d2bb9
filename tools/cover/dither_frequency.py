"""Which stabilator-dither frequencies separate a failed pitch-rate gyro from a free stabilator,
per unit of normal acceleration, computed from the bank's own models (no flight).

Truth: the bank's no-failure model (``Phi``, ``B_d``, ``H`` of NONE, perturbations from trim),
driven by a sinusoidal stabilator dither ``u = a w sin(2 pi f t)`` (``w``: LS and RS in phase
by default, ``--pattern``) and noise-free, with the failed sensor's reading held at its trim
(``--fail PIT``: the row of PIT reads 0; a ``complete`` failure).  The bank's level-0 filters
(``core.FilterBank``, the bank's models) run on that z and u; over the frames from ``--settle-s``
to the end the deterministic evidence of the failed sensor's hypothesis against rival k is

    G_k(f) = mean_i [l_fail,i - l_k,i] - (c_fail - c_k),

c_k the log-likelihood of k on the all-zero data (the same filters, no dither).  With sensor
noise and turbulence added, the expected evidence per frame is D0_k + a^2 G_k(f) (the noise's
part does not depend on the dither; the cross term has mean zero), so G_k(f) is what the dither
buys.  It is printed per unit of the dither's peak normal acceleration squared
(``G_k / n_z,peak^2``, nats per frame per g^2, n_z the AZ row of the healthy model) and per
unit peak pitch rate squared (deg/s): the n_z budget (0.05 g) and the rate criterion
(1 deg/s) bound the amplitude, so the frequency that maximises the smaller of the two
ratios x budget^2 buys the most evidence.  Open loop: the FCS, which adds its own
stabilator motion at the dither frequency, is not in it (the closed-loop check is a campaign).

Run: .venv/bin/python tools/cover/dither_frequency.py --bank results/cover.f16bank [--fail PIT]
     [--rivals LS,RS,NONE] [--freqs 0.5,0.8,1.0,1.3,1.7,2.2,2.9,3.5,4.5]
"""
from __future__ import annotations

import argparse

import numpy as np

from f16mmae import core, names
from f16mmae.truth.dither import CRITERION
from mode_evidence import level0  # tools/cover: the bank's level-0 filters as one core.FilterBank

PATTERNS = {"symmetric": (1.0, 1.0, 0.0, 0.0, 0.0), "left": (1.0, 0.0, 0.0, 0.0, 0.0),
            "differential": (1.0, -1.0, 0.0, 0.0, 0.0)}


def mean_loglik(bank, u, z, lo) -> np.ndarray:
    bank.reset()
    ll = np.zeros((len(z), names.K_BANK))
    for i in range(len(z)):
        bank.update(z[i])
        ll[i] = bank.log_likelihoods
        bank.propagate(u[i])
    return ll[lo:].mean(axis=0)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--fail", default="PIT")
    ap.add_argument("--rivals", default="LS,RS,NONE")
    ap.add_argument("--pattern", default="symmetric", choices=sorted(PATTERNS))
    ap.add_argument("--freqs", default="0.5,0.8,1.0,1.3,1.7,2.2,2.9,3.5,4.5")
    ap.add_argument("--duration-s", type=float, default=8.0)
    ap.add_argument("--settle-s", type=float, default=3.0)
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    hyps = names.SINGLE_HYPOTHESES
    fail_k = hyps.index(args.fail)
    j = names.SENSORS.index(args.fail)
    rivals = [hyps.index(r) for r in args.rivals.split(",")]
    none = list(mb.hypotheses)[0]
    phi, bd, h = (np.asarray(x) for x in (none.phi, none.bd, none.h))
    bank = level0(mb)
    rate = float(mb.frame_rate_hz)
    n = int(round(args.duration_s * rate))
    lo = int(round(args.settle_s * rate))
    t = np.arange(n) / rate
    w = np.asarray(PATTERNS[args.pattern])
    az, q = names.SENSORS.index("AZ"), names.SENSORS.index("PIT")
    base = mean_loglik(bank, np.zeros((n, names.NU)), np.zeros((n, names.NZ)), lo)
    a = np.radians(1.0)  # 1 deg of dither: G scales with a^2, the ratios below do not depend on it
    print(f"{args.fail} failed (reads trim), {args.pattern} stabilator dither, bank {mb.content_hash[:12]}; "
          f"budgets n_z {CRITERION['nz_g']} g, q {CRITERION['rate_deg_s']} deg/s")
    print("f_Hz  nz_g/deg  q_dps/deg  " + "  ".join(f"G_{hyps[k]}/nz^2  G_{hyps[k]}/q^2  G_{hyps[k]}@budget"
                                                  for k in rivals))
    for f in (float(x) for x in args.freqs.split(",")):
        u = a * np.outer(np.sin(2 * np.pi * f * t), w)
        x = np.zeros(phi.shape[0])
        zt = np.zeros((n, names.NZ))
        for i in range(n):
            zt[i] = h @ x
            x = phi @ x + bd @ u[i]
        nz_pk = np.abs(zt[lo:, az]).max()
        q_pk = np.degrees(np.abs(zt[lo:, q]).max())
        z = zt.copy()
        z[:, j] = 0.0
        ll = mean_loglik(bank, u, z, lo)
        g = (ll[fail_k] - ll) - (base[fail_k] - base)
        cols = []
        for k in rivals:
            # the largest amplitude within both budgets, and the evidence it buys per frame
            scale = min(CRITERION["nz_g"] / nz_pk, CRITERION["rate_deg_s"] / q_pk)
            cols.append(f"{g[k] / nz_pk**2:10.1f}  {g[k] / q_pk**2:10.3f}  {g[k] * scale**2:10.3f}")
        print(f"{f:4.2f}  {nz_pk:8.4f}  {q_pk:9.3f}  " + "  ".join(cols))


if __name__ == "__main__":
    main()
