"""Benchmark: the full truth model against bare JSBSim stepping of the stock F-16, one run,
and the closed loop (truth + estimator) against the truth alone.

    f16mmae bench truth [--duration-s 8] [--repeat 5]

Measures, in one process and interleaved (these machines are noisy, so ratios matter):
  bare      stock ``f16`` (its own FCS), trimmed at the nominal point, ``run()`` x duration*128;
  truth     TruthModel + FlightControlSystem (raw feedback) + dither + sensors + actuators,
            duration*64 frames of measure/command/advance (2 JSBSim steps each);
  *_total   the same including load + trim.
Real-time factor RTF = simulated seconds / wall seconds (best of ``repeat``), per core.
Also prints the dither levels at the nominal point (the subliminal criterion of truth.dither).
"""
from __future__ import annotations

import time

import numpy as np

from ..banks import load_bank
from ..loop.overhead import measure_overhead
from ..names import FRAME_RATE_HZ, SIM_RATE_HZ
from ..truth import aircraft
from ..truth.dither import CRITERION
from ..truth.fcs import FlightControlSystem
from ..truth.model import TruthModel, fly_raw
from ..truth.scenario import Scenario


def _bare_stock(duration_s: float) -> tuple[float, float]:
    t0 = time.perf_counter()
    fdm = aircraft.load_fdm(seed=1, stock=True)
    fdm["ic/h-sl-ft"] = 20_000.0
    fdm["ic/mach"] = 0.4
    fdm["ic/gamma-deg"] = 0.0
    fdm["gear/gear-cmd-norm"] = 0.0
    fdm["gear/gear-pos-norm"] = 0.0
    fdm["propulsion/engine[0]/set-running"] = 1
    fdm.run_ic()
    fdm["simulation/do_simple_trim"] = 1
    t1 = time.perf_counter()
    run = fdm.run
    for _ in range(int(round(duration_s * SIM_RATE_HZ))):
        run()
    t2 = time.perf_counter()
    return t2 - t1, t2 - t0


def _truth(duration_s: float) -> tuple[float, float]:
    t0 = time.perf_counter()
    sc = Scenario(duration_s=duration_s, feedback="raw")
    truth = TruthModel(sc)
    fcs = FlightControlSystem(truth.trim, dither=sc.dither, ari=sc.ari)
    t1 = time.perf_counter()
    measure, command, advance = truth.measure, fcs.command, truth.advance
    for i in range(int(round(duration_s * FRAME_RATE_HZ))):
        advance(command(measure(), i / FRAME_RATE_HZ))
    t2 = time.perf_counter()
    return t2 - t1, t2 - t0


def benchmark(duration_s: float = 8.0, repeat: int = 5) -> dict:
    """Best-of-``repeat`` wall times (s) and real-time factors of bare JSBSim and the truth model."""
    _truth(0.5)
    _bare_stock(0.5)  # warm up: derived aircraft written, files cached
    bare, bare_tot, tru, tru_tot = [], [], [], []
    for _ in range(repeat):
        a, b = _bare_stock(duration_s)
        c, d = _truth(duration_s)
        bare.append(a), bare_tot.append(b), tru.append(c), tru_tot.append(d)
    res = {"duration_s": duration_s, "repeat": repeat,
           "bare_loop_s": min(bare), "bare_total_s": min(bare_tot),
           "truth_loop_s": min(tru), "truth_total_s": min(tru_tot)}
    for k in ("bare_loop", "bare_total", "truth_loop", "truth_total"):
        res[f"{k}_rtf"] = duration_s / res[f"{k}_s"]
    res["truth_over_bare_loop"] = res["truth_loop_s"] / res["bare_loop_s"]
    res["truth_over_bare_total"] = res["truth_total_s"] / res["bare_total_s"]
    return res


def dither_levels(mach: float = 0.4, alt_ft: float = 20_000.0, duration_s: float = 8.0) -> dict:
    """Peak closed-loop response to the default dither (no noise, no turbulence): nz_g, ny_g,
    q/p/r in deg/s, alpha_deg, vel_fps (perturbations from trim)."""
    sc = Scenario(mach=mach, alt_ft=alt_ft, duration_s=duration_s, noise=False, feedback="raw")
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    dz = np.abs(log["z_ideal"] - truth.trim.z).max(axis=0)
    return {"vel_fps": dz[0], "alpha_deg": float(np.degrees(dz[1])), "q_deg_s": float(np.degrees(dz[2])),
            "nz_g": dz[3], "p_deg_s": float(np.degrees(dz[4])), "r_deg_s": float(np.degrees(dz[5])),
            "ny_g": dz[6]}


def closed_loop_overhead(duration_s: float = 8.0, repeat: int = 5) -> dict:
    """The nominal no-failure flight with the shipped tuned bank in the loop against the truth
    alone (:func:`f16mmae.loop.overhead.measure_overhead`)."""
    _, _, bank = load_bank("tuned")
    sc = Scenario(mach=float(bank.mach), alt_ft=float(bank.alt_ft), duration_s=duration_s)
    return measure_overhead(sc, bank, repeats=repeat)


def report(r: dict, lv: dict, ov: dict, stream) -> None:
    """Print :func:`benchmark` ``r``, :func:`dither_levels` ``lv`` and :func:`closed_loop_overhead` ``ov``."""
    print(f"truth-model benchmark: {r['duration_s']:g}-s nominal run (20,000 ft, M 0.4), "
          f"JSBSim {SIM_RATE_HZ} Hz, FCS {FRAME_RATE_HZ} Hz, best of {r['repeat']}", file=stream)
    print(f"  {'':34s}{'wall ms':>10s}{'RTF':>9s}", file=stream)
    rows = (("bare JSBSim stock f16, stepping", "bare_loop"),
            ("bare JSBSim stock f16, +load+trim", "bare_total"),
            ("full truth model, frames", "truth_loop"),
            ("full truth model, +build+trim", "truth_total"))
    for label, k in rows:
        print(f"  {label:34s}{1e3 * r[k + '_s']:10.1f}{r[k + '_rtf']:9.0f}x", file=stream)
    print(f"  truth / bare: {r['truth_over_bare_loop']:.2f} (stepping), "
          f"{r['truth_over_bare_total']:.2f} (with set-up); target RTF >= 150", file=stream)
    print(f"closed loop (tuned bank, probabilities recorded) / truth alone: {1e3 * ov['closed_loop_s']:.1f} ms / "
          f"{1e3 * ov['truth_only_s']:.1f} ms = {ov['ratio']:.2f}", file=stream)
    print("dither levels at 20,000 ft, M 0.4 (peak, closed loop, no noise/turbulence):", file=stream)
    print(f"  n_z {lv['nz_g']:.4f} g (< {CRITERION['nz_g']}), n_y {lv['ny_g']:.4f} g "
          f"(< {CRITERION['ny_g']}), q {lv['q_deg_s']:.3f}, p {lv['p_deg_s']:.3f}, "
          f"r {lv['r_deg_s']:.3f} deg/s (< {CRITERION['rate_deg_s']}), alpha {lv['alpha_deg']:.3f} deg, "
          f"u {lv['vel_fps']:.3f} ft/s", file=stream)
