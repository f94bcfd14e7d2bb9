"""Names and sizes shared by every part of f16mmae, in the paper's words.

The paper (Eide & Maybeck, Sec. II) fails five actuators and seven sensors; the level-0
bank holds the no-failure hypothesis and the twelve single failures, the level-1 banks
the 66 dual failures (Fig. 2).  Everything that orders actuators, sensors or hypotheses
imports the tuples below, so that an index means the same thing everywhere.
"""
from __future__ import annotations

from itertools import combinations

from .core import DEFAULT_THRESHOLD, MAX_DWELL_S

#: Surfaces in the order of the command vector ``u`` (rad, absolute or perturbation).
ACTUATORS: tuple[str, ...] = ("LS", "RS", "LF", "RF", "RUD")
#: Sensors in the order of the measurement vector ``z``.
SENSORS: tuple[str, ...] = ("VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY")
#: Units of each entry of ``z`` (see f16mmae.truth.sensors for definitions).
SENSOR_UNITS: tuple[str, ...] = ("ft/s", "rad", "rad/s", "g", "rad/s", "rad/s", "g")
#: Filter state order: 8 airframe perturbation states then the 5 actuator lag states.
STATES: tuple[str, ...] = (
    "u_fps", "alpha_rad", "q_rad_s", "theta_rad",
    "beta_rad", "p_rad_s", "r_rad_s", "phi_rad",
    "d_ls_rad", "d_rs_rad", "d_lf_rad", "d_rf_rad", "d_rud_rad",
)

NONE = "NONE"
#: Level-0 hypotheses (paper Fig. 2), index = position in the level-0 bank.
SINGLE_HYPOTHESES: tuple[str, ...] = (NONE,) + ACTUATORS + SENSORS
#: The 66 dual-failure hypotheses, named "A+B" in SINGLE_HYPOTHESES order.
DUAL_HYPOTHESES: tuple[str, ...] = tuple(
    f"{a}+{b}" for a, b in combinations(ACTUATORS + SENSORS, 2)
)
#: Every hypothesis a model bank stores: 13 singles then 66 duals (79).
ALL_HYPOTHESES: tuple[str, ...] = SINGLE_HYPOTHESES + DUAL_HYPOTHESES

#: Every component the paper fails, actuators then sensors (the rows and columns of Fig. 7).
COMPONENTS: tuple[str, ...] = ACTUATORS + SENSORS

NX, NU, NZ = len(STATES), len(ACTUATORS), len(SENSORS)
#: The throttle command's name as a bank's sixth input (``f16mmae design --throttle-input``).
THROTTLE_INPUT = "THR"
#: The inputs of a bank that models the throttle: the surfaces, then the throttle command.
INPUTS_WITH_THROTTLE: tuple[str, ...] = ACTUATORS + (THROTTLE_INPUT,)
K_BANK = len(SINGLE_HYPOTHESES)  # filters on line at any level (13)

#: Truth-model integration rate and the flight-control / sensor / estimator frame rate.
SIM_RATE_HZ = 128
FRAME_RATE_HZ = 64

#: The paper's design point: Mach 0.4 at 20,000 ft (the nominal banks are designed there).
DESIGN_MACH = 0.4
DESIGN_ALT_FT = 20_000.0
#: The paper's single-failure flight: the failure at 3.0 s of an 8-s flight (Sec. V).
FAILURE_TIME_S = 3.0
FLIGHT_S = 8.0
#: The longest flight a command or a soak campaign flies: one hour (230,400 frames at 64 Hz).
FLIGHT_S_MAX = 3600.0

#: Turbulence levels of the truth model, in increasing intensity (MIL-F-8785C).
TURBULENCE_LEVELS: tuple[str, ...] = ("none", "light", "moderate", "severe")
#: What the flight control system feeds back: the MMAE's z_hat on every channel (the paper),
#: the raw sensors, or the raw sensors reconfigured on a declaration -- the bank's estimate
#: only on the channels of the sensors the declared hypothesis has failed
#: (cpp/f16mmae/sensor_reconfiguration.h).
FEEDBACK_MODES: tuple[str, ...] = ("mmae", "raw", "reconfigure")
#: The nominal banks shipped in the package (``data/nominal_<tuning>.f16bank``).
SHIPPED_TUNINGS: tuple[str, ...] = ("tuned", "untuned")
#: The scheduled bank's name wherever ``--bank`` is accepted: banks designed on the grid
#: SCHEDULE_GRID with the tuned tuning (per SCHEDULE_NODE_TUNING), generated on first use
#: into the cache (banks.py).
SCHEDULED_BANK = "scheduled"
#: The turbulence bank set's name wherever ``--tuning`` is accepted: its start member
#: (design/turbulence_banks.py; flown as a set with --turbulence-banks), generated on first use.
TURBULENCE_BANK = "turbulence"

#: The hypotheses that keep the full tempering under --set-tempering W (the per-hypothesis
#: tempering, cpp/f16mmae/turbulence_adaptation.h): the stabilators, whose likelihoods the gusts
#: lift against NONE's the most in severe air (the greatest excursion of their log-odds over 10
#: held minutes, light member in force, tuning seeds: LS 12.7, RS 21.0 nats), and the flaperons
#: (LF 8.2, RF 5.3 there, but spared at W 0.25 they declared 9 times an hour in the held severe
#: soak of campaign seed 7; every other hypothesis 5.2 or less): docs/results/turbulence_banks.md.
SET_TEMPERING_FULL: tuple[str, ...] = ("LS", "RS", "LF", "RF")
#: The hypotheses kept at the full s by ``--set-tempering`` with a bank's own adaptation
#: (``--adapt-turbulence`` without a bank set; a scheduled bank): the surfaces above and the
#: sensors whose hypotheses the gusts mimic in light air, normal acceleration, angle of attack and
#: airspeed (at the nominal node LF, AZ and VEL reach a declaration on the node's calibration
#: flights even at s; spared at W 0.25 with the surfaces kept, AOA joins them and PIT reaches
#: 3.2 nats); the roll, pitch and yaw gyros, the lateral accelerometer and the rudder are spared
#: (docs/results/envelope_scheduled.md, round 20).
ADAPT_SET_TEMPERING_FULL: tuple[str, ...] = ("LS", "RS", "LF", "RF", "AZ", "AOA", "VEL")
#: The hypotheses whose share of the tempering ``--set-tempering-rough`` sets while the air reads
#: rough (cpp/f16mmae/turbulence_adaptation.h rough_tempering): the rudder and the lateral
#: accelerometer, spared in light and moderate air (their failures' evidence needs it there) and,
#: spared, lifted past declarations by lateral gusts in severe air above 29,000 ft
#: (docs/results/envelope_scheduled.md, round 51).
ADAPT_SET_TEMPERING_ROUGH: tuple[str, ...] = ("RUD", "AY")
#: The per-hypothesis tempering's margin reference with ``--set-tempering-margin-stabilators``
#: (with NONE; cpp/f16mmae/turbulence_adaptation.h ``spare_margin_over``): the stabilators.
SET_TEMPERING_MARGIN_STABILATORS: tuple[str, ...] = ("LS", "RS")

#: Every 0.1 Mach and 5,000 ft, plus Mach 0.35: on the low-q̄ side the trims (alpha ~ 1/M^2)
#: need the finer cell (docs/results/envelope_scheduled.md measures both grids).
SCHEDULE_GRID = "mach=0.3/0.35/0.4/0.5/0.6/0.7/0.8,alt=5000:35000:5000"
#: How the scheduled bank's nodes get their pseudonoise (design/schedule.py NODE_TUNINGS).
SCHEDULE_NODE_TUNING = "calibrated"
#: Revision of the scheduled design (design/schedule.py); part of the cached bank's name, so a
#: change of what a node carries designs the bank anew.  2: per-node adaptation reference;
#: 3: that reference bounded by the calibration flights' failure log-odds (calibrate.bounded_reference);
#: 4: then the smallest of the node's and its grid neighbours' (schedule.neighbourhood_minimum);
#: 5: a probability floor per node, chosen with the reference (calibrate.bounded_settings);
#: 6: both bounded on calibration flights flown with the estimator's start-up (since 10
#:    calibrate.CALIBRATION_START_UP_S);
#: 7: that start-up recommended by the file itself (schedule format 3's start_up_s);
#: 8: the nodes above 2 Q0 calibrated on flights with the dither's high-q̄ rule for the pairs
#: (truth/dither.py), which the truth flies there; 9: that rule's pairs at 3.5 / 4.2 Hz;
#: 10: the failed VEL's ``constant`` model (SCHEDULE_FAILURE_MODEL), floors and references bounded
#: on each node's ``complete`` bank (calibration start-up 0.25 s), the file recommending a start-up of 1 s
#: (calibrate.START_UP_S, CALIBRATION_START_UP_S); 11: a node whose calibrated NONE filter misfits
#: jointly (NIS / m above calibrate.JOINT_NIS_LIMIT) puts AOA's excess on its measurement, not on
#: the alpha state, where that fits better (calibrate.calibrate_node); 12: the failed roll gyro
#: read as a constant level too (SCHEDULE_FAILURE_MODEL), Dryden gust states at the nodes at or
#: below SCHEDULE_GUST_STATES_BELOW_FT where their calibration gains by them
#: (SCHEDULE_GUST_NODE_CHOICE), and the estimator's turbulence adaptation counting each filter's
#: residual power per channel it reads but VEL's (SCHEDULE_ADAPT_COUNTED_CHANNEL;
#: loop/estimator_options.py scheduled_defaults); 13: Dryden gust states at every node at or
#: below 20,000 ft (SCHEDULE_GUST_STATES_BELOW_FT, SCHEDULE_GUST_NODE_CHOICE ``all``): a filter that
#: models the gusts' colour leaves no slow residual for them to build a false AOA or AZ from in
#: hours of pilotless level flight (docs/results/envelope_scheduled.md, round 21); 14: each node's
#: calm-air reference (calibrate.calm_reference; schedule format 4), which SCHEDULE_CALM_COMPLETE reads;
#: 15: the throttle command as every node's sixth input (SCHEDULE_THROTTLE_INPUT); 16: a failed
#: sensor's channel at the sensor's own noise (SCHEDULE_FAILED_SENSOR_NOISE); 17: a node beside an
#: untrimmable grid point at its least candidate floor, its reference as bounded before (the
#: trimmable edge); 18: every node at its least candidate floor, its reference as bounded at the floor
#: its calibration chose (schedule.neighbourhood_settings: the calibration flies light air only);
#: 19: the floors of revision 17 again, the estimator moving the floor in force to SCHEDULE_ROUGH_P_MIN
#: in rough air (cpp/f16mmae/rough_air_floor.h); 20: every node calibrated in the one turbulence model
#: the truth now flies everywhere (truth/turbulence.py hold_axes: before, about half the nodes flew
#: their calibration flights with the yaw and pitch gusts' signs flipped); 21: each node's reference
#: bounded cell by cell at the cell's own floor (schedule.neighbourhood_settings); 22: the truth's
#: dither follows the pairs' high-q̄ rule from 1.1 Q0 (truth/dither.py; from 2 Q0 before), so the
#: nodes above it are calibrated on the dither they now fly.
SCHEDULE_DESIGN_REVISION = 22
#: The failure model of the scheduled design's hypotheses (design/hypotheses.py, per component):
#: a failed VEL reads an unknown constant within its scheduled trim's uncertainty, a failed roll
#: gyro (ROL) an unknown constant within its noise sigma (the trim roll rate is 0).
SCHEDULE_FAILURE_MODEL = "constant=VEL+ROL"
#: What a failed sensor's reading varies by about its hypothesis' prediction in the scheduled
#: design (design/tuning.py ``failed_sensor_noise``): the sensor's own noise, not the node's R with
#: the pseudonoise its calibration put there for the aircraft's unmodelled response (the normal
#: accelerometer's gusts at high dynamic pressure, up to 0.014 g^2), which a failed sensor no
#: longer reads. Kept on the failed AZ, it let the failed hypothesis explain the healthy reading,
#: which stays near its trim in calm air, better than the no-failure filter predicted it, and AZ was
#: declared in every calm flight at the high-q̄ points below 10,000 ft (docs/results/envelope_scheduled.md, round 36).
SCHEDULE_FAILED_SENSOR_NOISE = "sensor"
#: The failure model whose bank's power ratio a ``--calibration-bank scaled`` design reads its
#: nodes' in (design/schedule.py, reference scale): the model the scheduled estimator's references
#: and gates were tuned with (rounds 12-33).
SCHEDULE_SCALE_MODEL = "constant=VEL+ROL"
#: The scheduled design's nodes at or below this altitude (ft) carry Dryden gust states
#: (design/schedule.py gust_states_below_ft; the others inert ones) ...
SCHEDULE_GUST_STATES_BELOW_FT = 20000.0
#: ... every one of them (design/schedule.py GUST_NODE_CHOICES: ``all``; ``effort`` would keep
#: them only where the node's calibration flights ask a failure for less declaration effort).
SCHEDULE_GUST_NODE_CHOICE = "all"
#: The scheduled design's nodes model the throttle command as their sixth input (design/model.py,
#: ``design --throttle-input``), and the closed loop flies the truth's throttle dither with them
#: (loop/flight.py): the pilot's or the autopilot's throttle is then a known input, not a thrust
#: the filters read as a failure, and the dither moves the airspeed that the gusts move little
#: high up (docs/results/envelope_scheduled.md, round 30).
SCHEDULE_THROTTLE_INPUT = True
#: The scheduled estimator's turbulence adaptation counts each filter's residual power per
#: channel it reads, but for this sensor's uninformative channel, which counts as read
#: (loop/estimator_options.py scheduled_defaults; cpp/f16mmae/turbulence_adaptation.h): the
#: failed VEL's level follows the failed reading slowly, and counted per channel read its
#: hypothesis would temper its own evidence by up to 7/6 (docs/results/envelope_tuning.md).
SCHEDULE_ADAPT_COUNTED_CHANNEL = "VEL"
#: The scheduled estimator's per-hypothesis tempering weight W (``--set-tempering``, with the
#: turbulence adaptation; loop/estimator_options.py scheduled_defaults): the best-fitting failure
#: hypothesis outside ADAPT_SET_TEMPERING_FULL has its evidence tempered by 1 + W (s - 1). The
#: nodes' references put s at 2-4 in settled light air near Mach 0.4 (the flaperons' and AZ's gust
#: look-alikes need it), which held a failed roll gyro's evidence below a declaration in 40 of 400
#: settled random-point runs; spared, none (docs/results/envelope_scheduled.md, round 20).
SCHEDULE_SET_TEMPERING = 0.25
#: The scheduled estimator's rough-air bound on the air's measured rho (``--set-tempering-rough``,
#: with the per-hypothesis tempering): from it on the rudder's share of the tempering is
#: SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT (ADAPT_SET_TEMPERING_ROUGH). Over 40 random points
#: moderate air's rho reads at most 2.3 (95th percentile) and severe air's median 2.7-15.5,
#: growing with altitude; the rudder's false declarations in severe air were where it reads 9 or
#: more, above 29,000 ft. Fully tempered from 8 or 9 the same of them went; from 9 three more
#: failed rudders were found there within 5 s, from 10 23 declarations came back (tuning seed 7:
#: docs/results/envelope_scheduled.md, round 51).
SCHEDULE_SET_TEMPERING_ROUGH = 9.0
#: The rudder's share of s - 1 from SCHEDULE_SET_TEMPERING_ROUGH on (``--set-tempering-rough-weight``;
#: 1: the full s). Tuning seed 7, severe air, 40 random points: with 0.25 (spared as in calmer
#: air), 0.35, 0.5, 0.7 and 1 the held soak's rudder declarations in 40 h were 154, 37, 6, 4 and 3,
#: and failed rudders found within 5 s 113, 112, 111, 110 and 107 of 120: 0.5 is the knee. With
#: the lateral accelerometer's share 0.5 there too the soak's AY declarations went 12 -> 0 for one
#: failed AY of 120 (the roll gyro's 5 -> 1 cost five of its failures: left spared).
SCHEDULE_SET_TEMPERING_ROUGH_WEIGHT = 0.5
#: The scheduled estimator's trim tracking time constant in s (``--trim-tracking``, with the
#: turbulence adaptation; loop/estimator_options.py scheduled_defaults; cpp/f16mmae/trim_tracker.h).
#: Without it the truth's fuel burn walks the no-failure filter's AOA and AZ residuals off zero
#: over minutes (at the nominal point -0.0008 rad and +0.004 g after 5 min), and 10-h level soaks
#: there declare AOA and AZ falsely 38.6 times an hour, 4.3 with the pilot holding altitude and
#: Mach; with it 7.7 and 0.1 (docs/results/envelope_scheduled.md, round 20).
SCHEDULE_TRIM_TIME_CONSTANT_S = 30.0
#: The scheduled estimator's least dwell per hypothesis (``--dwell-s-per-hypothesis``, with the
#: turbulence adaptation; loop/estimator_options.py scheduled_defaults; cpp/f16mmae/declarer.h): a
#: failed VEL is declared after 1 s above the threshold, not the 0.25-s dwell. Its filter, free of
#: the airspeed reading, explains a gust's angle-of-attack and normal-acceleration excursion better
#: than the no-failure filter for a fraction of a second: at the nodes without gust states (above
#: 20,000 ft) those excursions declared VEL falsely 5 times an hour in pilotless flight, and were
#: the scheduled default's false-alarm runs on the settled envelope; its failures hold the
#: threshold for good (docs/results/envelope_scheduled.md, round 22). A failed angle-of-attack
#: sensor after 0.75 s (round 27): read against the trim averaged over
#: SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S, the AOA hypothesis fits a healthy sensor a little better
#: where the scheduled trim swings with the measured airspeed (Mach 0.35, 25,000 ft), and its short
#: false rises there are cut by the longer dwell; they come in light air (round 41: without the
#: dwell in light air a 10-h soak there declared AOA 13 times against 2, and a 30-deg turn's roll-in
#: declared it briefly), so it holds in all air. A dual with VEL or AOA waits as its component does
#: (declarer.h). The others are rough-air dwells (SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS).
SCHEDULE_DWELL_S_PER_HYPOTHESIS = "VEL=1,AOA=0.75"
#: The scheduled estimator's least dwells in rough air (``--rough-dwell-s-per-hypothesis``, with
#: the turbulence adaptation; cpp/f16mmae/declarer.h), in force while the adaptation's scale is at
#: least SCHEDULE_ROUGH_SCALE (all air before round 41). A failed rudder after 2 s (1 s in round
#: 40): at the trimmable edge in moderate air (Mach 0.36-0.365, 34,000-34,500 ft, scale 24-35) the
#: rudder swings +-13 deg as the yaw damper and the interconnect answer the gusts at alpha 0.34 rad,
#: and in a gust burst the no-failure filter (the nearest node's past the edge) misses roll and
#: lateral acceleration enough for the RUD hypothesis to hold the threshold for up to 1-2 s, 1-3
#: times an hour; a failed rudder holds it for good. In light air (scale <= 2.8 at every rudder
#: declaration over 60 random points) and in moderate air at the nominal point (<= 4.8) no such
#: excursion was seen, and there the rudder keeps its latency. A failed pitch gyro after 0.5 s
#: (round 39): at the same edge in moderate air gusts sweep alpha across the pitch break and the
#: PIT hypothesis held the threshold for 0.3-0.4 s at a time, 3 to 4 times an hour. A failed normal
#: accelerometer after 0.5 s (round 23, in gusts at Mach 0.35, 25,000 ft; round 41: no AZ
#: declaration in light air there without it, and failed AZ sensors found sooner over the
#: envelope). A dual with RUD, PIT or AZ waits as its component does in rough air.
SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS = "RUD=2,PIT=0.5,AZ=0.5"
#: Rough air for SCHEDULE_ROUGH_DWELL_S_PER_HYPOTHESIS: the adaptation's scale at least this.
SCHEDULE_ROUGH_SCALE = 4.0
#: The scheduled estimator's evidence dwell per hypothesis (``--dwell-nats-per-hypothesis``, with
#: the turbulence adaptation; cpp/f16mmae/declarer.h), kept through the climbs' and maneuvers'
#: dwells (``--evidence-dwell-in-phases``, cpp/f16mmae/hierarchical_bank.h): a hypothesis whose
#: log-odds above the threshold's, summed over its frames above it, reach N_k nats is declared
#: before the 16-frame dwell ends. N_k = max(32, 1.5 E_max,k), E_max,k the most a false excursion
#: of k gathered that the dwell in force rejected, each frame's sum over the dwell in force for k
#: on that frame in 16-frame dwells (the rule asks N_k times that: VEL 4 and AOA 3 everywhere, RUD
#: 8 and PIT and AZ 2 in rough air, a maneuver's longer), over 14,428 tuning flights flown with the
#: frame dwell alone (seeds 7-10: single campaigns at four levels, failures at 3 s and at 20-21 s;
#: 280 h of soaks at the nominal point and the trimmable edge, pilotless and holding; seed 7 also
#: the maneuvers, 60 random points, 40 h at Mach 0.35, 25,000 ft and the maneuvering tour, which
#: seed 8 flies too; tools/latency/dwell_per_hypothesis.py, docs/results/detection_latency.md,
#: rounds 42-43). VEL's 287 asks 1,149 nats in its 1-s dwell, which leaves it to the frame dwell in
#: effect.
SCHEDULE_DWELL_NATS_PER_HYPOTHESIS = ("LS=221.4,RS=128.7,LF=83.6,RF=120,RUD=124.1,VEL=287.3,AOA=152.1,"
                                      "PIT=274.4,AZ=204.8,ROL=120.7,YAW=32,AY=99.1")
#: The scheduled estimator's calm-air complete model (``--calm-complete``, with the turbulence
#: adaptation, on a schedule whose nodes carry a calm-air reference; loop/estimator_options.py
#: scheduled_defaults; cpp/f16mmae/calm_air_complete.h): while the measured power ratio is below the
#: node's reference (midway between its calm and light air), a failed VEL is the paper's complete
#: failure, not a free constant. The light-air design's no-failure filter follows the airspeed
#: sensor's noise, so in calm air a constant predicts the healthy reading better than it does: the
#: constant declared VEL about 3.7 s into every calm flight (6.0 an hour at the nominal point),
#: while a failed and a healthy airspeed sensor read the same constant there (round 24).
SCHEDULE_CALM_COMPLETE = "VEL=1"
#: How SCHEDULE_CALM_COMPLETE reads the air (``--calm-measure``): calm by either the power ratio
#: against the node's reference or the residual whiteness below its bound
#: (cpp/f16mmae/residual_whiteness.h). The power ratio alone read calm air as rough in the first
#: seconds of some calm flights and above 30,000 ft, each time a false VEL (179 of 3,900 calm
#: tuning runs); the whiteness separates the airs up to 30,000 ft from 2 s on, and the power
#: ratio still reads some calm flights above it (4 of 3,900; round 25).
SCHEDULE_CALM_MEASURE = "either"
#: The scheduled estimator's complete failures read against the trim held while a failure is
#: declared (``--complete-trim-hold``, with the turbulence adaptation; loop/estimator_options.py
#: scheduled_defaults; cpp/f16mmae/complete_trim_hold.h). The schedule's trim follows the measured
#: air data and light air moves the airspeed: over a few seconds the AOA trim moves by two or three
#: AOA noise sigmas, which a failed sensor does not follow, so a failed AOA declared in time was
#: backed out to NONE as the trim moved away. Held from a false rise already (``suspected``), the
#: trim prolonged some false AOA rises at Mach 0.35, 25,000 ft (round 26).
SCHEDULE_COMPLETE_TRIM_HOLD = "declared"
#: The trim a complete failure is read against while nothing is held, averaged over this many
#: seconds (``--complete-trim-time-constant``, with the turbulence adaptation; loop/estimator_options.py
#: scheduled_defaults; cpp/f16mmae/complete_trim_hold.h). Light air moves the measured airspeed and
#: with it the scheduled AOA trim by 0.003 rad within seconds after a failure; a failed AOA compared
#: with that trim was read as VEL or as nothing before it could be declared (round 27: 10 s). Over
#: 30 s (round 43) the gusts' wander averages out further: a failed AOA 20-21 s into a flight is
#: found at 13 more of 600 random-point runs on the tuning seed, with no tuning soak's declaration
#: changed (the evaluation seeds: 29 and 8 more of 400; docs/results/envelope_scheduled.md, round 43).
SCHEDULE_COMPLETE_TRIM_TIME_CONSTANT_S = 30.0
#: The scheduled estimator's load-factor tempering (``--maneuver-tempering``, n_ref in g, with the
#: turbulence adaptation; loop/estimator_options.py scheduled_defaults; cpp/f16mmae/maneuver_kinematics.h:
#: every likelihood tempered by 1 + (dn / n_ref)^2, dn the blended estimate's load factor off the
#: trim), the turbulence bank set's own (design/turbulence_banks.py MANEUVER_TEMPERING_G). In severe
#: air a gust takes the angle of attack far from the trim and the stabilators' linear models with it:
#: with the pilot holding altitude and Mach, 10-h soaks declared LS and RS falsely 1.5-2.0 times an
#: hour; with it 0.3-0.8, light, moderate and calm air as before (round 28).
SCHEDULE_MANEUVER_TEMPERING_G = 1.0
#: The scheduled estimator's angle-of-attack tempering (``--maneuver-tempering-alpha``, a_ref in deg,
#: and ``--maneuver-tempering-alpha-deadband``, a_d in deg, with the turbulence adaptation;
#: loop/estimator_options.py scheduled_defaults; cpp/f16mmae/maneuver_kinematics.h: y^2 added to the
#: turbulence scale s, y = max(0, |da| - a_d sqrt(s)) / a_ref, da the blended estimate's angle of
#: attack off the trim). With the pilot holding altitude and Mach at Mach 0.3, 10,000 ft (trim
#: alpha 9.5 deg) light gusts' pitch excursions take alpha 2-3 deg off the trim at 0.1 g, past the
#: linear drag and pitching moment, and stabilators and flaperons were declared falsely 4-8 times an
#: hour; with it 0-0.1 an hour (evaluation and held-out seeds), severe air unchanged: its gusts' alpha
#: lies inside a_d sqrt(s) (round 31). The dead band a_d 0.25 deg (0.75 in rounds 31-47, round 48):
#: at Mach 0.31-0.35 between 17,800 and 26,600 ft (trim alpha high, q̄ 0.55-0.75 Q0) moderate gusts'
#: excursions of 0.25-0.75 deg sqrt(s) were enough for false flaperon declarations (30 in 15 h on
#: the tuning seed, 13 with 0.25); at the design point the same campaigns give the same counts.
#: The trim knee a_k 8.5 deg (round 49; cpp/f16mmae/maneuver_kinematics.h): above a trim angle of
#: attack alpha0 of a_k the reference is a_ref (a_k / alpha0)^3, so at the low-speed points (trim
#: alpha 11-16 deg) a 2-deg gust excursion adds 5-40 times the square it adds at the design point
#: (8.1 deg, where nothing changes). Chosen on the tuning seed's envelope soak
#: (docs/results/envelope_scheduled.md).
SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEG = 1.0
SCHEDULE_MANEUVER_TEMPERING_ALPHA_DEADBAND_DEG = 0.25
SCHEDULE_MANEUVER_TEMPERING_ALPHA_TRIM_DEG = 8.5
#: The scheduled estimator's level channels' scale term (``--adapt-level-scale``, with the turbulence
#: adaptation; cpp/f16mmae/filter_bank.h): while a failure read as a sensor level is declared, the
#: hypotheses reading that level gain (1/2) ln s a frame on those that read the channel as tempered
#: Gaussians. Without it, in severe air (s 40-50) NONE gained 0.1-0.2 nats a frame on a declared
#: failed roll gyro, by the tempering's dropped ln s alone, and backed it out in 3-6 of 10 runs at
#: the nominal point; level 0 is unchanged (round 28).
SCHEDULE_ADAPT_LEVEL_SCALE = "on"
#: The scheduled estimator's level channels scaled at every level (``--adapt-level-scale-channel``,
#: ``--adapt-level-scale-from``, with the turbulence adaptation; cpp/f16mmae/filter_bank.h): the
#: hypotheses reading VEL's channel as a level gain (1/2) ln max(s / s_0, 1) a frame at every
#: level, before any failure is declared too. In severe air (s 17-100 over the envelope) a failed VEL's evidence is the
#: gusts', divided by s, and the level's density carries no s^-1/2: without the term VEL was missed
#: 4-6 times in 10 at the nominal point (7-9 settled). s_0 = 8 lies above light and moderate air's s
#: at the nominal point (at most 3.9) and light air's off it (at most 2.6), below severe air's
#: anywhere (5th percentile 16.6 at Mach 0.3, 5,000 ft); s_0 = 1 (the full (1/2) ln s) declared VEL
#: falsely in light air high up (round 29).
SCHEDULE_ADAPT_LEVEL_SCALE_CHANNEL = "VEL"
SCHEDULE_ADAPT_LEVEL_SCALE_FROM = 8.0
#: The scheduled estimator's lull floor (``--adapt-floor``, with the turbulence adaptation;
#: cpp/f16mmae/turbulence_adaptation.h): the scale reads the larger of the residual power ratio's
#: 5-s average and its average over this many seconds (a plain mean from the start, in force from
#: half of it on, held in a climb or maneuver), so a burst of gusts after a lull is not read by the
#: untempered design. In moderate air at the nominal point the false flaperon and roll-gyro
#: declarations began at s 1-1.55 against flight medians of 2-4; 40 h of soaks (tuning seeds 7-10)
#: declared falsely 7 times without it, 2 with it; the campaigns' flights (8-26 s) are unchanged.
#: A slower fall of the 5-s average itself (over 10 s) held s near the bursts' peaks and found 7 of
#: 20 flaperon failures in moderate air late in flight (round 44; docs/results/
#: turbulence_adaptation.md).
SCHEDULE_ADAPT_FLOOR_S = 60.0
#: The scheduled estimator's knee on the adaptation's bound (``--adapt-scale-max-from``, with the
#: turbulence adaptation; cpp/f16mmae/turbulence_adaptation.h): from this air's power ratio on the
#: bound on s (100, which the line 1 + 20 (rho - rho_0) meets near 5.5) rises with the air at the
#: line's gain. Over 40 random points severe air reads 6-10 between 23,000 and 32,000 ft and
#: 11.7-15.5 above, where s sat at the bound on every frame and 17 of the held soak's 19 false
#: declarations were (tuning seed 7; the other two rudders at 12,000 and 17,800 ft). Tuning seed
#: 7, severe air: the held soak declared falsely 19 times in 40 h with the bound alone and the
#: envelope found 1,334 of 1,560 failures within 5 s; with the knee at 12, 10.5 and 9.5 9, 5 and 3
#: times, for 1,330, 1,323 and 1,316; the bound raised to 150 or 400 everywhere 4 and 2 times, for
#: 1,292 and 1,271 (docs/results/envelope_scheduled.md, round 52).
SCHEDULE_ADAPT_SCALE_MAX_FROM = 10.5
#: The scheduled estimator's rough-air floor (``--rough-p-min``, with the turbulence adaptation;
#: cpp/f16mmae/rough_air_floor.h): the level-0 floor moves from the node's, chosen on the
#: calibration's light-air flights, to this one as the air's measured power ratio crosses the band
#: 1.3-1.5 in the node's calm-air units (the core's default band). The nodes' chosen floors in
#: moderate air lift gust-driven flaperon and rudder hypotheses to the threshold (10-h soaks at
#: 15,000 ft: 18-102 false declarations against 1-4 at this floor), the least floor everywhere costs
#: the light air's detections (docs/results/envelope_scheduled.md, rounds 45 and 46). The least
#: candidate floor of the calibration (design/calibrate.py P_MIN_CANDIDATES).
SCHEDULE_ROUGH_P_MIN = 1e-9
#: The scheduled estimator's maneuvering-flight setting (``--maneuver-setting on``, with the
#: turbulence adaptation; loop/estimator_options.py scheduled_defaults applies each entry unless
#: given, and none with ``--maneuver-setting off``): the turn kinematics and gravity in every
#: filter (cpp/f16mmae/maneuver_kinematics.h) with the actuators' limits; while the air data climb
#: or change Mach, or the low-passed load factor leaves the trim (the gates' thresholds times
#: sqrt(s_c), read from the node's calm-air reference, so level flight in any air keeps them shut;
#: cpp/f16mmae/hierarchical_bank.h), the adaptation's reference 0.6 in a climb and 0.65 in any
#: maneuver, held 30 s, and a 0.4-s dwell; the load factor beyond its own spread added to s; the
#: steady trim tracking of AOA, VEL, AZ and AY in level flight, whatever the air data's rates (AY
#: since round 40: a slow bias of the estimated lateral acceleration in a banked drift, fed back
#: through the FCS, rolled a pilotless aircraft at the trimmable edge into a spiral dive). Before
#: it the scheduled default flew the maneuver campaign 399/480 with 138 false-alarm runs (tuning
#: seed); with it 475/480 [97.6-99.7 %], no declaration in the 2.1-h tour and a latency median of
#: 0.91 s (VEL apart) on the evaluation seed, level flight as before within a few runs (round 33,
#: docs/results/envelope_scheduled.md).
SCHEDULE_MANEUVER_SETTING: dict[str, object] = {
    "maneuver_kinematics": True, "actuator_limits": True,
    "adapt_reference_climb": 0.6, "adapt_reference_climb_hold_s": 30.0,
    "maneuver_dwell_s": 0.4, "maneuver_dwell_hold_s": 30.0, "maneuver_dwell_g": 0.07, "maneuver_reference": 0.65,
    "maneuver_tempering_added_g": 0.03, "maneuver_tempering_added_deadband_g": 0.08,
    "maneuver_tempering_added_spread": 3.0,
    "maneuver_climb_ft_s": 10.0, "maneuver_mach_per_s": 0.002, "maneuver_gates_calm_scaled": True,
    "trim_steady_g": 0.1, "trim_steady_air_data": "off", "trim_steady_measurements": "AOA,VEL,AZ,AY",
}
#: How a scheduled bank follows the air data (core.HierarchicalBank schedule_mode); the first
#: is the default (docs/results/schedule.md compares them).
SCHEDULE_MODES: tuple[str, ...] = ("interpolate", "nearest")
#: The longest declaration dwell the estimator accepts (s): the core's bound
#: (cpp/f16mmae/estimator_settings.h kMaxDwellS), defined there once.
DWELL_S_MAX: float = MAX_DWELL_S
#: The declaration threshold the core defaults to and every shipped bank recommends
#: (cpp/f16mmae/estimator_settings.h kDefaultThreshold), defined there once.
THRESHOLD_DEFAULT: float = DEFAULT_THRESHOLD


def failed_components(hypothesis: str) -> tuple[str, ...]:
    """Components a hypothesis presumes failed: ``"LS+PIT" -> ("LS", "PIT")``, ``"NONE" -> ()``;
    a partial-loss hypothesis (``design --partial-loss``) its surface: ``"LS:loss=0.5" -> ("LS",)``."""
    if hypothesis == NONE:
        return ()
    parts = tuple(hypothesis.split("+"))
    if len(parts) == 1 and ":" in parts[0]:
        parts = (parts[0].split(":", 1)[0],)
    for p in parts:
        if p not in COMPONENTS:
            raise ValueError(
                f"unknown component {p!r} in hypothesis {hypothesis!r}; "
                f"valid: {', '.join(COMPONENTS)}"
            )
    return parts


def dual_name(a: str, b: str) -> str:
    """Canonical name of the dual hypothesis of components a and b (order-independent)."""
    order = COMPONENTS
    ia, ib = order.index(a), order.index(b)
    if ia == ib:
        raise ValueError(f"a dual failure needs two different components, got {a!r} twice")
    return f"{order[min(ia, ib)]}+{order[max(ia, ib)]}"


def level1_hypotheses(failed: str) -> tuple[str, ...]:
    """The level-1 bank brought on line when ``failed`` is declared (Fig. 2):
    NONE first (for back-out), the declared single failure, then its 11 duals."""
    others = [c for c in COMPONENTS if c != failed]
    return (NONE, failed) + tuple(dual_name(failed, c) for c in others)
