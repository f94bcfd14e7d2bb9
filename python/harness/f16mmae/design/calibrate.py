"""How the ``tuned`` pseudonoise was found: from measurements against the nonlinear truth,
not by guessing (paper Sec. V), in two stages -- stage 1 here (residual consistency of the
no-failure filter), stage 2 in ``convergence.py`` (probability convergence of the bank).

Stage 1 (``calibrate``), deterministic for given flights:

1. Fly the full truth model with no failure (``flights.fly_closed_loop``: light turbulence,
   the truth's default dither, FCS on raw sensor feedback so no estimator is in the loop,
   seeds 1..8, 8 s) and keep the (u, z) perturbation records.
2. Design the NONE filter with the current tuning, run it over the records, and measure per
   channel c the ratio ``var(r_c) / A_cc`` (1 when the filter is matched).
3. Move each channel's knob toward ratio 1:
   AOA -> method 1 ``Q_dalpha``, PIT -> method 1 ``Q_dq``; AY -> method 3 ``Q_dbeta``,
   ROL -> method 3 ``Q_dp``, YAW -> method 3 ``Q_dr`` (the excess is correlated in time --
   un-modelled rotational turbulence, gust dynamics and coupling disturbing the states -- so
   it goes on the states, which keeps the residuals whiter than R pseudonoise would);
   VEL, AZ -> method 2 ``R`` entries (used only if their ratio exceeds 1).
   A Q knob is scaled by ``ratio^2`` (ratio clipped to [0.1, 10]; a zero knob starts at a
   tenth of the excess); an R knob gets ``(ratio - 1) A_cc`` added (floored at 0).
   Channels already at or below 1 with a zero knob are left alone (pseudonoise only adds).
4. Repeat a fixed number of iterations (12); the final values, rounded to two significant
   digits, go into ``design/tunings/tuned.toml`` together with the statistics before and
   after (``render_toml``).

Run it: ``python -m f16mmae.design.calibrate`` prints the tables and the TOML;
``python -m f16mmae.design.calibrate --write`` rewrites ``design/tunings/tuned.toml`` and
regenerates the shipped nominal banks ``data/nominal_{tuned,untuned}.f16bank`` (~3 s) --
the one command to run after the truth model changes; ``--banks`` only regenerates the banks
from the committed tunings (after a change of the bank-file format) (tests/python/test_design_bank.py and
test_design_calibrate.py say when it is due).
"""
from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from .. import names
from ..seeds import TUNING_FLIGHT_SEEDS
from . import convergence
from .bank import design_bank, nominal_bank_path, write_bank
from .flights import fly_closed_loop
from .model import linearize_truth
from .residuals import ResidualStats, filter_residuals, residual_stats
from .tuning import TUNINGS_DIR, Tuning, load_tuning

#: Sensor channel -> (tuning field, key) of the knob that absorbs its residual excess.
KNOBS: dict[str, tuple[str, str]] = {
    "VEL": ("r_pseudonoise", "VEL"),
    "AOA": ("qd_longitudinal", "alpha_rad"),
    "PIT": ("qd_longitudinal", "q_rad_s"),
    "AZ": ("r_pseudonoise", "AZ"),
    "ROL": ("qd_lateral", "p_rad_s"),
    "YAW": ("qd_lateral", "r_rad_s"),
    "AY": ("qd_lateral", "beta_rad"),
}
#: Ratios within this band count as matched (no change).
TOLERANCE = 0.05
#: KNOBS with AOA's excess on its measurement (method 2 ``R`` AOA) instead of the alpha state:
#: the knobs ``calibrate_node`` falls back to where the alpha-state knob misfits the channels'
#: correlation (JOINT_NIS_LIMIT).
KNOBS_AOA_ON_R: dict[str, tuple[str, str]] = {**KNOBS, "AOA": ("r_pseudonoise", "AOA")}
#: The NONE filter's joint fit a node's calibration must reach with KNOBS: its mean normalised
#: innovation squared per channel, NIS / m = mean(r^T A^-1 r) / m (1 when matched).  The
#: per-channel ratios var/A see only A's diagonal; pseudonoise on the alpha state also raises
#: A's AZ entry and its AOA-AZ correlation through the lift, and at Mach 0.30-0.40 / 10,000 ft
#: the 5x alpha-state noise the ratios ask for gives A an AOA-AZ correlation of +0.8 where the
#: residuals have -0.1 to -0.3: the direction AOA - AZ carries 4x the power A gives it,
#: NIS / m 1.3 (docs/results/envelope_tuning.md, round 10).
JOINT_NIS_LIMIT = 1.2


def none_filter_stats(tuning: Tuning, flights, linearized) -> ResidualStats:
    """Residual statistics of the NONE filter of ``tuning`` over ``flights`` (first second
    of each dropped: the filter starts at x = 0 while the dither starts)."""
    d = design_bank(tuning=tuning, linearized=linearized, hypotheses=(names.NONE,))
    f = d.filters[0]
    res = [filter_residuals(f.model.phi, f.model.bd, f.model.h, f.gains.k, fl.u, fl.z)
           [names.FRAME_RATE_HZ:] for fl in flights]
    return residual_stats(res, f.gains.a)


def _round2(x: float) -> float:
    return float(f"{x:.2g}") if x > 0.0 else 0.0


def calibrate(base: Tuning, flights, linearized, iterations: int = 12,
              name: str = "tuned", knobs: dict[str, tuple[str, str]] = KNOBS) -> tuple[Tuning, list[ResidualStats]]:
    """Adjust ``base``'s knobs (``knobs``: channel -> (tuning field, key), KNOBS unless given)
    toward var/A = 1; returns the tuning (rounded to two significant digits) and the statistics
    after each iteration (first = ``base``)."""
    tun = dataclasses.replace(base, name=name)
    history = []
    for it in range(iterations + 1):
        st = none_filter_stats(tun, flights, linearized)
        history.append(st)
        if it == iterations:
            break
        d = design_bank(tuning=tun, linearized=linearized, hypotheses=(names.NONE,))
        a_diag = np.diag(d.filters[0].gains.a)
        fields = {f: dict(getattr(tun, f)) for f in ("r_pseudonoise", "qd_longitudinal", "qd_lateral")}
        for c, (field, key) in knobs.items():
            i = names.SENSORS.index(c)
            ratio = float(st.var_over_a[i])
            if abs(ratio - 1.0) <= TOLERANCE:
                continue
            cur = fields[field].get(key, 0.0)
            if field == "r_pseudonoise":
                new = max(cur + (ratio - 1.0) * a_diag[i], 0.0)
            elif cur > 0.0:
                new = cur * min(max(ratio, 0.1), 10.0) ** 2
            elif ratio > 1.0:  # first step: a tenth of the excess, as a per-frame variance
                new = 0.1 * (ratio - 1.0) * a_diag[i]
            else:
                continue
            fields[field][key] = new
        tun = dataclasses.replace(tun, **fields)
    rounded = {f: {k: _round2(v) for k, v in getattr(tun, f).items() if _round2(v) > 0}
               for f in ("r_pseudonoise", "qd_longitudinal", "qd_lateral")}
    tun = dataclasses.replace(tun, **rounded)
    history.append(none_filter_stats(tun, flights, linearized))
    return tun, history


SEEDS = TUNING_FLIGHT_SEEDS  # the tuning namespace (f16mmae.seeds): 1-8
#: The tuning calibrated for the filters with Dryden gust states (``--gust-states``).
GUST_TUNING = "tuned_gust"


def render_toml(tun: Tuning, before: ResidualStats, stage1: ResidualStats, after: ResidualStats,
                conv: list[dict], seeds=SEEDS) -> str:
    """The ``tuned.toml`` text: how it was found, the statistics, the knobs."""
    def row(label, vals):
        return f"#   {label:<15}" + " ".join(f"{v:6.2f}" for v in vals)

    cases = " ".join(names.SINGLE_HYPOTHESES)
    first, chosen = conv[0], [r for r in conv if r["kept"]][-1]
    stage2 = "\n".join(f"#   {r['step']:<16} J {r['J']:.3f}{'  <- kept' if r['kept'] else ''}"
                       for r in conv)
    head = f"""\
# The project's tuned design (paper Sec. V pseudonoise; methods 1-4 are all available, the
# calibration below decides which knobs are non-zero -- method 4 is not used, as in the
# paper's final design).  GENERATED by `python -m f16mmae.design.calibrate --write` -- edit
# the procedure there (design/calibrate.py, design/convergence.py), not the numbers here.
#
# How it was found -- from measurements against the nonlinear truth, not by guessing.
# Stage 1, residual consistency: the NONE filter of the `untuned` design (light-turbulence
# zero-order Dryden gusts + sensor noise only) was run on {len(seeds)} no-failure flights of the
# full truth model at Mach 0.4 / 20,000 ft (light turbulence, the truth's default dither, FCS
# on RAW sensor feedback so no estimator is in the loop; seeds {seeds[0]}-{seeds[-1]}, 8 s each, first
# second dropped; design/flights.py fly_closed_loop), {after.frames} frames.  Per channel
# (VEL AOA PIT AZ ROL YAW AY), var(r)/A_kk (1 = matched) and lag-1 autocorrelation:
#
{row("untuned var/A", before.var_over_a)}    NIS mean {before.nis_mean:.2f} (m = 7)
{row("        rho(1)", before.lag1_autocorr)}
{row("stage 1 var/A", stage1.var_over_a)}    NIS mean {stage1.nis_mean:.2f}
{row("        rho(1)", stage1.lag1_autocorr)}
{row("tuned   var/A", after.var_over_a)}    NIS mean {after.nis_mean:.2f}
{row("        rho(1)", after.lag1_autocorr)}
#
# Stage 1 knobs (design/calibrate.py KNOBS): the excess of AOA and PIT went into Q_d on alpha
# and q (method 1), of AY, ROL and YAW into Q_d on beta, p and r (method 3; Q_dr is the
# paper's method-3 knob) -- it is correlated in time (un-modelled rotational turbulence, gust
# dynamics, coupling), a disturbance of the states; VEL and AZ would get R pseudonoise
# (method 2) only if their ratio exceeded 1.  12 iterations toward var/A = 1, then rounded to
# two significant digits.
#
# Stage 2, probability convergence (design/convergence.py, the paper's criterion): J = mean
# over the cases {cases} (complete failures at 3 s; seeds {convergence.NONE_SEEDS[0]}-{convergence.NONE_SEEDS[-1]} no-failure,
# {convergence.FAILURE_SEEDS[0]}-{convergence.FAILURE_SEEDS[-1]} per failure) of the fraction of frames in which the true hypothesis
# holds the largest probability (core.FilterBank, p_min {convergence.P_MIN:g}; failures scored from {convergence.SETTLE_S:g} s
# after onset).  The channel whose residuals
# gave wrong hypotheses their lead got R pseudonoise (method 2) from a grid (kept when J
# rose by >= {convergence.MIN_GAIN}):
{stage2}
#   per case at the start: {" ".join(f"{k} {v:.2f}" for k, v in first["per_case"].items())}
#   per case, tuned:       {" ".join(f"{k} {v:.2f}" for k, v in chosen["per_case"].items())}
# The report (`f16mmae design --report DIR`) checks all this on other seeds.
"""
    def value(v):   # a number, or an inline table of numbers (the evidence dwell's N_k by name)
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {x:.1f}" for k, x in v.items()) + "}"
        return f"{v:.2g}"

    def section(title, comment, values):
        body = "".join(f"{k} = {value(v)}\n" for k, v in values.items()) or "# none\n"
        return f"\n[{title}]   # {comment}\n{body}"

    return (head
            + f'name = "{tun.name}"\n'
            + 'description = "pseudonoise from residual consistency and probability convergence '
              'measured against the nonlinear truth (design/calibrate.py, convergence.py)"\n'
            + f'turbulence = "{tun.turbulence}"\ngust_model = "{tun.gust_model}"\n'
            + section("method1_qd_longitudinal", "added to diag(Q_d), per frame, (state unit)^2",
                      tun.qd_longitudinal)
            + section("method2_r", "added to diag(R), (sensor unit)^2", tun.r_pseudonoise)
            + section("method3_qd_lateral", "added to diag(Q_d), per frame, (state unit)^2",
                      tun.qd_lateral)
            + section("method4_actuator_q", "white-noise strength (rad^2/s) through a B column, "
                      "eqs. 6-7", tun.actuator_q)
            + section("estimator", "recommended estimator settings (design/convergence.py "
                      "ESTIMATOR; dwell_nats_per_hypothesis: tools/latency/dwell_per_hypothesis.py), "
                      "stored as the bank's typed fields", tun.estimator))


def run_calibration(lin=None, gust_model: str = "gust_rate") -> tuple[Tuning, list[ResidualStats], list[dict]]:
    """The calibration of ``tuned.toml`` at the nominal point: stage 1 (residual consistency,
    from the untuned base) then stage 2 (probability convergence, ``convergence.py``).
    ``gust_model``: the base's (``dryden_states``: ``tuned_gust.toml``, the filters with
    Dryden gust states). Returns the tuning, stage 1's statistics history and stage 2's
    candidate records."""
    lin = lin if lin is not None else linearize_truth(0.4, 20_000.0)
    base = dataclasses.replace(load_tuning("untuned"), gust_model=gust_model)
    flights = [fly_closed_loop(0.4, 20_000.0, seed=s, turbulence_level=base.turbulence) for s in SEEDS]
    tun, hist = calibrate(base, flights, lin, name=GUST_TUNING if gust_model == "dryden_states" else "tuned")
    tun, conv = convergence.tune_convergence(tun, lin, convergence.case_flights(
        0.4, 20_000.0, base.turbulence))
    hist.append(none_filter_stats(tun, flights, lin))
    # the evidence dwell per hypothesis is derived from flights of the shipped bank
    # (tools/latency/dwell_per_hypothesis.py --tuning): the committed tuning's is kept; derive
    # it again after a recalibration
    kept = {k: v for k, v in load_tuning(tun.name).estimator.items() if k == "dwell_nats_per_hypothesis"} \
        if (TUNINGS_DIR / f"{tun.name}.toml").is_file() else {}
    tun = dataclasses.replace(tun, estimator={**convergence.ESTIMATOR, **kept})
    return tun, hist, conv


#: Name every node's calibrated tuning carries (the schedule file requires one tuning name
#: over its nodes; the per-node knobs are listed in the schedule's metadata).
NODE_TUNING_SUFFIX = "@node"


#: The length (s) of a node's calibration flights (``node_flights``).
NODE_FLIGHT_S = 8.0


def node_flights(mach: float, alt_ft: float, turbulence: str, duration_s: float = NODE_FLIGHT_S) -> list:
    """The no-failure tuning flights (seeds ``SEEDS``, raw feedback, ``duration_s`` each) at one
    design point. A longer flight starts as the shorter one with the same seed."""
    return [fly_closed_loop(mach, alt_ft, seed=s, turbulence_level=turbulence, duration_s=duration_s) for s in SEEDS]


def calibrate_node(mach: float, alt_ft: float, base: Tuning, linearized=None,
                   iterations: int = 12, flights=None) -> tuple[Tuning, ResidualStats, ResidualStats]:
    """Stage 1 at one design point of a schedule: fly the no-failure tuning flights (seeds
    ``SEEDS``, light turbulence, raw feedback) at (mach, alt_ft) and move ``base``'s knobs
    (KNOBS) toward var/A = 1 there, as ``calibrate`` does at the nominal point.

    Stage 2 is not repeated per node: at the nominal point it kept no candidate (tuned.toml),
    and its 44 flights per node would dominate the design time.  ``base``'s estimator
    settings are kept.  Returns the node's tuning (named ``base.name + NODE_TUNING_SUFFIX``),
    and the NONE filter's residual statistics under ``base`` and under the result.
    ``flights``: ``node_flights(mach, alt_ft, base.turbulence)`` if already flown.
    Deterministic for given (mach, alt_ft, base)."""
    lin = linearized if linearized is not None else linearize_truth(mach, alt_ft)
    flights = flights if flights is not None else node_flights(mach, alt_ft, base.turbulence)
    tun, hist = calibrate(base, flights, lin, iterations=iterations, name=base.name + NODE_TUNING_SUFFIX)
    if hist[-1].nis_mean / names.NZ > JOINT_NIS_LIMIT:
        alt_tun, alt_hist = calibrate(base, flights, lin, iterations=iterations,
                                      name=base.name + NODE_TUNING_SUFFIX, knobs=KNOBS_AOA_ON_R)
        if alt_hist[-1].nis_mean < hist[-1].nis_mean:
            tun, hist = alt_tun, alt_hist
    return tun, hist[0], hist[-1]


def adaptation_reference(design, flights) -> float:
    """The turbulence adaptation's reference rho_0 for a bank (cpp/f16mmae/turbulence_adaptation.h):
    the mean over ``flights``' frames (first second of each dropped) of min_k q_k / m, the
    quadratic forms of the level-0 hypotheses (NONE and the single failures) run as one
    core.FilterBank over the records -- the power ratio the adaptation reads in the turbulence
    the flights were flown in, so that it tempers only above it.  Rounded to 3 digits."""
    from .. import core

    models = [core.FilterModel(phi=f.model.phi, bd=f.model.bd, h=f.model.h, k=f.gains.k, a=f.gains.a)
              for f in design.filters if f.name in names.SINGLE_HYPOTHESES]
    if len(models) != names.K_BANK:
        raise ValueError(f"adaptation_reference needs the {names.K_BANK} level-0 filters, the design has {len(models)}")
    bank = core.FilterBank(models)
    ratios = []
    for fl in flights:
        bank.reset()
        for i in range(len(fl.z)):
            bank.update(fl.z[i])
            if i >= names.FRAME_RATE_HZ:
                ratios.append(float(np.min(bank.quadratic_forms)) / names.NZ)
            bank.propagate(fl.u[i])
    return round(float(np.mean(ratios)), 3)


def measured_power_ratio(model_bank, flights) -> float:
    """The mean over ``flights``' frames (first second of each dropped) of the turbulence
    adaptation's measured power ratio rho-bar (cpp/f16mmae/turbulence_adaptation.h) as the scheduled
    estimator reads it: ``model_bank``'s level-0 hypotheses, each filter's residual power per
    channel it reads but ``names.SCHEDULE_ADAPT_COUNTED_CHANNEL`` (``--adapt-own-channels``, the
    scheduled default), no declaration (the dwell longer than a flight). Rounded to 3 digits."""
    from .. import core

    counted = 1 << names.SENSORS.index(names.SCHEDULE_ADAPT_COUNTED_CHANNEL)
    bank = core.HierarchicalBank(model_bank, adapt_turbulence=True, adapt_own_channels=True,
                                 adapt_counted_channels=counted, dwell_s=float(core.MAX_DWELL_S))
    ratios = []
    for fl in flights:
        bank.reset()
        u, z = absolute_frames(model_bank, fl)
        for i in range(len(z)):
            bank.step(z[i], u[i])
            if i >= names.FRAME_RATE_HZ:
                ratios.append(float(bank.measured_power_ratio))
    return round(float(np.mean(ratios)), 3)


def calm_reference(model_bank, calm_flights, light_flights) -> tuple[float, float, float]:
    """A node's calm-air reference (cpp/f16mmae/calm_air_complete.h, bank_schedule.h): the measured
    power ratio midway between its no-failure flights in calm air and in light turbulence
    (``measured_power_ratio``), with the two means."""
    calm, light = measured_power_ratio(model_bank, calm_flights), measured_power_ratio(model_bank, light_flights)
    return round(0.5 * (calm + light), 3), calm, light


#: The turbulence adaptation's per-node reference bounded by false alarms (``bounded_reference``):
#: candidates from REFERENCE_RANGE[0] to REFERENCE_RANGE[1] in steps of REFERENCE_STEP, and the
#: bound on the peak failure log-odds of the calibration flights (REFERENCE_LOG_ODDS_BOUND).
REFERENCE_RANGE: tuple[float, float] = (0.30, 1.00)
REFERENCE_STEP = 0.02
REFERENCE_LOG_ODDS_BOUND = -6.0


def absolute_frames(model_bank, flight) -> tuple[np.ndarray, np.ndarray]:
    """``(u, z)`` of a flight's records (perturbations from trim) as the estimator reads them:
    plus the bank's trim; a bank with more inputs than the flight (the throttle) holds them at
    trim."""
    u_trim, z_trim = np.asarray(model_bank.u_trim), np.asarray(model_bank.z_trim)
    nu = min(flight.u.shape[1], u_trim.size)
    u = np.tile(u_trim, (len(flight.u), 1))
    u[:, :nu] += flight.u[:, :nu]
    return u, flight.z + z_trim


def failure_log_odds_peak(model_bank, flights, reference: float, scales: list | None = None,
                          start_up_s: float = 0.0, running_start: bool = False) -> float:
    """The largest failure log-odds ``max_t max_(k != NONE) ln(p_k / p_NONE)`` over ``flights``
    (no-failure records, perturbations from the bank's trim) of the estimator the bank makes
    (core.HierarchicalBank with the bank's settings and the turbulence adaptation on at
    ``reference``), run over them from its start state; +inf if it declared a failure.
    ``ln(p_min / (1 - 12 p_min))`` (about -20.7 at p_min 1e-9) is the floor; a declaration
    needs more than ``ln(threshold / (1 - threshold))`` (2.2 at 0.9) for the dwell.
    ``scales``: a list that receives the likelihood scale s the adaptation holds at every frame
    after each flight's first second.  ``start_up_s``: the estimator's start-up (the first
    round(64 start_up_s) frames of each flight weigh no hypothesis; ``--start-up-s``), as it
    will fly.  ``running_start``: the adaptation's power ratio a running mean from the start
    (``--adapt-running-start``), as it will fly."""
    from .. import core

    settings = dict(model_bank.estimator_settings)
    bank = core.HierarchicalBank(model_bank, adapt_turbulence=True, adapt_reference=float(reference),
                                 start_up_s=float(start_up_s), adapt_running_start=bool(running_start), **settings)
    peak = -np.inf
    for fl in flights:
        bank.reset()
        u, z = absolute_frames(model_bank, fl)
        for i in range(len(z)):
            if bank.step(z[i], u[i]) is not None:
                return float("inf")
            p = bank.probabilities
            peak = max(peak, float(np.log(np.max(p[1:])) - np.log(p[0])))
            if scales is not None and i >= names.FRAME_RATE_HZ:
                scales.append(float(bank.turbulence_scale))
    return peak


def bounded_reference(model_bank, flights, bound: float = REFERENCE_LOG_ODDS_BOUND,
                      reference_range: tuple[float, float] = REFERENCE_RANGE,
                      step: float = REFERENCE_STEP, start_up_s: float = 0.0,
                      running_start: bool = False) -> tuple[float, float]:
    """The largest reference on the grid ``reference_range`` (``step``) at which the
    estimator's peak failure log-odds over the no-failure ``flights`` stays at or below
    ``bound`` (``failure_log_odds_peak``): the least tempering that keeps the calibration
    flights this far from a declaration.  The peak falls as the reference falls (a lower
    reference, a larger likelihood scale s); the search is a bisection on the grid, and
    returns the grid's lower end if even that exceeds the bound.  Returns (reference, peak at
    it).  ``start_up_s``, ``running_start``: the estimator's start-up and adaptation start the
    flights are run with (``failure_log_odds_peak``).  Deterministic for given flights."""
    lo_ref, hi_ref = reference_range
    grid = [round(lo_ref + n * step, 6) for n in range(int(round((hi_ref - lo_ref) / step)) + 1)]
    lo, hi = 0, len(grid) - 1   # invariant: every index < lo passes (or lo == 0); none > hi passes
    peaks = {}

    def passes(n):
        peaks[n] = failure_log_odds_peak(model_bank, flights, grid[n], start_up_s=start_up_s,
                                         running_start=running_start)
        return peaks[n] <= bound

    best = 0
    while lo <= hi:
        mid = (lo + hi) // 2
        if passes(mid):
            best, lo = mid, mid + 1
        else:
            hi = mid - 1
    if best not in peaks:
        passes(best)
    return grid[best], peaks[best]


#: The per-node probability floor (``bounded_settings``): the candidates, from the shipped 1e-9
#: up: a larger floor shortens a failure's climb to a declaration where the node's calibration
#: flights allow it.  Floors below 1e-9 (1e-12, 1e-15) were measured as candidates too
#: (docs/results/envelope_tuning.md, round 5): they bound the low nodes' false alarms, but
#: through the neighbourhood step they slow detection around them more than they gain.
P_MIN_CANDIDATES: tuple[float, ...] = (1e-9, 1e-7, 1e-5, 1e-3)
#: The estimator start-up (s) a scheduled design's file recommends (schedule format 3's
#: start_up_s: the estimator flies it unless ``--start-up-s`` overrides it): the first 64
#: frames, in which the first trims rest on a few air-data samples and the filters' start
#: transient (NONE absorbing the scheduled trim's offset) would lift a ``constant`` failed-sensor
#: hypothesis (docs/results/envelope_tuning.md, rounds 6-9).
START_UP_S = 1.0
#: The start-up (s) the scheduled design's calibration flights bound the nodes' floors and
#: references with (``bounded_settings``; ``--calibration-start-up-s``): the first 16 frames.
#: Shorter than the file's: the bound then also counts the excursions of frames 16-63, which
#: the flight with START_UP_S weighs nothing; bounded with START_UP_S itself, 29 of 78 nodes
#: moved their reference and 4 their floor, and the tuning set lost VEL runs and a Fig. 9 point
#: (docs/results/envelope_tuning.md, round 9).
CALIBRATION_START_UP_S = 0.25
#: The floor at which REFERENCE_LOG_ODDS_BOUND was chosen (the shipped tuning's p_min).
BOUND_P_MIN = 1e-9


def log_odds_floor(p_min: float, k: int = names.K_BANK) -> float:
    """The failure log-odds of a hypothesis at the floor while NONE holds the rest:
    ln(p_min / (1 - (k-1) p_min))."""
    return float(np.log(p_min / (1.0 - (k - 1) * p_min)))


def declaration_effort(p_min: float, threshold: float, scale: float, k: int = names.K_BANK) -> float:
    """How long a failure takes to be declared, in frames times its evidence per frame (the
    mean of l_f - l_NONE at s = 1, a property of the node and the failure, not of the settings):
    its log-odds must climb from the floor ``log_odds_floor(p_min)`` to
    ``ln(threshold / (1 - threshold))``, and the adaptation's scale s divides the evidence
    (likelihoods -q/(2 s)):  effort = s (ln(thr / (1 - thr)) - log_odds_floor(p_min))."""
    return scale * (np.log(threshold / (1.0 - threshold)) - log_odds_floor(p_min, k))


def log_odds_bound(p_min: float, threshold: float, bound: float = REFERENCE_LOG_ODDS_BOUND) -> float:
    """The false-alarm bound on the calibration flights' peak failure log-odds at floor p_min:
    the same share of the climb from the floor to a declaration as ``bound`` is at BOUND_P_MIN,
        floor + f (ln(thr / (1 - thr)) - floor),  f = (bound - floor_0) / (ln(thr / (1 - thr)) - floor_0)
    (f = 0.642 for -6 at 1e-9 and threshold 0.9).  Why a share: the noise's excursions above the
    floor, like a failure's evidence, are divided by the scale s, so a candidate's margin against
    a false alarm is its climb s (ln(thr/(1-thr)) - floor) over the largest excursion; a fixed
    share gives every floor the same margin (an absolute bound would let a low floor's
    excursions grow to nearly its whole climb: 28 of 37 nats at 1e-15)."""
    top, f0 = np.log(threshold / (1.0 - threshold)), log_odds_floor(BOUND_P_MIN)
    share = (bound - f0) / (top - f0)
    floor = log_odds_floor(p_min)
    return float(floor + share * (top - floor))


def bounded_settings(model_bank, flights, candidates: tuple[float, ...] = P_MIN_CANDIDATES,
                     bound: float = REFERENCE_LOG_ODDS_BOUND, start_up_s: float = 0.0,
                     running_start: bool = False) -> dict:
    """A node's probability floor and adaptation reference, bounded by its calibration
    flights' false alarms: for each candidate p_min, the largest reference whose peak failure
    log-odds over ``flights`` stays within ``log_odds_bound(p_min)`` (``bounded_reference`` on
    the bank recommending that floor) and the mean scale s the estimator holds there (their
    turbulence); of the candidates that meet their bound, the one of least
    ``declaration_effort`` (ties: the smaller floor); if none does, the smallest candidate.
    Returns {p_min, adapt_reference, failure_log_odds_peak, bound_met, scale, effort,
    candidates: [[p_min, reference, peak, s, met], ...] (ascending floors)}.  ``start_up_s``,
    ``running_start``: the estimator's start-up and adaptation start, flown in every
    calibration run (``failure_log_odds_peak``).
    Deterministic for given flights."""
    rows, best = [], None
    threshold = float(model_bank.threshold)
    for p_min in sorted(candidates):
        bank = model_bank.with_settings(p_min=p_min)
        limit = log_odds_bound(p_min, threshold, bound)
        reference, peak = bounded_reference(bank, flights, limit, start_up_s=start_up_s, running_start=running_start)
        scales: list[float] = []
        failure_log_odds_peak(bank, flights, reference, scales, start_up_s=start_up_s, running_start=running_start)
        scale = float(np.mean(scales)) if scales else 1.0
        row = {"p_min": p_min, "adapt_reference": reference, "failure_log_odds_peak": round(peak, 2),
               "bound_met": bool(peak <= limit), "scale": round(scale, 3),
               "effort": round(float(declaration_effort(p_min, threshold, scale)), 2)}
        rows.append(row)
        if row["bound_met"] and (best is None or row["effort"] < best["effort"]):
            best = row
    chosen = dict(best if best is not None else rows[0])
    chosen["candidates"] = [[r["p_min"], r["adapt_reference"], r["failure_log_odds_peak"], r["scale"], r["bound_met"]]
                            for r in rows]
    return chosen


def write_nominal_banks(lin) -> None:
    """Design and write the shipped nominal banks from the committed tunings."""
    for name in ("tuned", "untuned"):
        d = design_bank(0.4, 20_000.0, name, linearized=lin)
        mb = write_bank(d, nominal_bank_path(name))
        print(f"wrote {nominal_bank_path(name)} ({mb.content_hash[:12]})")


def main(argv=None) -> Tuning:
    ap = argparse.ArgumentParser(prog="python -m f16mmae.design.calibrate",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--write", action="store_true",
                    help="rewrite design/tunings/tuned.toml and the shipped nominal banks")
    ap.add_argument("--gust-states", action="store_true",
                    help=f"calibrate the filters with Dryden gust states instead: {GUST_TUNING}.toml "
                         "(--write writes it, no shipped bank)")
    ap.add_argument("--banks", action="store_true",
                    help="only regenerate the shipped nominal banks from the committed tunings "
                         "(after a bank-format change; no calibration flights)")
    args = ap.parse_args(argv)
    lin = linearize_truth(0.4, 20_000.0)
    if args.banks:
        write_nominal_banks(lin)
        return load_tuning("tuned")
    gust = "dryden_states" if args.gust_states else "gust_rate"
    tun, hist, conv = run_calibration(lin, gust)
    print("untuned:\n" + hist[0].table(names.SENSORS))
    print("stage 1 (rounded):\n" + hist[-2].table(names.SENSORS))
    print("stage 2:\n" + hist[-1].table(names.SENSORS))
    for rec in conv:
        print(f"  {rec['step']:<16} J {rec['J']:.3f}  "
              + " ".join(f"{k} {v:.2f}" for k, v in rec["per_case"].items()))
    text = render_toml(tun, hist[0], hist[-2], hist[-1], conv)
    if args.gust_states:
        text = text.replace("calibrate --write`", "calibrate --write --gust-states`").replace(
            "zero-order Dryden gusts", "Dryden gust states (design/gust_states.py)")
        if args.write:
            (TUNINGS_DIR / f"{GUST_TUNING}.toml").write_text(text)
            print(f"wrote {TUNINGS_DIR / f'{GUST_TUNING}.toml'}")
        else:
            print(text)
        return tun
    if args.write:
        path = TUNINGS_DIR / "tuned.toml"
        path.write_text(text)
        print(f"wrote {path}")
        write_nominal_banks(lin)
    else:
        print(text)
    return tun


if __name__ == "__main__":
    main()
