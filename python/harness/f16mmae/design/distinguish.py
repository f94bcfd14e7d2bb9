"""How far apart two hypotheses are, from the models alone (issue 13 item 5): the expected
evidence per frame that the bank gathers for the true hypothesis against a competitor.

Truth: hypothesis T's linear model (perturbations from trim), the failed sensors reading
their trim value plus noise (the ``complete`` mode), the failed surfaces held at trim::

    x_{i+1} = Phi x_i + Bd_T u_i + w_i,   w ~ N(0, Q),     z_i = H_T x_i + v_i,   v ~ N(0, R)

``Phi, Q, R`` are the design's no-failure ones (``Q`` = the design's ``Q_d``, gusts and the
pseudonoise the calibration matched to the truth's residuals; ``Q = 0`` for calm air), the
inputs ``u`` the dither (``truth.dither``), open loop (the FCS is not modelled here).
Every bank filter k runs on ``(z, u)``: ``r_k = z - H_k x^-_k``, ``x^+_k = x^-_k + K_k r_k``,
``x^-_k <- Phi_k x^+_k + Bd_k u``, and the bank scores it by (filter_bank.h, leading term
stripped) ``l_k = -r_k' Ainv_k r_k / 2 + u_k(r_k)``, with ``Ainv_k`` and the uninformative
channels' term ``u_k`` as the core builds them (steady_state_filter.h).

The expected log-likelihood ratio per frame in steady state, filter T' (T's own) against F::

    D(T, F) = E[l_T' - l_F] = tr(Ainv_F S_F)/2 - tr(Ainv_T' S_T')/2
              + mean_t (m_F' Ainv_F m_F - m_T'' Ainv_T' m_T') / 2 + E[u_T'] - E[u_F]

``S_k = C_k P C_k' + R`` the residual covariance, ``P`` the stationary covariance of
``xi = [x; x^-_T'; b^_T'; x^-_F; b^_F]`` (discrete Lyapunov: the truth, both filters and
their uninformative channels' levels ``b^``, driven by w and v),
``m_k(t)`` the residual's deterministic part under the dither (the same system simulated
noise-free to its periodic steady state); a tracked level's innovation ``e_j`` is a state of
the same system, so ``E[u_k]`` is exact in steady state but for the level's jump branch
(probability 1e-3 per frame; counted as ln(1 - eps), which holds while no jump is likely)
and its first frame. When
the models are exact, D(T, F) is the
Kullback-Leibler divergence rate of F's residual density from T's. The bank needs about
``ln(1/p_min)`` nats to lift a hypothesis from the floor, so ``ln(1/p_min) / D`` frames
estimates how long it takes (``frames_to_lift``); ``D <= 0`` means F explains the data at
least as well as T: the two are indistinguishable by this bank whatever the dwell.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_discrete_lyapunov

from .. import names
from ..truth import dither as dither_mod
from .bank import BankDesign

LOG_2PI = float(np.log(2.0 * np.pi))
#: ln(1 - eps), eps the core's probability per frame that a failed sensor's level jumps
#: (steady_state_filter.h kLevelJumpProbability); the jump branch itself is left out.
LOG_STAY = float(np.log1p(-1e-3))


@dataclass(frozen=True)
class ScoredFilter:
    """A filter as the bank scores it: its matrices, Ainv (uninformative channels zeroed), the
    constant of its memoryless uninformative channels and its tracked levels ``(j, g, s, A_jj)``
    (steady_state_filter.h)."""

    phi: np.ndarray
    bd: np.ndarray
    h: np.ndarray
    k: np.ndarray
    a_inv: np.ndarray
    c: float = 0.0
    levels: tuple[tuple[int, float, float, float], ...] = ()


def level_filter(q: float, a_jj: float) -> tuple[float, float]:
    """``(g, s)`` of a level's steady-state scalar Kalman filter (steady_state_filter.h)."""
    p = 0.5 * (q + np.sqrt(q * q + 4.0 * q * a_jj))
    return p / (p + a_jj), p + a_jj


def scored_filter(design: BankDesign, name: str) -> ScoredFilter:
    """Filter ``name`` of ``design`` as the bank scores it (module docstring)."""
    f = design.filter(name)
    a = f.gains.a
    a_inv = np.linalg.inv(a)
    c, levels = 0.0, []
    for j, (width, q) in enumerate(zip(f.model.uninformative_width, f.model.uninformative_level_q)):
        if width > 0.0:
            a_inv[j, :] = 0.0
            a_inv[:, j] = 0.0
            if q > 0.0:
                levels.append((j, *level_filter(float(q), float(a[j, j])), float(a[j, j])))
            else:
                c += 0.5 * (LOG_2PI + np.log(a[j, j])) - np.log(width)
    return ScoredFilter(phi=f.model.phi, bd=f.model.bd, h=f.model.h, k=f.gains.k, a_inv=a_inv, c=c,
                        levels=tuple(levels))


def truth_matrices(design: BankDesign, truth: str) -> tuple[np.ndarray, np.ndarray]:
    """``(Bd_T, H_T)`` of a complete failure ``truth``: failed columns of B_d and rows of H zeroed."""
    bd = np.array(design.discrete.bd, copy=True)
    h = np.array(design.continuous.h, copy=True)
    for comp in names.failed_components(truth):
        if comp in names.ACTUATORS:
            bd[:, names.ACTUATORS.index(comp)] = 0.0
        else:
            h[names.SENSORS.index(comp), :] = 0.0
    return bd, h


def _layout(n: int, filters: list[ScoredFilter]) -> tuple[list[int], list[list[int]], int]:
    """Offsets in xi = [x; x^-_0; levels_0; x^-_1; levels_1; ...]: each filter's state, its levels."""
    at, states, levels = n, [], []
    for f in filters:
        states.append(at)
        at += n
        levels.append(list(range(at, at + len(f.levels))))
        at += len(f.levels)
    return states, levels, at


def _stochastic(phi, q, r, h_t, filters: list[ScoredFilter]) -> list[tuple[np.ndarray, list[float]]]:
    """Stationary residual covariance S_k and level-innovation variances of ``filters`` under
    the truth (discrete Lyapunov of the truth, the filters and their levels, driven by w, v)."""
    n, m = phi.shape[0], r.shape[0]
    states, levels, size = _layout(n, filters)
    big = np.zeros((size, size))
    drive = np.zeros((size, n + m))
    big[:n, :n] = phi
    drive[:n, :n] = np.eye(n)
    for f, s0, lv in zip(filters, states, levels):
        s = slice(s0, s0 + n)
        big[s, :n] = f.phi @ f.k @ h_t
        big[s, s] = f.phi @ (np.eye(n) - f.k @ f.h)
        drive[s, n:] = f.phi @ f.k
        for (j, g, _, _), b in zip(f.levels, lv):  # b^ <- (1 - g) b^ + g z_j
            big[b, :n] = g * h_t[j]
            big[b, b] = 1.0 - g
            drive[b, n + j] = g
    noise = np.zeros((n + m, n + m))
    noise[:n, :n] = q
    noise[n:, n:] = r
    p = solve_discrete_lyapunov(big, drive @ noise @ drive.T)
    out = []
    for f, s0, lv in zip(filters, states, levels):
        c = np.zeros((m, size))
        c[:, :n] = h_t
        c[:, s0:s0 + n] = -f.h
        cov = c @ p @ c.T + r
        e_var = []
        for (j, _, _, _), b in zip(f.levels, lv):  # e = z_j - b^
            ce = np.zeros(size)
            ce[:n] = h_t[j]
            ce[b] = -1.0
            e_var.append(float(ce @ p @ ce + r[j, j]))
        out.append((cov, e_var))
    return out


def _deterministic(phi, bd_t, h_t, filters: list[ScoredFilter], u: np.ndarray,
                   keep: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each filter's residual mean m(t) (keep, m) and level-innovation means (keep, levels) over
    the last ``keep`` frames of the noise-free response to ``u``."""
    n = phi.shape[0]
    x = np.zeros(n)
    xf = [np.zeros(n) for _ in filters]
    lv = [np.zeros(len(f.levels)) for f in filters]
    out = [(np.zeros((keep, h_t.shape[0])), np.zeros((keep, len(f.levels)))) for f in filters]
    for i, ui in enumerate(u):
        z = h_t @ x
        for j, f in enumerate(filters):
            res = z - f.h @ xf[j]
            e = np.array([z[c] for c, _, _, _ in f.levels]) - lv[j]
            if i >= len(u) - keep:
                out[j][0][i - (len(u) - keep)] = res
                out[j][1][i - (len(u) - keep)] = e
            lv[j] = lv[j] + np.array([g for _, g, _, _ in f.levels]) * e
            xf[j] = f.phi @ (xf[j] + f.k @ res) + f.bd @ ui
        x = phi @ x + bd_t @ ui
    return out


def dither_inputs(frames: int, frame_rate_hz: float, spec: dither_mod.DitherSpec | None = None,
                  throttle_at: tuple[float, float] | None = None) -> np.ndarray:
    """(frames, 5) the truth's default dither sampled at the frame rate (rad); with
    ``throttle_at`` (Mach, altitude ft), (frames, 6): the throttle dither a throttle bank flies
    with as the sixth column, its amplitude scheduled at that air data (``truth.dither``),
    about the trim throttle."""
    d = dither_mod.Dither(spec or dither_mod.DitherSpec())
    u = np.array([d.value(i / frame_rate_hz) for i in range(frames)])
    if throttle_at is None:
        return u
    a = dither_mod.scheduled_throttle_amplitude(*throttle_at)
    w = 2.0 * np.pi * dither_mod.SCHEDULED_THROTTLE_FREQUENCY_HZ
    return np.column_stack([u, a * np.sin(w * np.arange(frames) / frame_rate_hz)])


def rates(phi: np.ndarray, q: np.ndarray, r: np.ndarray, bd_t: np.ndarray, h_t: np.ndarray,
          own: ScoredFilter, competitors: list[ScoredFilter], u: np.ndarray | None = None) -> list[float]:
    """D(T, F) in nats per frame for each competitor (module docstring): the truth
    ``(phi, q, r, bd_t, h_t)``, its own filter ``own``, inputs ``u`` (frames, nu) or none."""
    filters = [own] + list(competitors)
    stoch = _stochastic(phi, q, r, h_t, filters)
    m = h_t.shape[0]
    means = (_deterministic(phi, bd_t, h_t, filters, u, keep=len(u) // 2) if u is not None
             else [(np.zeros((1, m)), np.zeros((1, len(f.levels)))) for f in filters])
    score = []  # E[l_k]
    for f, (cov, e_var), (mk, ek) in zip(filters, stoch, means):
        quad = float(np.trace(f.a_inv @ cov)) + float(np.mean(np.einsum("ti,ij,tj->t", mk, f.a_inv, mk)))
        u_k = f.c + sum(LOG_STAY + 0.5 * np.log(a_jj / s) - (ev + float(np.mean(ek[:, i] ** 2))) / (2.0 * s)
                        for i, ((_, _, s, a_jj), ev) in enumerate(zip(f.levels, e_var)))
        score.append(-0.5 * quad + u_k)
    return [score[0] - sc for sc in score[1:]]


def evidence_rates(design: BankDesign, truth: str, competitors: list[str], *, calm: bool = False,
                   dither: bool = True, seconds: float = 20.0) -> dict[str, float]:
    """D(truth, F) in nats per frame for every competitor F named (module docstring), in
    light turbulence (the design's Q_d) or calm air (Q = 0), with or without the dither (and,
    for a bank that models the throttle, the throttle dither; ``seconds`` should then hold
    whole periods of it: the mean is taken over the second half)."""
    bd_t, h_t = truth_matrices(design, truth)
    q = np.zeros_like(design.discrete.qd) if calm else design.discrete.qd
    throttle_at = (design.mach, design.alt_ft) if design.throttle_input else None
    u = (dither_inputs(int(seconds * design.frame_rate_hz), design.frame_rate_hz, throttle_at=throttle_at)
         if dither else None)
    d = rates(design.discrete.phi, q, design.r, bd_t, h_t, scored_filter(design, truth),
              [scored_filter(design, c) for c in competitors], u)
    return dict(zip(competitors, d))


def level1_competitors(first: str, second: str) -> list[str]:
    """The level-1 bank of ``first`` (NONE, first, first + each other) without the dual
    ``first+second`` itself: the hypotheses that dual must win against."""
    dual = names.dual_name(first, second)
    others = [names.dual_name(first, x) for x in names.SINGLE_HYPOTHESES[1:] if x != first]
    return ["NONE", first] + [d for d in others if d != dual]


def frames_to_lift(rate: float, p_min: float) -> float:
    """Frames to gather ln(1/p_min) nats at ``rate`` nats per frame (inf when rate <= 0)."""
    return float("inf") if rate <= 0.0 else float(np.log(1.0 / p_min) / rate)


#: The longitudinal sensors whose dual pairs the table covers.
LONGITUDINAL_SENSORS: tuple[str, ...] = ("VEL", "AOA", "PIT", "AZ")


def dual_table(design: BankDesign, pairs: list[tuple[str, str]], p_min: float) -> list[dict]:
    """Per ordered pair (first, second): the weakest competitor of the dual in the level-1
    bank of ``first`` and D against it, in light turbulence and calm air (dither on), with
    the seconds ``frames_to_lift`` takes at the frame rate."""
    rows = []
    for first, second in pairs:
        truth = names.dual_name(first, second)
        row = {"pair": f"{first}>{second}"}
        for label, calm in (("light", False), ("calm", True)):
            d = evidence_rates(design, truth, level1_competitors(first, second), calm=calm)
            weakest = min(d, key=d.get)
            row[label] = {"rate": d[weakest], "against": weakest,
                          "seconds": frames_to_lift(d[weakest], p_min) / design.frame_rate_hz}
        rows.append(row)
    return rows


def main(argv: list[str] | None = None) -> int:
    """``python -m f16mmae.design.distinguish [--failure-model complete|cover] [--throttle-input]``:
    the table of the longitudinal sensor pairs as Markdown on stdout (``--throttle-input``: the
    bank that models the throttle, with the throttle dither it flies)."""
    import argparse
    import dataclasses

    from .tuning import load_tuning

    p = argparse.ArgumentParser(description=main.__doc__)
    p.add_argument("--failure-model", default="complete", choices=("complete", "cover"))
    p.add_argument("--tuning", default="tuned")
    p.add_argument("--throttle-input", action="store_true",
                   help="the throttle as the sixth modelled input, with its scheduled dither")
    args = p.parse_args(argv)
    tuning = load_tuning(args.tuning)
    tuning = dataclasses.replace(tuning, failure_model=args.failure_model)
    pairs = [(a, b) for a in LONGITUDINAL_SENSORS for b in LONGITUDINAL_SENSORS if a != b]
    from .bank import design_bank

    design = design_bank(tuning=tuning, throttle_input=args.throttle_input)
    p_min = tuning.estimator.get("p_min", 1e-3)
    print(f"failure model {args.failure_model}, tuning {args.tuning}, "
          f"{'throttle input, ' if args.throttle_input else ''}p_min {p_min:g}: "
          f"ln(1/p_min) = {np.log(1 / p_min):.1f} nats to lift a hypothesis from the floor\n")
    print("| pair | light: D (nats/frame) | weakest competitor | s to lift | calm: D | weakest competitor | s to lift |")
    print("|---|---|---|---|---|---|---|")
    for r in dual_table(design, pairs, p_min):
        cells = [r["pair"]]
        for label in ("light", "calm"):
            c = r[label]
            cells += [f"{c['rate']:.3g}", c["against"], "never" if c["seconds"] == float("inf") else f"{c['seconds']:.2f}"]
        print("| " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
