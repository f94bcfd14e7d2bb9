"""The design report of a model bank: text + PNG figures.

- ``report.txt``: flight condition and trim; the airframe linearization (finite differences
  against JSBSim's FGLinearization); airframe eigenvalues; the tuning; per hypothesis the
  error-dynamics spectral radius and residual standard deviations sqrt(diag A_k); linear vs
  nonlinear step responses (peak error); the NONE filter's residual statistics in no-failure
  nonlinear flight (mean, variance against A_kk, lag-1 autocorrelation for whiteness, NIS
  against m = 7 with its 95 % band); failure sensitivity (which level-0 filter has the
  largest likelihood after each single failure); probability convergence of the level-0
  bank on seeds the tuning did not see (``convergence.score``).
- ``eigenvalues.png``: continuous-equivalent eigenvalues ``ln(lambda) f_frame`` of the model
  and of every hypothesis filter's error dynamics Phi (I - K H).
- ``gains.png``: the NONE filter's K and each level-0 filter's gain column norms.
- ``step_responses.png``: linear model vs nonlinear truth, 0.2 deg command steps.
- ``residuals.png``: NONE-filter residuals over sqrt(A_kk) and NIS in no-failure flight.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .. import names
from ..truth import aircraft
from . import convergence
from .bank import BankDesign
from .flights import fly_closed_loop, fly_open_loop
from .linearize import jsbsim_linearization
from .residuals import filter_residuals, residual_stats

#: Step amplitude of the step-response comparison (rad) and its duration (s).
STEP_RAD = math.radians(0.2)
STEP_DURATION_S = 3.0
STEP_SURFACES = ("LS", "LF", "RUD")
#: No-failure flights of the residual statistics (seeds), and failure flights (seed).
REPORT_SEEDS = tuple(range(101, 105))
SENSITIVITY_SEED = 11


def linear_step(design: BankDesign, surface: str, amplitude_rad: float, n: int) -> np.ndarray:
    """(n, 7) sensor perturbations of the discrete NONE model for a command step at t = 0."""
    f = design.filter(names.NONE).model
    u = np.zeros(names.NU)
    u[names.ACTUATORS.index(surface)] = amplitude_rad
    x = np.zeros(names.NX)
    out = np.empty((n, names.NZ))
    for i in range(n):
        out[i] = f.h @ x
        x = f.phi @ x + f.bd @ u
    return out


def _loglik(f, flight, start: int) -> tuple[float, float]:
    r = filter_residuals(f.model.phi, f.model.bd, f.model.h, f.gains.k, flight.u, flight.z)[start:]
    nis = np.einsum("ij,ij->i", r, np.linalg.solve(f.gains.a, r.T).T)
    return float(nis.mean()), float(-0.5 * nis.sum())


def write_report(design: BankDesign, out_dir: Path) -> list[Path]:
    """Write report.txt and the four figures into ``out_dir``; returns their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    lines: list[str] = []
    w = lines.append
    trim, lin = design.linearized.trim, design.linearized.lin
    fr = design.frame_rate_hz
    w(f"f16mmae design report -- Mach {design.mach:g}, {design.alt_ft:.0f} ft, tuning "
      f"'{design.tuning.name}', {len(design.filters)} hypotheses, frame rate {fr:g} Hz")
    w(f"trim: Vt {trim.vt_fps:.2f} ft/s, alpha {math.degrees(trim.alpha_rad):.3f} deg, "
      f"qbar {trim.qbar_psf:.1f} psf, throttle {trim.throttle:.4f}, surfaces (deg) "
      + " ".join(f"{a} {math.degrees(v):.3f}" for a, v in zip(names.ACTUATORS, trim.u_rad)))
    w("z_trim: " + " ".join(f"{s} {v:.5g}" for s, v in zip(names.SENSORS, design.z_trim)))

    # -- linearization cross-check ------------------------------------------------------------
    fdm, _ = aircraft.trimmed_fdm(design.mach, design.alt_ft)
    a_j, b_j, u_names = jsbsim_linearization(fdm)
    scale = np.maximum(np.abs(lin.a).max(axis=1, keepdims=True), 1e-12)
    w("")
    w(f"airframe linearization: central differences ({lin.evaluations} evaluations) vs JSBSim "
      f"FGLinearization: max |dA| / row scale = {np.max(np.abs(a_j - lin.a) / scale):.2e}")
    ev = np.linalg.eigvals(lin.a)
    w("bare-airframe eigenvalues (1/s): " + ", ".join(f"{e.real:.4f}{e.imag:+.4f}j"
                                                       for e in sorted(ev, key=lambda e: (e.real, e.imag))))
    w(f"design model: gust model {design.continuous.gust_model}, gust sigma (u v w) "
      f"{np.round(design.continuous.gust_sigma_fps, 2).tolist()} ft/s; actuator lags "
      f"20.2 rad/s; sensor noise sigma {np.round(np.sqrt(design.continuous.r_diag), 5).tolist()}")
    t = design.tuning
    w(f"tuning '{t.name}': method 1 {t.qd_longitudinal or '-'}; method 2 {t.r_pseudonoise or '-'}; "
      f"method 3 {t.qd_lateral or '-'}; method 4 {t.actuator_q or '-'}")

    # -- per hypothesis --------------------------------------------------------------------------
    w("")
    w("hypothesis  rho(Phi(I-KH))  sqrt(diag A): " + " ".join(f"{s:>8}" for s in names.SENSORS))
    for f in design.filters[:names.K_BANK]:
        w(f"{f.name:>10}  {f.gains.spectral_radius:14.6f}  {'':13} "
          + " ".join(f"{v:8.4g}" for v in np.sqrt(np.diag(f.gains.a))))
    duals = design.filters[names.K_BANK:]
    if duals:
        worst = max(duals, key=lambda f: f.gains.spectral_radius)
        w(f"66 duals: largest spectral radius {worst.gains.spectral_radius:.6f} ({worst.name})")

    # -- step responses ----------------------------------------------------------------------------
    n = int(STEP_DURATION_S * fr)
    steps = {}
    w("")
    w(f"step responses ({math.degrees(STEP_RAD):.1f} deg command step, {STEP_DURATION_S:g} s, no "
      "turbulence, open loop): peak |nonlinear - linear| / max(peak |nonlinear|, 3 noise sigma)")
    for s in STEP_SURFACES:
        nl = fly_open_loop(design.mach, design.alt_ft, turbulence_level="none", duration_s=STEP_DURATION_S,
                           dither=False, noise=False, step=(s, STEP_RAD)).z_ideal
        li = linear_step(design, s, STEP_RAD, n)
        steps[s] = (nl, li)
        floor = 3.0 * np.sqrt(design.continuous.r_diag)
        rel = np.abs(nl - li).max(axis=0) / np.maximum(np.abs(nl).max(axis=0), floor)
        w(f"  {s:>4}: " + " ".join(f"{c} {v:6.1%}" for c, v in zip(names.SENSORS, rel)))

    # -- residual statistics, no failure -------------------------------------------------------
    none = design.filter(names.NONE)
    flights = [fly_closed_loop(design.mach, design.alt_ft, seed=s, turbulence_level=t.turbulence)
               for s in REPORT_SEEDS]
    start = int(fr)
    res = [filter_residuals(none.model.phi, none.model.bd, none.model.h, none.gains.k, f.u, f.z)[start:]
           for f in flights]
    st = residual_stats(res, none.gains.a)
    nframes = st.frames
    half = 1.96 * math.sqrt(2 * names.NZ / nframes)
    w("")
    w(f"NONE filter residuals, no-failure nonlinear flight ({t.turbulence} turbulence, FCS on raw "
      f"feedback, dither on, seeds {REPORT_SEEDS[0]}-{REPORT_SEEDS[-1]}, first second dropped):")
    w(st.table(names.SENSORS))
    w(f"  95% band of the NIS mean for a matched filter: {names.NZ} +- {half:.2f}; white "
      f"residuals: |rho(1)| < {1.96 / math.sqrt(nframes):.3f}")

    # -- failure sensitivity -----------------------------------------------------------------
    w("")
    w(f"failure sensitivity (seed {SENSITIVITY_SEED}, complete failure at 3 s, frames 4-8 s): "
      "mean NIS of NONE and of the failed hypothesis' filter; the level-0 filter with the largest "
      "likelihood")
    level0 = design.filters[:names.K_BANK]
    for h in names.SINGLE_HYPOTHESES:
        fl = fly_closed_loop(design.mach, design.alt_ft, seed=SENSITIVITY_SEED,
                             turbulence_level=t.turbulence, failure=None if h == names.NONE else h)
        stats = [_loglik(f, fl, int(4 * fr)) for f in level0]
        best = names.SINGLE_HYPOTHESES[int(np.argmax([s[1] for s in stats]))]
        k = names.SINGLE_HYPOTHESES.index(h)
        w(f"  {h:>5}: NIS NONE {stats[0][0]:8.2f}  NIS {h:>5} {stats[k][0]:8.2f}  most likely "
          f"{best:>5} {'ok' if best == h else 'WRONG'}")
    # -- probability convergence on held-out seeds ----------------------------------------
    held_out = convergence.case_flights(design.mach, design.alt_ft, t.turbulence,
                                        none_seeds=REPORT_SEEDS, failure_seeds=(SENSITIVITY_SEED,))
    j, per_case, _ = convergence.score(t, design.linearized, held_out)
    w("")
    w(f"probability convergence (level-0 bank, core.FilterBank, p_min 0.001; seeds "
      f"{REPORT_SEEDS[0]}-{REPORT_SEEDS[-1]} no failure, {SENSITIVITY_SEED} per failure): fraction of "
      f"frames the true hypothesis leads, J = {j:.3f}")
    w("  " + " ".join(f"{k} {v:.2f}" for k, v in per_case.items()))
    paths = [out_dir / "report.txt"]
    paths[0].write_text("\n".join(lines) + "\n")

    # -- figures ----------------------------------------------------------------------------------
    fig, ax = plt.subplots(figsize=(8, 5))
    styles = {"dual": (".", 2, "0.7"), "single": ("o", 4, "C1"), names.NONE: ("D", 5, "C0")}
    for kind in ("dual", "single", names.NONE):  # NONE drawn last, on top
        for f in design.filters:
            k_f = names.NONE if f.name == names.NONE else (
                "single" if f.name in names.SINGLE_HYPOTHESES else "dual")
            if k_f != kind:
                continue
            lam = np.linalg.eigvals(f.model.phi @ (np.eye(names.NX) - f.gains.k @ f.model.h))
            s_eq = np.log(lam.astype(complex)) * fr
            marker, size, color = styles[kind]
            ax.plot(s_eq.real, s_eq.imag, marker, ms=size, color=color)
    s_model = np.log(np.linalg.eigvals(design.discrete.phi).astype(complex)) * fr
    ax.plot(s_model.real, s_model.imag, "kx", ms=7, label="model Phi")
    ax.plot([], [], "D", color="C0", label="NONE filter")
    ax.plot([], [], "o", color="C1", label="single-failure filters")
    ax.plot([], [], ".", color="0.7", label="dual-failure filters")
    ax.set_xscale("symlog", linthresh=0.1)
    ax.set_xlabel("Re s (1/s), s = ln(lambda) f_frame")
    ax.set_ylabel("Im s (rad/s)")
    ax.set_title("Error-dynamics eigenvalues Phi (I - K H) per hypothesis")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    paths.append(out_dir / "eigenvalues.png")
    fig.savefig(paths[-1], dpi=110, bbox_inches="tight")
    plt.close(fig)

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 5))
    k = none.gains.k
    mag = np.ma.masked_less(np.abs(k), 1e-9 * np.abs(k).max())
    im = a1.imshow(np.ma.log10(mag), cmap="viridis", aspect="auto")
    a1.set_xticks(range(names.NZ), names.SENSORS)
    a1.set_yticks(range(names.NX), names.STATES, fontsize=7)
    a1.set_title("NONE filter gain: log10 |K_ij| (blank: zero)")
    fig.colorbar(im, ax=a1)
    norms = np.array([np.linalg.norm(f.gains.k, axis=0) for f in level0])
    for j in range(names.NZ):
        a2.semilogy(range(names.K_BANK), norms[:, j] + 1e-12, "o-", ms=3, label=names.SENSORS[j])
    a2.set_xticks(range(names.K_BANK), names.SINGLE_HYPOTHESES, rotation=60, fontsize=7)
    a2.set_title("|K column| per level-0 hypothesis")
    a2.legend(fontsize=7)
    paths.append(out_dir / "gains.png")
    fig.savefig(paths[-1], dpi=110, bbox_inches="tight")
    plt.close(fig)

    fig, axes = plt.subplots(names.NZ, len(STEP_SURFACES), figsize=(12, 13), sharex=True)
    tt = np.arange(n) / fr
    for c, s in enumerate(STEP_SURFACES):
        nl, li = steps[s]
        for r in range(names.NZ):
            ax = axes[r, c]
            ax.plot(tt, nl[:, r], "k-", lw=1.2, label="nonlinear truth")
            ax.plot(tt, li[:, r], "C3--", lw=1.2, label="linear model")
            if c == 0:
                ax.set_ylabel(f"{names.SENSORS[r]} ({names.SENSOR_UNITS[r]})", fontsize=8)
            if r == 0:
                ax.set_title(f"{s} step {math.degrees(STEP_RAD):.1f} deg")
    axes[0, 0].legend(fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    paths.append(out_dir / "step_responses.png")
    fig.savefig(paths[-1], dpi=100, bbox_inches="tight")
    plt.close(fig)

    fig, axes = plt.subplots(names.NZ + 1, 1, figsize=(10, 12), sharex=True)
    r0 = res[0]
    tt = (np.arange(len(r0)) + start) / fr
    sd = np.sqrt(np.diag(none.gains.a))
    for j in range(names.NZ):
        axes[j].plot(tt, r0[:, j] / sd[j], lw=0.7)
        axes[j].axhline(2, color="0.6", lw=0.5)
        axes[j].axhline(-2, color="0.6", lw=0.5)
        axes[j].set_ylabel(f"{names.SENSORS[j]}/sqrt(A)", fontsize=8)
    nis = np.einsum("ij,ij->i", r0, np.linalg.solve(none.gains.a, r0.T).T)
    axes[-1].plot(tt, nis, lw=0.7, label="NIS")
    axes[-1].axhline(names.NZ, color="k", lw=0.8, label=f"m = {names.NZ}")
    axes[-1].set_ylabel("NIS")
    axes[-1].legend(fontsize=7)
    axes[-1].set_xlabel("time (s)")
    axes[0].set_title(f"NONE filter residuals, no failure (seed {REPORT_SEEDS[0]})")
    paths.append(out_dir / "residuals.png")
    fig.savefig(paths[-1], dpi=100, bbox_inches="tight")
    plt.close(fig)
    return paths
