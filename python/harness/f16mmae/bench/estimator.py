"""Benchmark of the MMAE estimator: one frame of the 13-filter F-16-size bank.

One frame (paper Sec. III, Fig. 1), every hypothesis k = 1..K, perturbations from trim:

    r_k  = z - H_k x-_k                      residual
    q_k  = r_k^T A_k^-1 r_k                  quadratic form of eq. 2
    x+_k = x-_k + K_k r_k
    l_k  = -q_k / 2                          log-likelihood, leading term stripped (eq. 2)
    p_k <- exp(l_k + ln p_k - LSE_j(l_j + ln p_j))      Bayes update (eq. 1), log domain
    floor p_min by water-filling (every p_k >= p_min, ratios above the floor kept)
    x-_k <- Phi_k x+_k + Bd_k u              propagation

Four implementations of that frame are timed on the same synthetic bank and data:
(a) the C++ loop alone (``f16mmae.core``, timed in C++), (b) ``FilterBank.step(z, u)``
called from Python once per frame, (c) :class:`NumpyMMAE`, a vectorised numpy reference
that also cross-checks the C++ probabilities (tests/python/test_bench.py), and (d)
filterpy's ``MMAEFilterBank`` (full covariance Kalman filters; optional). The synthetic
bank is F-16 sized (13 states, 5 inputs, 7 measurements): a random stable Phi, and per
hypothesis the failed actuator's Bd column or the failed sensor's H row zeroed, with the
steady-state gain from scipy's discrete algebraic Riccati equation (DARE).
(e) The hierarchical bank (79 filters stored, 13 on line, timed in C++) at 13 states and at
19 (the filters with Dryden gust states, ``f16mmae design --gust-states``), and at 13 states
with 6 inputs (the throttle as the sixth, ``f16mmae design --throttle-input``), and at 13
states and 5 inputs with a cold cache: before every frame a buffer of ``EVICT_BYTES`` is read,
which evicts the bank from the cores' own caches (L1, L2) as the truth model's JSBSim steps do
between two frames of a closed loop; each frame timed alone, the median frame counts; and with
a partial-loss hypothesis per surface (``f16mmae design --partial-loss 0.5``: 18 filters on line
at level 0, the partial hypothesis' Bd column scaled by the effectiveness kept).
"""
from __future__ import annotations

import math
import os
import platform
import sys
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from .. import __version__, core, names
from ..design.hypotheses import parse_partial, partial_hypotheses

#: Process and measurement noise of the synthetic bank (the DARE's Q = q I, R = r I).
#: The estimator's targets: the C++ frame within 1 us, filterpy at least 3000x slower.
TARGET_CPP_US = 1.0
TARGET_FILTERPY_RATIO = 3000.0
Q_SYNTHETIC = 1e-3
R_SYNTHETIC = 1e-2
#: The cold-cache row's buffer, read before every frame: larger than a core's L1 and L2.
EVICT_BYTES = 4 << 20


def synthetic_models(
    hypotheses: tuple[str, ...] = names.SINGLE_HYPOTHESES, seed: int = 1, nx: int = names.NX,
    nu: int = names.NU,
) -> list[tuple[str, dict[str, np.ndarray]]]:
    """An F-16-size bank of proper steady-state filters, one per hypothesis name (``nx``
    states: 13, or 19 as the filters with Dryden gust states; ``nu`` inputs: 5, or 6 with the
    throttle, whose column no hypothesis removes).

    Phi is random with spectral radius 0.97, Bd and H random; a hypothesis fails the
    components it names (``names.failed_components``): an actuator's Bd column or a
    sensor's H row is zeroed. K and A come from the DARE with Q = Q_SYNTHETIC I,
    R = R_SYNTHETIC I. A partial hypothesis (``"LS:loss=0.5"``) scales its surface's Bd column
    by the effectiveness it keeps. Each model is a dict with phi, bd, h, k, a and, for full Kalman
    filters (filterpy), q, r and the a-priori covariance p.
    """
    rng = np.random.default_rng(seed)
    nz = names.NZ
    phi = rng.standard_normal((nx, nx))
    phi *= 0.97 / np.max(np.abs(np.linalg.eigvals(phi)))
    bd = 0.1 * rng.standard_normal((nx, nu))
    h = rng.standard_normal((nz, nx))
    q = Q_SYNTHETIC * np.eye(nx)
    r = R_SYNTHETIC * np.eye(nz)
    models = []
    for name in hypotheses:
        bd_k, h_k = bd.copy(), h.copy()
        partial = parse_partial(name)
        if partial is not None:
            surface, kept = partial
            bd_k[:, names.ACTUATORS.index(surface)] *= kept
        for component in (() if partial is not None else names.failed_components(name)):
            if component in names.ACTUATORS:
                bd_k[:, names.ACTUATORS.index(component)] = 0.0
            else:
                h_k[names.SENSORS.index(component), :] = 0.0
        p = scipy.linalg.solve_discrete_are(phi.T, h_k.T, q, r)
        a = h_k @ p @ h_k.T + r
        a = 0.5 * (a + a.T)
        k = np.linalg.solve(a, h_k @ p).T  # P H^T A^-1 (A symmetric)
        models.append((name, dict(phi=phi.copy(), bd=bd_k, h=h_k, k=k, a=a, q=q, r=r, p=p)))
    return models


def synthetic_bank(hypotheses: tuple[str, ...] = names.SINGLE_HYPOTHESES, seed: int = 1, nx: int = names.NX,
                   nu: int = names.NU):
    """:func:`synthetic_models` as a validated ``core.ModelBank`` (trim at zero, 64 Hz)."""
    return core.ModelBank(
        synthetic_models(hypotheses, seed, nx, nu),
        state_names=names.STATES + tuple(f"gust{i}" for i in range(nx - names.NX)),
        input_names=names.INPUTS_WITH_THROTTLE[:nu],
        measurement_names=names.SENSORS,
        frame_rate_hz=float(names.FRAME_RATE_HZ),
        tuning="synthetic",
        metadata={"generator": "f16mmae.bench.synthetic_models", "seed": seed},
    )


def synthetic_frames(
    models: list[tuple[str, dict[str, np.ndarray]]], n_frames: int, seed: int = 2,
    failed: str = "AOA",
) -> tuple[np.ndarray, np.ndarray]:
    """Measurements z (n_frames, nz) and inputs u (n_frames, nu) of the no-failure model
    driven by process and measurement noise and a small sinusoidal input, with hypothesis
    ``failed``'s model in force for the second half (so the probabilities move)."""
    rng = np.random.default_rng(seed)
    by_name = dict(models)
    nominal, failure = by_name[names.NONE], by_name[failed]
    nx, nu = nominal["bd"].shape
    nz = nominal["h"].shape[0]
    t = np.arange(n_frames) / names.FRAME_RATE_HZ
    u = 0.05 * np.sin(2 * np.pi * np.outer(t, 0.5 + np.arange(nu)))
    z = np.empty((n_frames, nz))
    x = np.zeros(nx)
    sq, sr = math.sqrt(Q_SYNTHETIC), math.sqrt(R_SYNTHETIC)
    for i in range(n_frames):
        m = nominal if i < n_frames // 2 else failure
        z[i] = m["h"] @ x + sr * rng.standard_normal(nz)
        x = m["phi"] @ x + m["bd"] @ u[i] + sq * rng.standard_normal(nx)
    return z, u


class NumpyMMAE:
    """The MMAE frame of the module docstring in vectorised numpy (reference and cross-check).

    ``models``: (name, mapping with phi, bd, h, k, a) pairs; hypothesis 0 presumed at the
    start (p_0 = 1 - (K-1) p_min), states x- = 0. Leading term stripped.
    """

    def __init__(self, models, p_min: float = 0.001):
        mats = [m for _, m in models]
        self.phi = np.stack([m["phi"] for m in mats])
        self.bd = np.stack([m["bd"] for m in mats])
        self.h = np.stack([m["h"] for m in mats])
        self.k = np.stack([m["k"] for m in mats])
        self.a_inv = np.stack([np.linalg.inv(m["a"]) for m in mats])
        n_hyp, nx = self.phi.shape[:2]
        self.p_min = p_min
        self.x_prior = np.zeros((n_hyp, nx))
        self.x_post = np.zeros((n_hyp, nx))
        self.log_p = np.full(n_hyp, math.log(p_min) if p_min > 0 else -np.inf)
        self.log_p[0] = math.log(1.0 - (n_hyp - 1) * p_min)
        self.probabilities = np.exp(self.log_p)

    def step(self, z: np.ndarray, u: np.ndarray) -> np.ndarray:
        r = z - np.einsum("kmn,kn->km", self.h, self.x_prior)
        q = np.einsum("km,kmj,kj->k", r, self.a_inv, r)
        self.x_post = self.x_prior + np.einsum("knm,km->kn", self.k, r)
        self.residuals = r
        a = -0.5 * q + self.log_p
        log_p = a - (a.max() + math.log(np.exp(a - a.max()).sum()))
        self.probabilities, self.log_p = _floor(np.exp(log_p), log_p, self.p_min)
        self.blended_state = self.probabilities @ self.x_post
        self.z_hat = self.h[0] @ self.blended_state
        self.x_prior = np.einsum("kij,kj->ki", self.phi, self.x_post) + self.bd @ u
        return self.probabilities


def _floor(p: np.ndarray, log_p: np.ndarray, p_min: float) -> tuple[np.ndarray, np.ndarray]:
    """Water-filling floor: set the hypotheses below p_min to p_min and rescale the rest to
    1 - n_floor p_min, until no rescaled one falls below p_min."""
    floored = np.zeros(p.shape, dtype=bool)
    scale = 1.0
    for _ in range(p.size + 1):
        scale = (1.0 - floored.sum() * p_min) / p[~floored].sum()
        below = ~floored & (p * scale < p_min)
        if not below.any():
            break
        floored |= below
    p_out = np.where(floored, p_min, p * scale)
    log_out = np.where(floored, math.log(p_min) if p_min > 0 else -np.inf, log_p + math.log(scale))
    return p_out, log_out


def filterpy_bank(models, p_min: float = 0.001):
    """filterpy's MMAEFilterBank of full Kalman filters on the same models (F, B, H, Q, R,
    started at the DARE covariance), or None if filterpy is not installed."""
    try:
        from filterpy.kalman import KalmanFilter, MMAEFilterBank
    except ImportError:
        return None
    filters = []
    for _, m in models:
        nx, nu = m["bd"].shape
        kf = KalmanFilter(dim_x=nx, dim_z=m["h"].shape[0], dim_u=nu)
        kf.F, kf.B, kf.H, kf.Q, kf.R, kf.P = m["phi"], m["bd"], m["h"], m["q"], m["r"], m["p"].copy()
        filters.append(kf)
    p0 = np.full(len(models), p_min)
    p0[0] = 1.0 - (len(models) - 1) * p_min
    return MMAEFilterBank(filters, p0, dim_x=models[0][1]["phi"].shape[0])


@dataclass
class BenchResult:
    """Per-frame costs in microseconds (None: not measured) and the run's parameters."""

    frames: int
    bank_hash: str = ""
    cpp_loop_us: float | None = None
    #: (a) with the turbulence adaptation on (cpp/f16mmae/turbulence_adaptation.h)
    cpp_loop_adaptive_us: float | None = None
    #: the hierarchical bank (79 filters stored, 13 on line), 13 and 19 states (gust states)
    hierarchical_us: float | None = None
    hierarchical_gust_us: float | None = None
    #: the hierarchical bank, 13 states and 6 inputs (the throttle)
    hierarchical_throttle_us: float | None = None
    #: the hierarchical bank with a partial-loss hypothesis per surface (18 filters at level 0)
    hierarchical_partial_us: float | None = None
    #: a turbulence bank set of 4 members of 19 states and 6 inputs (cpp/f16mmae/turbulence_bank_set.h),
    #: one member in force; and with a standby running beside it all along
    bank_set_us: float | None = None
    bank_set_standby_us: float | None = None
    #: (e) at 13 states with the cache evicted before every frame (EVICT_BYTES)
    hierarchical_cold_us: float | None = None
    python_call_us: float | None = None
    numpy_us: float | None = None
    filterpy_us: float | None = None
    max_probability_difference: float | None = None  # numpy reference vs C++, all frames
    notes: list[str] = field(default_factory=list)

    def ratios(self) -> dict[str, float]:
        """Speed-ups: slower implementation's cost over the faster one's."""
        out = {}
        pairs = [
            ("filterpy / cpp_loop", self.filterpy_us, self.cpp_loop_us),
            ("filterpy / python_call", self.filterpy_us, self.python_call_us),
            ("numpy / cpp_loop", self.numpy_us, self.cpp_loop_us),
            ("numpy / python_call", self.numpy_us, self.python_call_us),
            ("python_call / cpp_loop", self.python_call_us, self.cpp_loop_us),
            ("cpp_loop_adaptive / cpp_loop", self.cpp_loop_adaptive_us, self.cpp_loop_us),
            ("hierarchical 19 states / 13 states", self.hierarchical_gust_us, self.hierarchical_us),
            ("hierarchical 6 inputs / 5 inputs", self.hierarchical_throttle_us, self.hierarchical_us),
            ("hierarchical 18 filters (partial loss) / 13", self.hierarchical_partial_us, self.hierarchical_us),
            ("hierarchical cold / hot", self.hierarchical_cold_us, self.hierarchical_us),
            ("bank set / hierarchical 19 states", self.bank_set_us, self.hierarchical_gust_us),
            ("bank set with a standby / without", self.bank_set_standby_us, self.bank_set_us),
        ]
        for label, slow, fast in pairs:
            if slow is not None and fast:
                out[label] = slow / fast
        return out


def _time_per_frame(step, z: np.ndarray, u: np.ndarray, min_time_s: float, min_passes: int = 3) -> float:
    """Microseconds per frame of ``step(z_i, u_i)``: the frames are replayed pass after pass
    for at least ``min_time_s`` and ``min_passes`` passes; the fastest pass counts (the
    least disturbed by other load on the machine)."""
    best, start, passes = math.inf, time.perf_counter(), 0
    while passes < min_passes or time.perf_counter() - start < min_time_s:
        t0 = time.perf_counter()
        for zi, ui in zip(z, u):
            step(zi, ui)
        best = min(best, time.perf_counter() - t0)
        passes += 1
    return best / len(z) * 1e6


def core_filter_bank(models, p_min: float = 0.001):
    """``core.FilterBank`` of the models (the C++ bank called from Python)."""
    return core.FilterBank(
        [core.FilterModel(**{key: m[key] for key in ("phi", "bd", "h", "k", "a")}) for _, m in models],
        p_min=p_min,
    )


def max_probability_difference(models, z: np.ndarray, u: np.ndarray) -> float:
    """Largest |p_numpy - p_C++| over every hypothesis and frame, both from the start."""
    cpp, reference = core_filter_bank(models), NumpyMMAE(models)
    return max(float(np.max(np.abs(cpp.step(zi, ui) - reference.step(zi, ui)))) for zi, ui in zip(z, u))


def run_bench(frames: int = 2000, min_time_s: float = 0.2, seed: int = 1) -> BenchResult:
    """Times (a)-(d) of the module docstring on ``frames`` synthetic frames."""
    models = synthetic_models(seed=seed)
    bank = synthetic_bank(seed=seed)
    z, u = synthetic_frames(models, frames, seed=seed + 1)
    result = BenchResult(frames=frames, bank_hash=bank.content_hash)

    result.cpp_loop_us = core._bench_filter_bank_loop(bank, z, u, min_time_s) * 1e6
    result.cpp_loop_adaptive_us = core._bench_filter_bank_loop(bank, z, u, min_time_s, adapt_turbulence=True) * 1e6

    for nx, nu, attr in ((names.NX, names.NU, "hierarchical_us"), (names.NX + 6, names.NU, "hierarchical_gust_us"),
                         (names.NX, names.NU + 1, "hierarchical_throttle_us")):
        stored = synthetic_bank(names.ALL_HYPOTHESES, seed=seed, nx=nx, nu=nu)
        zh, uh = synthetic_frames(synthetic_models(names.SINGLE_HYPOTHESES, seed, nx, nu), frames, seed=seed + 1)
        setattr(result, attr, core._bench_hierarchical_loop(stored, zh, uh, min_time_s=min_time_s)[0] * 1e6)
        if attr == "hierarchical_us":
            result.hierarchical_cold_us = core._bench_hierarchical_loop(
                stored, zh, uh, min_time_s=min_time_s, evict_bytes=EVICT_BYTES)[0] * 1e6
    partials = partial_hypotheses([0.5])
    stored = synthetic_bank(names.SINGLE_HYPOTHESES + partials + names.DUAL_HYPOTHESES, seed=seed)
    zh, uh = synthetic_frames(synthetic_models(names.SINGLE_HYPOTHESES + partials, seed), frames, seed=seed + 1)
    result.hierarchical_partial_us = core._bench_hierarchical_loop(stored, zh, uh, min_time_s=min_time_s)[0] * 1e6

    # the turbulence bank set: 4 members of the set's sizes; bounds that keep member 0 in force, then
    # bounds that want member 1 all along with a hold longer than the frames (a standby throughout)
    stored = synthetic_bank(names.ALL_HYPOTHESES, seed=seed, nx=names.NX + 6, nu=names.NU + 1)
    zh, uh = synthetic_frames(synthetic_models(names.SINGLE_HYPOTHESES, seed, names.NX + 6, names.NU + 1), frames,
                              seed=seed + 1)
    result.bank_set_us = core._bench_bank_set_loop([stored] * 4, zh, uh, [1e3, 2e3, 3e3] * 4, [1.0] * 4,
                                                   min_time_s=min_time_s)[0] * 1e6
    result.bank_set_standby_us = core._bench_bank_set_loop([stored] * 4, zh, uh, [1e-9, 1e3, 2e3] + [1e3, 2e3, 3e3] * 3,
                                                           [1.0] * 4, hold_s=600.0, min_time_s=min_time_s)[0] * 1e6
    result.python_call_us = _time_per_frame(core_filter_bank(models).step, z, u, min_time_s)
    result.max_probability_difference = max_probability_difference(models, z, u)

    result.numpy_us = _time_per_frame(NumpyMMAE(models).step, z, u, min_time_s)

    fp = filterpy_bank(models)
    if fp is None:
        result.notes.append("filterpy not installed (pip install filterpy, or the 'bench' extra)")
    else:
        def filterpy_step(zi, ui):
            fp.predict(ui[:, None])  # filterpy states are columns
            fp.update(zi)

        n_fp = min(frames, 50)  # filterpy is slow per frame: 3 passes of 50 frames suffice
        result.filterpy_us = _time_per_frame(filterpy_step, z[:n_fp], u[:n_fp], 0.0)
    return result


def report(result: BenchResult, stream) -> dict:
    """Print the table, ratios, cross-check and targets of ``result``; return its JSON record
    (the numbers, the targets and :func:`machine_info`)."""
    rows = [
        ("(a) C++ loop, F16FilterBank.step", result.cpp_loop_us),
        ("(a') (a) + turbulence adaptation", result.cpp_loop_adaptive_us),
        ("(e) C++ hierarchical bank, 13 states", result.hierarchical_us),
        ("(e') (e), 19 states (gust states)", result.hierarchical_gust_us),
        ("(e'') (e), 6 inputs (throttle)", result.hierarchical_throttle_us),
        ("(e''') (e), cold cache every frame", result.hierarchical_cold_us),
        ("(e4) (e), 18 filters (partial loss)", result.hierarchical_partial_us),
        ("(f) turbulence bank set, 19 st. 6 in.", result.bank_set_us),
        ("(f') (f) with a standby beside", result.bank_set_standby_us),
        ("(b) Python call, bank.step(z, u)", result.python_call_us),
        ("(c) numpy reference", result.numpy_us),
        ("(d) filterpy MMAEFilterBank", result.filterpy_us),
    ]
    print(f"f16mmae bench estimator: one MMAE frame, 13 filters x (13 states, 5 inputs, 7 measurements); "
          f"synthetic bank {result.bank_hash[:12]}, {result.frames} frames, f16mmae {__version__}", file=stream)
    print(f"  {'implementation':36s} {'us/frame':>12s} {'frames/s':>12s}", file=stream)
    for label, us in rows:
        if us is None:
            print(f"  {label:36s} {'-':>12s} {'-':>12s}", file=stream)
        else:
            print(f"  {label:36s} {us:12.3f} {1e6 / us:12.0f}", file=stream)
    ratios = result.ratios()
    if ratios:
        print("  ratios: " + ", ".join(f"{k} = {v:,.1f}x" for k, v in ratios.items()), file=stream)
    print(f"  cross-check: max |p_numpy - p_C++| over {result.frames} frames = "
          f"{result.max_probability_difference:.1e}", file=stream)
    met = targets(result)
    for name, t in met.items():
        print(f"  target {name}: {'met' if t['met'] else 'NOT met'} ({t['measured']:,.3f} vs {t['target']:,})",
              file=stream)
    for note in result.notes:
        print(f"  note: {note}", file=stream)
    return {
        "f16mmae_version": __version__,
        "machine": machine_info(),
        "frames": result.frames,
        "bank_hash": result.bank_hash,
        "us_per_frame": {
            "cpp_loop": result.cpp_loop_us, "cpp_loop_adaptive": result.cpp_loop_adaptive_us,
            "hierarchical": result.hierarchical_us, "hierarchical_gust": result.hierarchical_gust_us,
            "hierarchical_throttle": result.hierarchical_throttle_us, "hierarchical_cold": result.hierarchical_cold_us,
            "hierarchical_partial": result.hierarchical_partial_us,
            "bank_set": result.bank_set_us, "bank_set_standby": result.bank_set_standby_us,
            "python_call": result.python_call_us,
            "numpy": result.numpy_us, "filterpy": result.filterpy_us,
        },
        "ratios": ratios,
        "max_probability_difference": result.max_probability_difference,
        "targets": met,
        "notes": result.notes,
    }


def targets(result: BenchResult) -> dict:
    """Each target of the estimator: its value, what was measured, whether it is met."""
    out = {}
    if result.cpp_loop_us is not None:
        out["cpp_loop_us <= 1"] = {"target": TARGET_CPP_US, "measured": result.cpp_loop_us,
                                   "met": result.cpp_loop_us <= TARGET_CPP_US}
    ratio = result.ratios().get("filterpy / cpp_loop")
    if ratio is not None:
        out["filterpy / cpp_loop >= 3000"] = {"target": TARGET_FILTERPY_RATIO, "measured": ratio,
                                              "met": ratio >= TARGET_FILTERPY_RATIO}
    return out


def machine_info() -> dict:
    """Where the numbers were measured."""
    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), cpu)
    except OSError:
        pass
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:
        cores = os.cpu_count()
    return {
        "cpu": cpu, "cores": cores, "platform": platform.platform(),
        "python": sys.version.split()[0], "numpy": np.__version__,
    }
