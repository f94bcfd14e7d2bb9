"""One flight's rise, frame by frame: why a sensor failure with tens of nats a frame of mean
evidence still takes 0.1-0.4 s to pass the threshold.

Reads the ``flight.parquet`` that ``f16mmae run ... --out DIR`` writes and, for the failed
sensor S, prints per frame (from ``--from`` to ``--to`` s) the reading z_S, the blended
estimate z_hat_S, p_S, p_NONE and ln(p_S / p_NONE) (the evidence S has gathered against
NONE, clipped by the floor), and draws them (``--figure FILE``):

    f16mmae run --seed 7 --duration 5.0 --turbulence light --fail AZ@3.0:complete --bank tuned --out DIR
    .venv/bin/python tools/latency/rise_trace.py DIR AZ --from 2.9 --to 3.5 --figure FILE.png
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run_dir", type=Path)
    p.add_argument("sensor", help="the failed sensor: VEL AOA PIT AZ ROL YAW AY")
    p.add_argument("--from", dest="t0", type=float, default=2.9)
    p.add_argument("--to", dest="t1", type=float, default=3.6)
    p.add_argument("--figure", type=Path, default=None)
    a = p.parse_args()
    path = a.run_dir / "flight.parquet"
    if not path.exists():
        raise SystemExit(f"rise_trace: no {path}: run 'f16mmae run ... --out {a.run_dir}' first")
    t = pq.read_table(path).to_pydict()
    s = a.sensor.upper()
    if f"z_{s}" not in t:
        raise SystemExit(f"rise_trace: {s!r} is not a measurement of this flight")
    time = np.asarray(t["time_s"])
    z, z_hat = np.asarray(t[f"z_{s}"]), np.asarray(t[f"z_hat_{s}"])
    p_s, p_none = np.asarray(t[f"p_{s}"]), np.asarray(t["p_NONE"])
    llr = np.log(p_s / p_none)
    sel = (time >= a.t0) & (time <= a.t1)
    print("time_s z z_hat p p_NONE ln(p/p_NONE)")
    for i in np.flatnonzero(sel):
        print(f"{time[i]:.3f} {z[i]:+.4f} {z_hat[i]:+.4f} {p_s[i]:.3g} {p_none[i]:.3g} {llr[i]:+.1f}")
    if a.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        ax[0].plot(time[sel], z[sel], ".-", label=f"z_{s} (failed at trim + noise after the failure)")
        ax[0].plot(time[sel], z_hat[sel], "-", label=f"z_hat_{s} (blended estimate)")
        ax[0].legend(fontsize=8)
        ax[1].plot(time[sel], llr[sel], ".-", label=f"ln(p_{s} / p_NONE)")
        ax[1].axhline(np.log(9.0), color="k", lw=0.5, ls="--", label="threshold 0.9 (against NONE alone)")
        ax[1].set_xlabel("time (s)")
        ax[1].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.figure, dpi=110)
        print(f"figure: {a.figure}")


if __name__ == "__main__":
    main()
