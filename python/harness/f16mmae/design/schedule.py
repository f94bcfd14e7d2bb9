"""The scheduled design: one bank per point of a Mach x altitude grid over the trimmable
envelope, written as one scheduled-bank file (``cpp/bankfile/schedule_file.h``) that the core
schedules on measured air data (``cpp/f16mmae/scheduled_filters.h``).

Every covered point is the ordinary design (``design_bank``), with the given tuning at every
point (``--node-tuning fixed``) or with its pseudonoise calibrated at the point (``calibrated``,
the default: ``calibrate.calibrate_node``, per channel and, where the alpha-state knob misfits
the channels' correlation, with AOA's excess on its measurement), which also sets the point's turbulence adaptation
reference and its probability floor p_min and stores them with the node: for each candidate
floor, the largest reference at which the node's estimator keeps its no-failure calibration
flights' peak failure log-odds within ``calibrate.log_odds_bound`` (``calibrate.bounded_reference``:
a reference that bounds the false alarms, not the mean power ratio, which the metadata also
records), and of these pairs the one a failure needs the least evidence to be declared with
(``calibrate.bounded_settings``; the estimator on those flights runs with the start-up
``calibrate.CALIBRATION_START_UP_S``, 0.25 s, and the file recommends ``calibrate.START_UP_S``,
1 s, its typed ``start_up_s`` (schedule format 3), as it recommends each node's floor: the
estimator flies it unless ``--start-up-s`` says otherwise); then the floor lowered to its grid neighbours' and the
reference to theirs at the largest floor around it (``neighbourhood_settings``), so that the
reference and floor the core blends over a cell bound them at every corner.  The floor is the node bank's
recommended p_min (its estimator settings; the core blends the nodes' floors).  A point whose truth cannot trim is left out of the
grid and listed in the metadata; the core clamps air data to the grid, and where a cell lacks a
corner blends its covered triangle (beyond it: the nearest covered node's filters, the triangle
plane's trims, in the lift coordinate; cpp/f16mmae/scheduled_filters.h).  Each node also stores
its trim state ``x_trim`` (the absolute state its filters' perturbation states are taken from): body u and
alpha from the trim's noise-free measurements, theta, the five surfaces at their trim
commands, zero rates, sideslip and bank.

Calm-air reference (calibrated nodes): after the design, each grid point's node (its flap layers'
alike) stores the scheduled estimator's measured power ratio midway between its no-failure flights
on the tuning seeds in calm air and in the tuning's turbulence (``calibrate.calm_reference``); the
core's calm-air complete model (cpp/f16mmae/calm_air_complete.h, ``--calm-complete``) reads the
air as calm below a multiple of it.

Failure model: the hypotheses take ``failure_model`` (default ``names.SCHEDULE_FAILURE_MODEL``:
a failed VEL reads an unknown constant within its scheduled trim's uncertainty, a failed roll
gyro one within its noise sigma, ``hypotheses.py``'s ``constant``; the other components the
paper's ``complete``), but a node's
floor and reference are bounded on the node's ``complete`` bank: on failure-free calibration
flights a ``constant`` hypothesis rises while NONE's filter absorbs the scheduled trim's offset,
and bounding on it tempers nearly every node for that transient (docs/results/envelope_tuning.md,
round 8: 71 of 78 nodes, VEL 27 of 75 on the tuning seeds), which the campaigns' false alarms
do not show (round 9).

Failed sensors' noise: the hypotheses' failed sensors take ``failed_sensor_noise`` (default
``names.SCHEDULE_FAILED_SENSOR_NOISE``, ``sensor``: a failed sensor's channel variance is the
sensor's own noise, not the node's R with its method-2 pseudonoise, tuning.py), in every bank of
the design (the nodes', and those they are bounded and scaled on). A node's calibration puts
the healthy normal accelerometer's gust-driven excess on its R (up to 0.014 g^2 at Mach 0.8,
5,000 ft); a failed AZ hypothesis that kept it explained the healthy reading, which stays near its
trim in calm air, better than the no-failure filter predicted it, and was declared in every calm
flight at the high-q̄ points below 10,000 ft (docs/results/envelope_scheduled.md, round 36).

Reference scale (``calibration_bank`` ``scaled``): a node whose hypotheses cover more than the
paper's complete model (a failed sensor's reading at an unknown level over its range, a surface at
an unknown position) explains no-failure air better than the complete bank does, so the
adaptation's measured power ratio, the minimum over the level-0 hypotheses, runs lower on its
bank (0.72-0.79 of the complete bank's over the default grid in light air), and references
bounded on the complete bank leave its tempering idle where the complete bank's would temper,
while references bounded on its own bank over-temper (docs/results/failure_models.md, round 34).
With ``scaled`` the floor and reference are bounded on the complete bank and the node carries
sigma = rho-bar(own) / rho-bar(scale model), its bank's and the bank of ``scale_model``'s mean
measured power ratios on the same calibration flights (``calibrate.measured_power_ratio``;
schedule format 5): the core's adaptation reads its power ratio divided by sigma against every
reference, the node's and the climb's and maneuver's of the estimator's options
(cpp/f16mmae/turbulence_adaptation.h, power scale), so that it tempers as the scale model's bank
would in the same air.  The default scale model (``names.SCHEDULE_SCALE_MODEL``) is the failure
model the estimator's flight-phase references and gates were tuned with (rounds 12-33); the
complete model, whose bank the references are bounded on, runs at a higher power ratio again
(1.11 of it at the nominal point) and over-tempers the cover sensors high up
(docs/results/failure_models.md, round 35).  A flap layer's node takes its grid point's sigma.

Leading-edge flap (the truth holds it where the trim's alpha puts it: ``aircraft.lef_schedule_rad``,
a switch at 5 and 15 deg that crosses the grid near q̄ 170 lbf/ft^2 and at low Mach high up):
each node is designed in its own flap position, its configuration layer; a cell whose corners
are in different positions gets its corners designed in the others too (the flap held there,
the node's own tuning and reference), and the file carries the flap law (layers switched on
the interpolated trim alpha), so the core blends the filters of one aircraft configuration,
never two (``cpp/f16mmae/bank_schedule.h``).

With ``throttle_input`` every node is the 6-input design (``design_bank(..., throttle_input=True)``:
the throttle command's column from JSBSim's linearization at the node).  Its calibration and
adaptation reference are those of the node's 5-input design (the same K and A: the gains do
not depend on B; the tuning flights fly no throttle dither).

Gust states at the low nodes (``gust_states_below_ft`` FT): the nodes at or below FT are
designed with Dryden gust states (``gust_states.py``, ``GUST_NODE_MODEL``, 19 states) from the
tuning's gust counterpart (``gust_node_tuning``: the shipped gust-state tuning's pseudonoise
knobs, everything else the tuning's), calibrated there as any node; the others are padded with
inert gust states (``gust_states.pad_bank``: no coupling, no gain, their residuals their 13-state
design's), so that the file holds one state count, as the core requires.  Floor and reference:
a gust node whose covered grid neighbours all carry gust states keeps its own bounded pair;
every other node takes the pair the neighbourhood rule gives without that exception
(``neighbourhood_settings`` ``keep_own``), since the gust and plain filters' power ratios are
on different levels and a cell blending the two is bounded only by the smaller.
With ``gust_node_choice`` ``effort`` a node at or below FT is designed and calibrated both ways
and carries the gust states only where its calibration gains by them (``gust_gains``: less
declaration effort at the smallest candidate floor on its tuning-seed flights); the others are
its plain design, padded, and count as plain nodes in the rule above.

Deterministic: the same grid and tuning give the same file byte for byte (nodes in grid
order; the metadata holds no time or host).  The points are designed in parallel (a process
pool, ``workers``), the file written once all are in.
"""
from __future__ import annotations

import dataclasses
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from .. import banks, names
from ..errors import F16mmaeError
from ..truth.aircraft import ALT_FT_RANGE, LEF_ALPHA_SWITCH_RAD, LEF_POSITIONS_RAD, MACH_RANGE, TrimError
from .bank import DESIGN_VERSION, NOMINAL_ALT_FT, NOMINAL_MACH, design_bank, to_model_bank
from .calibrate import (BOUND_P_MIN, CALIBRATION_START_UP_S, P_MIN_CANDIDATES, REFERENCE_LOG_ODDS_BOUND, REFERENCE_RANGE, REFERENCE_STEP, SEEDS,
                        NODE_FLIGHT_S, START_UP_S, adaptation_reference, bounded_settings, calibrate_node,
                        calm_reference, measured_power_ratio, node_flights)
from .gains import DesignError
from .gust_states import GUST_STATE_MODELS, pad_bank, pad_state
from .hypotheses import check_failure_model, component_models, failure_model_table
from .model import linearize_truth
from .tuning import FAILED_SENSOR_NOISES, Tuning, load_tuning

#: The grid of the ``scheduled`` bank (docs/results/schedule.md measures how far from its
#: point a bank stays acceptable).
DEFAULT_GRID = names.SCHEDULE_GRID


class ScheduleSpecError(F16mmaeError):
    """A grid specification that cannot be read; the message names the part and the rule."""


@dataclass(frozen=True)
class Grid:
    mach: tuple[float, ...]
    alt_ft: tuple[float, ...]

    @property
    def spec(self) -> str:
        return f"mach={','.join(f'{m:g}' for m in self.mach)};alt={','.join(f'{a:g}' for a in self.alt_ft)}"


def _axis(name: str, text: str, lo: float, hi: float) -> tuple[float, ...]:
    """``start:stop:step`` (inclusive) or a list ``a/b/c``; values rounded to 1e-9."""
    try:
        if ":" in text:
            start, stop, step = (float(x) for x in text.split(":"))
            if not step > 0:
                raise ScheduleSpecError(f"grid {name}={text}: the step must be > 0")
            n = int(np.floor((stop - start) / step + 1e-9)) + 1
            values = [start + i * step for i in range(max(n, 0))]
        else:
            values = [float(x) for x in text.split("/")]
    except ValueError:
        raise ScheduleSpecError(f"grid {name}={text!r} is not start:stop:step or a list a/b/c of numbers") from None
    values = [round(v, 9) for v in values]
    if not values:
        raise ScheduleSpecError(f"grid {name}={text}: no point")
    if any(not np.isfinite(v) or v < lo - 1e-9 or v > hi + 1e-9 for v in values):
        raise ScheduleSpecError(f"grid {name}={text}: every point must lie in the design envelope {lo:g}-{hi:g}")
    if any(b <= a for a, b in zip(values, values[1:])):
        raise ScheduleSpecError(f"grid {name}={text}: the points must be strictly ascending")
    return tuple(values)


def parse_grid(spec: str = DEFAULT_GRID) -> Grid:
    """``mach=START:STOP:STEP,alt=START:STOP:STEP`` (or lists ``mach=0.3/0.4/0.6``)."""
    parts = dict(p.split("=", 1) for p in spec.split(",") if "=" in p)
    unknown = set(parts) - {"mach", "alt"}
    if unknown or set(parts) != {"mach", "alt"} or spec.count("=") != 2:
        raise ScheduleSpecError(f"grid spec {spec!r}: give mach=START:STOP:STEP,alt=START:STOP:STEP "
                                f"(e.g. {DEFAULT_GRID})")
    return Grid(mach=_axis("mach", parts["mach"], *MACH_RANGE), alt_ft=_axis("alt", parts["alt"], *ALT_FT_RANGE))


def x_trim(design) -> np.ndarray:
    """(nx,) the trim state of a design, in ``names.STATES`` order (module docstring)."""
    trim = design.linearized.trim
    x = np.zeros(design.continuous.nx)
    x[names.STATES.index("u_fps")] = trim.z[names.SENSORS.index("VEL")]
    x[names.STATES.index("alpha_rad")] = trim.z[names.SENSORS.index("AOA")]
    x[names.STATES.index("theta_rad")] = trim.theta_rad
    x[names.NX - names.NU:names.NX] = np.asarray(trim.u_rad, dtype=float)  # gust states trim at 0
    return x


#: How each node gets its pseudonoise: ``fixed`` (the tuning as given, at every node) or
#: ``calibrated`` (stage 1 of the calibration at each node, from the given tuning:
#: ``calibrate.calibrate_node``; docs/results/envelope_scheduled.md measures the two).
NODE_TUNINGS: tuple[str, ...] = ("calibrated", "fixed")
DEFAULT_NODE_TUNING = names.SCHEDULE_NODE_TUNING
#: The gust model of the nodes at or below ``gust_states_below_ft`` (module docstring).
GUST_NODE_MODEL = "dryden_states"


def gust_node_tuning(tuning: Tuning) -> Tuning:
    """The tuning a gust-state node starts from: ``tuning`` itself if it models the gust states,
    else ``tuning`` with ``GUST_NODE_MODEL`` and the pseudonoise knobs (methods 1-4) of the
    shipped gust-state tuning (``calibrate.GUST_TUNING``, calibrated for those filters: the plain
    tuning's knobs cover the gusts the states now model); name, turbulence, failure model and
    estimator settings stay the tuning's (the core requires one tuning name per schedule)."""
    if tuning.gust_model == GUST_NODE_MODEL:
        return tuning
    from .calibrate import GUST_TUNING

    g = load_tuning(GUST_TUNING)
    return dataclasses.replace(tuning, gust_model=GUST_NODE_MODEL, qd_longitudinal=dict(g.qd_longitudinal),
                               r_pseudonoise=dict(g.r_pseudonoise), qd_lateral=dict(g.qd_lateral),
                               actuator_q=dict(g.actuator_q))


def check_gust_altitude(grid: Grid, below_ft: float) -> float:
    """``below_ft`` as a float if some node of ``grid`` lies at or below it; ScheduleSpecError
    naming the value and the grid's altitudes otherwise (not a finite number, or below every node)."""
    try:
        ft = float(below_ft)
    except (TypeError, ValueError):
        raise ScheduleSpecError(f"gust states below {below_ft!r} ft: not a number of feet") from None
    if not np.isfinite(ft):
        raise ScheduleSpecError(f"gust states below {below_ft!r} ft: not a finite number of feet")
    if ft < grid.alt_ft[0]:
        raise ScheduleSpecError(f"gust states below {ft:g} ft: no node of the grid (altitudes "
                                f"{', '.join(f'{a:g}' for a in grid.alt_ft)} ft) lies at or below it")
    return ft


def gust_neighbourhoods(covered, gust) -> frozenset:
    """The gust nodes (grid indices in ``gust``) whose covered grid neighbours (the 8 around,
    those in ``covered``) all carry gust states: the nodes that keep their own floor and
    reference (module docstring)."""
    covered = set(covered)
    return frozenset(k for k in covered & set(gust)
                     if all((k[0] + di, k[1] + dj) in gust for di in (-1, 0, 1) for dj in (-1, 0, 1)
                            if (di or dj) and (k[0] + di, k[1] + dj) in covered))


#: How the nodes at or below ``gust_states_below_ft`` get their gust states: ``all`` (every one)
#: or ``effort`` (each designed both ways and calibrated on its own tuning-seed flights; it
#: carries gust states when its calibration shows it gains: ``gust_gains``).
GUST_NODE_CHOICES: tuple[str, ...] = ("all", "effort")
#: The bank a calibrated node's floor and reference are bounded on (``design_schedule``
#: ``calibration_bank``): the node's ``complete`` bank (module docstring), its ``own``, or
#: ``scaled``: on the complete bank, and the node carries its reference scale (module docstring).
CALIBRATION_BANKS: tuple[str, ...] = ("complete", "own", "scaled")
#: The longest calibration flight (s) a design may ask for: the bound's flights are replayed
#: through the node's estimator frame by frame, about six bisection steps for each candidate floor.
MAX_CALIBRATION_FLIGHT_S = 600.0

#: ``--gust-states-below-ft none``: no node carries gust states (the scheduled design's shape
#: before revision 12).
NO_GUST_STATES = "none"


def default_gust_shape(grid: Grid, tuning, node_tuning: str) -> tuple[float | None, str]:
    """The gust-state nodes a scheduled design takes when none are named: (altitude, choice).
    The shipped default's, ``names.SCHEDULE_GUST_STATES_BELOW_FT`` chosen by
    ``names.SCHEDULE_GUST_NODE_CHOICE``, for a calibrated design whose grid has a node at or below
    that altitude and whose tuning (a ``Tuning``) models no gust states at every node; otherwise
    (None, ``all``): no gust states.  A fixed node tuning gets none because the default's choice
    compares each node's calibration flights with and without them, and a fixed design flies none."""
    if (node_tuning != "calibrated" or tuning.gust_model in GUST_STATE_MODELS
            or grid.alt_ft[0] > names.SCHEDULE_GUST_STATES_BELOW_FT):
        return None, "all"
    return check_gust_altitude(grid, names.SCHEDULE_GUST_STATES_BELOW_FT), names.SCHEDULE_GUST_NODE_CHOICE


def floor_effort(record: dict, threshold: float = names.THRESHOLD_DEFAULT) -> tuple[float, float, bool]:
    """(floor, declaration effort, bound met) of a node's calibration record
    (``calibrate.bounded_settings``) at its smallest candidate floor: s (ln(thr/(1-thr)) -
    floor's log-odds) with s the adaptation's scale the node's estimator holds there at the
    row's bounded reference (``calibrate.declaration_effort``)."""
    from .calibrate import declaration_effort

    rows = record.get("candidates")
    if not rows:
        raise ValueError("the record has no calibration candidates (p_min, reference, peak, s, met): "
                         "the effort choice needs --node-tuning calibrated")
    p_min, _, _, scale, met = min(rows, key=lambda r: r[0])
    return float(p_min), round(float(declaration_effort(p_min, threshold, scale)), 2), bool(met)


def gust_gains(plain: dict, gust: dict) -> bool:
    """Whether a node carries gust states under the ``effort`` choice: on the node's
    tuning-seed calibration flights its gust design asks a failure for strictly less
    declaration effort than its plain design at the smallest candidate floor (``floor_effort``;
    the floor the neighbourhood rule gives nearly every node, where the two designs' bounded
    references are compared at one climb), a design that met its bound there winning over one
    that did not.  A tie keeps the plain design (the calibration shows no gain; the gust states
    cost frame time).  ValueError for records without a calibration, or of different floors."""
    try:
        fp, ep, mp = floor_effort(plain)
        fg, eg, mg = floor_effort(gust)
    except ValueError as exc:
        raise ValueError(f"gust_gains: {exc}") from None
    if fp != fg:
        raise ValueError(f"gust_gains: the records' smallest floors differ ({fp:g} plain, {fg:g} gust)")
    if mp != mg:
        return mg
    return eg < ep


def _layer(lef_rad: float) -> int:
    """The configuration layer of a leading-edge flap position (``aircraft.LEF_POSITIONS_RAD``)."""
    return int(np.argmin([abs(lef_rad - p) for p in LEF_POSITIONS_RAD]))


def in_model(tuning: Tuning, failure_model: str) -> Tuning:
    """``tuning`` with ``failure_model`` in place of its own, its failed sensors' level widths kept
    for the sensors that model covers (a width applies to a ``cover`` sensor only: the complete
    and scale-model banks a node is bounded and scaled on)."""
    per = component_models(failure_model)
    return dataclasses.replace(tuning, failure_model=failure_model, failed_sensor_level_width={
        s: w for s, w in tuning.failed_sensor_level_width.items() if per[s] == "cover"})


def _design_point(args):
    """One design in a worker: (i, j, layer, ModelBank or None, x_trim, reason, seconds, node
    record, tuning, adaptation reference or None).  ``lef_rad`` None: the point in its own
    configuration (the flap on the truth's schedule), the tuning calibrated there if
    ``node_tuning`` is ``calibrated`` (the node record then holds the knobs, the NONE filter's
    var/A, the mean power ratio ``calibrate.adaptation_reference``, and the adaptation reference
    ``calibrate.bounded_reference`` with its peak failure log-odds, on the same tuning flights); else the flap held at ``lef_rad`` with ``tuning`` and ``reference`` as given (the
    node's own: the truth never flies the point in that configuration, so there is nothing to
    calibrate on)."""
    i, j, mach, alt_ft, tuning, node_tuning, lef_rad, reference, throttle, p_mins, calibration_start_up_s, \
        running_start, calibration_flight_s, calibration_bank, scale_model = args
    t0 = time.perf_counter()
    record, layer, tun = {}, 0, None
    try:
        lin = linearize_truth(mach, alt_ft, throttle=throttle, lef_rad=lef_rad)
        layer = _layer(lin.trim.lef_rad)
        tun = load_tuning(tuning) if isinstance(tuning, str) else tuning
        # the evidence dwell per hypothesis is the nominal bank's (derived from its flights): the
        # nodes keep the frame dwell alone
        tun = dataclasses.replace(tun, estimator={k: v for k, v in tun.estimator.items()
                                                  if k != "dwell_nats_per_hypothesis"})
        if node_tuning == "calibrated" and lef_rad is None:
            flights = node_flights(mach, alt_ft, tun.turbulence)
            tun, before, after = calibrate_node(mach, alt_ft, tun, linearized=lin, flights=flights)
            record = {"knobs": {k: v for f in ("qd_longitudinal", "r_pseudonoise", "qd_lateral")
                                for k, v in sorted(getattr(tun, f).items())},
                      "var_over_a_before": [round(float(v), 3) for v in before.var_over_a],
                      "var_over_a_after": [round(float(v), 3) for v in after.var_over_a]}
        design = design_bank(mach, alt_ft, tun, linearized=lin)
        if node_tuning == "calibrated" and lef_rad is None:
            paper = design if tun.failure_model == "complete" else design_bank(
                mach, alt_ft, in_model(tun, "complete"), linearized=lin)
            bounded_on = design if calibration_bank == "own" else paper
            if calibration_bank == "scaled":   # sigma (module docstring)
                own_rho = measured_power_ratio(to_model_bank(design), flights)
                scaled_by = design if scale_model == tun.failure_model else paper if scale_model == "complete" else \
                    design_bank(mach, alt_ft, in_model(tun, scale_model), linearized=lin)
                scale_rho = own_rho if scaled_by is design else measured_power_ratio(to_model_bank(scaled_by), flights)
                record.update({"power_ratio_own": own_rho, "power_ratio_scale_model": scale_rho,
                               "reference_scale": round(own_rho / scale_rho, 3)})
            bound_flights = flights if calibration_flight_s == NODE_FLIGHT_S else node_flights(
                mach, alt_ft, tun.turbulence, calibration_flight_s)
            chosen = bounded_settings(to_model_bank(bounded_on), bound_flights, p_mins,
                                      start_up_s=calibration_start_up_s, running_start=running_start)
            reference = chosen["adapt_reference"]
            record.update({"power_ratio_mean": adaptation_reference(paper, flights), **chosen})
        if throttle:
            design = design_bank(mach, alt_ft, tun, linearized=lin, throttle_input=True)
    except (TrimError, DesignError) as exc:
        return i, j, layer, None, None, str(exc), time.perf_counter() - t0, record, tun, None
    return (i, j, layer, to_model_bank(design), x_trim(design), "", time.perf_counter() - t0, record, tun,
            reference)


def _calm_point(args):
    """One node's calm-air reference in a worker: (i, j, (reference, calm mean, light mean)) from its
    no-failure flights in calm air and in ``turbulence`` (``calibrate.calm_reference``)."""
    i, j, mach, alt_ft, bank, turbulence = args
    return i, j, calm_reference(bank, node_flights(mach, alt_ft, "none"), node_flights(mach, alt_ft, turbulence))


def schedule_failure_model(tuning, given: str | None = None) -> str:
    """The canonical failure model a scheduled design gives its hypotheses: ``given`` if not
    None, else the tuning's if it names one other than ``complete``, else
    ``names.SCHEDULE_FAILURE_MODEL``.  ValueError (hypotheses.check_failure_model) for one it
    cannot read."""
    if given is not None:
        return check_failure_model(given)
    return tuning.failure_model if tuning.failure_model != "complete" else check_failure_model(names.SCHEDULE_FAILURE_MODEL)


def schedule_failed_sensor_noise(tuning, given: str | None = None) -> str:
    """A scheduled design's failed sensors' noise (tuning.py ``failed_sensor_noise``): ``given`` if
    not None, else the tuning's if it names one other than ``design``, else
    ``names.SCHEDULE_FAILED_SENSOR_NOISE``.  ValueError naming the choices for one not in
    ``FAILED_SENSOR_NOISES``."""
    noise = given if given is not None else (
        tuning.failed_sensor_noise if tuning.failed_sensor_noise != "design" else names.SCHEDULE_FAILED_SENSOR_NOISE)
    if noise not in FAILED_SENSOR_NOISES:
        raise ValueError(f"{noise!r} is not one of {', '.join(FAILED_SENSOR_NOISES)}")
    return noise


def neighbourhood_minimum(bounded: dict[tuple[int, int], tuple[float, bool]]) -> dict[tuple[int, int], float]:
    """Each covered node's adaptation reference (or probability floor) in the file: the smallest
    of its own bounded value (``calibrate.bounded_settings``) and those of its covered grid
    neighbours (the 8 around it) whose bound was met.  ``bounded``: grid index -> (value, bound met).

    Why: the core blends the corners' references (and floors) over a cell, and each bounds the
    false alarms only at its own node; the node's 8 neighbours are every corner of the 4 cells
    that touch it, so the blend anywhere in a cell is at most the smallest bounded value of the
    cell's corners, and since the false alarms grow with both the reference and the floor, a
    pair no larger than a node's bounded pair keeps that node's bound (measured: between the
    20,000-ft nodes at 0.6 and the 25,000-ft nodes at 1.0 a blend gave the paper's Fig. 9 points
    false alarms).  A node whose calibration flights exceed the bound at every candidate has
    none that bounds them: it keeps its own (the range's lower end) but does not lower its
    neighbours'."""
    out = {}
    for (i, j), (ref, _) in bounded.items():
        around = [bounded[(i + di, j + dj)][0] for di in (-1, 0, 1) for dj in (-1, 0, 1)
                  if (di or dj) and (i + di, j + dj) in bounded and bounded[(i + di, j + dj)][1]]
        out[(i, j)] = min([ref] + around)
    return out


def neighbourhood_settings(records: dict[tuple[int, int], dict], keep_own=frozenset(),
                           untrimmable=frozenset()) -> tuple[dict, dict]:
    """Each covered node's probability floor and adaptation reference in the file, from the
    nodes' ``calibrate.bounded_settings`` records (grid index -> {p_min, bound_met, candidates:
    [[p_min, reference, peak, s, met], ...]}):

    1. floor: the smallest of the node's chosen floor and its neighbours' that met their bound
       (``neighbourhood_minimum``);
    2. for each of the (up to four) grid cells the node is a corner of, the largest floor P_c of
       step 1 at the cell's covered corners: the core blends ln p_min over a cell, so that cell
       blends no larger floor than P_c;
    3. reference: over those cells, the smallest of the corners' bounded references at their
       cell's P_c (the node's own, and a neighbour's only where its row at P_c met the bound);
    4. the floor in the file: the node's floor of step 1; at the trimmable edge, a node with an
       ``untrimmable`` grid neighbour (a point left out of the design: JSBSim cannot trim the F-16
       there) takes its least candidate floor, with the reference of step 3: its calibration flew
       at the node, not in the cut cells between it and the edge, which the aircraft flies at the
       edge's lowest speeds (at Mach 0.36, 34,000 ft a cut cell put the (0.4, 35,000 ft) node's
       1e-7 in force in calm and light air, and the short false stabilator and flaperon
       declarations of 10-h soaks there came with it; docs/results/envelope_scheduled.md, round
       45). A lower floor with the same reference only lowers the false log-odds' peak (below), so
       the calibration's bound still holds. The calibration flies light air; in rougher air the
       estimator lowers the floor in force itself (names.SCHEDULE_ROUGH_P_MIN,
       cpp/f16mmae/rough_air_floor.h: the nodes' 1e-5 at 15,000 ft lifted false flaperon and rudder
       hypotheses to the threshold in moderate air, round 45).
    Why this keeps the bound at every corner that met it: the blend anywhere in a cell has a
    floor of at most its P_c and a reference of at most every corner's bounded reference at P_c,
    and the peak falls with the floor as with the reference.  (One P over the node's whole
    neighbourhood, the rule before revision 21, paired a floor of the cells on one side with a
    reference bounded at that floor on the other: at Mach 0.4, 20,000 ft the 15,000-ft nodes' 1e-5
    with the 25,000-ft node's 0.58 at 1e-5, where the cells above blend 1e-9 and bound 0.72.)
    (Taking the smallest floor and the smallest reference apart would pair a floor chosen with a high reference with a reference
    chosen for a high floor: tempering far more than either node needs.)
    ``keep_own``: nodes that keep their own chosen floor and reference (``gust_neighbourhoods``);
    every other node's reference is the one this rule gives without them (their neighbours see them as above,
    not at their own chosen floor: an own floor above the rule's would otherwise lower the
    references around it)."""
    chosen = neighbourhood_minimum({k: (r["p_min"], r["bound_met"]) for k, r in records.items()})   # 1.
    at = {k: {row[0]: (row[1], row[4]) for row in r["candidates"]} for k, r in records.items()}
    references = {}
    for (i, j) in records:
        bounds = []
        for ci in (i - 1, i):   # the cells whose corner (i, j) is: lower-left corner (ci, cj)
            for cj in (j - 1, j):
                corners = [(ci + a, cj + b) for a in (0, 1) for b in (0, 1) if (ci + a, cj + b) in records]
                if len(corners) < 2:
                    continue   # no cell there: the node alone, or beyond the grid
                top = max(chosen[k] for k in corners)   # 2. P_c
                bounds += [at[k][top][0] for k in corners if k == (i, j) or at[k][top][1]]   # 3.
        references[(i, j)] = min(bounds) if bounds else at[(i, j)][chosen[(i, j)]][0]
    for k in keep_own:
        references[k] = records[k]["adapt_reference"]
    floors = dict(chosen)   # 4.
    for k in keep_own:
        floors[k] = records[k]["p_min"]
    for (i, j), r in records.items():   # the trimmable edge's least floors
        if any((i + di, j + dj) in untrimmable for di in (-1, 0, 1) for dj in (-1, 0, 1)):
            floors[(i, j)] = min(row[0] for row in r["candidates"])
    return floors, references


def alternate_nodes(grid: Grid, own: dict[tuple[int, int], int]) -> list[tuple[int, int, int]]:
    """(i, j, layer) of the designs a cell whose covered corners ``own`` (grid index -> own
    configuration layer) straddle a flap switch needs: every covered corner in every layer
    another corner of the cell has, so the cell can be blended within the configuration in
    force (bank_schedule.h configuration layers).  Sorted: deterministic."""
    out = set()
    for i in range(max(len(grid.mach) - 1, 1)):
        for j in range(max(len(grid.alt_ft) - 1, 1)):
            corners = [c for c in ((i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)) if c in own]
            layers = {own[c] for c in corners}
            if len(layers) > 1:
                out |= {(c[0], c[1], layer) for c in corners for layer in layers if layer != own[c]}
    return sorted(out)


def design_schedule(grid: Grid, tuning: str = "tuned", out: str | Path = "scheduled.f16sched",
                    workers: int | None = None,
                    progress: Callable[[str], None] | None = None,
                    node_tuning: str = DEFAULT_NODE_TUNING, flap_layers: bool = True,
                    throttle_input: bool = False,
                    p_min_candidates: tuple[float, ...] = P_MIN_CANDIDATES,
                    start_up_s: float = START_UP_S,
                    calibration_start_up_s: float = CALIBRATION_START_UP_S,
                    failure_model: str | None = None,
                    gust_states_below_ft: float | None = None,
                    gust_node_choice: str = "all",
                    running_start: bool = False,
                    calibration_flight_s: float = NODE_FLIGHT_S,
                    calibration_bank: str = "complete",
                    scale_model: str = names.SCHEDULE_SCALE_MODEL,
                    failed_sensor_noise: str | None = None) -> dict:
    """Design every grid point (in ``workers`` processes, default all cores), then, with
    ``flap_layers``, where a cell straddles a leading-edge-flap switch, its corners in the
    other configuration (``alternate_nodes``), and write the file with the flap law (switch on
    trim alpha at ``aircraft.LEF_ALPHA_SWITCH_RAD``); without, one layer (every node in layer 0,
    blended across the switch).
    ``node_tuning`` (NODE_TUNINGS): ``tuning`` at every node, or calibrated at each node from it.
    ``throttle_input``: every node models the throttle as its sixth input (module docstring).
    ``p_min_candidates``: the probability floors a calibrated node chooses from
    (``calibrate.bounded_settings``; one value: that floor at every node).
    ``start_up_s``: the estimator start-up (``--start-up-s``) the file recommends (its typed
    ``start_up_s``, and the metadata's); ``calibration_start_up_s``: the one the calibration
    flights are run with when the nodes' floors and references are bounded (calibrated nodes
    only; neither is recorded for fixed nodes).
    ``failure_model``: the hypotheses' failure model at every node (hypotheses.py), in place of
    the tuning's; None: ``schedule_failure_model`` (the tuning's if it names one, else
    ``names.SCHEDULE_FAILURE_MODEL``).  A calibrated node's floor and reference are bounded on
    the node's ``complete`` bank whatever the model (module docstring), unless
    ``calibration_bank`` is ``own`` (CALIBRATION_BANKS): then on the node's bank itself; with
    ``scaled`` each node also carries its reference scale against ``scale_model``'s bank (module
    docstring).
    ``calibration_flight_s``: the length of the flights the floor and reference are bounded on
    (calibrated nodes only; the knobs are calibrated on ``calibrate.NODE_FLIGHT_S``-second
    flights whatever it is, which a longer flight of the same seed begins with).
    ``gust_states_below_ft``: the nodes at or below it with Dryden gust states, the others padded
    with inert ones (module docstring); ScheduleSpecError if no node lies at or below it.
    ``gust_node_choice`` (GUST_NODE_CHOICES): ``all`` of those nodes carry gust states, or, with
    ``effort`` (calibrated nodes only), each is designed both ways and keeps the gust design
    only where ``gust_gains`` says its calibration gains; the metadata lists both efforts.
    ``running_start`` (calibrated nodes only): the calibration flights run the adaptation's
    running start (``calibrate.failure_log_odds_peak``), and the metadata's
    ``adapt_running_start`` makes the file recommend it (``estimator_options.recommends_running_start``).

    Returns a summary: path, content hash, covered and skipped points, size in bytes, wall
    and summed design seconds."""
    from .. import core

    if node_tuning not in NODE_TUNINGS:
        raise ScheduleSpecError(f"node tuning {node_tuning!r} is not one of {', '.join(NODE_TUNINGS)}")
    tuning_obj = load_tuning(tuning)
    fm = schedule_failure_model(tuning_obj, failure_model)
    try:
        noise = schedule_failed_sensor_noise(tuning_obj, failed_sensor_noise)
    except ValueError as exc:
        raise ScheduleSpecError(f"failed sensor noise: {exc}") from None
    if fm != tuning_obj.failure_model or noise != tuning_obj.failed_sensor_noise:
        tuning_obj = dataclasses.replace(tuning_obj, failure_model=fm, failed_sensor_noise=noise)
        tuning = tuning_obj   # the workers design with the object (its name unchanged)
    per = component_models(fm)
    uncovered = [sensor for sensor in tuning_obj.failed_sensor_level_width if per[sensor] != "cover"]
    if uncovered:
        raise ScheduleSpecError(f"the tuning {tuning_obj.name}'s failed_sensor_level_width names "
                                f"{', '.join(uncovered)}, whose failure model under {fm} is not cover: a level "
                                "width applies to a cover sensor")
    if calibration_bank not in CALIBRATION_BANKS:
        raise ScheduleSpecError(f"calibration bank {calibration_bank!r} is not one of {', '.join(CALIBRATION_BANKS)}")
    scale_model = check_failure_model(scale_model)
    if not (NODE_FLIGHT_S <= calibration_flight_s <= MAX_CALIBRATION_FLIGHT_S):
        raise ScheduleSpecError(f"calibration flight length {calibration_flight_s:g} s is outside "
                                f"{NODE_FLIGHT_S:g}-{MAX_CALIBRATION_FLIGHT_S:g} s")
    if node_tuning != "calibrated":   # no calibration flights: nothing was bounded with a start-up
        start_up_s = calibration_start_up_s = 0.0
        running_start = False
        calibration_flight_s, calibration_bank = NODE_FLIGHT_S, "complete"
    gust_ft = None if gust_states_below_ft is None else check_gust_altitude(grid, gust_states_below_ft)
    if gust_ft is not None and tuning_obj.gust_model in GUST_STATE_MODELS:
        raise ScheduleSpecError(f"gust states below {gust_ft:g} ft: the tuning {tuning_obj.name} already models "
                                f"gust states ({tuning_obj.gust_model}) at every node")
    gust_tuning = None if gust_ft is None else gust_node_tuning(tuning_obj)
    if gust_node_choice not in GUST_NODE_CHOICES:
        raise ScheduleSpecError(f"gust node choice {gust_node_choice!r} is not one of {', '.join(GUST_NODE_CHOICES)}")
    choose = gust_ft is not None and gust_node_choice == "effort"
    if choose and node_tuning != "calibrated":
        raise ScheduleSpecError("the gust node choice effort compares each node's calibration with and without "
                                "gust states: it needs the node tuning calibrated")

    def point_tuning(alt_ft):
        return gust_tuning if gust_ft is not None and alt_ft <= gust_ft else tuning

    points = [(i, j, m, a, point_tuning(a), node_tuning, None, None, throttle_input, tuple(p_min_candidates),
               calibration_start_up_s, running_start, calibration_flight_s, calibration_bank, scale_model)
              for j, a in enumerate(grid.alt_ft) for i, m in enumerate(grid.mach)]
    gust = {(i, j) for j, a in enumerate(grid.alt_ft) for i in range(len(grid.mach))
            if gust_ft is not None and a <= gust_ft}
    # the effort choice: the gust nodes' plain designs too, after the grid (the same worker arguments as a plain node)
    plain_points = [(i, j, m, a, tuning) + p[5:] for p in points for (i, j, m, a) in [p[:4]]
                    if choose and (i, j) in gust]
    t0 = time.perf_counter()
    results, alternates, plain_results, choice, unused = {}, {}, {}, {}, []
    with ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
        for n, r in enumerate(pool.map(_design_point, points + plain_points), start=1):
            variant = n > len(points)
            (plain_results if variant else results)[(r[0], r[1])] = r
            if progress:
                m, a = grid.mach[r[0]], grid.alt_ft[r[1]]
                state = ("skipped: " + r[5] if r[3] is None else f"designed (flap layer {r[2]}"
                         + (", without gust states)" if variant else ", gust states)" if (r[0], r[1]) in gust else ")"))
                progress(f"[{n}/{len(points) + len(plain_points)}] Mach {m:.2f}, {a:.0f} ft: {state} ({r[6]:.1f} s)")
        for k, p in sorted(plain_results.items()):   # each chosen node: the gust design where it gains
            g = results[k]
            if g[3] is None or p[3] is None:
                keep_gust = g[3] is not None
            else:
                keep_gust = gust_gains(p[7], g[7])
            choice[k] = {"gust": keep_gust, **({"effort_plain": floor_effort(p[7])[1], "effort_gust": floor_effort(g[7])[1]}
                                               if g[3] is not None and p[3] is not None else {})}
            unused.append((p if keep_gust else g)[6])
            if not keep_gust:
                results[k] = p
                gust.discard(k)
            if progress:
                progress(f"Mach {grid.mach[k[0]]:.2f}, {grid.alt_ft[k[1]]:.0f} ft: "
                         f"{'gust states' if keep_gust else 'no gust states'} (declaration effort at the "
                         f"smallest floor {choice[k].get('effort_gust')} with, {choice[k].get('effort_plain')} without)")
        own = {k: r[2] for k, r in results.items() if r[3] is not None}
        p_min_of = {}   # grid index -> the node's floor in the file (calibrated nodes)
        keep = gust_neighbourhoods(own, gust) if node_tuning == "calibrated" else frozenset()
        if node_tuning == "calibrated":   # each node's floor and reference from its neighbourhood (neighbourhood_settings)
            covered = [k for k, r in results.items() if r[3] is not None]
            p_min_of, references = neighbourhood_settings({k: results[k][7] for k in covered},
                                                          keep_own=keep,
                                                          untrimmable={k for k, r in results.items() if r[3] is None})
            for k in covered:
                r = results[k]
                r[7]["adapt_reference_node"], r[7]["adapt_reference"] = r[9], references[k]
                r[7]["p_min_node"], r[7]["p_min"] = r[7]["p_min"], p_min_of[k]
                results[k] = r[:9] + (references[k],)
        tasks = [] if not flap_layers else [(i, j, grid.mach[i], grid.alt_ft[j], results[(i, j)][8], node_tuning, LEF_POSITIONS_RAD[layer],
                  results[(i, j)][9], throttle_input, (), calibration_start_up_s, running_start,
                  calibration_flight_s, calibration_bank, scale_model)
                 for i, j, layer in alternate_nodes(grid, own)]
        for n, r in enumerate(pool.map(_design_point, tasks), start=1):
            alternates[(r[0], r[1], r[2])] = r
            if progress:
                state = "skipped: " + r[5] if r[3] is None else "designed"
                progress(f"[{n}/{len(tasks)}] Mach {grid.mach[r[0]]:.2f}, {grid.alt_ft[r[1]]:.0f} ft, flap layer "
                         f"{r[2]}: {state} ({r[6]:.1f} s)")
    nodes, skipped, node_records = [], [], []
    for key in [(p[0], p[1]) for p in points] + sorted(alternates):  # grid order, then the alternates
        i, j, layer, bank, xt, reason, _, record, _, reference = (results[key] if len(key) == 2 else alternates[key])
        if bank is None:
            skipped.append({"mach": grid.mach[i], "alt_ft": grid.alt_ft[j], "layer": layer, "reason": reason})
        else:
            if (i, j) in p_min_of:   # the node's floor (its bank's recommended p_min; bank_schedule.h)
                bank = bank.with_settings(p_min=p_min_of[(i, j)])
            if gust_ft is not None:   # one state count in the file: plain nodes with inert gust states
                bank, xt = pad_bank(bank, GUST_NODE_MODEL), pad_state(xt, GUST_NODE_MODEL)
            nodes.append((i, j, bank, xt, reference, layer if flap_layers else 0))
            if record:
                node_records.append({"mach": grid.mach[i], "alt_ft": grid.alt_ft[j], **record})
    if not nodes:
        raise DesignError(f"no point of the grid {grid.spec} could be designed")
    if node_tuning == "calibrated":   # each node's calm-air reference, its flap layers' alike (bank_schedule.h)
        first = {}   # each grid point's own node: the grid order puts it before its alternates
        for i, j, bank, *_ in nodes:
            first.setdefault((i, j), bank)
        own_nodes = [(i, j, grid.mach[i], grid.alt_ft[j], bank, tuning_obj.turbulence) for (i, j), bank in first.items()]
        calm = {}
        with ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
            for n, (i, j, c) in enumerate(pool.map(_calm_point, own_nodes), start=1):
                calm[(i, j)] = c
                if progress:
                    progress(f"[{n}/{len(own_nodes)}] Mach {grid.mach[i]:.2f}, {grid.alt_ft[j]:.0f} ft: calm-air "
                             f"reference {c[0]:.3f} (measured power ratio {c[1]:.3f} calm, {c[2]:.3f} light)")
        nodes = [(*node[:6], calm[(node[0], node[1])][0]) for node in nodes]
        if calibration_bank == "scaled":   # each node's reference scale, its flap layers' alike (module docstring)
            scale = {(grid.mach.index(r["mach"]), grid.alt_ft.index(r["alt_ft"])): r["reference_scale"]
                     for r in node_records if "reference_scale" in r}
            nodes = [(*node[:7], scale[(node[0], node[1])]) for node in nodes]
        for r in node_records:
            c = calm.get((grid.mach.index(r["mach"]), grid.alt_ft.index(r["alt_ft"])))
            if c is not None:
                r["calm_reference"], r["power_ratio_calm"], r["power_ratio_light"] = c
    primary = min(range(len(nodes)), key=lambda n: (
        abs(grid.mach[nodes[n][0]] - NOMINAL_MACH) / 0.1 + abs(grid.alt_ft[nodes[n][1]] - NOMINAL_ALT_FT) / 10_000, n))
    import jsbsim

    metadata = {
        "generator": "f16mmae.design.schedule",
        "design_version": DESIGN_VERSION,
        "jsbsim_version": jsbsim.__version__,
        "command": (f"f16mmae design --schedule {format_spec(grid)} --tuning {tuning_obj.name} "
                    f"--node-tuning {node_tuning} --flap-layers {'on' if flap_layers else 'off'}"
                    + (" --throttle-input" if throttle_input else " --no-throttle-input")
                    + (f" --start-up-s {start_up_s:g} --calibration-start-up-s {calibration_start_up_s:g}"
                       if node_tuning == "calibrated" else "")
                    + (" --adapt-running-start" if running_start and node_tuning == "calibrated" else "")
                    + (f" --calibration-flight-s {calibration_flight_s:g}" if calibration_flight_s != NODE_FLIGHT_S else "")
                    + (f" --calibration-bank {calibration_bank}" if calibration_bank != "complete" else "")
                    + (f" --scale-model {scale_model}" if calibration_bank == "scaled" else "")
                    + f" --failure-model {tuning_obj.failure_model}"
                    + (f" --gust-states-below-ft {NO_GUST_STATES}" if gust_ft is None else
                       f" --gust-states-below-ft {gust_ft:g} --gust-node-choice {gust_node_choice}")),
        "grid": {"mach": list(grid.mach), "alt_ft": list(grid.alt_ft)},
        "tuning": tuning_obj.name,
        "node_tuning": node_tuning,
        "tuning_note": ("stage 1 of design/calibrate.py at every node from this tuning (no-failure "
                        f"flights on the tuning seeds {SEEDS[0]}-{SEEDS[-1]} at the node), and the "
                        "turbulence adaptation's reference and the probability floor from the same flights: "
                        f"for each floor of {', '.join(f'{p:g}' for p in p_min_candidates)} the largest reference of "
                        f"{REFERENCE_RANGE[0]:g}-{REFERENCE_RANGE[1]:g} (step {REFERENCE_STEP:g}) whose peak "
                        f"failure log-odds is within calibrate.log_odds_bound ({REFERENCE_LOG_ODDS_BOUND:g} at p_min "
                        f"{BOUND_P_MIN:g}, the same share of the climb to a declaration at every floor), "
                        "the pair of least declaration effort (calibrate.bounded_settings: adapt_reference_node, "
                        "p_min_node, candidates [p_min, reference, peak, s, met]), then the floor the smallest of "
                        "it and its grid neighbours' that met the bound, the reference the smallest of theirs at "
                        "the largest floor around the node (schedule.neighbourhood_settings: p_min, the node bank's "
                        "recommended floor, adapt_reference), both bounded on "
                        + ("the node's bank of the paper's complete failure model whatever the hypotheses' failure model"
                           if calibration_bank == "complete" else "the node's own bank (its hypotheses' failure model)"
                           if calibration_bank == "own" else "the node's bank of the paper's complete failure model, "
                           "and each node carries its reference scale (reference_scale: power_ratio_own over "
                           f"power_ratio_scale_model, the mean measured power ratios of its own bank and of its bank of the "
                           f"failure model {scale_model} on the same flights), which the estimator divides its power "
                           "ratio by")
                        + (f" over {calibration_flight_s:g}-s flights of the same seeds"
                           if calibration_flight_s != NODE_FLIGHT_S else "") + "; "
                        "the other estimator settings of this tuning" if node_tuning == "calibrated"
                        else "the same tuning at every point (no per-point retune)"),
        "flap_layers": None if not flap_layers else {"positions_rad": list(LEF_POSITIONS_RAD), "alpha_switch_rad": list(LEF_ALPHA_SWITCH_RAD),
                        "alternates": [{"mach": grid.mach[i], "alt_ft": grid.alt_ft[j], "layer": layer}
                                       for i, j, layer in sorted(alternates)],
                        "note": "a straddling cell's corners in the other flap position: the node's own "
                                "tuning and adaptation reference, the trim and dynamics with the flap held"},
        "nodes": node_records,
        **({"calm_reference": "each node's measured power ratio rho-bar (the scheduled estimator's, own channels but "
                              f"{names.SCHEDULE_ADAPT_COUNTED_CHANNEL}) midway between its no-failure flights on the "
                              f"tuning seeds {SEEDS[0]}-{SEEDS[-1]} in calm air and in {tuning_obj.turbulence} "
                              "turbulence (calibrate.calm_reference; the nodes' power_ratio_calm and "
                              "power_ratio_light); a flap layer's node takes its grid point's"}
           if node_tuning == "calibrated" else {}),
        "skipped": skipped,
        **({"throttle_input": True} if throttle_input else {}),
        # the start-up the file is to be flown with, and the one its calibration flights were run with
        **({"start_up_s": start_up_s, "calibration_start_up_s": calibration_start_up_s}
           if node_tuning == "calibrated" else {}),
        # the adaptation's running start, which the calibration flew and the file recommends
        **({"adapt_running_start": True} if running_start and node_tuning == "calibrated" else {}),
        # which model each hypothesis' failed components have (hypotheses.py); paper schedules keep their bytes
        **({"failure_model": failure_model_table(tuning_obj.failure_model)}
           if tuning_obj.failure_model != "complete" else {}),
        # a failed sensor's channel variance (tuning.py); the paper's R keeps the former bytes
        **({"failed_sensor_noise": tuning_obj.failed_sensor_noise}
           if tuning_obj.failed_sensor_noise != "design" else {}),
        # which nodes carry gust states, and which keep their own floor and reference
        **({"gust_states": {
            "below_ft": gust_ft, "model": GUST_NODE_MODEL, "states": list(GUST_STATE_MODELS[GUST_NODE_MODEL]),
            "nodes": [{"mach": grid.mach[i], "alt_ft": grid.alt_ft[j]} for (i, j) in sorted(gust, key=lambda k: (k[1], k[0]))],
            "own_settings": [{"mach": grid.mach[i], "alt_ft": grid.alt_ft[j]}
                             for (i, j) in sorted(keep, key=lambda k: (k[1], k[0]))],
            "other_nodes": "inert gust states (no coupling, no gain): their 13-state design's residuals",
            **({"choice": gust_node_choice,
                "efforts": [{"mach": grid.mach[i], "alt_ft": grid.alt_ft[j], **choice[(i, j)]}
                            for (i, j) in sorted(choice, key=lambda k: (k[1], k[0]))]} if choose else {})}}
           if gust_ft is not None else {}),
    }
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    content_hash = core.save_schedule(list(grid.mach), list(grid.alt_ft), nodes, primary=primary,
                                      metadata=json.dumps(metadata, sort_keys=True, separators=(",", ":")),
                                      path=str(path), switch_state=names.STATES.index("alpha_rad") if flap_layers else -1,
                                      switch_thresholds=list(LEF_ALPHA_SWITCH_RAD) if flap_layers else [],
                                      start_up_s=float(start_up_s))
    return {"path": str(path), "content_hash": content_hash, "covered": len(nodes), "skipped": skipped,
            "alternates": len([a for a in alternates.values() if a[3] is not None]),
            "bytes": path.stat().st_size, "wall_s": time.perf_counter() - t0,
            "design_s": (sum(r[6] for r in results.values()) + sum(r[6] for r in alternates.values())
                         + sum(unused)),   # with the designs the effort choice did not keep
            "primary": (grid.mach[nodes[primary][0]], grid.alt_ft[nodes[primary][1]])}


def format_spec(grid: Grid) -> str:
    """The grid as a spec ``parse_grid`` reads back (lists)."""
    return (f"mach={'/'.join(f'{m:g}' for m in grid.mach)},"
            f"alt={'/'.join(f'{a:g}' for a in grid.alt_ft)}")


def _generate_scheduled_bank(path: Path) -> None:
    """Design the ``scheduled`` bank (DEFAULT_GRID, tuned, DEFAULT_NODE_TUNING, the failure model
    ``names.SCHEDULE_FAILURE_MODEL``, gust states at or below ``names.SCHEDULE_GUST_STATES_BELOW_FT``
    chosen by ``names.SCHEDULE_GUST_NODE_CHOICE``, the throttle input ``names.SCHEDULE_THROTTLE_INPUT``)
    into ``path``, saying so (first use): the file ``f16mmae design --schedule`` writes without those
    flags (``--failure-model ... --gust-states-below-ft ... --gust-node-choice ... --throttle-input``)."""
    import sys

    print(f"designing the scheduled bank ({DEFAULT_GRID}, tuned, {DEFAULT_NODE_TUNING} at every node, failure "
          f"model {names.SCHEDULE_FAILURE_MODEL}, failed sensors' noise {names.SCHEDULE_FAILED_SENSOR_NOISE}, gust states "
          f"at or below {names.SCHEDULE_GUST_STATES_BELOW_FT:g} ft by {names.SCHEDULE_GUST_NODE_CHOICE}"
          f"{', the throttle as sixth input' if names.SCHEDULE_THROTTLE_INPUT else ''}) "
          f"into {path} (once; cached)...", file=sys.stderr, flush=True)
    s = design_schedule(parse_grid(DEFAULT_GRID), "tuned", path,
                        progress=lambda line: print("  " + line, file=sys.stderr, flush=True),
                        node_tuning=DEFAULT_NODE_TUNING, failure_model=names.SCHEDULE_FAILURE_MODEL,
                        failed_sensor_noise=names.SCHEDULE_FAILED_SENSOR_NOISE,
                        gust_states_below_ft=names.SCHEDULE_GUST_STATES_BELOW_FT,
                        gust_node_choice=names.SCHEDULE_GUST_NODE_CHOICE, throttle_input=names.SCHEDULE_THROTTLE_INPUT)
    print(f"  {s['covered']} points in {s['wall_s']:.0f} s, {s['bytes'] / 1e6:.1f} MB", file=sys.stderr, flush=True)


banks.register_schedule_generator(_generate_scheduled_bank)
