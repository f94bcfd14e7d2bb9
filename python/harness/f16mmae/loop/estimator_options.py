"""The estimator's settings and their command-line flags: one table.

Every setting of ``core.HierarchicalBank`` a user may give is one :class:`EstimatorOption`:
its key (in ``Estimator(**options)``, in each run record's ``estimator`` and in
``summary.json``), the flag that sets it -- the same flag on ``f16mmae run``, every campaign,
``bench truth``, ``hil`` and ``mmae-daemon`` --, its kind, its valid range and its help.  The
command line (``cli.options``), the reproduce command of a run (``campaign.engine.drilldown``)
and the daemon's arguments (``lcm.daemon.daemon_flags``) all read this table, so an option
added here is accepted, recorded, reproduced and passed to the daemon alike.

Kinds: ``number`` (a finite float in a range), ``choice`` (one of ``choices``), ``switch`` (on
when given), ``file`` (the path of a file the option reads: :data:`FILE_LOADERS`), ``table``
(``NAME=VALUE`` entries separated by commas, kept as given and read by :data:`TABLE_PARSERS`) and
``values`` (comma-separated positive numbers; daemon only: the form ``core_arguments`` gives
``actuator_limits``).
"""
from __future__ import annotations

import json

from dataclasses import dataclass

from .. import core
from ..names import (DWELL_S_MAX, K_BANK, SCHEDULE_ADAPT_COUNTED_CHANNEL, SCHEDULE_CALM_COMPLETE,
                     SCHEDULE_CALM_MEASURE, SCHEDULE_COMPLETE_TRIM_HOLD,
                     SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S, SCHEDULE_DWELL_NATS_PER_HYPOTHESIS,
                     SCHEDULE_DWELL_S_PER_HYPOTHESIS,
                     SCHEDULE_ADAPT_LEVEL_SCALE, SCHEDULE_ADAPT_LEVEL_SCALE_CHANNEL,
                     SCHEDULE_ADAPT_LEVEL_SCALE_FROM, SCHEDULE_ADAPT_FLOOR_S, SCHEDULE_ADAPT_SCALE_MAX_FROM,
                     SCHEDULE_MANEUVER_SETTING,
                     SCHEDULE_MANEUVER_TEMPERING_G,
                     SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG, SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG,
                     SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG,
                     SCHEDULE_MODES, SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS, SCHEDULE_ROUGH_P_MIN, SCHEDULE_ROUGH_SCALE,
                     SCHEDULE_SET_TEMPERING, SCHEDULE_SET_TEMPERING_ROUGH, SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT,
                     SCHEDULE_TRIM_TIME_CONSTANT_S, SENSORS,
                     THRESHOLD_DEFAULT)


#: The level-1 floor's bound at the default threshold (0.9, which every shipped bank
#: recommends): with the K_BANK - 1 other hypotheses on their floors a hypothesis holds at most
#: 1 - (K_BANK - 1) P, which must exceed the threshold.
LEVEL1_P_MIN_BELOW = (1.0 - THRESHOLD_DEFAULT) / (K_BANK - 1)


@dataclass(frozen=True)
class EstimatorOption:
    key: str
    flag: str
    kind: str                       # number | choice | switch | file | table | values
    help: str
    metavar: str | None = None
    minimum: float | None = None    # number: at least this (above it if exclusive)
    exclusive: bool = False
    below: float | None = None      # number: below this
    maximum: float | None = None    # number: at most this
    choices: tuple[str, ...] = ()
    requires: str | None = None     # the key of an option this one applies with
    on_command_line: bool = True    # False: a daemon flag only (core_arguments' expansion)
    in_daemon: bool = True          # False: mmae-daemon has no flag for it (in process only, or CLOSED_LOOP)
    inline: bool = False            # file: an argument with '=' is the table itself, not a path

    def is_inline(self, value) -> bool:
        """Whether ``value`` of this ``file`` option is its table inline (kept as given, not a path)."""
        return self.inline and isinstance(value, str) and "=" in value

    @property
    def dest(self) -> str:
        """The argparse attribute of :attr:`flag`."""
        return self.flag[2:].replace("-", "_")

    @property
    def negatable(self) -> bool:
        """A switch a default setting turns on (``names.SCHEDULE_MANEUVER_SETTING``): ``--no-FLAG``
        turns it off."""
        return self.kind == "switch" and SCHEDULE_MANEUVER_SETTING.get(self.key) is True


ESTIMATOR_OPTIONS: tuple[EstimatorOption, ...] = (
    EstimatorOption("threshold", "--threshold", "number", metavar="P", minimum=0.5, exclusive=True, below=1.0,
                    help="declare a hypothesis when its probability exceeds P (0.5 < P < 1; "
                         "default: the bank's recommended, else 0.9)"),
    EstimatorOption("dwell_s", "--dwell-s", "number", metavar="S", minimum=0.0, maximum=DWELL_S_MAX,
                    help="... for S seconds in a row (default: the bank's recommended, else 0.25)"),
    EstimatorOption("p_min", "--p-min", "number", metavar="P", minimum=0.0, below=1.0 / K_BANK,
                    help="probability floor everywhere (default: the bank's recommended -- tuned: 1e-9; "
                         "a scheduled bank: each node's, blended -- else the core's 0.001, the paper's)"),
    EstimatorOption("start_up_s", "--start-up-s", "number", metavar="S", minimum=0.0, maximum=3600.0,
                    help="the first S seconds of frames after the estimator starts update its filters but "
                         "weigh no hypothesis: the filters start at the design trim while the aircraft is in "
                         "flight near it (cpp/f16mmae/filter_bank.h). Default: the bank's recommendation -- "
                         "a scheduled-bank file's start_up_s (the scheduled bank: 1 s, design/calibrate.py "
                         "START_UP_S; its floors bounded on calibration flights with 0.25 s) -- else 0, "
                         "weigh from the first frame"),
    EstimatorOption("fresh_floor_levels", "--fresh-floor-levels", "switch",
                    help="a hypothesis on its probability floor restarts the tracked levels of the sensors it "
                         "fails at each reading (the floor is the mass of a failure beginning now) instead of "
                         "following the healthy reading there: a cover or constant sensor hypothesis that leaves "
                         "the floor predicts the failed reading from what it has read since (cpp/f16mmae/"
                         "filter_bank.h). Default off"),
    EstimatorOption("adapt_turbulence", "--adapt-turbulence", "switch",
                    help="adapt the likelihoods on line to the turbulence intensity (one residual "
                         "covariance scale common to all hypotheses; cpp/f16mmae/turbulence_adaptation.h). "
                         "Default off: the bank as designed"),
    EstimatorOption("adapt_reference", "--adapt-reference", "number", metavar="RHO", minimum=0.0, maximum=100.0,
                    requires="adapt_turbulence",
                    help="with --adapt-turbulence: the residual power ratio rho_0 above which the "
                         "likelihoods are tempered (default: a scheduled bank's per-node references where "
                         "it carries them, else 0.6; higher tempers less)"),
    EstimatorOption("adapt_channel_weight", "--adapt-channel-weight", "number", metavar="G", minimum=0.0,
                    maximum=1.0,
                    help="with --adapt-turbulence or --turbulence-banks: temper each measurement channel by "
                         "s^(1-G) s_j^G, s_j its own scale from the best-fitting filter's share of that channel "
                         "in its residual power, so that gusts in one channel temper the evidence in the others "
                         "less (cpp/f16mmae/turbulence_adaptation.h). Default 0: one scale common to all"),
    EstimatorOption("adapt_own_channels", "--adapt-own-channels", "switch", requires="adapt_turbulence",
                    help="with --adapt-turbulence: each filter's residual power counts per channel it reads "
                         "(rho = min_k q_k / m_k, m_k the channels filter k reads), so that a hypothesis whose "
                         "failed sensor's channel is uninformative (a `constant` or `cover` failed sensor) does "
                         "not read the air calmer than it is (cpp/f16mmae/turbulence_adaptation.h). A bank "
                         "without uninformative channels is unchanged. Default: on for a scheduled bank "
                         "(scheduled_defaults: with VEL's channel counted, --adapt-counted-channel; given, "
                         "every uninformative channel left out unless --adapt-counted-channel), off otherwise; "
                         "a turbulence bank set's members always run with it"),
    EstimatorOption("adapt_running_start", "--adapt-running-start", "switch", requires="adapt_turbulence",
                    help="with --adapt-turbulence: the residual power ratio rho is the plain mean of its "
                         "samples from the start until the average's length (then its usual exponential "
                         "average), so the tempering is the air's within a second of the start instead of "
                         "rising from none over the time constant (cpp/f16mmae/turbulence_adaptation.h). "
                         "Default: a scheduled bank's recommendation, else off"),
    EstimatorOption("adapt_level_scale", "--adapt-level-scale", "choice", metavar="on|off", choices=("on", "off"),
                    requires="adapt_turbulence",
                    help="with --adapt-turbulence: on, while a failure read as a sensor level (a failed VEL or "
                         "roll gyro of the scheduled design) is declared, every hypothesis reading that level "
                         "gains (1/2) ln s a frame: the others' tempered densities carry s on its channel, the "
                         "level's does not, so NONE does not win the failure back by the tempering alone "
                         "(cpp/f16mmae/filter_bank.h). Default: on on a scheduled bank "
                         "(names.SCHEDULE_ADAPT_LEVEL_SCALE), else off"),
    EstimatorOption("adapt_level_scale_channel", "--adapt-level-scale-channel", "choice",
                    metavar="|".join(SENSORS) + "|none",
                    choices=tuple(s.lower() for s in SENSORS) + ("none",), requires="adapt_turbulence",
                    help="with --adapt-turbulence: every hypothesis reading the SENSOR's channel as a level "
                         "gains (1/2) ln max(s / S0, 1) a frame at every level, not only while that failure "
                         "is declared (--adapt-level-scale): the tempered densities of the others carry s on "
                         "that channel, the level's does not (cpp/f16mmae/filter_bank.h). Default: vel on a "
                         "scheduled bank (names.SCHEDULE_ADAPT_LEVEL_SCALE_CHANNEL), else none; none: off"),
    EstimatorOption("adapt_level_scale_from", "--adapt-level-scale-from", "number", metavar="S0", minimum=1.0,
                    maximum=1000.0, requires="adapt_turbulence",
                    help="with --adapt-turbulence: the S0 of --adapt-level-scale-channel's gain, nothing while "
                         "the adaptation's scale s is below it (cpp/f16mmae/filter_bank.h). Default: 8 on a "
                         "scheduled bank (names.SCHEDULE_ADAPT_LEVEL_SCALE_FROM), else 1: (1/2) ln s"),
    EstimatorOption("adapt_floor_time_constant_s", "--adapt-floor", "number", metavar="TAU_S", minimum=0.0,
                    maximum=3600.0, requires="adapt_turbulence",
                    help="with --adapt-turbulence: a lull floor on the tempering: the scale s reads the larger of "
                         "the residual power ratio (averaged over 5 s) and the same ratio averaged over TAU_S "
                         "seconds (a plain mean from the start, in force from TAU_S / 2 on, held while climbing "
                         "or maneuvering), so a burst of gusts after a lull does not meet the untempered design "
                         "(cpp/f16mmae/turbulence_adaptation.h). 0: off; else at least the 5-s averaging time. "
                         "Default: names.SCHEDULE_ADAPT_FLOOR_S on a scheduled bank, else 0"),
    EstimatorOption("adapt_scale_max_from", "--adapt-scale-max-from", "number", metavar="RHO", minimum=0.0,
                    maximum=100.0, requires="adapt_turbulence",
                    help="with --adapt-turbulence: the bound's knee: from the residual power ratio RHO on, the "
                         "bound on the tempering s (100) rises with the air at the adaptation's gain, so air "
                         "rougher than RHO is tempered as the adaptation's line reads and gusts there are not "
                         "read as failures; between the line's meeting the bound and RHO, s stays at the bound, "
                         "so failures there are not tempered away (cpp/f16mmae/turbulence_adaptation.h). "
                         "Moderate air reads at most 2.3, severe air 2.7 to 15.5 over the envelope. 0: off. "
                         "Default: names.SCHEDULE_ADAPT_SCALE_MAX_FROM on a scheduled bank, else 0"),
    EstimatorOption("adapt_all_channels", "--adapt-all-channels", "switch", requires="adapt_turbulence",
                    in_daemon=False,
                    help="with --adapt-turbulence on a scheduled bank: the residual power over all channels "
                         "(rho = min_k q_k / m), the rule a scheduled bank was flown with before its design's "
                         "revision 12, in place of its default --adapt-own-channels (mmae-daemon: leave out "
                         "--adapt-own-channels)"),
    EstimatorOption("adapt_counted_channel", "--adapt-counted-channel", "choice", metavar="|".join(SENSORS),
                    choices=tuple(s.lower() for s in SENSORS), requires="adapt_turbulence",
                    help="with own channels (--adapt-own-channels, a scheduled bank's default): the failed SENSOR's uninformative channel still counts in "
                         "m_k: the hypotheses that leave out only that channel count their residual power over "
                         "every channel, as without own channels; the others per channel they read "
                         "(cpp/f16mmae/turbulence_adaptation.h). Default: VEL on a scheduled bank without "
                         "--adapt-own-channels, else none"),
    EstimatorOption("adapt_excluded_channel", "--adapt-excluded-channel", "choice", metavar="|".join(SENSORS),
                    choices=tuple(s.lower() for s in SENSORS), requires="adapt_turbulence",
                    help="with --adapt-turbulence: the hypotheses that read the SENSOR's channel as a free level "
                         "(a `constant` or `cover` level for it) leave the adaptation's minimum over the "
                         "hypotheses; they still get its scale (unless the presumed hypothesis reads it so "
                         "too; cpp/f16mmae/turbulence_adaptation.h). Default: none"),
    EstimatorOption("calm_complete", "--calm-complete", "table", metavar="NAME=RHO,...", requires="adapt_turbulence",
                    help="with --adapt-turbulence: while the adaptation's measured residual power ratio (rho-bar, "
                         "the least of the hypotheses' q_k / m averaged) is below RHO, decided while no failure "
                         "is presumed or rising, the hypotheses that read sensor NAME as a tracked level read it "
                         "as the paper's complete failure, the trim plus its noise: a constant that fits a calm "
                         "reading is then no evidence (cpp/f16mmae/calm_air_complete.h). RHO is a multiple of "
                         "the scheduled bank's calm-air reference at the flight condition (its nodes' rho-bar "
                         "midway between calm and light air), the bound itself on a bank without one; NAME=0: "
                         "off. Default: "
                         f"{SCHEDULE_CALM_COMPLETE} on a scheduled bank whose nodes carry the reference, with "
                         "--adapt-turbulence (names.SCHEDULE_CALM_COMPLETE), else none"),
    EstimatorOption("calm_measure", "--calm-measure", "choice", metavar="power|whiteness|either",
                    choices=("power", "whiteness", "either"), requires="adapt_turbulence",
                    help="with --calm-complete, how the air is read: power, the measured power ratio against "
                         "RHO times the reference; whiteness, how white the presumed filter's residuals are on "
                         "VEL, AOA, AZ, AY and ROL (W-bar: the power of 8-frame block means over the mean power, "
                         "about 1 in the light turbulence a scheduled bank is designed for, below it in calm air, "
                         "where the gusts' gains chase the sensors' noise) against --calm-whiteness-bound; "
                         "either: calm by one or the other (cpp/f16mmae/residual_whiteness.h). Default: "
                         f"{SCHEDULE_CALM_MEASURE} where --calm-complete is a scheduled bank's default "
                         "(names.SCHEDULE_CALM_MEASURE), else power"),
    EstimatorOption("calm_whiteness_bound", "--calm-whiteness-bound", "number", metavar="W", minimum=0.0,
                    exclusive=True, maximum=100.0, requires="adapt_turbulence",
                    help="with --calm-measure whiteness or either: the air is calm while W-bar < W "
                         "(0 < W <= 100; default 0.78)"),
    EstimatorOption("complete_trim_hold", "--complete-trim-hold", "choice", metavar="off|suspected|declared",
                    choices=("off", "suspected", "declared"),
                    help="a complete sensor failure's hypothesis reads the failed sensor against the trim in force "
                         "when a failure began to show, held while one is suspected (declared, or a failure "
                         "hypothesis above the trim tracker's freeze probability) or only while one is declared, "
                         "not against the trim the schedule and the trim tracker move with the aircraft: a failed "
                         "sensor does not follow them (cpp/f16mmae/complete_trim_hold.h). Default: "
                         f"{SCHEDULE_COMPLETE_TRIM_HOLD} on a scheduled bank with --adapt-turbulence "
                         "(names.SCHEDULE_COMPLETE_TRIM_HOLD), else off"),
    EstimatorOption("complete_trim_time_constant_s", "--complete-trim-time-constant", "number", metavar="S",
                    minimum=0.0, maximum=3600.0,
                    help="a complete sensor failure's hypothesis reads the failed sensor against the trim in force "
                         "averaged over S seconds while nothing is held (with --complete-trim-hold), the flight "
                         "condition's trim rather than the gusts' wander of the measured airspeed "
                         "(cpp/f16mmae/complete_trim_hold.h). Default: "
                         f"{SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S:g} on a scheduled bank with --adapt-turbulence "
                         "(names.SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S), else 0 (the trim in force)"),
    EstimatorOption("adapt_reference_climb", "--adapt-reference-climb", "number", metavar="RHO", minimum=0.0,
                    maximum=100.0, requires="adapt_turbulence",
                    help="with --adapt-turbulence: the reference while the measured air data climb or descend "
                         "faster than 300 ft/min or change Mach faster than 0.001/s (and the hold after; "
                         "cpp/f16mmae/climb_reference.h); elsewhere the reference above. Default off"),
    EstimatorOption("adapt_reference_climb_hold_s", "--adapt-reference-climb-hold", "number", metavar="S",
                    minimum=0.0, maximum=3600.0, requires="adapt_reference_climb",
                    help="with --adapt-reference-climb: keep the climb reference S seconds after the climb, "
                         "descent or speed change ends (the level-off; default 0)"),
    EstimatorOption("adapt_reference_climb_dwell_s", "--adapt-reference-climb-dwell", "number", metavar="S",
                    minimum=0.0, maximum=DWELL_S_MAX, requires="adapt_reference_climb",
                    help="with --adapt-reference-climb: a declaration at level 0 while that reference is in force "
                         "(the climb, descent or speed change and its hold) needs S seconds above the threshold "
                         "instead of the dwell (cpp/f16mmae/climb_reference.h). Default 0: the dwell everywhere"),
    EstimatorOption("turbulence_banks", "--turbulence-banks", "switch",
                    help="fly the turbulence bank set: banks designed for rising turbulence intensities (the "
                         "shipped set: calm air and light turbulence), the running one chosen on line by its "
                         "measured residual power, handed over bumplessly (cpp/f16mmae/turbulence_bank_set.h; "
                         "with --tuning turbulence, whose bank file is the set's: mmae-daemon --bank SET "
                         "--turbulence-banks; flown with the load-factor tempering its file recommends, "
                         "docs/results/turbulence_banks.md). Default off"),
    EstimatorOption("set_tempering", "--set-tempering", "number", metavar="W", minimum=0.0, exclusive=True,
                    maximum=1.0,
                    help="with --turbulence-banks or --adapt-turbulence: each frame the best-fitting failure "
                         "hypothesis has its evidence against NONE tempered by 1 + W (s - 1) in place of the "
                         "turbulence adaptation's s, except the hypotheses the gusts mimic, kept at s: the "
                         "stabilators and flaperons with --turbulence-banks, and with a bank's own adaptation "
                         "also AZ, AOA and VEL (names.ADAPT_SET_TEMPERING_FULL; "
                         "cpp/f16mmae/turbulence_adaptation.h). Default: 0.25 on a scheduled bank with "
                         "--adapt-turbulence (names.SCHEDULE_SET_TEMPERING), else 1: every hypothesis by s"),
    EstimatorOption("set_tempering_rho", "--set-tempering-rho", "number", metavar="RHO", minimum=0.0,
                    maximum=100.0, requires="set_tempering",
                    help="with --set-tempering: spare only while the member in force measures rho >= RHO "
                         "(the set's measure of the air; between moderate and severe air: "
                         "design.turbulence_banks.FLOOR_RHO, 2.68, spares in severe air only). Default 0: at any rho"),
    EstimatorOption("set_tempering_rough", "--set-tempering-rough", "number", metavar="RHO", minimum=0.0,
                    maximum=100.0, requires="set_tempering",
                    help="with --set-tempering: while the air's measured rho reads at least RHO (severe air) the "
                         "rudder and the lateral accelerometer (names.ADAPT_SET_TEMPERING_ROUGH) keep the full s too, "
                         "or the share --set-tempering-rough-weight gives: spared as before in moderate air, where "
                         "their failures need the sparing, tempered more where the gusts lift them "
                         "(cpp/f16mmae/turbulence_adaptation.h rough_tempering). Default on a scheduled bank "
                         f"with --adapt-turbulence: {SCHEDULE_SET_TEMPERING_ROUGH:g} "
                         "(names.SCHEDULE_SET_TEMPERING_ROUGH; moderate air reads at most 2.3, severe air "
                         "2.7 low to 15 high up); 0: off, spared at any rho"),
    EstimatorOption("set_tempering_rough_weight", "--set-tempering-rough-weight", "number", metavar="W",
                    minimum=0.0, exclusive=True, maximum=1.0, requires="set_tempering_rough",
                    help="with --set-tempering-rough: in rough air the rudder's or the lateral accelerometer's "
                         "evidence is tempered by "
                         "1 + W (s - 1) when it fits best, in place of --set-tempering's share. Default on a "
                         f"scheduled bank with --adapt-turbulence: {SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT:g} "
                         "(names.SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT), else 1: the full s"),
    EstimatorOption("set_tempering_margin", "--set-tempering-margin", "switch", requires="set_tempering",
                    help="with --set-tempering: the spared hypothesis's evidence is its margin over the "
                         "best-fitting of NONE and the hypotheses kept at s (the stabilators and flaperons), "
                         "not over NONE alone: a sensor hypothesis that fits a stabilator's onset a little "
                         "better than the stabilator's own filter gains only that little over it "
                         "(cpp/f16mmae/turbulence_adaptation.h). Default: over NONE"),
    EstimatorOption("spare_dwell_s", "--set-tempering-dwell", "number", metavar="S", minimum=0.0,
                    maximum=DWELL_S_MAX, requires="set_tempering",
                    help="with --set-tempering: a declaration at level 0 needs S seconds above the threshold, "
                         "instead of the dwell, on the frames where the tempering spares the best-fitting "
                         "hypothesis (with --set-tempering-rho: severe air only; the tempering has already held "
                         "the onset back there; cpp/f16mmae/hierarchical_bank.h spare_dwell_s). "
                         "Default 0: the dwell everywhere"),
    # mmae-daemon takes it by the hypotheses' names, --set-tempering-margin-over LS,RS (lcm.daemon.daemon_flags)
    EstimatorOption("set_tempering_margin_stabilators", "--set-tempering-margin-stabilators", "switch",
                    requires="set_tempering_margin", in_daemon=False,
                    help="with --set-tempering-margin: the margin is over the best-fitting of NONE and the "
                         "stabilators only (not the flaperons, which fit severe air's gusts better than NONE "
                         "on many frames; cpp/f16mmae/turbulence_adaptation.h spare_margin_over). Default: "
                         "over NONE and every hypothesis kept at s"),
    EstimatorOption("adaptive_dither", "--adaptive-dither", "switch", in_daemon=False,
                    help="with --turbulence-banks or --adapt-turbulence: the closed loop scales the truth's "
                         "surface dither each frame by the turbulence the estimator measures (the set member's "
                         "rho over the member's reference, or the adaptation's measured rho-bar over a "
                         "reference scheduled on the air data; square root, capped by the actuators' rates; "
                         "truth/dither.py adaptive_gains): the calm-air dither in calm, light and moderate "
                         "air, a slower, larger flaperon line in severe gusts; with one adapted bank also the "
                         "rudder's line grown with the air above light (at most 1.5 x). The default with "
                         "--turbulence-banks and with a scheduled bank's --adapt-turbulence (over LCM too: the "
                         "status carries the member and its rho); --fixed-dither turns it off"),
    EstimatorOption("fixed_dither", "--fixed-dither", "switch", in_daemon=False,
                    help="with --turbulence-banks, or a scheduled bank with --adapt-turbulence: the fixed "
                         "(calm-air) dither at every turbulence level instead of the adaptive dither "
                         "(--adaptive-dither, the default there)"),
    EstimatorOption("fixed_rudder_dither", "--fixed-rudder-dither", "switch", in_daemon=False,
                    help="with one adapted bank's adaptive dither (a scheduled bank's --adapt-turbulence): the "
                         "rudder's line stays the calm-air one at every level, as before round 50 (the "
                         "adaptive dither grows it with the air above light: truth/dither.py "
                         "adaptive_rudder_gain). Default off"),
    EstimatorOption("sensor_loss_dither", "--sensor-loss-dither", "switch", in_daemon=False,
                    help="the closed loop raises the truth's surface dither on the lines a sensor saw best "
                         "while the estimator declares that sensor failed, within the subliminal criterion "
                         "(truth/dither.py sensor_loss_gains). Default off"),
    EstimatorOption("trim_time_constant_s", "--trim-tracking", "number", metavar="TAU_S", minimum=0.0,
                    maximum=1e6,
                    help="track the trim on line with time constant TAU_S seconds (e.g. 30): the "
                         "bank's trim plus a slow low-pass offset of u and z, frozen while a failure "
                         "hypothesis rises or is declared; 0: off (default: 30 on a scheduled bank with "
                         "--adapt-turbulence, names.SCHEDULE_TRIM_TIME_CONSTANT_S; else off)"),
    EstimatorOption("trim_freeze_probability", "--trim-freeze-probability", "number", metavar="P", minimum=0.0,
                    exclusive=True, maximum=1.0, requires="trim_time_constant_s",
                    help="with --trim-tracking: a failure hypothesis above P freezes the trim "
                         "estimate (0 < P <= 1; default 0.05; 1 freezes only at a declaration)"),
    EstimatorOption("trim_steady_g", "--trim-tracking-steady", "number", metavar="G", minimum=0.0,
                    exclusive=True, maximum=10.0, requires="trim_time_constant_s",
                    help="with --trim-tracking: track only in steady level flight, frozen (and the hold after) "
                         "while the estimated load factor is more than G g off the trim, the estimated roll rate "
                         "above 5 deg/s, or the air data climb (300 ft/min) or change Mach (0.001/s); and of the "
                         "measurements only AOA, the one a lighter aircraft's trim moves "
                         "(cpp/f16mmae/trim_tracker.h). Default off: every frame the freeze rule allows"),
    EstimatorOption("trim_steady_air_data", "--trim-tracking-steady-air-data", "choice", metavar="on|off",
                    choices=("on", "off"), requires="trim_steady_g",
                    help="with --trim-tracking-steady: off lets the air data's climb and Mach rates no longer "
                         "freeze the tracking (the load factor and roll rate still do), for a trim in force that "
                         "carries the climb's and the acceleration's own trim (--maneuver-trim), so a lighter "
                         "aircraft's angle of attack is tracked through climbs, descents and speed changes too "
                         "(core trim_steady_climb_ft_s and trim_steady_mach_per_s infinite; "
                         "cpp/f16mmae/trim_tracker.h). Default on"),
    EstimatorOption("trim_steady_measurements", "--trim-tracking-steady-measurements", "table", metavar="NAME,...",
                    requires="trim_steady_g",
                    help="with --trim-tracking-steady: the measurements whose trim offsets are tracked (the others "
                         "keep the scheduled trim), e.g. AOA,VEL: between the nodes in slow flight the held speed's "
                         "trim differs from the interpolated one, and with AOA alone the flaperons read the "
                         "difference (cpp/f16mmae/trim_tracker.h). Default AOA"),
    EstimatorOption("trim_load_factor", "--trim-tracking-load-factor", "choice", metavar="on|off",
                    choices=("on", "off"), requires="trim_steady_g",
                    help="with --trim-tracking-steady: on applies the tracked angle-of-attack offset as n times "
                         "the 1-g offset, n the measured AZ low-passed (0.5 s): a lighter aircraft's alpha offset "
                         "grows with the load factor (lift equation), so turns and pull-ups, where the tracking "
                         "is frozen, get the weight's offset at their load factor "
                         "(cpp/f16mmae/trim_tracker.h). Default off"),
    EstimatorOption("schedule_mode", "--schedule-mode", "choice", metavar="|".join(SCHEDULE_MODES),
                    choices=SCHEDULE_MODES,
                    help="a scheduled bank (--bank scheduled): interpolate between grid points on the "
                         "measured air data, or switch to the nearest with hysteresis (default "
                         f"{SCHEDULE_MODES[0]}; a bank designed at one point ignores it)"),
    EstimatorOption("air_data_time_constant_s", "--air-data-time-constant", "number", metavar="TAU_S",
                    minimum=0.0, maximum=60.0,
                    help="a scheduled bank: time constant of the air data's low-pass the schedule follows "
                         "(s; a running mean for its first TAU_S; 0: none; default 2; cpp/f16mmae/scheduled_filters.h)"),
    EstimatorOption("maneuver_kinematics", "--maneuver-kinematics", "switch",
                    help="add to the filters' propagation the kinematic and gravity terms their wings-level "
                         "linearization drops (steady turns and pull-ups; cpp/f16mmae/maneuver_kinematics.h). "
                         "Default off (the bank as designed), but on with a scheduled bank's --adapt-turbulence "
                         "(--maneuver-setting); --no- turns it off there"),
    EstimatorOption("actuator_limits", "--actuator-limits", "switch",
                    help="the filters see the commands through the actuators' rate and position limits "
                         "(a roll-in's or pull-up's saturated commands; cpp/f16mmae/actuator_limits.h). "
                         "Default off (the bank as designed), but on with a scheduled bank's --adapt-turbulence "
                         "(--maneuver-setting); --no- turns it off there"),
    EstimatorOption("maneuver_tempering_g", "--maneuver-tempering", "number", metavar="G", minimum=0.0,
                    maximum=100.0,
                    help="temper every likelihood by 1 + (dn/G)^2 while the estimated load factor is dn g off "
                         "the trim (a pull-up's or a severe gust's model error; cpp/f16mmae/maneuver_kinematics.h; "
                         "0: off). Default off; with --turbulence-banks the set file's recommended tempering (1 g); "
                         f"{SCHEDULE_MANEUVER_TEMPERING_G:g} g on a scheduled bank with --adapt-turbulence "
                         "(names.SCHEDULE_MANEUVER_TEMPERING_G)"),
    EstimatorOption("maneuver_tempering_deadband_g", "--maneuver-tempering-deadband", "number", metavar="D",
                    minimum=0.0, maximum=10.0, requires="maneuver_tempering_g",
                    help="with --maneuver-tempering G: only the load factor beyond D g tempers, "
                         "1 + (max(0, |dn| - D)/G)^2, so that turbulence in level flight tempers nothing while a "
                         "pull-up still does (cpp/f16mmae/maneuver_kinematics.h). Default 0: no dead band"),
    EstimatorOption("maneuver_tempering_alpha_deg", "--maneuver-tempering-alpha", "number", metavar="DEG",
                    minimum=0.0, maximum=90.0,
                    help="temper every likelihood by a further (da/DEG)^2 added to the turbulence scale s while the "
                         "estimated angle of attack is da deg off the trim beyond the dead band: slow flight's excursions take the aircraft out of the linear "
                         "aerodynamics at a load factor too small to temper (cpp/f16mmae/maneuver_kinematics.h; "
                         "0: off). Default off; "
                         f"{SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG:g} deg on a scheduled bank with --adapt-turbulence "
                         "(names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG)"),
    EstimatorOption("maneuver_tempering_alpha_deadband_deg", "--maneuver-tempering-alpha-deadband", "number",
                    metavar="DEG", minimum=0.0, maximum=90.0, requires="maneuver_tempering_alpha_deg",
                    help="with --maneuver-tempering-alpha: only the excursion beyond DEG sqrt(s) tempers, s the "
                         "turbulence adaptation's scale, so that the angle of attack the gusts themselves give "
                         "tempers nothing (cpp/f16mmae/maneuver_kinematics.h). Default 0: no dead band; "
                         f"{SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG:g} deg with a scheduled bank's default "
                         "angle-of-attack tempering"),
    EstimatorOption("maneuver_tempering_alpha_trim_deg", "--maneuver-tempering-alpha-trim", "number",
                    metavar="DEG", minimum=0.0, maximum=90.0, requires="maneuver_tempering_alpha_deg",
                    help="with --maneuver-tempering-alpha A: above a trim angle of attack of DEG the reference "
                         "shrinks to A (DEG / alpha0)^3, alpha0 the trim in force's angle of attack (the scheduled "
                         "node's with the trim tracker's and the maneuver trim's offsets), so that slow flight near "
                         "the lift curve's bend tempers sooner "
                         "(cpp/f16mmae/maneuver_kinematics.h). Default 0: off; "
                         f"{SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG:g} deg with a scheduled bank's default "
                         "angle-of-attack tempering"),
    EstimatorOption("maneuver_tempering_added_g", "--maneuver-tempering-added", "number", metavar="G",
                    minimum=0.0, maximum=100.0,
                    help="temper every likelihood by a further (dn/G)^2 added to the turbulence scale s while the "
                         "estimated load factor is dn g off the trim beyond the dead band: a pull-up or a turn in "
                         "light air tempers as --maneuver-tempering G does, severe air's gusts inside the band "
                         "do not (cpp/f16mmae/maneuver_kinematics.h; 0: off). Default off"),
    EstimatorOption("maneuver_tempering_added_deadband_g", "--maneuver-tempering-added-deadband", "number",
                    metavar="D", minimum=0.0, maximum=10.0, requires="maneuver_tempering_added_g",
                    help="with --maneuver-tempering-added: only the load factor beyond D sqrt(s) g tempers "
                         "(cpp/f16mmae/maneuver_kinematics.h). Default 0: no dead band"),
    EstimatorOption("maneuver_tempering_added_spread", "--maneuver-tempering-added-spread", "number",
                    metavar="K", minimum=0.0, maximum=100.0, requires="maneuver_tempering_added_g",
                    help="with --maneuver-tempering-added: its band is at least K sigma_n, sigma_n the estimated "
                         "load factor's own spread about its 0.35-s mean (averaged over 30 s): the gusts' load factor "
                         "grows with the dynamic pressure, which the adaptation's s, read against each node's "
                         "light air, does not show (cpp/f16mmae/maneuver_kinematics.h). Default 0: off"),
    EstimatorOption("maneuver_dwell_s", "--maneuver-dwell", "number", metavar="S", minimum=0.0,
                    maximum=DWELL_S_MAX,
                    help="a level-0 declaration needs S seconds above the threshold while the aircraft maneuvers "
                         "(the estimated load factor, low-passed, more than --maneuver-dwell-g off the trim, or the "
                         "air data climb faster than 300 ft/min or change Mach faster than 0.001/s) and for "
                         "--maneuver-dwell-hold after; in steady level flight the dwell above "
                         "(cpp/f16mmae/maneuver_dwell.h). Default 0: the dwell everywhere"),
    EstimatorOption("maneuver_dwell_hold_s", "--maneuver-dwell-hold", "number", metavar="S", minimum=0.0,
                    maximum=3600.0, requires="maneuver_dwell_s",
                    help="with --maneuver-dwell: the maneuver's dwell (and --maneuver-reference) stays S seconds "
                         "after the maneuver ends (default 0)"),
    EstimatorOption("maneuver_dwell_g", "--maneuver-dwell-g", "number", metavar="G", minimum=0.0, exclusive=True,
                    maximum=10.0, requires="maneuver_dwell_s",
                    help="with --maneuver-dwell: the low-passed estimated load factor more than G g off the trim "
                         "is a maneuver (default 0.1; a 30 deg turn: 0.155 g)"),
    EstimatorOption("maneuver_dwell_time_constant_s", "--maneuver-dwell-time-constant", "number", metavar="TAU_S",
                    minimum=0.0, maximum=60.0, requires="maneuver_dwell_s",
                    help="with --maneuver-dwell: the time constant of the load factor's low-pass (s; 0: none; "
                         "default 2)"),
    EstimatorOption("maneuver_mach_per_s", "--maneuver-mach-rate", "number", metavar="MACH_PER_S", minimum=0.0,
                    exclusive=True, maximum=1.0,
                    help="with --maneuver-dwell or --adapt-reference-climb: the measured air data's Mach changing "
                         "faster than this (per s) opens their gates (cpp/f16mmae/air_data_rates.h; default 0.001, "
                         "which light turbulence reaches in level flight at high dynamic pressure; the maneuvers' "
                         "speed changes are 0.005-0.01 per s)"),
    EstimatorOption("maneuver_climb_ft_s", "--maneuver-climb-rate", "number", metavar="FT_S", minimum=0.0,
                    exclusive=True, maximum=1000.0,
                    help="with --maneuver-dwell or --adapt-reference-climb: the measured air data's altitude "
                         "changing faster than this (ft/s) opens their gates (cpp/f16mmae/air_data_rates.h; default "
                         "5, 300 ft/min, which light turbulence's gusts reach in level flight; the maneuvers' climbs "
                         "are 33-50 ft/s)"),
    EstimatorOption("maneuver_rate_gust_scaled", "--maneuver-rate-gust-scaled", "switch",
                    requires="adapt_turbulence",
                    help="with --maneuver-dwell or --adapt-reference-climb: their gates' climb-rate and Mach-rate "
                         "thresholds times sqrt(s_b), s_b the turbulence adaptation's scale at the node's own "
                         "reference (never a flight phase's): the gusts move the measured air data too, about "
                         "twice light air's rates in moderate air and five times in severe air "
                         "(cpp/f16mmae/hierarchical_bank.h). Default off"),
    EstimatorOption("maneuver_gates_calm_scaled", "--maneuver-gates-calm-scaled", "switch",
                    requires="adapt_turbulence",
                    help="with --maneuver-dwell or --adapt-reference-climb: all three thresholds of their gates "
                         "(the climb rate, the Mach rate and --maneuver-dwell-g's load factor) times sqrt(s_c), "
                         "s_c the turbulence adaptation's scale at the node's calm-air reference (midway between "
                         "calm and light air): light air's gusts already raise them a little, moderate air's about "
                         "threefold, severe air's ninefold, so level flight in any air keeps the gates shut "
                         "(cpp/f16mmae/hierarchical_bank.h). Takes precedence over --maneuver-rate-gust-scaled. "
                         "Default off, but on with a scheduled bank's --adapt-turbulence (--maneuver-setting); "
                         "--no- turns it off there"),
    EstimatorOption("maneuver_setting", "--maneuver-setting", "choice", metavar="on|off", choices=("on", "off"),
                    requires="adapt_turbulence", in_daemon=False,
                    help="with --adapt-turbulence on a scheduled bank: on flies the maneuvering-flight setting, "
                         "each of its options unless given: --maneuver-kinematics --actuator-limits "
                         "--adapt-reference-climb 0.6 --adapt-reference-climb-hold 30 --maneuver-dwell 0.4 "
                         "--maneuver-dwell-hold 30 --maneuver-dwell-g 0.07 --maneuver-reference 0.65 "
                         "--maneuver-tempering-added 0.03 --maneuver-tempering-added-deadband 0.08 "
                         "--maneuver-tempering-added-spread 3 --maneuver-climb-rate 10 --maneuver-mach-rate 0.002 "
                         "--maneuver-gates-calm-scaled --trim-tracking-steady 0.1 --trim-tracking-steady-air-data off "
                         "--trim-tracking-steady-measurements AOA,VEL,AZ,AY (names.SCHEDULE_MANEUVER_SETTING; "
                         "mmae-daemon takes them as flags); off none of them, the default before round 33. "
                         "Default on"),
    EstimatorOption("maneuver_reference", "--maneuver-reference", "number", metavar="RHO", minimum=0.0,
                    maximum=100.0, requires="adapt_turbulence",
                    help="with --adapt-turbulence: the adaptation's reference while the aircraft maneuvers (the "
                         "gate of --maneuver-dwell, its threshold, time constant and hold) unless "
                         "--adapt-reference-climb is in force (cpp/f16mmae/maneuver_dwell.h). Default off"),
    EstimatorOption("maneuver_trim", "--maneuver-trim", "switch",
                    help="the trim the filters are linearized about follows the climb and the acceleration the "
                         "air data show (pressure-altitude and Mach rates): the level trim plus the climb's and "
                         "acceleration's trim offsets of each node's own model, the filters' states moved with it "
                         "(cpp/f16mmae/maneuver_trim.h). Default off"),
    EstimatorOption("maneuver_trim_time_constant_s", "--maneuver-trim-time-constant", "number", metavar="T_S",
                    minimum=0.05, maximum=60.0, requires="maneuver_trim",
                    help="with --maneuver-trim: the rates' low-passes, T and 5 T seconds (default 0.5)"),
    EstimatorOption("maneuver_trim_accel", "--maneuver-trim-accel", "choice", metavar="on|off", choices=("on", "off"),
                    requires="maneuver_trim",
                    help="with --maneuver-trim: off keeps the climb's trim only, not the acceleration's "
                         "(default on)"),
    EstimatorOption("maneuver_trim_rates", "--maneuver-trim-rates", "choice", metavar="air|inertial",
                    choices=("air", "inertial"), requires="maneuver_trim",
                    help="with --maneuver-trim: where the climb angle and acceleration come from: the air data's "
                         "rates (air, the default) or a complementary filter, fast from the measured pitch, roll "
                         "and yaw rates, AOA and VEL, slow from the air data, that reads no sensor while a failure "
                         "is suspected (inertial; cpp/f16mmae/inertial_flight_path.h)"),
    EstimatorOption("maneuver_trim_blend_s", "--maneuver-trim-blend", "number", metavar="T_S", minimum=0.05,
                    maximum=600.0, requires="maneuver_trim",
                    help="with --maneuver-trim-rates inertial: the air data take over the pitch attitude over "
                         "T_S seconds (default 2)"),
    EstimatorOption("maneuver_trim_accel_airspeed_rad_s", "--maneuver-trim-accel-airspeed", "number",
                    metavar="W0", minimum=0.05, maximum=20.0, requires="maneuver_trim",
                    help="with --maneuver-trim and the air data's rates: W0 (rad/s) takes the "
                         "acceleration from the airspeed of z, VEL / cos(AOA), through a second-order tracking "
                         "differentiator of natural frequency W0 (delay 1.41 / W0 s against the air data's "
                         "6 T), reading no sensor while a failure is suspected (cpp/f16mmae/maneuver_trim.h, "
                         "AirspeedAccel). Default: the air data's"),
    EstimatorOption("maneuver_trim_gamma_load_factor", "--maneuver-trim-gamma-load-factor", "choice",
                    metavar="on|off", choices=("on", "off"), requires="maneuver_trim",
                    help="with --maneuver-trim and the air data's rates: on adds to the air data's climb angle "
                         "what their low-passes hold back of the path's turn, (1 - L(s)) / s of "
                         "(g / V)(AZ cos(bank) - cos(gamma)), so a pull-out or level-off is followed without "
                         "their 6 T of lag; reads no sensor while a failure is suspected "
                         "(cpp/f16mmae/maneuver_trim.h, ClimbAngleComplement). Default off"),
    EstimatorOption("level1_p_min", "--level1-p-min", "number", metavar="P", minimum=0.0,
                    below=LEVEL1_P_MIN_BELOW,
                    help="probability floor while a failure's level-1 (dual) bank is on line: a second "
                         "failure rises from it (cpp/f16mmae/hierarchical_bank.h). Below (1 - 0.9) / 12: "
                         "at or above (1 - threshold) / 12 no hypothesis can pass the threshold (the core "
                         "checks it with the threshold in force). Default 0: the level-0 floor"),
    EstimatorOption("level1_dwell_s", "--level1-dwell-s", "number", metavar="S", minimum=0.0, maximum=DWELL_S_MAX,
                    help="... and the dwell while it is on line: a dual (or the back-out) must stay above the "
                         "threshold S seconds in a row (cpp/f16mmae/hierarchical_bank.h). Default 0: the level-0 dwell"),
    EstimatorOption("level1_allowance", "--level1-allowance", "number", metavar="K", minimum=0.0, maximum=5.0,
                    help="... and the duals' drift allowance while it is on line: every dual's likelihood is "
                         "multiplied by exp(-K) a frame, so its log-odds against the declared failure drift down "
                         "by K nats a frame unless its evidence outgrows that (Page's reference value; "
                         "cpp/f16mmae/level1_allowance.h). Default 0: none"),
    EstimatorOption("level1_allowance_pairs", "--level1-allowance-pairs", "file", metavar="FILE",
                    help="... or each dual's own: FILE (tools/cover/dual_rates.py) gives the dual F+C the allowance "
                         "k = a r_{F>C} in F's level-1 bank, r its drift measured under its second failure, so a "
                         "dual slow by nature gets a small k (cpp/f16mmae/level1_allowance.h); a dual it does not "
                         "name takes --level1-allowance. Default: none (in process only)",
                    in_daemon=False),
    EstimatorOption("departure_hold", "--departure-hold", "choice", metavar="on|off", choices=("on", "off"),
                    help="while a failure's level-1 (dual) bank is on line, declare nothing while the measured "
                         "angle of attack is more than 5 deg off the trim or a measured body rate above 10 deg/s, "
                         "nor for 1 s after: the linear models do not cover a departed aircraft (a stabilator "
                         "hardover; cpp/f16mmae/hierarchical_bank.h). Default on"),
    EstimatorOption("declare_components", "--declare-components", "switch",
                    help="a bank with partial-loss hypotheses (design --partial-loss): declare a surface's "
                         "forms (its complete/cover and its partial hypothesis) as one component -- the sum of "
                         "their probabilities against the threshold, the dwell on the sum -- naming the form "
                         "that holds more mass (cpp/f16mmae/declarer.h). Default off: each hypothesis alone; "
                         "a bank without partial hypotheses is unchanged"),
    EstimatorOption("dwell_nats", "--dwell-nats", "number", metavar="N", minimum=0.0, maximum=1.0e6,
                    help="the evidence dwell: a hypothesis above the threshold P is also declared, before --dwell-s "
                         "has passed, once its log-odds above the threshold's, ln(p/(1-p)) - ln(P/(1-P)), summed "
                         "over its consecutive frames above, reach N nats: one the data hold near the ceiling is "
                         "declared in a few frames, one hovering near the threshold still needs the dwell "
                         "(cpp/f16mmae/declarer.h). Given, N replaces the bank's own table and the scheduled "
                         "default's for every hypothesis (0: the dwell alone). Default: the bank's recommended N "
                         "per hypothesis (bank format 4; none: the dwell alone), a scheduled bank's table below. "
                         "Off with a climb or maneuver dwell unless --evidence-dwell-in-phases "
                         "(cpp/f16mmae/hierarchical_bank.h)"),
    EstimatorOption("dwell_nats_per_hypothesis", "--dwell-nats-per-hypothesis", "file", metavar="FILE|NAME=N,...",
                    inline=True,
                    help="... per hypothesis: FILE (tools/latency/dwell_per_hypothesis.py; one 'NAME N' a line), or "
                         "the table inline (an argument with '=': NAME=N entries separated by commas), gives "
                         "hypothesis NAME its own evidence dwell of N nats, 0 leaving it to --dwell-s alone; a "
                         "hypothesis the table does not name takes --dwell-nats (cpp/f16mmae/declarer.h). "
                         "Default: the bank's own table (its hypotheses' dwell_nats); on a scheduled bank with "
                         f"--adapt-turbulence {SCHEDULE_DWELL_NATS_PER_HYPOTHESIS} "
                         "(names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS) with --evidence-dwell-in-phases, unless "
                         "--dwell-nats is given"),
    EstimatorOption("evidence_dwell_in_phases", "--evidence-dwell-in-phases", "switch",
                    help="keep the evidence dwell (--dwell-nats, --dwell-nats-per-hypothesis) through a climb's "
                         "and a maneuver's dwell, asking N times the phase's dwell over --dwell-s: for tables "
                         "measured on flights that maneuver and climb too (cpp/f16mmae/hierarchical_bank.h). "
                         "Default: on with a scheduled bank's default table, else off (the evidence dwell off "
                         "in those phases)"),
    EstimatorOption("dwell_s_per_hypothesis", "--dwell-s-per-hypothesis", "table", metavar="NAME=S,...",
                    help="the least dwell of these hypotheses: NAME is declared after the longer of the dwell in "
                         "force (--dwell-s, a maneuver's or a climb's) and S seconds above the threshold, its "
                         "evidence dwell scaled alike; a dual A+B not named takes the longer of A's and B's "
                         "(cpp/f16mmae/declarer.h); NAME=0: the dwell in force. Default: "
                         f"{SCHEDULE_DWELL_S_PER_HYPOTHESIS} on a scheduled bank with --adapt-turbulence "
                         "(names.SCHEDULE_DWELL_S_PER_HYPOTHESIS), else none"),
    EstimatorOption("rough_dwell_s_per_hypothesis", "--rough-dwell-s-per-hypothesis", "table",
                    metavar="NAME=S,...", requires="adapt_turbulence",
                    help="the least dwell of these hypotheses in rough air: while the turbulence adaptation's "
                         "scale s is at least --rough-scale, NAME is declared after the longer of its "
                         "--dwell-s-per-hypothesis entry and S; in calmer air that entry alone "
                         "(cpp/f16mmae/declarer.h); NAME=0: none. Default: "
                         f"{SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS} on a scheduled bank with --adapt-turbulence "
                         "(names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS), else none"),
    EstimatorOption("rough_scale", "--rough-scale", "number", metavar="S", minimum=1.0, exclusive=True,
                    maximum=1.0e6, requires="rough_dwell_s_per_hypothesis",
                    help="rough air for --rough-dwell-s-per-hypothesis: the adaptation's scale s at least S "
                         f"(> 1, its floor; default {SCHEDULE_ROUGH_SCALE:g}: light air and moderate air at the "
                         "nominal point read s <= 2.8 and <= 4.8, moderate air at Mach 0.365, 34,500 ft 24-35)"),
    EstimatorOption("partial_p_min", "--partial-p-min", "number", metavar="P", minimum=0.0, maximum=0.1,
                    help="a bank with partial-loss hypotheses (design --partial-loss): their probability floor at "
                         "level 0, the others keeping the level-0 floor; a half loss's hypothesis then climbs "
                         "ln(P / p_min) nats less to the threshold (cpp/f16mmae/hierarchical_bank.h). The core "
                         "refuses floors that leave no room for a declaration and a bank without partial "
                         "hypotheses. Default 0: the level-0 floor"),
    EstimatorOption("rough_p_min", "--rough-p-min", "number", metavar="P", minimum=0.0, below=1.0 / K_BANK,
                    requires="adapt_turbulence",
                    help="the level-0 probability floor in rough air: the floor in force moves log-linearly from "
                         "the bank's (a scheduled bank's node floor, chosen in light air) to P as the air's "
                         "measured residual power ratio, in the schedule's calm-air units, crosses "
                         "--rough-p-min-from .. --rough-p-min-to (cpp/f16mmae/rough_air_floor.h). Default: "
                         f"{SCHEDULE_ROUGH_P_MIN:g} on a scheduled bank with --adapt-turbulence "
                         "(names.SCHEDULE_ROUGH_P_MIN), else 0 (off)"),
    EstimatorOption("rough_p_min_from", "--rough-p-min-from", "number", metavar="X", minimum=0.0, below=1000.0,
                    requires="rough_p_min",
                    help="... the band's lower end: the bank's floor wherever the air reads below X (calm-air "
                         "units: calm air 0.7-1.0, light 1.0-1.3, moderate 1.6-3.4). Default 1.3"),
    EstimatorOption("rough_p_min_to", "--rough-p-min-to", "number", metavar="X", minimum=0.0, exclusive=True,
                    maximum=1000.0, requires="rough_p_min",
                    help="... the band's upper end (above --rough-p-min-from): the rough-air floor wherever the "
                         "air reads above X. Default 1.5"),
    EstimatorOption("actuator_rate_limits_rad_s", "--actuator-rate-limits", "values", on_command_line=False,
                    help="the actuators' rate limits, rad/s, one per input"),
    EstimatorOption("actuator_position_limits_rad", "--actuator-position-limits", "values",
                    on_command_line=False, help="the actuators' position limits, rad, one per input"),
)

#: The keywords of ``core.HierarchicalBank`` (bindings/estimator_init.h) that no row of the table
#: sets, and why: the estimator's own wiring, or constants of the core's rules kept as keywords
#: for tests and lab tools.  With the table they are the estimator's options, one list
#: (tests/python/test_hil_daemon_cli.py checks it against the binding).
CORE_ONLY: dict[str, str] = {
    "node_p_min": "the estimator's wiring: a scheduled bank's per-node floors unless --p-min is given "
                  "(loop/estimator.py, mmae-daemon alike)",
    "declarer": "a core.Declarer in place of threshold and dwell_s (tests)",
    "strip_leading_term": "the paper's likelihood without 1/((2 pi)^(m/2) |A_k|^(1/2)) (filter_bank.h)",
    "trim_hold_s": "trim tracking's hold after a freezing frame (trim_tracker.h)",
    "trim_freeze": "trim tracking frozen while a failure rises (trim_tracker.h; off: a lab tool's comparison)",
    "trim_steady_roll_rate_rad_s": "steady trim tracking's roll-rate gate (trim_tracker.h)",
    "trim_steady_climb_ft_s": "steady trim tracking's climb-rate gate (trim_tracker.h, air_data_rates.h)",
    "trim_steady_mach_per_s": "steady trim tracking's Mach-rate gate (trim_tracker.h, air_data_rates.h)",
    "hysteresis_cells": "the nearest-node schedule's hysteresis (scheduled_filters.h)",
    "blend_step_cells": "the schedule's re-blend step (scheduled_filters.h)",
    "cubic_trims": "the schedule's trims to third order (scheduled_filters.h)",
    "plane_trims": "the schedule's trims in a cell's uncovered half from its covered triangle's plane "
                   "(scheduled_filters.h)",
    "row_trims": "the schedule's trims row by row where no 4 x 4 stencil is covered (scheduled_filters.h)",
    "neighbour_trims": "the schedule's trims in a cell missing two or more corners from its neighbouring "
                       "cells' planes (scheduled_filters.h)",
    "lift_trims": "the schedule's linear trims in a cut cell in the lift coordinate, airspeed in Mach "
                  "(scheduled_filters.h)",
    "stabilator_trims": "the schedule's stabilator trims past the trimmable edge along its nodes' trim alpha "
                        "(scheduled_filters.h)",
    "gust_airspeed": "the schedule's Mach less the estimated along-track gust's, on a bank with gust states "
                     "(hierarchical_bank.h)",
    "adapt_time_constant_s": "the adaptation's averaging time, tuned with its gain (turbulence_adaptation.h)",
    "adapt_scale_min": "the adaptation's lower bound on s, the design's A_k (turbulence_adaptation.h)",
    "adapt_scale_max": "the adaptation's upper bound on s (turbulence_adaptation.h)",
    "adapt_gain": "the adaptation's gain on the excess residual power (turbulence_adaptation.h)",
    "adapt_counted_channels": "the counted channels as a bit mask over z (turbulence_adaptation.h); the "
                              "estimator sets it from --adapt-counted-channel (loop/estimator.py core_arguments)",
    "adapt_excluded_channels": "the excluded channels as a bit mask over z (turbulence_adaptation.h); the "
                               "estimator sets it from --adapt-excluded-channel (loop/estimator.py core_arguments)",
    "adapt_level_scale_channels": "the level channels scaled at every level as a bit mask over z (filter_bank.h); "
                                  "the estimator sets it from --adapt-level-scale-channel (loop/estimator.py "
                                  "core_arguments)",
    "adapt_hypothesis_weight": "the per-hypothesis tempering's weight (turbulence_adaptation.h); the estimator "
                               "sets it from --set-tempering (loop/estimator.py core_arguments)",
    "adapt_full_tempering": "the hypotheses the per-hypothesis tempering leaves at s, a bit mask over the "
                            "level-0 hypotheses; the estimator sets it with --set-tempering",
    "adapt_spare_margin": "the per-hypothesis tempering's spared margin (turbulence_adaptation.h); the "
                          "estimator sets it from --set-tempering-margin",
    "adapt_spare_margin_over": "the per-hypothesis tempering's margin reference, a bit mask over the level-0 "
                               "hypotheses (turbulence_adaptation.h); the estimator sets it from "
                               "--set-tempering-margin-stabilators",
    "calm_complete_rho": "the calm-air bounds by measurement (calm_air_complete.h); the estimator sets it from "
                         "--calm-complete (loop/estimator.py core_arguments)",
    "adapt_spare_rho": "the per-hypothesis tempering's least measured rho (turbulence_adaptation.h); the "
                       "estimator sets it from --set-tempering-rho",
    "adapt_rough_rho": "the air's rho from which the rough-air hypotheses take their own share of s - 1 "
                       "(turbulence_adaptation.h); the estimator sets it from --set-tempering-rough",
    "adapt_rough_weight": "the rough-air hypotheses' share of s - 1 (turbulence_adaptation.h); the estimator sets "
                          "it from --set-tempering-rough-weight",
    "adapt_rough_tempering": "the rough-air hypotheses, a bit mask over the level-0 hypotheses; the "
                             "estimator sets it with --set-tempering-rough",
}
#: The rows that are no keyword of the binding: the estimator (loop/estimator.py) takes them
#: (``actuator_limits`` becomes the two limit keywords, ``turbulence_banks`` the set;
#: ``adaptive_dither``, ``fixed_dither``, ``fixed_rudder_dither`` and ``sensor_loss_dither`` are the closed
#: loop's, loop/flight.py;
#: ``adapt_all_channels``, ``adapt_counted_channel``, ``adapt_excluded_channel`` and ``adapt_level_scale_channel`` are resolved by ``scheduled_defaults`` and the estimator;
#: ``maneuver_setting`` is resolved by ``scheduled_defaults`` into the options it sets;
#: ``trim_steady_air_data`` becomes the steady tracking's climb and Mach limits, ``set_tempering`` the
#: per-hypothesis tempering's keywords and ``calm_complete`` ``calm_complete_rho``, loop/estimator.py core_arguments).
HARNESS_ONLY: tuple[str, ...] = ("actuator_limits", "turbulence_banks", "adaptive_dither", "fixed_dither",
                               "fixed_rudder_dither", "sensor_loss_dither", "calm_complete", "adapt_all_channels", "adapt_counted_channel", "adapt_excluded_channel",
                               "adapt_level_scale_channel", "trim_steady_air_data", "set_tempering", "set_tempering_rho",
                               "set_tempering_rough", "set_tempering_rough_weight", "set_tempering_margin", "set_tempering_margin_stabilators", "maneuver_setting")
#: The rows that are the closed loop's, the truth side's (loop/flight.py), not the estimator's:
#: ``mmae-daemon`` takes no flag for them (``lcm.daemon.daemon_flags`` passes none) and an
#: executive over LCM runs as without them; the status carries what they read.
CLOSED_LOOP: tuple[str, ...] = ("adaptive_dither", "fixed_dither", "fixed_rudder_dither", "sensor_loss_dither")


def with_closed_loop_defaults(settings: dict) -> dict:
    """``settings`` with the closed loop's defaults in force written out: with
    ``turbulence_banks`` the adaptive dither (``adaptive_dither`` True) unless ``fixed_dither``.
    The estimator's settings (loop/estimator.py) and the executive's over LCM (lcm/hil.py) hold
    them so, and records name the dither flown."""
    out = dict(settings)
    if out.get("turbulence_banks") and not out.get("fixed_dither"):
        out["adaptive_dither"] = True
    return out

#: The table by key.
BY_KEY: dict[str, EstimatorOption] = {o.key: o for o in ESTIMATOR_OPTIONS}
#: The options a user gives on the command line (and a run record may hold), in table order.
COMMAND_LINE: tuple[EstimatorOption, ...] = tuple(o for o in ESTIMATOR_OPTIONS if o.on_command_line)


def load_allowance_pairs(path: str) -> dict[str, float]:
    """The pair table of ``--level1-allowance-pairs`` (tools/cover/dual_rates.py writes it):
    ``{"F>C": k}`` from the file's ``pairs``. ValueError naming the file and what is wrong (the
    core refuses names that are not two singles of the bank, and k < 0)."""
    import json
    import pathlib
    try:
        table = json.loads(pathlib.Path(path).read_text())
    except (OSError, ValueError) as exc:
        raise ValueError(f"--level1-allowance-pairs {path!r}: not a readable JSON pair table ({exc})") from None
    pairs = table.get("pairs") if isinstance(table, dict) else None
    if not isinstance(pairs, dict) or not pairs or not all(
            isinstance(k, str) and isinstance(v, (int, float)) and not isinstance(v, bool) for k, v in pairs.items()):
        raise ValueError(f"--level1-allowance-pairs {path!r}: needs a non-empty object 'pairs' of \"F>C\": k "
                         f"(nats a frame; tools/cover/dual_rates.py writes it)")
    return {k: float(v) for k, v in pairs.items()}


def load_dwell_nats_table(argument: str) -> dict[str, float]:
    """The table of ``--dwell-nats-per-hypothesis``, ``{name: N}``: inline ``NAME=N,...`` when
    ``argument`` holds an '=', else the file of that path (tools/latency/dwell_per_hypothesis.py
    writes it: one ``NAME N`` a line, ``#`` a comment), read by the core as mmae-daemon reads it
    (cpp/f16mmae/declarer.h ``dwell_nats_table_argument``). ValueError naming the flag, the entry
    or the file and the line, and what is wrong (the core refuses names that are not hypotheses of
    the bank when it is built)."""
    from .. import core
    try:
        return dict(core.dwell_nats_table_argument(str(argument)))
    except ValueError as exc:   # the core's "dwell_nats_per_hypothesis: why" inline, "dwell-nats table 'F' line n: why"
        why = str(exc).removeprefix("dwell_nats_per_hypothesis: ")
        raise ValueError(f"--dwell-nats-per-hypothesis: {why}") from None


#: The reader of each ``file`` option's file: the table the core takes for the path.
FILE_LOADERS = {"level1_allowance_pairs": load_allowance_pairs, "dwell_nats_per_hypothesis": load_dwell_nats_table}


def _core_table(parser: str, flag: str):
    """The parser of a ``table`` option's text ``NAME=V[,NAME=V...]``: ``{name: V}`` by the core's
    ``parser`` as mmae-daemon parses it, ValueError naming ``flag`` and the entry (the core refuses
    names the bank does not have when it is built)."""
    def parse(text: str) -> dict[str, float]:
        from .. import core
        try:
            return dict(getattr(core, parser)(str(text)))
        except ValueError as exc:   # the core's "<table>: why"
            raise ValueError(f"{flag}: {str(exc).split(': ', 1)[-1]}") from None
    return parse


#: ``--dwell-s-per-hypothesis``: the least dwells {hypothesis: S} (cpp/f16mmae/declarer.h).
parse_dwell_s_table = _core_table("parse_dwell_s_per_hypothesis", "--dwell-s-per-hypothesis")
#: ``--calm-complete``: the calm-air bounds {measurement: rho} (cpp/f16mmae/calm_air_complete.h).
parse_calm_complete_table = _core_table("parse_calm_complete", "--calm-complete")


def parse_steady_measurements(text) -> list[str]:
    """``--trim-tracking-steady-measurements``: ``NAME[,NAME...]``, each a measurement, once
    (upper case; a list is checked as it is): the list the core takes; ValueError naming the flag."""
    names = [str(n).strip().upper() for n in (text if isinstance(text, (list, tuple)) else str(text).split(","))]
    for n in names:
        if n not in SENSORS:
            raise ValueError(f"--trim-tracking-steady-measurements: {n!r} is not a measurement; "
                             f"valid: {', '.join(SENSORS)}")
    if len(set(names)) != len(names):
        raise ValueError(f"--trim-tracking-steady-measurements: a measurement named twice in {','.join(names)}")
    return names


#: The parser of each ``table`` option's text: the table the core takes.
TABLE_PARSERS = {"dwell_s_per_hypothesis": parse_dwell_s_table, "calm_complete": parse_calm_complete_table,
                 "trim_steady_measurements": parse_steady_measurements,
                 "rough_dwell_s_per_hypothesis": _core_table("parse_dwell_s_per_hypothesis",
                                                             "--rough-dwell-s-per-hypothesis")}


def valid_range(option: EstimatorOption) -> str:
    """The valid values of a ``number`` or ``choice`` option, as its refusal names them."""
    if option.kind == "choice":
        return ", ".join(option.choices)
    upper = option.below if option.below is not None else option.maximum
    return (f"{'(' if option.exclusive else '['}{option.minimum:g}, {upper:g}"
            f"{')' if option.below is not None else ']'}")


def check(settings: dict) -> None:
    """ValueError naming the flag, the value and the valid ones for a setting that is unknown,
    out of its range, or given without the option it applies with."""
    for key, value in settings.items():
        o = BY_KEY.get(key)
        if o is None or not o.on_command_line:
            raise ValueError(f"unknown estimator setting {key!r}; valid: {', '.join(x.key for x in COMMAND_LINE)}")
        if o.kind == "switch":
            ok = isinstance(value, bool)
        elif o.kind == "choice":
            ok = value in o.choices
        elif o.kind == "file":
            if not isinstance(value, str):
                raise ValueError(f"{o.flag} {value!r} must be the path of a file"
                                 + (" or NAME=N entries separated by commas" if o.inline else ""))
            FILE_LOADERS[key](value)
            ok = True
        elif o.kind == "table":
            if not isinstance(value, str):
                raise ValueError(f"{o.flag} {value!r} must be NAME=VALUE entries separated by commas")
            TABLE_PARSERS[key](value)
            ok = True
        else:
            ok = (isinstance(value, (int, float)) and not isinstance(value, bool)
                  and (value > o.minimum if o.exclusive else value >= o.minimum)
                  and (o.below is None or value < o.below) and (o.maximum is None or value <= o.maximum))
        if not ok:
            valid = {"switch": "be true or false", "choice": f"be one of {valid_range(o)}"}.get(
                o.kind, f"lie in {valid_range(o)}")
            raise ValueError(f"{o.flag} {value!r} must {valid}")
        if o.requires is not None and not settings.get(o.requires):
            scheduled = SCHEDULED_DEFAULT_FLAGS.get(o.requires)
            if scheduled is not None and settings.get("adapt_turbulence"):
                continue   # a scheduled bank's default may give it: checked with the bank's defaults
            raise ValueError(f"{o.flag} applies with {BY_KEY[o.requires].flag} only"
                             + ("" if scheduled is None else
                                f" (or with --adapt-turbulence on a scheduled bank, whose default is {scheduled})"))
    if settings.get("adaptive_dither") and not (settings.get("turbulence_banks") or settings.get("adapt_turbulence")):
        raise ValueError("--adaptive-dither applies with --turbulence-banks or --adapt-turbulence only (it reads "
                         "the air the estimator measures)")
    if settings.get("fixed_dither") and not (settings.get("turbulence_banks") or settings.get("adapt_turbulence")):
        raise ValueError("--fixed-dither applies with --turbulence-banks or --adapt-turbulence only (where the "
                         "adaptive dither is the default)")
    if settings.get("fixed_rudder_dither") and not settings.get("adapt_turbulence"):
        raise ValueError("--fixed-rudder-dither applies with --adapt-turbulence only (one adapted bank's adaptive "
                         "dither grows the rudder's line; the turbulence bank set's does not)")
    if settings.get("adaptive_dither") and settings.get("fixed_dither"):
        raise ValueError("--adaptive-dither and --fixed-dither exclude each other (the adaptive dither is the "
                         "default with --turbulence-banks and with a scheduled bank's --adapt-turbulence)")
    if settings.get("sensor_loss_dither") and (settings.get("adaptive_dither") or (
            settings.get("turbulence_banks") and not settings.get("fixed_dither"))):
        raise ValueError("--sensor-loss-dither and --adaptive-dither both set the dither's gains: give one "
                         "(with --turbulence-banks the adaptive dither is the default: add --fixed-dither)")
    if settings.get("set_tempering") is not None and not (settings.get("adapt_turbulence")
                                                          or settings.get("turbulence_banks")):
        raise ValueError("--set-tempering applies with --adapt-turbulence or --turbulence-banks only")
    if "rough_p_min_from" in settings or "rough_p_min_to" in settings:
        defaults = core.estimator_defaults()
        low = settings.get("rough_p_min_from", defaults["rough_p_min_from"])
        high = settings.get("rough_p_min_to", defaults["rough_p_min_to"])
        if not low < high:
            raise ValueError(f"--rough-p-min-from {low!r} must lie below --rough-p-min-to {high!r} (the band the "
                             "floor moves across)")
    floor = settings.get("adapt_floor_time_constant_s")
    if floor:
        averaging = core.estimator_defaults()["adapt_time_constant_s"]
        if floor < averaging:
            raise ValueError(f"--adapt-floor {floor!r} must be 0 (off) or a time in [{averaging:g}, 3600] s (at least "
                             "the adaptation's averaging time)")
    if settings.get("adapt_all_channels") and settings.get("adapt_own_channels"):
        raise ValueError("--adapt-all-channels and --adapt-own-channels are two rules for the same residual "
                         "power: give one")


def recommends_running_start(model_bank) -> bool:
    """Whether ``model_bank`` is a scheduled bank whose nodes were calibrated with the
    adaptation's running start (``design --schedule --adapt-running-start``: its metadata's
    ``adapt_running_start``), which it then recommends."""
    schedule = model_bank.schedule
    if schedule is None:
        return False
    try:
        return bool(json.loads(schedule["metadata"]).get("adapt_running_start", False))
    except (ValueError, TypeError, KeyError):
        return False


#: The settings ``scheduled_defaults`` gives a scheduled bank flown with --adapt-turbulence, as
#: flags: ``check``, which runs before the bank is read, lets an option that applies with one of
#: them wait for the bank's defaults (``check_requirements``) when --adapt-turbulence is given.
SCHEDULED_DEFAULT_FLAGS: dict[str, str] = {
    "rough_dwell_s_per_hypothesis": f"--rough-dwell-s-per-hypothesis {SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS}",
    "set_tempering": f"--set-tempering {SCHEDULE_SET_TEMPERING:g}",
    "set_tempering_rough": f"--set-tempering-rough {SCHEDULE_SET_TEMPERING_ROUGH:g}",
    "maneuver_tempering_alpha_deg": f"--maneuver-tempering-alpha {SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG:g}",
    "trim_time_constant_s": f"--trim-tracking {SCHEDULE_TRIM_TIME_CONSTANT_S:g}",
    "rough_p_min": f"--rough-p-min {SCHEDULE_ROUGH_P_MIN:g}",
    **{key: f"{BY_KEY[key].flag} {SCHEDULE_MANEUVER_SETTING[key]:g}"
       for key in ("adapt_reference_climb", "maneuver_dwell_s", "maneuver_tempering_added_g", "trim_steady_g")},
}


def has_calm_reference(model_bank) -> bool:
    """Whether ``model_bank`` is a scheduled bank whose nodes carry a calm-air reference (schedule
    format 4, ``design --schedule`` with calibrated nodes; cpp/f16mmae/bank_schedule.h)."""
    schedule = model_bank.schedule
    return schedule is not None and schedule["nodes"][0].get("calm_reference") is not None


def scheduled_defaults(settings: dict, scheduled: bool, running_start: bool = False,
                       calm_reference: bool = False) -> dict:
    """``settings`` with the scheduled estimator's defaults applied: on a ``scheduled`` bank
    with ``adapt_turbulence`` (and no turbulence bank set, whose members always count per
    channel), unless ``adapt_all_channels`` asks for the plain minimum, ``adapt_own_channels``
    on, and, unless ``adapt_own_channels`` or ``adapt_counted_channel`` was given,
    ``adapt_counted_channel`` ``names.SCHEDULE_ADAPT_COUNTED_CHANNEL`` (``--adapt-own-channels``
    alone: every uninformative channel left out, the rule before revision 12).
    ``adapt_all_channels`` stays (records name the rule; ``loop.estimator.core_arguments``
    drops it: its rule is ``adapt_own_channels`` off), so applying the defaults twice gives
    what applying them once does. With ``adapt_turbulence`` on a ``scheduled`` bank (and no
    turbulence bank set), ``set_tempering`` ``names.SCHEDULE_SET_TEMPERING`` unless given (1
    turns it off) with ``set_tempering_rough`` ``names.SCHEDULE_SET_TEMPERING_ROUGH`` unless given
    (0 turns it off), then with ``set_tempering_rough_weight``
    ``names.SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT`` unless given (a bound given takes the core's
    weight 1, the full s, unless its weight is given too), whatever the channel rule, ``trim_time_constant_s``
    ``names.SCHEDULE_TRIM_TIME_CONSTANT_S`` unless given (0 turns it off) and
    ``dwell_s_per_hypothesis`` ``names.SCHEDULE_DWELL_S_PER_HYPOTHESIS`` unless given (``VEL=0,AOA=0``
    turns it off), ``rough_dwell_s_per_hypothesis`` ``names.SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS``
    unless given (``RUD=0,PIT=0,AZ=0`` turns it off), then with ``rough_scale`` ``names.SCHEDULE_ROUGH_SCALE``
    unless given (a table given takes the core's default scale unless its scale is given too),
    ``dwell_nats_per_hypothesis`` ``names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS`` with
    ``evidence_dwell_in_phases`` on (unless given) unless a table or ``dwell_nats`` is given
    (``--dwell-nats 0`` turns it off),
    ``complete_trim_hold`` ``names.SCHEDULE_COMPLETE_TRIM_HOLD`` unless given
    (``off`` turns it off) and ``complete_trim_time_constant_s``
    ``names.SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S`` unless given (0 turns it off),
    ``maneuver_tempering_g`` ``names.SCHEDULE_MANEUVER_TEMPERING_G``, ``maneuver_tempering_alpha_deg``
    ``names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG`` with ``maneuver_tempering_alpha_deadband_deg``
    ``names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG`` and ``maneuver_tempering_alpha_trim_deg``
    ``names.SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG`` unless the former is given (0 turns it
    off; given, the dead band and the knee are as given), ``adapt_level_scale``
    ``names.SCHEDULE_ADAPT_LEVEL_SCALE`` and ``adapt_level_scale_channel``
    ``names.SCHEDULE_ADAPT_LEVEL_SCALE_CHANNEL`` unless given (``none`` turns it off), with
    ``adapt_level_scale_from`` ``names.SCHEDULE_ADAPT_LEVEL_SCALE_FROM`` unless given,
    ``adapt_floor_time_constant_s`` ``names.SCHEDULE_ADAPT_FLOOR_S`` unless given (0 turns it off),
    ``adapt_scale_max_from`` ``names.SCHEDULE_ADAPT_SCALE_MAX_FROM`` unless given (0 turns it off),
    ``rough_p_min`` ``names.SCHEDULE_ROUGH_P_MIN`` unless given (0 turns it off), and the closed
    loop's ``adaptive_dither`` unless ``fixed_dither`` or ``sensor_loss_dither`` is given (the
    adaptive dither of one adapted bank, truth/dither.py ``adapted_dither_reference``). ``running_start``: the bank recommends the
    adaptation's running start (``recommends_running_start``): then ``adapt_running_start`` on
    too. ``calm_reference``: its nodes carry a calm-air reference (``has_calm_reference``): then
    ``calm_complete`` ``names.SCHEDULE_CALM_COMPLETE`` and ``calm_measure``
    ``names.SCHEDULE_CALM_MEASURE`` unless given; and ``maneuver_setting`` "on" unless given, which
    gives each entry of ``names.SCHEDULE_MANEUVER_SETTING`` not given whose option's requirement is
    in force (``--maneuver-dwell 0`` leaves out its hold and gate, ``--trim-tracking 0`` the steady
    tracking; "off": none). A copy; ``settings`` is not changed."""
    out = dict(settings)
    all_channels = out.get("adapt_all_channels", False)
    if scheduled and out.get("adapt_turbulence") and not out.get("turbulence_banks") and not all_channels:
        if not out.get("adapt_own_channels") and "adapt_counted_channel" not in out:
            out["adapt_counted_channel"] = SCHEDULE_ADAPT_COUNTED_CHANNEL.lower()
        out["adapt_own_channels"] = True
    if scheduled and out.get("adapt_turbulence") and not out.get("turbulence_banks"):
        out.setdefault("set_tempering", SCHEDULE_SET_TEMPERING)
        if "set_tempering_rough" not in out:
            out["set_tempering_rough"] = SCHEDULE_SET_TEMPERING_ROUGH
            out.setdefault("set_tempering_rough_weight", SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT)
        out.setdefault("trim_time_constant_s", SCHEDULE_TRIM_TIME_CONSTANT_S)
        out.setdefault("dwell_s_per_hypothesis", SCHEDULE_DWELL_S_PER_HYPOTHESIS)
        if "rough_dwell_s_per_hypothesis" not in out:
            out["rough_dwell_s_per_hypothesis"] = SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS
            out.setdefault("rough_scale", SCHEDULE_ROUGH_SCALE)
        if "dwell_nats_per_hypothesis" not in out and "dwell_nats" not in out:
            out["dwell_nats_per_hypothesis"] = SCHEDULE_DWELL_NATS_PER_HYPOTHESIS
            out.setdefault("evidence_dwell_in_phases", True)
        out.setdefault("complete_trim_hold", SCHEDULE_COMPLETE_TRIM_HOLD)
        out.setdefault("complete_trim_time_constant_s", SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S)
        out.setdefault("maneuver_tempering_g", SCHEDULE_MANEUVER_TEMPERING_G)
        if "maneuver_tempering_alpha_deg" not in out:
            out["maneuver_tempering_alpha_deg"] = SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG
            out.setdefault("maneuver_tempering_alpha_deadband_deg", SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG)
            out.setdefault("maneuver_tempering_alpha_trim_deg", SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG)
        out.setdefault("adapt_level_scale", SCHEDULE_ADAPT_LEVEL_SCALE)
        out.setdefault("adapt_level_scale_channel", SCHEDULE_ADAPT_LEVEL_SCALE_CHANNEL.lower())
        if out["adapt_level_scale_channel"] != "none":
            out.setdefault("adapt_level_scale_from", SCHEDULE_ADAPT_LEVEL_SCALE_FROM)
        out.setdefault("adapt_floor_time_constant_s", SCHEDULE_ADAPT_FLOOR_S)
        out.setdefault("adapt_scale_max_from", SCHEDULE_ADAPT_SCALE_MAX_FROM)
        out.setdefault("rough_p_min", SCHEDULE_ROUGH_P_MIN)
        if not (out.get("fixed_dither") or out.get("sensor_loss_dither")):
            out["adaptive_dither"] = True   # the closed loop's (loop/flight.py)
        if running_start:
            out["adapt_running_start"] = True
        if calm_reference:
            out.setdefault("calm_complete", SCHEDULE_CALM_COMPLETE)
            out.setdefault("calm_measure", SCHEDULE_CALM_MEASURE)
        if out.setdefault("maneuver_setting", "on") == "on":   # each entry unless given, and only where
            for key, value in SCHEDULE_MANEUVER_SETTING.items():   # what it applies with is in force
                requires = BY_KEY[key].requires
                if key not in out and (requires is None or out.get(requires)):
                    out[key] = value
    return out


def bank_defaults(settings: dict, model_bank) -> dict:
    """``scheduled_defaults`` of ``settings`` for ``model_bank``: scheduled when it carries a
    schedule, with the running start when its file recommends it (``recommends_running_start``).
    The in-process estimator, ``hil`` (as the daemon's flags) and ``replay`` apply it alike.
    ValueError (``check_requirements``) when an option is left without the one it applies with."""
    scheduled = model_bank.schedule is not None
    out = scheduled_defaults(settings, scheduled, recommends_running_start(model_bank), has_calm_reference(model_bank))
    check_requirements(out, scheduled)
    return out


def check_requirements(settings: dict, scheduled: bool) -> None:
    """ValueError naming an option of ``settings`` (a bank's defaults applied) given without the
    option it applies with, where that is a scheduled default: what ``check`` let wait for the
    bank's defaults and the bank, or its settings (``--maneuver-setting off``, a default turned
    off), did not give."""
    for key in settings:
        o = BY_KEY.get(key)
        if o is None or o.requires not in SCHEDULED_DEFAULT_FLAGS or settings.get(o.requires):
            continue
        need = BY_KEY[o.requires].flag
        why = ("the bank is not scheduled, so no default gives it" if not scheduled else
               "the scheduled defaults do not give it with these settings")
        raise ValueError(f"{o.flag} applies with {need} only ({why}: give {need})")


def command_line_flags(settings: dict) -> list[str]:
    """The arguments of ``f16mmae run`` that give the estimator ``settings`` (keys of
    :data:`COMMAND_LINE`): the valued options in table order, then the switches that are on.
    ValueError naming a setting no option sets."""
    unknown = [k for k in settings if k not in BY_KEY or not BY_KEY[k].on_command_line]
    if unknown:
        raise ValueError(f"estimator setting(s) {', '.join(sorted(unknown))} have no run option; "
                         f"valid: {', '.join(o.key for o in COMMAND_LINE)}")
    args: list[str] = []
    for o in COMMAND_LINE:
        if o.kind != "switch" and o.key in settings:
            value = settings[o.key]
            args += [o.flag, value if o.kind in ("choice", "file", "table") else repr(float(value))]
    args += [o.flag for o in COMMAND_LINE if o.kind == "switch" and settings.get(o.key)]
    args += ["--no-" + o.flag[2:] for o in COMMAND_LINE if o.negatable and settings.get(o.key) is False]
    return args
