"""``f16mmae design``: trim + linearize the truth, build the 13 + 66 hypothesis filters,
tune them, write the model-bank file (and optionally the design report)."""
from __future__ import annotations

import argparse
import dataclasses
import math
import time

from ..design.bank import design_bank, write_bank
from ..design.calibrate import CALIBRATION_START_UP_S, NODE_FLIGHT_S, P_MIN_CANDIDATES, START_UP_S
from ..design.gains import DesignError
from ..design.report import write_report
from ..design.dwell import with_calibrated_dwell
from ..design.hypotheses import FAILURE_MODELS, TRIM_SIGMA, check_failure_model, component_models, uses_cover
from ..design.level_width import RANGE, READING
from ..design.gust_states import GUST_STATE_MODELS
from ..design.schedule import (CALIBRATION_BANKS, DEFAULT_GRID, DEFAULT_NODE_TUNING, GUST_NODE_CHOICES,
                               MAX_CALIBRATION_FLIGHT_S, NO_GUST_STATES, NODE_TUNINGS, ScheduleSpecError, check_gust_altitude, default_gust_shape,
                               design_schedule, format_spec, parse_grid, schedule_failed_sensor_noise,
                               schedule_failure_model)
from ..design.tuning import FAILED_SENSOR_NOISES, TuningError, _sensor_level_width, load_tuning
from ..design.turbulence_banks import MEMBER_LEVELS, BankSetError, design_set, load_set
from .. import names
from ..names import DESIGN_ALT_FT, DESIGN_MACH, TURBULENCE_LEVELS
from ..outputs import writable_dir, writable_file
from ..truth.aircraft import ALT_FT_RANGE, MACH_RANGE, TrimError
from .options import CliError, number

DESCRIPTION = """\
Design a model bank (paper Sec. IV-V): trim the nonlinear JSBSim F-16 of the truth model at
the flight condition, linearize its bare airframe (finite differences, cross-checked against
JSBSim's FGLinearization), add the five first-order actuator lags, a zero-order Dryden gust
input (or, --gust-states, three first-order Dryden gust states) and the seven sensors' noise, discretize exactly at the 64-Hz frame rate, and for each
of the 79 hypotheses (NONE, 12 single failures, 66 duals: a failed actuator's B column or a
failed sensor's H row removed) solve the Riccati equation for the steady-state gain K and
residual covariance A = H P- H^T + R (eq. 5), with the tuning's pseudonoise (methods 1-4).
An unstable filter is refused.  Deterministic: the same arguments give the same file.
--failure-model cover designs hypotheses that cover the failure whatever value it takes: a
failed surface at an unknown position the filter estimates (a random-walk state in place of
its lag), a failed sensor's reading uninformative (uniform over its full range); such a bank
recommends its own declaration dwell, the shortest (0.25-1 s) that no no-failure calibration
flight fills with a failure hypothesis above the threshold (design/dwell.py; a tuning file
with failure_model cover and an [estimator] dwell_s keeps its own).
--throttle-input makes the throttle command the model's sixth input (its column from JSBSim's
own linearization; the bank's inputs LS RS LF RF RUD THR): the closed loop then flies the
truth's throttle dither, scheduled on the measured air data, and hands the commanded throttle
to the estimator with the surface commands; with --schedule it is the default (the shipped
scheduled design's since revision 15), --no-throttle-input the five-input shape before it.
"""

EXAMPLES = f"""\
examples:
  f16mmae design                                   # nominal point, tuned, ./f16mmae_M0.40_20000ft_tuned.f16bank
  f16mmae design --mach 0.4 --alt-ft 20000 --tuning tuned --out bank.f16bank
  f16mmae design --tuning untuned --out untuned.f16bank --report design-report/
  f16mmae design --mach 0.45 --alt-ft 25000 --tuning my_tuning.toml --out off_nominal.f16bank
  f16mmae design --failure-model cover --out cover.f16bank
  f16mmae design --gust-states --gust-level moderate --out gust.f16bank   # 19 states: Dryden gusts
  f16mmae design --throttle-input --gust-level none --out calm_throttle.f16bank   # 6 inputs, calm air
  f16mmae design --schedule --out scheduled.f16sched                  # the design of --bank scheduled
  f16mmae design --schedule --no-throttle-input --out r14.f16sched   # revision 14's shape: five inputs
  f16mmae design --schedule --failure-model constant=VEL --gust-states-below-ft none --no-throttle-input --out r11.f16sched   # revision 11's shape
  f16mmae design --schedule --failure-model constant=VEL+ROL --gust-states-below-ft 15000 --gust-node-choice effort --no-throttle-input --out r12.f16sched   # revision 12's
  f16mmae design --turbulence-banks --out turbulence_banks.f16set      # the set of --turbulence-banks
  f16mmae design --schedule mach=0.3:0.8:0.05,alt=5000:35000:2500 --workers 2 --out fine.f16sched
  f16mmae design --schedule --gust-states-below-ft 15000 --gust-node-choice all --workers 2 --out low_gust.f16sched   # every low node

Scheduled design (--schedule [GRID]): one bank per point of a Mach x altitude grid, the
tuning's pseudonoise re-calibrated at every point (--node-tuning calibrated: stage 1 of
design/calibrate.py from --tuning, on no-failure truth flights at the point) or the same
at every point (--node-tuning fixed), in one scheduled-bank file (versioned, SHA-256 content hash) that
core.load_bank, every --bank option and mmae-daemon --bank read. GRID is
mach=START:STOP:STEP,alt=START:STOP:STEP (or lists mach=0.3/0.4/0.6); default
{DEFAULT_GRID}. Points that do not trim are left out (listed in the file's metadata);
the estimator clamps air data to the grid and, where a grid cell lacks a corner, blends the
three covered ones (beyond their triangle: the nearest covered node's filters, the triangle's
plane for the trims, in the lift coordinate (delta M^2)^(-3/4)). Where a cell straddles a
switch of the leading-edge flap (the truth's flap follows trim alpha: 0 below 5 deg, 15 deg of
flap to 15 deg, 25 above), its corners are also designed in the other flap position
(--flap-layers on, the default), and the estimator blends the cell within the position its
interpolated trim alpha calls for (off: one bank per point, blended across the switch).
Deterministic; the points are designed on --workers processes.

Flight condition: Mach 0.3-0.8, 5,000-35,000 ft (level trim).
Tunings: 'tuned' (the project's design, from measured residual statistics against the
truth: design/calibrate.py) and 'untuned' (physical noises only), shipped in
f16mmae/design/tunings/, or a TOML file of the same layout:
  name, description, turbulence (none|light|moderate|severe), gust_model (gust_rate|white_gust|dryden_states),
  failure_model (complete|cover, or per component {{default = "complete", cover = ["VEL", "AOA"]}}),
  failed_surface_q (rad^2/s, a failed surface's random walk; one number or {{LS = 3e-4, RUD = 1e-3}}),
  failed_surface_q_dual (the same in the dual hypotheses, e.g. {{LS = 1e-5, RS = 1e-5}}; default failed_surface_q),
  failed_sensor_level_q (a failed sensor's level walk per frame in noise variances; one number or {{AOA = 1e-3}}),
  failed_sensor_level_width (a failed cover sensor's level range per sensor: "reading", "range" or a number;
    default PIT "reading", the others "range")
  [method1_qd_longitudinal] u_fps alpha_rad q_rad_s theta_rad     (+ diag Q_d, per frame)
  [method2_r]               VEL AOA PIT AZ ROL YAW AY             (+ diag R)
  [method3_qd_lateral]      beta_rad p_rad_s r_rad_s phi_rad      (+ diag Q_d, per frame)
  [method4_actuator_q]      LS RS LF RF RUD    (white noise strength through a B column, rad^2/s)
The shipped nominal banks (f16mmae/data/nominal_{{tuned,untuned}}.f16bank) are this command at
Mach 0.4, 20,000 ft.  --report DIR writes report.txt and figures (eigenvalues per hypothesis,
gains, linear vs nonlinear step responses, NONE-filter residual statistics); ~10 s.
Re-tuning after a truth-model change (re-measures the residual statistics, rewrites
tunings/tuned.toml and both shipped banks): python -m f16mmae.design.calibrate --write
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "design", help="design a model bank (linear models, 79 filters, tuning) and write it",
        description=DESCRIPTION, epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--mach", default=str(DESIGN_MACH), metavar="M",
                   help=f"design Mach number, {MACH_RANGE[0]}-{MACH_RANGE[1]} (default {DESIGN_MACH})")
    p.add_argument("--alt-ft", default=f"{DESIGN_ALT_FT:g}", metavar="H",
                   help=f"design altitude in ft, {ALT_FT_RANGE[0]:g}-{ALT_FT_RANGE[1]:g} (default {DESIGN_ALT_FT:g})")
    p.add_argument("--tuning", default="tuned", metavar="NAME|FILE",
                   help="pseudonoise tuning: tuned | untuned | a .toml file (default tuned)")
    p.add_argument("--gust-states", action="store_true",
                   help="carry first-order Dryden gust states (u_g, v_g, w_g and the rotational p_g, q_g, "
                        "r_g) in every filter: 19 states (the tuning's gust_model dryden_states; "
                        "design/gust_states.py)")
    p.add_argument("--gust-level", default=None, metavar="|".join(TURBULENCE_LEVELS),
                   help="turbulence level the gust model is designed for (default: the tuning's, light "
                        "for the shipped ones)")
    p.add_argument("--failure-model", default=None, metavar="|".join(FAILURE_MODELS) + "|MODEL=C+C",
                   help="hypotheses of the paper's complete failures, or hypotheses that cover the "
                        "failure, for every component or per component: cover=VEL+AOA (those two cover, "
                        "the others complete), cover,complete=PIT (default first), constant=VEL (a failed VEL "
                        "at an unknown constant within its trim's uncertainty; constant applies to "
                        f"{', '.join(TRIM_SIGMA)}, e.g. constant=VEL+ROL) (default: the tuning's "
                        "failure_model, complete for the shipped ones; with --schedule, a tuning naming none "
                        f"designs {names.SCHEDULE_FAILURE_MODEL})")
    p.add_argument("--failed-sensor-level-q", default=None, metavar="Q",
                   help="with --failure-model cover: random walk per frame of a failed sensor's unknown "
                        "level, in units of its noise variance, >= 0; 0: no memory, the reading uniform over "
                        "its range every frame (default: the tuning's; AOA 1e-3, VEL 1e-4, the other sensors 0.01)")
    p.add_argument("--failed-sensor-level-width", default=None, metavar="SENSOR=W|reading|range[,...]",
                   help="with --failure-model cover: the range of a failed sensor's unknown level, in its units, "
                        "or 'reading': derived from the no-failure model's stationary spread of the healthy "
                        "reading (design/level_width.py), or 'range': the sensor's full range, e.g. PIT=range "
                        "(the rule before the pitch gyro's derived default) (default: the tuning's; PIT reading, "
                        "the other sensors range)")
    p.add_argument("--failed-sensor-noise", default=None, metavar="|".join(FAILED_SENSOR_NOISES),
                   help="a failed sensor's reading about what its hypothesis predicts varies by the design's R "
                        "(design: the paper's, with the tuning's method-2 pseudonoise) or by the sensor's own "
                        "noise alone (sensor: the pseudonoise stands for the aircraft's response the healthy "
                        "sensor reads, which a failed one no longer reads); default: the tuning's "
                        "failed_sensor_noise (design for the shipped ones); with --schedule, a tuning naming "
                        f"none designs {names.SCHEDULE_FAILED_SENSOR_NOISE}")
    p.add_argument("--throttle-input", action=argparse.BooleanOptionalAction, default=None,
                   help="model the throttle command as a sixth input (JSBSim's linearization column; "
                        "the closed loop flies the throttle dither with such a bank); default: off for one "
                        f"bank, {'on' if names.SCHEDULE_THROTTLE_INPUT else 'off'} with --schedule (names.SCHEDULE_THROTTLE_INPUT, "
                        "the shipped default's since revision 15; --no-throttle-input the shape before it)")
    p.add_argument("--partial-loss", default=None, metavar="F[,F...]",
                   help="add one partial-loss hypothesis per surface and F, the surface having lost the fraction "
                        "F of its effectiveness (0 < F < 1, as campaign detectability --losses; named C:loss=R, "
                        "R = 1 - F kept, as the truth's C@T:loss=R), to the level-0 bank (13 + 5 per F filters; "
                        "design/hypotheses.py); one design point only")
    p.add_argument("--out", default=None, metavar="FILE",
                   help="bank file to write (default ./f16mmae_M<mach>_<alt>ft_<tuning>.f16bank)")
    p.add_argument("--report", default=None, metavar="DIR",
                   help="also write the design report (text + PNG figures) into DIR")
    p.add_argument("--schedule", nargs="?", const=DEFAULT_GRID, default=None, metavar="GRID",
                   help=f"design a scheduled bank on a Mach x altitude grid (default {DEFAULT_GRID})")
    p.add_argument("--workers", default=None, metavar="N",
                   help="--schedule: processes designing the points (default all cores)")
    p.add_argument("--node-tuning", default=None, metavar="|".join(NODE_TUNINGS),
                   help=f"--schedule: the tuning re-calibrated at every node (stage 1 of design/calibrate.py, "
                        f"no-failure flights on the tuning seeds at the node), or the same at every node "
                        f"(default {DEFAULT_NODE_TUNING})")
    p.add_argument("--flap-layers", default=None, metavar="on|off",
                   help="--schedule: design a straddling cell's corners in the other leading-edge-flap position "
                        "too, and schedule the flap law (default on)")
    p.add_argument("--node-p-min", default=None, metavar="P1/P2/...",
                   help="--schedule (calibrated nodes): the probability floors each node chooses from, bounded "
                        "by its calibration flights' false alarms with its adaptation reference "
                        f"(default {'/'.join(f'{v:g}' for v in P_MIN_CANDIDATES)}; one value: that floor everywhere)")
    p.add_argument("--start-up-s", default=None, metavar="S",
                   help="--schedule (calibrated nodes): the estimator start-up (the run option --start-up-s) the "
                        f"file recommends (default {START_UP_S:g})")
    p.add_argument("--calibration-start-up-s", default=None, metavar="S",
                   help="--schedule (calibrated nodes): the estimator start-up the calibration flights bound the "
                        f"nodes' floors and references with (default {CALIBRATION_START_UP_S:g})")
    p.add_argument("--calibration-flight-s", default=None, metavar="S",
                   help="--schedule (calibrated nodes): the length of the no-failure flights the nodes' floors "
                        "and references are bounded on, the same seeds longer (the knobs are calibrated on the "
                        f"first {NODE_FLIGHT_S:g} s; default {NODE_FLIGHT_S:g}, at most {MAX_CALIBRATION_FLIGHT_S:g})")
    p.add_argument("--calibration-bank", default=None, metavar="|".join(CALIBRATION_BANKS),
                   help="--schedule (calibrated nodes): the bank the floors and references are bounded on: the "
                        "node's bank of the paper's complete failure model, its own (its hypotheses' "
                        "failure model, --failure-model), or scaled: on the complete bank, and each node carries "
                        "the ratio of its own bank's measured power ratio to the --scale-model bank's on the "
                        "same flights, which the estimator divides its power ratio by, so that it tempers as "
                        "that bank would (default complete)")
    p.add_argument("--scale-model", default=None, metavar="MODEL",
                   help="--calibration-bank scaled: the failure model (--failure-model's syntax) whose bank's "
                        "measured power ratio each node's is read against, the reference scale being the ratio "
                        f"of the two (default {names.SCHEDULE_SCALE_MODEL}, the model the estimator's references "
                        "were tuned with; complete: the bank the references are bounded on)")
    p.add_argument("--adapt-running-start", action="store_true",
                   help="--schedule (calibrated nodes): bound the nodes' floors and references on calibration "
                        "flights flown with the adaptation's running start (the run option "
                        "--adapt-running-start), and recommend it: an estimator on this file runs with it "
                        "(default off)")
    p.add_argument("--gust-states-below-ft", default=None, metavar=f"FT|{NO_GUST_STATES}",
                   help="--schedule: the nodes at or below FT ft carry Dryden gust states (19 states, from the "
                        "gust-state tuning's knobs, calibrated at the node), the others inert gust states (one "
                        f"state count per file); {NO_GUST_STATES}: no gust states (the shape before revision 12); "
                        f"default {names.SCHEDULE_GUST_STATES_BELOW_FT:g} for a calibrated design with a node at or "
                        f"below it and a tuning without gust states, else {NO_GUST_STATES}")
    p.add_argument("--gust-node-choice", default=None, metavar="|".join(GUST_NODE_CHOICES),
                   help="--gust-states-below-ft: which of those nodes carry gust states: all, or "
                        "effort: each designed with and without, the gust design kept where its calibration "
                        "asks a failure for less declaration effort (calibrated nodes; about 1.3x the design time); "
                        f"default {names.SCHEDULE_GUST_NODE_CHOICE} for calibrated nodes, all for fixed ones")
    p.add_argument("--turbulence-banks", action="store_true",
                   help=f"design the turbulence bank set ({', '.join(MEMBER_LEVELS)}; 6 inputs) into the set "
                        "file --out (default: the cache that --tuning turbulence reads)")
    p.set_defaults(func=_run)


def _partial_loss(text: str) -> tuple[float, ...]:
    """The --partial-loss fractions (CliError naming a bad one)."""
    out = []
    for part in text.split(","):
        f = number("--partial-loss", part.strip())
        if not 0.0 < f < 1.0:
            raise CliError(f"--partial-loss {part.strip()}: the fraction of effectiveness lost F must lie in (0, 1)")
        if f in out:
            raise CliError(f"--partial-loss {text}: {part.strip()} is given twice")
        out.append(f)
    return tuple(out)


def _level_width(tuning, text: str):
    """The tuning with --failed-sensor-level-width's sensors set (CliError naming a bad entry),
    named NAME-wSENSORS."""
    table = {}
    for part in text.split(","):
        sensor, eq, value = part.strip().partition("=")
        if not eq:
            raise CliError(f"--failed-sensor-level-width {part.strip()!r}: give SENSOR=W, SENSOR=reading or SENSOR=range")
        if sensor in table:
            raise CliError(f"--failed-sensor-level-width {text}: {sensor} is given twice")
        table[sensor] = value if value in (READING, RANGE) else number("--failed-sensor-level-width", value)
    per = component_models(tuning.failure_model)
    try:
        widths = _sensor_level_width(table, "--failed-sensor-level-width")
    except TuningError as exc:
        raise CliError(str(exc)) from None
    for sensor in widths:
        if per[sensor] != "cover":
            raise CliError(f"--failed-sensor-level-width {sensor}: the sensor's failure model is {per[sensor]}; "
                           "a level width needs cover for it (e.g. --failure-model cover)")
    return dataclasses.replace(tuning, name=f"{tuning.name}-w{''.join(widths)}",
                               failed_sensor_level_width={**tuning.failed_sensor_level_width, **widths})


def _run(args) -> int:
    if args.partial_loss is not None and (args.turbulence_banks or args.schedule is not None):
        raise CliError("--partial-loss designs one point's bank; it is not supported with --schedule or "
                       "--turbulence-banks")
    if args.failed_sensor_level_width is not None and (args.turbulence_banks or args.schedule is not None):
        raise CliError("--failed-sensor-level-width designs one point's bank; give a tuning file with "
                       "failed_sensor_level_width to --schedule or --turbulence-banks instead")
    if args.turbulence_banks:
        return _run_turbulence_banks(args)
    if args.schedule is not None:
        return _run_schedule(args)
    if (args.node_tuning is not None or args.flap_layers is not None or args.node_p_min is not None
            or args.start_up_s is not None or args.calibration_start_up_s is not None or args.adapt_running_start
            or args.calibration_flight_s is not None or args.calibration_bank is not None
            or args.scale_model is not None):
        raise CliError("--node-tuning, --flap-layers, --node-p-min, --start-up-s, --calibration-start-up-s, "
                       "--calibration-flight-s, --calibration-bank, --scale-model and --adapt-running-start apply to a "
                       "scheduled design; "
                       "give --schedule [GRID] too")
    if args.gust_states_below_ft is not None:
        raise CliError("--gust-states-below-ft applies to a scheduled design; give --schedule [GRID] too "
                       "(--gust-states gives one point's bank gust states)")
    if args.gust_node_choice is not None:
        raise CliError("--gust-node-choice applies to a scheduled design with --gust-states-below-ft; "
                       "give --schedule [GRID] too")
    mach = number("--mach", args.mach)
    alt_ft = number("--alt-ft", args.alt_ft)
    if not MACH_RANGE[0] <= mach <= MACH_RANGE[1]:
        raise CliError(f"--mach {args.mach} is outside the design envelope "
                       f"{MACH_RANGE[0]}-{MACH_RANGE[1]}")
    if not ALT_FT_RANGE[0] <= alt_ft <= ALT_FT_RANGE[1]:
        raise CliError(f"--alt-ft {args.alt_ft} is outside the design envelope "
                       f"{ALT_FT_RANGE[0]:.0f}-{ALT_FT_RANGE[1]:.0f} ft")
    try:
        tuning = load_tuning(args.tuning)
    except TuningError as exc:
        raise CliError(f"--tuning: {exc}") from None
    tuning = gust_options(tuning, args.gust_level, args.gust_states)
    # a cover design calibrates its own dwell unless its tuning recommends one for that model
    calibrate_dwell = "dwell_s" not in tuning.estimator
    if args.failure_model is not None:
        try:
            failure_model = check_failure_model(args.failure_model)
        except ValueError as exc:
            raise CliError(f"--failure-model: {exc}") from None
        if failure_model != tuning.failure_model:
            calibrate_dwell = True
            tuning = dataclasses.replace(tuning, name=f"{tuning.name}-{failure_model}",
                                         failure_model=failure_model)
    if args.failed_sensor_noise is not None:
        if args.failed_sensor_noise not in FAILED_SENSOR_NOISES:
            raise CliError(f"--failed-sensor-noise {args.failed_sensor_noise!r}: valid: "
                           f"{', '.join(FAILED_SENSOR_NOISES)}")
        if args.failed_sensor_noise != tuning.failed_sensor_noise:
            tuning = dataclasses.replace(tuning, name=f"{tuning.name}-noise-{args.failed_sensor_noise}",
                                         failed_sensor_noise=args.failed_sensor_noise)
    if args.failed_sensor_level_q is not None:
        w = number("--failed-sensor-level-q", args.failed_sensor_level_q)
        if not w >= 0.0 or not uses_cover(tuning.failure_model):
            raise CliError(f"--failed-sensor-level-q {args.failed_sensor_level_q} must be >= 0 "
                           "and needs the cover failure model for some component (e.g. --failure-model cover)")
        tuning = dataclasses.replace(tuning, name=f"{tuning.name}-q{w:g}", failed_sensor_level_q=w)
    if args.failed_sensor_level_width is not None:
        tuning = _level_width(tuning, args.failed_sensor_level_width)
    partial = _partial_loss(args.partial_loss) if args.partial_loss is not None else ()
    thr = "_throttle" if args.throttle_input else ""
    thr += "".join(f"_partial{f:g}" for f in partial)
    out = writable_file(args.out or f"f16mmae_M{mach:.2f}_{alt_ft:.0f}ft_{tuning.name}{thr}.f16bank", "--out")
    report_dir = writable_dir(args.report, "--report") if args.report else None  # before the design
    t0 = time.perf_counter()
    try:
        design = design_bank(mach, alt_ft, tuning, throttle_input=bool(args.throttle_input), partial_loss=partial)
    except TrimError as exc:
        raise CliError(str(exc)) from None
    except DesignError as exc:
        raise CliError(f"the design is refused: {exc}") from None
    if calibrate_dwell and uses_cover(tuning.failure_model):
        design, cal = with_calibrated_dwell(design)
        print(f"  recommended dwell {cal['dwell_s']:g} s: the no-failure calibration flights' longest "
              f"excursion above the threshold is {cal['longest_s']:g} s ({cal['hypothesis']}; design/dwell.py)"
              + ("" if cal["bound_met"] else " -- longer than every candidate"))
    try:
        bank = write_bank(design, out)
    except OSError as exc:
        raise CliError(f"cannot write --out {out}: {exc}") from None
    trim = design.linearized.trim
    rho = max(f.gains.spectral_radius for f in design.filters)
    print(f"bank {out}: {len(bank)} hypotheses, tuning {tuning.name}, content hash {bank.content_hash}")
    print(f"  trim Mach {mach:g}, {alt_ft:.0f} ft: Vt {trim.vt_fps:.1f} ft/s, alpha "
          f"{math.degrees(trim.alpha_rad):.2f} deg, stabilators {math.degrees(trim.u_rad[0]):.2f} deg, "
          f"throttle {trim.throttle:.3f}")
    print(f"  largest error-dynamics spectral radius {rho:.6f} (all filters stable); "
          f"designed in {time.perf_counter() - t0:.2f} s")
    if args.report:
        paths = write_report(design, report_dir)
        print(f"  report: {', '.join(str(p) for p in paths)}")
    return 0


def gust_options(tuning, gust_level: str | None, gust_states: bool):
    """The tuning with ``--gust-level`` / ``--gust-states`` applied; the name says so
    (``NAME[-LEVEL][-gust]``, undone by ``design.bank.tuning_arguments``)."""
    if gust_level is not None:
        if gust_level not in TURBULENCE_LEVELS:
            raise CliError(f"--gust-level {gust_level!r} is not a turbulence level; valid: "
                           f"{', '.join(TURBULENCE_LEVELS)}")
        if gust_level != tuning.turbulence:
            tuning = dataclasses.replace(tuning, name=f"{tuning.name}-{gust_level}", turbulence=gust_level)
    if gust_states and tuning.gust_model != "dryden_states":
        tuning = dataclasses.replace(tuning, name=f"{tuning.name}-gust", gust_model="dryden_states")
    return tuning


def _run_schedule(args) -> int:
    if args.report:
        raise CliError("--report describes one design point; it cannot be combined with --schedule")
    if args.gust_states or args.gust_level is not None:
        raise CliError("--gust-states and --gust-level design one point; give a tuning file with gust_model "
                       "and turbulence to --schedule instead")
    if args.failed_sensor_level_q is not None:
        raise CliError("--failed-sensor-level-q designs one point; give a tuning file with "
                       "failed_sensor_level_q to --schedule instead")
    try:
        grid = parse_grid(args.schedule)
        tuning = load_tuning(args.tuning)
    except ScheduleSpecError as exc:
        raise CliError(f"--schedule: {exc}") from None
    except TuningError as exc:
        raise CliError(f"--tuning: {exc}") from None
    try:
        failure_model = schedule_failure_model(tuning, args.failure_model)
    except ValueError as exc:
        raise CliError(f"--failure-model: {exc}") from None
    try:
        sensor_noise = schedule_failed_sensor_noise(tuning, args.failed_sensor_noise)
    except ValueError as exc:
        raise CliError(f"--failed-sensor-noise: {exc}") from None
    workers = number("--workers", args.workers, integer=True, minimum=1, maximum=256) if args.workers else None
    node_tuning = args.node_tuning or DEFAULT_NODE_TUNING
    if node_tuning not in NODE_TUNINGS:
        raise CliError(f"--node-tuning {node_tuning!r}: valid: {', '.join(NODE_TUNINGS)}")
    if args.flap_layers not in (None, "on", "off"):
        raise CliError(f"--flap-layers {args.flap_layers!r}: valid: on, off")
    p_mins = P_MIN_CANDIDATES
    if args.node_p_min is not None:
        if node_tuning != "calibrated":
            raise CliError("--node-p-min chooses among floors on the calibration flights: it needs "
                           "--node-tuning calibrated (the fixed tuning's nodes keep its p_min)")
        p_mins = tuple(number("--node-p-min", v, minimum=0.0, exclusive=True,
                                      below=round(1.0 / len(names.ALL_HYPOTHESES), 6)) for v in args.node_p_min.split("/"))
    start_up = {"--start-up-s": START_UP_S, "--calibration-start-up-s": CALIBRATION_START_UP_S}
    for flag, given in (("--start-up-s", args.start_up_s), ("--calibration-start-up-s", args.calibration_start_up_s)):
        if given is not None:
            if node_tuning != "calibrated":
                raise CliError(f"{flag} goes with the calibration flights: it needs --node-tuning calibrated")
            start_up[flag] = number(flag, given, minimum=0.0, maximum=3600.0)
    if args.adapt_running_start and node_tuning != "calibrated":
        raise CliError("--adapt-running-start goes with the calibration flights: it needs --node-tuning calibrated")
    calibration_flight_s, calibration_bank, scale_model = NODE_FLIGHT_S, "complete", names.SCHEDULE_SCALE_MODEL
    if args.calibration_flight_s is not None or args.calibration_bank is not None:
        if node_tuning != "calibrated":
            raise CliError("--calibration-flight-s and --calibration-bank go with the calibration flights: they need "
                           "--node-tuning calibrated")
        if args.calibration_flight_s is not None:
            calibration_flight_s = number("--calibration-flight-s", args.calibration_flight_s,
                                          minimum=NODE_FLIGHT_S, maximum=MAX_CALIBRATION_FLIGHT_S)
        if args.calibration_bank is not None:
            calibration_bank = args.calibration_bank
            if calibration_bank not in CALIBRATION_BANKS:
                raise CliError(f"--calibration-bank {calibration_bank!r}: valid: {', '.join(CALIBRATION_BANKS)}")
    if args.scale_model is not None:
        if calibration_bank != "scaled":
            raise CliError("--scale-model gives the reference scale's model: it needs --calibration-bank scaled")
        try:
            scale_model = check_failure_model(args.scale_model)
        except ValueError as exc:
            raise CliError(f"--scale-model: {exc}") from None
    gust_ft, gust_choice = default_gust_shape(grid, tuning, node_tuning)   # the shipped default's shape
    if args.gust_states_below_ft is not None:
        gust_ft, gust_choice = None, "all"
        if args.gust_states_below_ft.strip().lower() != NO_GUST_STATES:
            try:
                gust_ft = check_gust_altitude(grid, args.gust_states_below_ft)
            except ScheduleSpecError as exc:
                raise CliError(f"--gust-states-below-ft: {exc}") from None
            if tuning.gust_model in GUST_STATE_MODELS:
                raise CliError(f"--gust-states-below-ft: the tuning {tuning.name} already models gust states "
                               f"({tuning.gust_model}) at every node")
            if node_tuning == "calibrated":
                gust_choice = names.SCHEDULE_GUST_NODE_CHOICE
    if args.gust_node_choice is not None:
        gust_choice = args.gust_node_choice
        if gust_choice not in GUST_NODE_CHOICES:
            raise CliError(f"--gust-node-choice {gust_choice!r}: valid: {', '.join(GUST_NODE_CHOICES)}")
        if gust_choice == "effort" and node_tuning != "calibrated":
            raise CliError("--gust-node-choice effort compares each node's calibration with and without gust "
                           "states: it needs --node-tuning calibrated")
        if gust_ft is None:
            raise CliError("--gust-node-choice chooses among the nodes at or below --gust-states-below-ft, and this "
                           "design has none (--gust-states-below-ft none, --node-tuning fixed without it, or a tuning "
                           "with gust states at every node): give --gust-states-below-ft FT")
    throttle = names.SCHEDULE_THROTTLE_INPUT if args.throttle_input is None else args.throttle_input
    thr = "_throttle" if throttle else ""
    gst = "" if gust_ft is None else f"_gust{gust_ft:g}"
    out = writable_file(args.out or f"f16mmae_scheduled_{tuning.name}{thr}{gst}.f16sched", "--out")
    how = "calibrated at every point from" if node_tuning == "calibrated" else "at every point:"
    print(f"scheduled design {format_spec(grid)}: {len(grid.mach) * len(grid.alt_ft)} points, "
          f"tuning {how} {tuning.name}, failure model {failure_model}, failed sensors' noise {sensor_noise}"
          + ("" if gust_ft is None else f", Dryden gust states at the nodes at or below {gust_ft:g} ft "
             + ("(the others inert)" if gust_choice == "all" else
                "where a node's calibration gains by them (the others inert)"))
          + (", the throttle as sixth input" if throttle else ""), flush=True)
    try:
        s = design_schedule(grid, args.tuning, out, workers=workers,
                            progress=lambda line: print("  " + line, flush=True), node_tuning=node_tuning,
                            flap_layers=args.flap_layers != "off", throttle_input=throttle,
                            p_min_candidates=p_mins, start_up_s=start_up["--start-up-s"],
                            calibration_start_up_s=start_up["--calibration-start-up-s"], failure_model=failure_model,
                            gust_states_below_ft=gust_ft, gust_node_choice=gust_choice,
                            running_start=args.adapt_running_start, calibration_flight_s=calibration_flight_s,
                            calibration_bank=calibration_bank, scale_model=scale_model,
                            failed_sensor_noise=sensor_noise)
    except ScheduleSpecError as exc:
        raise CliError(f"--schedule: {exc}") from None
    except DesignError as exc:
        raise CliError(f"the scheduled design is refused: {exc}") from None
    except OSError as exc:
        raise CliError(f"cannot write --out {out}: {exc}") from None
    print(f"scheduled bank {s['path']}: {s['covered']} banks ({s['alternates']} of them in the other flap "
          f"position), {len(s['skipped'])} left out (do not trim), {s['bytes'] / 1e6:.1f} MB, "
          f"content hash {s['content_hash']}")
    for p in s["skipped"]:
        print(f"  left out: Mach {p['mach']:g}, {p['alt_ft']:.0f} ft: {p['reason']}")
    print(f"  designed in {s['wall_s']:.1f} s wall ({s['design_s']:.1f} s of design over the workers); "
          f"in force before air data: Mach {s['primary'][0]:g}, {s['primary'][1]:.0f} ft")
    return 0


def _run_turbulence_banks(args) -> int:
    """``--turbulence-banks``: the set's members and selector into the set file --out."""
    from ..design.turbulence_banks import set_path

    if (args.schedule is not None or args.gust_states or args.throttle_input is not None or args.gust_level is not None
            or args.failure_model is not None or args.failed_sensor_noise is not None):
        raise CliError("--turbulence-banks designs its own members (the tuned tuning, the throttle input, "
                       "each turbulence level, its failure model and failed sensors' noise); give only --out")
    out = writable_file(args.out, "--out") if args.out else set_path()
    t0 = time.perf_counter()
    try:
        design_set(out, progress=lambda line: print("  " + line, flush=True))
    except (TrimError, DesignError, BankSetError) as exc:
        raise CliError(f"the design is refused: {exc}") from None
    s = load_set(out)
    print(f"turbulence bank set {out}: members {', '.join(s.levels)}, set hash {s.set_hash[:12]}, "
          f"designed in {time.perf_counter() - t0:.1f} s")
    return 0
