// HierarchicalBank — the paper's hierarchical MMAE (Eide & Maybeck, Sec. III, Fig. 2):
// a FilterBank of K filters on line, a Declarer, and every hypothesis filter of a ModelBank
// preloaded in storage. Eigen and std only.
//
// Levels (K = 1 + number of failable components; 13 for the F-16: 5 actuators, 7 sensors):
//   level 0   {NONE, every single failure c}, in the ModelBank's order. Starts here with
//             NONE presumed.
//   level 1   brought on line when single failure f is declared at level 0:
//             {NONE, f, f+c for every other component c} (NONE first, for back-out).
//   back-out  NONE declared at level 1 -> level 0 again, NONE presumed.
//   final     a dual f+c declared at level 1 is the final answer: the bank stays at level 1
//             (it keeps running; a later NONE declaration still backs out).
// The hypotheses of each level are found by NAME in the ModelBank, once, at construction:
// hierarchy_levels.h (singles, the duals "a+b" or "b+a", the partial hypotheses "c:MODE" and
// their level-1 banks with spare slots off line, the components for declare_components).
//
// Initialisation at a switch (after the update of the frame on which the declaration
// happened, before its propagate): every filter brought on line starts from the posterior
// state x⁺ of the declared filter — the best-matched filter at that moment — and the
// probabilities presume the declared hypothesis (p = 1 - (K-1) p_min on it, p_min on the
// others), exactly as level 0 presumes NONE at start. The declarer restarts with the
// declared hypothesis current, so it must be out-voted for a dwell before the next switch.
//
// Frame order. update(z_abs), one frame (accepted or rejected; frame index i, 0-based, has
// time_s = i / frame_rate_hz):
//   1. z = z_abs - z_trim - dz, the readings about the trim in force (below);
//   2. with maneuver.tempering_g, the likelihoods' tempering scale is set;
//   3. the FilterBank's update (filter_bank.h); a rejected update ends the frame (-1): the
//      declarer sees only accepted updates; at level 1 with options.level1_allowance the
//      duals' drift allowance (level1_allowance.h) on the probabilities it left;
//   4. the maneuver trim's inertial rates (maneuver_trim.inertial, inertial_flight_path.h) and
//      the maneuver dwell's load factor (maneuver_dwell.h) read the frame;
//   5. at level 1, the departure hold (departure_hold.h): on a held frame the declarer's dwell
//      restarts and nothing is declared;
//   6. the declarer (declarer.h) with the dwell and the components in force, and the
//      adaptation's scale at the base reference, s_b (below), for its rough-air least dwell;
//      a declaration is recorded, and switches the level (initialisation above);
//   7. the trim tracker (trim_tracker.h) reads the frame.
// propagate(u_abs): the actuators' limits on u (actuator_limits.h), u - u_trim - du, the
// kinematic forcing of the blended posterior (maneuver_kinematics.h), the FilterBank's
// propagate, every x⁻ plus the forcing, the trim tracker. step(z, u) = update, then propagate.
//
// Where each rule is stated:
//   hierarchy_levels.h   the hypotheses on line at each level, partial hypotheses, live slots,
//                        components
//   departure_hold.h     level 1: no declaration while the measurements leave the
//                        linearization (options.departure; on by default)
//   declarer.h           threshold, dwell, declaring on components
//   filter_bank.h        likelihoods, probabilities, floors, live slots
//   level1_allowance.h   level 1: the duals' drift allowance (Page's reference value) and why
//   level_floors.h       the level-1 floor and dwell, the partial hypotheses' floor
//   rough_air_floor.h    the level-0 floor that follows the air
//   below                declaring on components, air data and scheduling, trims, maneuvering
//                        flight
//
// The floors and dwell of the levels (level_floors.h: the derivation, equations and bounds):
//   options.level1_p_min (0, the default: the level-0 floor, bit for bit), the floor of a
//   level-1 bank's duals f+c while it is on line, NONE and f keeping the level-0 floor (p_min,
//   or a scheduled bank's node floor), the level-0 floor for all again back at level 0
//   (back-out, reset()); options.level1_dwell_s (0: the level-0 dwell), the dwell a
//   declaration needs while a level-1 bank is on line; options.partial_p_min (0: the level-0
//   floor), the floor of every partial hypothesis c:MODE at level 0.
// The level-0 floor in rough air (options.rough_floor, rough_air_floor.h; off by default): the
//   level-0 floor moves log-linearly to rough_floor.p_min as the air's measured power ratio, in
//   the schedule's calm-air units, crosses the band [from, to]; set before each update from the
//   frames before, wherever the level-0 floor enters (level 1's NONE and f included).
// The duals' allowance at level 1 (options.level1_allowance, nats a frame, >= 0; 0, the default:
//   none, bit for bit): while a level-1 bank is on line every dual's likelihood carries the
//   factor e^{-k} (level1_allowance.h: the derivation); NONE, f and a partial f's other form
//   take none. options.level1_allowance_pairs ("F>C" -> k_{F>C}, empty by default) gives a dual
//   F+C its own k in F's level-1 bank (level1_allowance.h: k = min(a r_{F>C}, k_max), r the
//   dual's drift under its second failure); a dual not named there takes
//   options.level1_allowance. Refused (naming level1_allowance_pairs): a key that is not two
//   different singles of the bank, a k < 0 or not finite.
// Declaring on components (options.declare_components; off by default: each hypothesis alone,
//   bit for bit): a partial hypothesis c:MODE and its single c are one component for the
//   declarer (declarer.h: the sum of their probabilities against the threshold, the dwell on
//   the sum, the declaration names the form that holds more mass), at level 0 and in the
//   partial's level-1 bank (c:MODE and c both on line: the mass moving between c's two forms
//   there is no new declaration; the groups: hierarchy_levels.h). The level-1 bank is the
//   declared form's: a declared c:MODE brings both forms on line, a declared c its own bank
//   {NONE, c, c+d} (the duals are complete failures of c; c held more mass than c:MODE when
//   declared). A bank without partial hypotheses is unchanged by the option.
//
// Air data (air_data.h): schedule(a) before a frame's update hands the bank the measured
// air data. A non-finite value is counted in air_data_rejected() and the last usable value
// stays in force. air_data() reports what is in force (the ModelBank's design condition
// (mach, alt_ft) until the first usable value; reset() returns to it).
//   A bank designed at one flight condition: its filters and trim do not depend on it.
//   A scheduled bank (ModelBank::schedule, bank_schedule.h): every node's 79 filters are
//   preloaded, and schedule(a) selects the filters and trims in force on the grid
//   (scheduled_filters.h: bilinear interpolation or nearest node with hysteresis,
//   HierarchicalOptions::schedule). A change of filters reloads the on-line ones (and a
//   hierarchical switch loads the ones in force); when the trim state x_trim moves, every
//   on-line filter's x⁻ and x⁺ move by x_trim_old - x_trim_new (bumpless: the absolute
//   estimate is continuous); before the first frame nothing moves (the filters start at the
//   trim in force at their first frame); likewise the levels b̂ of the failed sensors'
//   uninformative channels (filter_bank.h) move by z_trim_old - z_trim_new, so a level is that
//   of the absolute reading and a failed sensor's constant reading stays a constant level
//   while the scheduled trim moves. Probabilities, the declarer, the declarations and the level are
//   untouched by a schedule change. A schedule whose nodes carry an adaptation reference
//   (bank_schedule.h) sets the turbulence adaptation's rho_0 to the blend in force with the
//   filters (ScheduleOptions::node_adapt_reference, on by default; rho itself carries on, and
//   starts at that reference at construction and reset()). A schedule whose nodes carry a
//   reference scale sigma (bank_schedule.h) sets the adaptation's power scale to the blend of
//   sigma in force with the filters (turbulence_adaptation.h: it reads rho / sigma against every
//   reference, the node's, the option's, the climb's and the maneuver's, which stay in the
//   units of the bank sigma is taken against; the calm-air rule reads the measured rho-bar
//   unscaled against the node's calm-air reference, measured on the node's own bank, and the
//   gates' s_c reads that reference divided by sigma). Likewise each node's probability
//   floor (its bank's p_min): the FilterBank's p_min is the blend in force with the filters
//   (ScheduleOptions::node_p_min, on by default; off: options.bank.p_min everywhere), and
//   NONE is presumed with it at construction and reset().
//   With options.schedule.gust_airspeed (off by default) and a bank whose state carries the
//   along-track gust u_g (state "u_g_fps", design/gust_states.py: the turbulence axes' north,
//   the trim's heading) and whose measurements include VEL (else the measured Mach), the
//   schedule follows the Mach number of the aircraft's speed through the mean air, not the
//   gust's:
//     M_s = M + u_g^ / c,   c = VEL_trim / M_f   (the speed of sound of the trims in force),
//   u_g^ the blended prior estimate (the previous frame's propagation; 0 before the first
//   frame and while it is not finite). The pitot reads the gust's airspeed (V_air = V - u_g),
//   and the filters carry the gust as a state about the trim; a trim that follows the gust
//   counts it twice: in moderate turbulence at Mach 0.4, 20,000 ft a 5-s gust moves the
//   measured Mach by 0.012, the scheduled AOA trim by 0.006 rad, and a failed AOA sensor's
//   constant reading (its trim at the start) reads as the aircraft's alpha moving away. Off by
//   default: the truer trim is also what a complete AOA failure reads, so in light air the
//   no-failure filter explains it more often (tuning seed: moderate air at the nominal point
//   114 -> 117 of 120 correct, 60 random points' settled failures 7,020 -> 7,004 of 7,200;
//   docs/results/envelope_scheduled.md, round 40).
//   With options.climb_reference (off by default) the adaptation's rho_0 is its reference
//   while the air data handed to schedule() climb, descend or change speed, and for its hold
//   after (climb_reference.h); else the node's or the option's as above. With its dwell_s, a
//   level-0 declaration in that phase needs that dwell instead of the declarer's.
//   With options.maneuver_dwell (off by default; maneuver_dwell.h) a level-0 declaration needs
//   its dwell while the estimated load factor (low-passed) or the air data say the aircraft
//   maneuvers, and for its hold after; and the adaptation's rho_0 is its reference then, unless
//   the climb reference is in force. Its state is updated after each accepted update, before
//   the declarer.
//   With options.rate_gates_gust_scaled (off by default) both gates' air-data thresholds (the
//   climb rate and the Mach rate, not the load factor) are multiplied by sqrt(s_b),
//       s_b = clamp(1 + kappa (rho - rho_b), s_min, s_max)   (turbulence_adaptation.h, scale_at)
//   the adaptation's scale at the base reference rho_b (the node's or the option's, never a
//   flight phase's), with the rho of the latest update (1 without the adaptation). Why: the
//   gusts move the measured air data too (in moderate air at Mach 0.4, 20,000 ft the rates'
//   p99 is about 19 ft/s and 0.003 Mach/s against light air's 10 and 0.0015, in severe air 51
//   and 0.008; their ratios follow the gusts' intensity, sqrt of the residual power), so a
//   gate set above light air's rates stays open in rougher air, where its reference and dwell
//   cost the failures' evidence; s_b is the gate's own reading of the air, not moved by the
//   phase references the gate itself sets.
//   With options.gates_calm_scaled (off by default; over rate_gates_gust_scaled) all three
//   thresholds -- the climb rate, the Mach rate and the maneuver dwell's load factor g -- are
//   multiplied by sqrt(s_c),
//       s_c = clamp(1 + kappa (rho - rho_c), s_min, s_max)
//   rho_c the schedule's calm-air reference in force (bank_schedule.h: rho-bar midway between the
//   node's calm and light air; the base reference without one). Why: s_b reads moderate air at
//   about the node reference as 1, and its gusts (19 ft/s, 0.003 Mach/s, and the 2-s low-passed
//   load factor beyond 0.1 g at the nominal point) hold the gates open 85 % of a level flight;
//   read from calm air, the gusts' power ratio grows as their intensity squared (calm, light,
//   moderate and severe air: rho-bar 0.54, 0.66, 1.03 and 5.0 at the nominal point), so sqrt(s_c)
//   is about 1.5, 3 and 9 and the gates stay shut in level flight at every level.
//   With either flight-phase dwell configured (climb_reference.dwell_s > 0 or
//   maneuver_dwell.dwell_s > 0) the declarers have no evidence dwell (declarer.h: dwell_nats
//   and the per-hypothesis N_k are set to 0) and declare by their frame dwells alone, unless
//   options.evidence_dwell_in_phases. Why: N_k measured on the excursions of level flight
//   alone miss a maneuver's onset (a roll-in, a pull-up), which holds a hypothesis at the
//   ceiling for a few frames before the load factor or the air data open the phase's gate:
//   the frame dwell rejects it, such an evidence dwell does not. With
//   evidence_dwell_in_phases the evidence dwell stays, asking N_k times the phase's dwell over
//   the declarer's own (declarer.h), for N_k measured on flights that maneuver and climb too
//   (tools/latency/dwell_per_hypothesis.py over maneuver campaigns and soaks).
//   With options.spare_dwell_s (0, the default: off) a level-0 declaration needs that dwell
//   instead of the declarer's on the frames where the per-hypothesis tempering spares the
//   best-fitting failure hypothesis (turbulence_adaptation.h, ResidualScale::spares(): w < 1,
//   s > 1, rho >= rho-bar / 2, rho-bar >= rho_s: with rho_s set, severe air only); a flight-phase
//   dwell in force takes precedence. Why: in air rougher than the design the tempering holds a
//   failure's evidence back by s_b per frame, so every onset reaches the threshold later than in
//   light air, while the dwell that follows is the one chosen against light air's excursions;
//   where the sparing is in force the frames above the threshold are already the tempered ones.
//   A value outside [1 frame, kMaxDwellS] (estimator_settings.h), or one given without the
//   per-hypothesis tempering (options.bank.adaptation.hypothesis_weight < 1, enabled), is
//   refused at construction.
//
// Signals are ABSOLUTE at this interface: update(z) subtracts the trim in force,
// z_trim + dz, propagate(u) u_trim + du, and z_hat() adds z_trim + dz back
// (z_hat_perturbation() does not). States are perturbations from the trim in force.
// Trim in force = the bank's trim (a scheduled bank: the scheduled trim) + the trim offset
// (du, dz): zero unless set_trim_offset()
// sets it or trim tracking (options.trim, trim_tracker.h: a slow low-pass of u and z about the
// trim, frozen while a failure hypothesis rises or a failure is declared; with steady_g also
// while the estimated load factor z_hat(AZ) is off the trim or the air data handed to
// schedule() climb or accelerate, and then only the named measurements) estimates it, after each update and propagate. With zero offsets the arithmetic is the bank's without them.
// Calm air (options.calm_complete, off by default): after each update the calm-air rule
// (calm_air_complete.h) reads the adaptation's measured power ratio against its bounds times the
// schedule's calm-air reference in force (1 unscheduled), while no failure is presumed or rising
// (the trim tracker's condition at its own freeze probability), and hands the bank the channels
// whose tracked levels are read as the paper's complete failure from the next update on
// (FilterBank::set_complete_channels); every bounded channel at the start and reset(). By its
// measure 'whiteness' or 'either' it reads, too, how white the presumed filter's residuals are
// (residual_whiteness.h, averaged over the adaptation's time constant). It needs the adaptation
// (refused at construction without it).
// Maneuvering flight (all off by default: the bank as designed, bit for bit):
//   options.maneuver.kinematics   after each propagate every filter's x⁻ gains dt R(x̂), the
//                                 kinematic/gravity terms the wings-level linearization drops,
//                                 of the blended posterior (maneuver_kinematics.h);
//   options.maneuver.tempering_g  before each update the likelihoods are tempered by
//                                 s_m = 1 + (dn / n_ref)^2, dn the estimated load factor off the
//                                 trim (z_hat's AZ; FilterBank::set_extra_scale);
//   options.actuators             the filters see the commands through the actuators' rate and
//                                 position limits (actuator_limits.h);
//   options.maneuver_trim         the trim in force follows the air data's climb and
//                                 acceleration: u_trim + du_m, z_trim + dz_m, x_trim + dx_m with
//                                 (du_m, dz_m, dx_m) = S (gamma, dV/dt), S the nodes' climb and
//                                 acceleration sensitivities, the states and failed sensors'
//                                 levels moved bumplessly as for a scheduled trim
//                                 (maneuver_trim.h); with maneuver_trim.inertial (gamma, dV/dt)
//                                 from z's rates, AOA and VEL against the air data's, read
//                                 after each update under the trim tracker's freeze condition
//                                 (inertial_flight_path.h);
//   options.complete_trim_hold    the complete failures' channels read against the trim in
//                                 force (or its average over time_constant_s) when a failure
//                                 began to show, held while one is suspected (trim_freezing
//                                 below) or declared (complete_trim_hold.h).
// Sizes: K, NX, NU, NZ compile-time (F16HierarchicalBank = HierarchicalBank<13, 13, 5, 7>;
// F16GustHierarchicalBank = HierarchicalBank<13, 19, 5, 7>, the same bank whose filters carry
// six Dryden gust states, `f16mmae design --gust-states`; F16ThrottleHierarchicalBank =
// HierarchicalBank<13, 13, 6, 7>, the 13-state bank with the throttle command as its sixth
// input, `f16mmae design --throttle-input`; F16GustThrottleHierarchicalBank =
// HierarchicalBank<13, 19, 6, 7>, both: the turbulence bank set's members;
// F16PartialHierarchicalBank = HierarchicalBank<18, 13, 5, 7>, the 13-state bank with a partial
// hypothesis per surface, `f16mmae design --partial-loss F`) or Eigen::Dynamic
// (DynamicHierarchicalBank, any K = 1 + number of singles).
// Throws: the constructor throws std::invalid_argument (invalid ModelBank, sizes that do not
// match the template, a missing hypothesis: hierarchy_levels.h; an option out of range, e.g.
// departure_hold.h). update/propagate/step are noexcept and, for
// fixed sizes, allocate nothing: switches copy preloaded fixed-size hypothesis filters
// (their matrices; the on-line bank holds the states, filter_bank.h); the
// declaration history has a fixed reserved capacity (further declarations are counted in
// declarations_dropped()).
#pragma once

#include "f16mmae/actuator_limits.h"
#include "f16mmae/air_data.h"
#include "f16mmae/air_data_rates.h"
#include "f16mmae/declarer.h"
#include "f16mmae/estimator_settings.h"
#include "f16mmae/departure_hold.h"
#include "f16mmae/filter_bank.h"
#include "f16mmae/hierarchy_levels.h"
#include "f16mmae/level1_allowance.h"
#include "f16mmae/level_floors.h"
#include "f16mmae/rough_air_floor.h"
#include "f16mmae/maneuver_kinematics.h"
#include "f16mmae/model_bank.h"
#include "f16mmae/scheduled_filters.h"
#include "f16mmae/calm_air_complete.h"
#include "f16mmae/complete_trim_hold.h"
#include "f16mmae/climb_reference.h"
#include "f16mmae/maneuver_dwell.h"
#include "f16mmae/maneuver_trim.h"
#include "f16mmae/trim_tracker.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace f16mmae {

struct Declaration {
  int hypothesis = -1;      // index into ModelBank::hypotheses (names via name())
  int level = 0;            // level at which it was declared (0 or 1)
  std::int64_t frame = 0;   // frame index of the update that completed the dwell
  double time_s = 0.0;      // frame / frame_rate_hz
};

struct HierarchicalOptions {
  FilterBankOptions bank;     // p_min, strip_leading_term, adaptation (its rate: the ModelBank's)
  DeclarerOptions declarer;   // threshold, dwell_s (frame_rate_hz is taken from the ModelBank)
  ScheduleOptions schedule;   // a scheduled bank: interpolate or nearest (scheduled_filters.h)
  TrimTrackingOptions trim;   // time_constant_s (0 = off), freeze_probability, hold_s
  ClimbReferenceOptions climb_reference;   // the adaptation's reference while climbing (NaN: off)
  ManeuverDwellOptions maneuver_dwell;     // the dwell and reference while maneuvering (maneuver_dwell.h; off)
  bool rate_gates_gust_scaled = false;     // both gates' air-data thresholds x sqrt(s_b) (header; off)
  bool gates_calm_scaled = false;          // all three gates' thresholds x sqrt(s_c) (header; off)
  ManeuverTrimOptions maneuver_trim;       // the climb's and acceleration's trim (maneuver_trim.h; off)
  ManeuverOptions maneuver;   // kinematics: the kinematic/gravity remainder in the propagation
  ActuatorLimitOptions actuators;   // the actuators' rate/position limits on the commands (empty: off)
  CalmAirCompleteOptions calm_complete;   // a failed sensor's level read as complete in calm air (calm_air_complete.h)
  CompleteTrimHoldOptions complete_trim_hold;   // a complete failure reads a held trim (complete_trim_hold.h; off)
  double level1_p_min = 0.0;  // the floor while a level-1 bank is on line; 0: the level-0 floor (level_floors.h)
  double level1_dwell_s = 0.0;   // the dwell while a level-1 bank is on line; 0: the level-0 dwell (level_floors.h)
  double spare_dwell_s = 0.0;    // the level-0 dwell while the tempering spares (header); 0: off
  bool evidence_dwell_in_phases = false;   // keep the evidence dwell with a flight-phase dwell (header; off)
  double level1_allowance = 0.0;   // the duals' drift allowance at level 1, nats a frame; 0: none (level1_allowance.h)
  std::map<std::string, double> level1_allowance_pairs;   // "F>C" -> the dual F+C's own allowance in F's level-1 bank (level1_allowance.h)
  DepartureOptions departure;    // level 1: no declaration while the measurements leave the linearization (departure_hold.h)
  bool declare_components = false;   // a partial hypothesis and its single declared as one component (hierarchy_levels.h)
  double partial_p_min = 0.0;   // the partial hypotheses' floor at level 0; 0: the level-0 floor (level_floors.h)
  RoughAirFloorOptions rough_floor;   // the level-0 floor follows the air (rough_air_floor.h; off)
  int history_capacity = 1024;
};

template <int K, int NX, int NU, int NZ>
class HierarchicalBank {
 public:
  using Bank = FilterBank<K, NX, NU, NZ>;
  using Hypothesis = typename Bank::Hypothesis;
  using Model = typename Bank::Model;
  using XVector = typename Bank::XVector;
  using UVector = typename Bank::UVector;
  using ZVector = typename Bank::ZVector;
  using PVector = typename Bank::PVector;
  static constexpr bool kFixed = K != Eigen::Dynamic;
  using Levels = HierarchyLevels<K>;
  using Indices = typename Levels::Indices;
  using Schedule = ScheduledFilters<NX, NU, NZ>;

  explicit HierarchicalBank(const ModelBank& bank, const HierarchicalOptions& options = {})
      : HierarchicalBank(bank, options, build(bank)) {}

  // ---- per frame (noexcept; absolute signals) ---------------------------------------------
  // Returns the ModelBank index of the hypothesis declared on this frame, or -1.
  int update(const ZVector& z_abs) noexcept {
    const std::int64_t frame = frame_++;
    z_pert_.noalias() = z_abs - z_trim_;
    z_pert_ -= dz_;
    if (trim_hold_.enabled()) {   // complete_trim_hold.h
      trim_in_force_.noalias() = z_trim_ + dz_;
      const TrimHold rule = trim_hold_.options().hold;
      const bool held = rule == TrimHold::kDeclared ? failure_declared() : rule == TrimHold::kSuspected && trim_freezing();
      bank_.set_held_offset(trim_hold_.observe(trim_in_force_, held));
    }
    if (options_.bank.adaptation.floor_time_constant_s > 0.0)   // the lull floor, held in a flight phase
      bank_.set_adapt_floor_held(climb_ref_.climbing() || maneuver_dwell_.maneuvering());   // (turbulence_adaptation.h)
    if (options_.rough_floor.enabled()) set_floors();   // the floor the air of the frames before gives (rough_air_floor.h)
    if (maneuver_.tempering()) {   // maneuver_kinematics.h
      maneuver_.observe_spread(bank_.z_hat());
      const int a = maneuver_.aoa_tempering_index();   // the trim in force's alpha, with a trim knee
      const double trim_alpha = maneuver_.reads_trim_alpha() ? z_trim_(a) + dz_(a) : 0.0;
      bank_.set_extra_scale(maneuver_.tempering_scale(bank_.z_hat(), bank_.turbulence_scale(), trim_alpha));
    }
    if (!bank_.update(z_pert_)) return -1;
    if (level_ == 1 && allowance_on_[static_cast<std::size_t>(level1_bank_)]) {   // level1_allowance.h
      p_allow_ = bank_.probabilities();
      if (Level1Allowance::apply_each(p_allow_, allowances_[static_cast<std::size_t>(level1_bank_)]))
        bank_.set_probabilities(p_allow_);
    }
    if (maneuver_trim_.reads_z())   // maneuver_trim.h / inertial_flight_path.h
      maneuver_trim_.observe_inertial(z_abs(mt_z_[0]), z_abs(mt_z_[1]), z_abs(mt_z_[2]), z_abs(mt_z_[3]),
                                      z_abs(mt_vel_), z_abs(mt_z_[4]), trim_freezing());
    if (maneuver_dwell_.enabled()) {   // maneuver_dwell.h
      const double c = rate_gate_scale();   // the load factor's too when calm-scaled (header)
      maneuver_dwell_.observe_load_factor(bank_.z_hat()(maneuver_dwell_az_), air_rates_, c,
                                          options_.gates_calm_scaled ? c : 1.0);
      if (maneuver_dwell_.options().has_reference()) bank_.set_adapt_reference(adapt_reference_in_force());
    }
    if (level_ == 1 && departure_.observe(z_pert_, online_[1]))   // departure_hold.h
      declarer_in_force().reset(declarer_in_force().current());   // the dwell restarts
    // the rough-air least dwell (declarer.h) reads the air: s_b, not a flight phase's reference
    if (declarer_in_force().reads_scale())
      declarer_in_force().observe_scale(bank_.adaptation().scale_at(base_adapt_reference()));
    const int d = departure_.held() ? -1
                                      : declarer_in_force().update(bank_.probabilities(), dwell_frames_in_force(),
                                                                   component_groups(), online_.data());
    int hypothesis = -1;
    if (d >= 0) {
      hypothesis = online_[d];
      record(hypothesis, frame);
      if (level_ == 0 && d != 0) {
        switch_to(levels_.level1(d - 1), d, 1, &levels_.level1_live(d - 1));
        level1_bank_ = d - 1;
      } else if (level_ == 1 && d == 0) {
        switch_to(levels_.level0(), 0, 0);
        level1_bank_ = -1;
      }
    }
    if (calm_.enabled()) {   // calm_air_complete.h: decided while no failure is presumed or rising
      const bool decide = !failure_suspected_at(calm_.options().freeze_probability);
      const double reference = sched_.active() ? sched_.calm_reference() : 1.0;
      calm_.observe_residual(bank_.residual(0));   // the presumed filter's (with the whiteness)
      bank_.set_complete_channels(calm_.observe(bank_.adaptation().measured_power_ratio(), decide, reference));
    }
    if (trim_tracker_.options().enabled()) {
      z_pert_.noalias() = z_abs - z_trim_;
      trim_tracker_.after_update(z_pert_, trim_freezing(), bank_.z_hat(), air_rates_, z_abs);
      dz_ = trim_tracker_.dz();
    }
    return hypothesis;
  }
  // The trim offset in force from the next update/propagate on: the bank subtracts
  // u_trim + du and z_trim + dz (header). With trim tracking on, the tracker overwrites it.
  template <class U, class Z>
  void set_trim_offset(const U& du, const Z& dz) noexcept {
    du_ = du;
    dz_ = dz;
  }
  // The measured air data for the coming frames (see the header comment); noexcept.
  void schedule(const AirData& a) noexcept {
    if (!a.finite()) {
      ++air_data_rejected_;
      return;
    }
    air_data_ = a;
    air_rates_.observe(a.mach, a.pressure_altitude_ft);   // the phase gates' rates (air_data_rates.h)
    if (climb_ref_.enabled()) {   // climb_reference.h
      climb_ref_.observe(air_rates_, rate_gate_scale());
      bank_.set_adapt_reference(adapt_reference_in_force());
    }
    if (!sched_.active()) {
      if (maneuver_trim_.enabled()) {   // maneuver_trim.h, a bank of one design
        mt_shift_ = mt_dx_;
        maneuver_trim_.observe(a.mach, a.pressure_altitude_ft, mt_sound_fps_);
        blend_maneuver_trim(kOneNode, kOneWeight);
        if (frame_ > 0) {
          mt_shift_ -= mt_dx_;
          shift_states(mt_shift_);
          z_shift_.noalias() = z_trim_ - base_z_trim_;
          z_shift_ -= mt_dz_;
          if (!z_shift_.isZero(0.0)) bank_.shift_levels(z_shift_);
        }
        apply_trims();
      }
      return;
    }
    XVector x_before = sched_.x_trim();
    if (maneuver_trim_.enabled()) x_before += mt_dx_;
    const bool reload = sched_.select(gust_free(a));
    if (reload) load_scheduled();
    if (maneuver_trim_.enabled()) {   // maneuver_trim.h: c = the scheduled trim's VEL over its Mach
      maneuver_trim_.observe(a.mach, a.pressure_altitude_ft, scheduled_sound_fps(mt_vel_));
      blend_maneuver_trim(sched_.corners(), sched_.weights());
    }
    if (frame_ > 0) {  // before the first frame x = 0 is the trim
      if (maneuver_trim_.enabled()) {
        x_before -= mt_dx_;
        shift_states(x_before - sched_.x_trim());
        z_shift_.noalias() = z_trim_ - sched_.z_trim();
        z_shift_ -= mt_dz_;
      } else {
        shift_states(x_before - sched_.x_trim());
        z_shift_.noalias() = z_trim_ - sched_.z_trim();   // failed sensors' levels: absolute
      }
      if (!z_shift_.isZero(0.0)) bank_.shift_levels(z_shift_);
    }
    apply_trims();
  }
  bool propagate(const UVector& u_in) noexcept {
    actuators_.effective(u_in, u_eff_);   // u_in itself unless actuator limits are on
    const UVector& u_abs = u_eff_;
    u_pert_.noalias() = u_abs - u_trim_;
    u_pert_ -= du_;
    if (maneuver_.enabled()) {
      const int v = maneuver_.vel_index(), a = maneuver_.aoa_index();
      maneuver_.forcing(z_trim_(v) + dz_(v), z_trim_(a) + dz_(a), bank_.blended_state(), x_force_);
    }
    const bool ok = bank_.propagate(u_pert_);
    if (ok && maneuver_.enabled() && x_force_.allFinite()) {   // (a state far outside the flight envelope: none)
      for (int k = 0; k < size(); ++k) {
        x_shift_ = bank_.prior(k);
        x_shift_ += x_force_;
        bank_.set_prior(k, x_shift_);
      }
    }
    if (ok && trim_tracker_.options().enabled()) {
      u_pert_.noalias() = u_abs - u_trim_;
      trim_tracker_.after_propagate(u_pert_);
      du_ = trim_tracker_.du();
    }
    return ok;
  }
  // update(z) then propagate(u); returns update's result.
  int step(const ZVector& z_abs, const UVector& u_abs) noexcept {
    const int d = update(z_abs);
    propagate(u_abs);
    return d;
  }
  // Back to the start: level 0, NONE presumed, states zero, history and counters cleared.
  void reset() noexcept {
    // the level-0 filters back on line (already there, unchanged, when the bank is at level 0
    // and unscheduled: a flight without a declaration); bank_.reset() clears the states
    if (!(level_ == 0 && online_ == levels_.level0() && !sched_.active()))
      for (int k = 0; k < size(); ++k) bank_.load_filter(k, storage_[levels_.level0()[k]]);
    online_ = levels_.level0();
    set_held_channels();
    trim_hold_.reset();
    level_ = 0;
    level1_bank_ = -1;
    if (levels_.partial())
      for (int k = 1; k < size(); ++k) bank_.set_live(k, true);
    set_floors();   // the level-0 floor again (no-op unless level1_p_min)
    bank_.reset();
    declarer_.reset(0);
    declarer1_.reset(0);
    frame_ = 0;
    departure_.reset();
    history_.clear();
    dropped_ = 0;
    air_data_ = design_air_data_;
    air_data_rejected_ = 0;
    air_rates_.reset();
    trim_tracker_.reset();
    calm_.reset();
    bank_.set_complete_channels(calm_.calm());
    climb_ref_.reset();
    maneuver_dwell_.reset();
    maneuver_.reset_spread();
    if (climb_ref_.enabled() || maneuver_dwell_.options().has_reference())
      bank_.set_adapt_reference(adapt_reference_in_force());
    actuators_.reset();
    du_.setZero();
    dz_.setZero();
    if (maneuver_trim_.enabled()) {
      maneuver_trim_.reset();
      mt_dx_.setZero();
      mt_du_.setZero();
      mt_dz_.setZero();
      if (!sched_.active()) apply_trims();
    }
    if (sched_.active()) {
      sched_.reset(design_air_data_);
      load_scheduled();
      apply_trims();
      bank_.reset_adaptation();
      bank_.presume(0);   // with the node floor in force
    }
  }

  // The turbulence adaptation's ρ set to `rho` (s follows; turbulence_adaptation.h).
  void set_turbulence_power_ratio(double rho) noexcept { bank_.set_adapt_power_ratio(rho); }

  // The level-0 floor p_min from this frame on (options().bank.p_min; the turbulence bank set's
  // floor by rho, turbulence_bank_set.h): the floors in force are set again for the level on
  // line. A level-1 bank's duals keep the floor they had (level1_p_min; unset, it becomes the
  // level-0 floor as built), so the change moves the level-0 hypotheses' floor, and NONE's and
  // f's at level 1. Ignored unless p_min >= 0 and p_min K < 1 (K hypotheses on line); reset()
  // keeps it.
  void set_level0_p_min(double p_min) noexcept {
    if (!(p_min >= 0.0 && p_min * size() < 1.0) || p_min == options_.bank.p_min) return;
    if (options_.level1_p_min == 0.0) options_.level1_p_min = options_.bank.p_min;
    options_.bank.p_min = p_min;
    set_floors();
  }

  // Bumpless handover (turbulence_bank_set.h): this bank takes over from `from`, a bank of
  // the same sizes and hypotheses (designed for another turbulence level), between a frame's
  // update and its propagate. Carried over: the level and the hypotheses on line (this bank's
  // own filters for them), the probabilities, the declarer's state, the declarations, the
  // frame count, the air data, the trim offsets and the trim tracker, the calm-air decision, the
  // flight-phase gates, the load factor's measured spread (maneuver_kinematics.h), the
  // actuator model's positions; and, unless `warm`, every on-line filter's states (the adaptation then restarts
  // at its reference, ρ = ρ_0). warm: this bank ran on the same frames with the same
  // hypotheses on line, so its filters keep their own states and its adaptation its own ρ.
  // This bank's own: what the filters are, its trims, its options. A scheduled bank is not
  // supported (the set checks). noexcept, no allocation for fixed sizes (the declaration
  // history is copied within its reserved capacity).
  void take_over(const HierarchicalBank& from, bool warm = false) noexcept {
    if (online_ != from.online_) {
      for (int k = 0; k < size(); ++k) bank_.load_filter(k, storage_[from.online_[k]]);
      warm = false;
    }
    online_ = from.online_;
    set_held_channels();
    trim_hold_.carry_over(from.trim_hold_);
    level_ = from.level_;
    level1_bank_ = from.level1_bank_;
    set_floors();   // this bank's floors for the level carried over
    bank_.carry_over(from.bank_, !warm);
    if (!warm) bank_.reset_adaptation();
    declarer_.carry_over(from.declarer_);
    declarer1_.carry_over(from.declarer1_);
    const std::size_t n = from.history_.size() < history_.capacity() ? from.history_.size() : history_.capacity();
    history_.assign(from.history_.begin(), from.history_.begin() + static_cast<std::ptrdiff_t>(n));
    dropped_ = from.dropped_ + static_cast<std::int64_t>(from.history_.size() - n);
    frame_ = from.frame_;
    departure_.carry_over(from.departure_);
    air_data_ = from.air_data_;
    air_data_rejected_ = from.air_data_rejected_;
    air_rates_ = from.air_rates_;
    trim_tracker_ = from.trim_tracker_;
    calm_.carry_over(from.calm_);
    bank_.set_complete_channels(calm_.calm());
    climb_ref_ = from.climb_ref_;
    maneuver_dwell_ = from.maneuver_dwell_;
    maneuver_.carry_over_spread(from.maneuver_);
    if (climb_ref_.enabled() || maneuver_dwell_.options().has_reference())
      bank_.set_adapt_reference(adapt_reference_in_force());
    actuators_.carry_over(from.actuators_);
    du_ = from.du_;
    dz_ = from.dz_;
    if (maneuver_trim_.enabled() && from.maneuver_trim_.enabled()) {   // its rates; this bank's own offsets
      maneuver_trim_ = from.maneuver_trim_;
      if (!sched_.active()) {
        blend_maneuver_trim(kOneNode, kOneWeight);
        apply_trims();
      }
    }
  }

  // Touch the on-line bank's per-frame working set (FilterBank::warm_cache) and the
  // declarer's, ahead of a frame that has a deadline. Reads only.
  void warm_cache() const noexcept {
    bank_.warm_cache();
    touch(declarer_in_force());
  }

  // ---- outputs -----------------------------------------------------------------------------
  int level() const noexcept { return level_; }
  // ModelBank index of the single failure whose level-1 bank is on line, or -1 at level 0.
  int level1_failure() const noexcept { return level_ == 1 ? online_[1] : -1; }
  int size() const noexcept { return bank_.size(); }
  const Indices& online() const noexcept { return online_; }   // ModelBank indices on line
  std::vector<std::string> online_names() const {
    std::vector<std::string> out;
    for (int i : online_) out.push_back(names_[i]);
    return out;
  }
  const std::string& name(int hypothesis) const { return names_.at(hypothesis); }
  int hypothesis_count() const noexcept { return static_cast<int>(names_.size()); }
  // ModelBank index of the current (presumed or last declared) hypothesis.
  int current_hypothesis() const noexcept { return online_[declarer_in_force().current()]; }
  const std::vector<Declaration>& declarations() const noexcept { return history_; }
  std::int64_t declarations_dropped() const noexcept { return dropped_; }
  std::int64_t frames() const noexcept { return frame_; }
  // Frames on which the departure hold kept the level-1 bank from declaring (departure_hold.h).
  std::int64_t departure_frames() const noexcept { return departure_.frames(); }
  double frame_rate_hz() const noexcept { return frame_rate_hz_; }
  // The calm-air rule's whiteness W̄ (calm_air_complete.h; NaN without it or before its first block).
  double calm_whiteness() const noexcept { return calm_.whiteness(); }
  // The complete channels' held offset d = (z_trim + dz) - z_ref of the last update (zero while
  // nothing is held or the hold is off; complete_trim_hold.h).
  const ZVector& complete_trim_offset() const noexcept { return trim_hold_.offset(); }
  const PVector& probabilities() const noexcept { return bank_.probabilities(); }
  // The turbulence adaptation's likelihood scale s (1 when off; turbulence_adaptation.h):
  // the estimated ratio of the residual power to the design's, the estimator's own measure
  // of the turbulence intensity. It carries over level switches; reset() restarts it.
  double turbulence_scale() const noexcept { return bank_.turbulence_scale(); }
  const XVector& blended_state() const noexcept { return bank_.blended_state(); }
  const ZVector& z_hat_perturbation() const noexcept { return bank_.z_hat(); }
  ZVector z_hat() const noexcept { return bank_.z_hat() + z_trim_ + dz_; }   // absolute
  const UVector& u_trim_offset() const noexcept { return du_; }   // du in force
  const ZVector& z_trim_offset() const noexcept { return dz_; }   // dz in force
  const AirDataRates& air_data_rates() const noexcept { return air_rates_; }   // from the usable samples
  const TrimTracker<NU, NZ>& trim_tracker() const noexcept { return trim_tracker_; }
  const ClimbReference& climb_reference() const noexcept { return climb_ref_; }
  const ManeuverDwell& maneuver_dwell() const noexcept { return maneuver_dwell_; }
  const ManeuverTrim& maneuver_trim() const noexcept { return maneuver_trim_; }
  // The trim tracker's freeze condition on the last frame (level 1, a failure declared or a
  // failure hypothesis on line above its freeze probability): the maneuver trim's inertial
  // rates read no sensor while it holds (inertial_flight_path.h).
  bool failure_suspected() const noexcept { return trim_freezing(); }
  // The maneuver trim's offsets in force (zero when it is off; maneuver_trim.h).
  const XVector& maneuver_trim_dx() const noexcept { return mt_dx_; }
  const UVector& maneuver_trim_du() const noexcept { return mt_du_; }
  const ZVector& maneuver_trim_dz() const noexcept { return mt_dz_; }
  const ZVector& z_trim() const noexcept { return z_trim_; }
  // The schedule (inactive for a bank designed at one flight condition).
  const Schedule& scheduled() const noexcept { return sched_; }
  const UVector& u_trim() const noexcept { return u_trim_; }
  std::int64_t rejected_frames() const noexcept { return bank_.rejected_frames(); }
  const AirData& air_data() const noexcept { return air_data_; }            // in force
  std::int64_t air_data_rejected() const noexcept { return air_data_rejected_; }
  const Bank& bank() const noexcept { return bank_; }
  // The hypotheses on line at each level (hierarchy_levels.h).
  const Levels& levels() const noexcept { return levels_; }
  // The declarer in force: level 0's, or at level 1 with level1_dwell_s its own.
  const Declarer& declarer() const noexcept { return declarer_in_force(); }
  // The options in force: as given, without the evidence dwell under a flight-phase dwell (header).
  const HierarchicalOptions& options() const noexcept { return options_; }

 private:
  struct Built {
    Levels levels;
    std::vector<Model> models;
  };

  // Validates the ModelBank, resolves the levels by name (hierarchy_levels.h) and builds every
  // hypothesis filter's model.
  static Built build(const ModelBank& mb) {
    Built b{Levels(mb), {}};
    for (const auto& h : mb.hypotheses)
      b.models.push_back(
          Model::from_matrices(h.phi, h.bd, h.h, h.k, h.a, h.uninformative_width, h.uninformative_level_q,
                               "hypothesis '" + h.name + "'"));
    return b;
  }

  static std::vector<Model> pick(const std::vector<Model>& models, const Indices& idx) {
    std::vector<Model> out;
    for (int i : idx) out.push_back(models[i]);
    return out;
  }

  // The hypotheses' names by ModelBank index (the declarer's per-hypothesis dwell, declarer.h).
  static std::vector<std::string> hypothesis_names(const ModelBank& mb) {
    std::vector<std::string> out;
    for (const auto& h : mb.hypotheses) out.push_back(h.name);
    return out;
  }
  static DeclarerOptions with_rate(DeclarerOptions d, double rate_hz) {
    d.frame_rate_hz = rate_hz;
    return d;
  }
  // The options in force: `o` without the declarers' evidence dwell when a flight-phase dwell
  // is configured and evidence_dwell_in_phases is off (header); options() reports them.
  static HierarchicalOptions in_force(HierarchicalOptions o) {
    if ((o.climb_reference.dwell_s > 0.0 || o.maneuver_dwell.dwell_s > 0.0) && !o.evidence_dwell_in_phases) {
      o.declarer.dwell_nats = 0.0;
      for (auto& [name, nats] : o.declarer.dwell_nats_per_hypothesis) nats = 0.0;   // names still checked
    }
    return o;
  }
  // The level-1 declarer: level 0's threshold, level1_dwell_s (0: level 0's dwell). Throws
  // std::invalid_argument (declarer.h) for a dwell out of range.
  static DeclarerOptions level1_declarer(const HierarchicalOptions& o, double rate_hz) {
    DeclarerOptions d = with_rate(o.declarer, rate_hz);
    d.dwell_s = LevelFloors::level1_dwell(o.level1_dwell_s, d.dwell_s);
    return d;
  }
  bool own_level1_dwell() const noexcept { return LevelFloors::own_level1_dwell(level_, options_.level1_dwell_s); }
  // spare_dwell_s in frames (0: off); throws std::invalid_argument for a value the header refuses.
  static int spare_dwell_frames(const HierarchicalOptions& o, double rate_hz) {
    const double s = o.spare_dwell_s;
    if (s == 0.0) return 0;
    const double frame = 1.0 / rate_hz;
    if (!(s >= frame && s <= kMaxDwellS))
      throw std::invalid_argument("hierarchical bank: spare_dwell_s must be 0 (off) or in [" + format_value(frame) +
                                  ", " + format_value(kMaxDwellS) + "] s (a frame to a minute), got " + format_value(s));
    const auto& a = o.bank.adaptation;
    if (!(a.enabled && a.hypothesis_weight < 1.0))
      throw std::invalid_argument("hierarchical bank: spare_dwell_s " + format_value(s) +
                                  " applies while the per-hypothesis tempering spares; it needs adapt_hypothesis_weight "
                                  "below 1 with the adaptation on");
    return std::max(1, static_cast<int>(std::lround(s * rate_hz)));
  }
  // The dwell in force (frames): at level 0 the maneuver dwell's while maneuvering, if it has
  // one (maneuver_dwell.h), else the climb reference's while climbing, if it has one
  // (climb_reference.h), else spare_dwell_s's while the tempering spares (header), if set,
  // else the declarer's in force.
  int dwell_frames_in_force() const noexcept {
    const int base = declarer_in_force().dwell_frames();
    if (level_ != 0) return base;
    const int level0 = spare_dwell_frames_ > 0 && bank_.adaptation().spares() ? spare_dwell_frames_ : base;
    return maneuver_dwell_.dwell_frames(climb_ref_.dwell_frames(level0));
  }
  // The declarer's components in force (header), or null: each hypothesis alone.
  const int* component_groups() const noexcept {
    if (!levels_.partial() || !options_.declare_components) return nullptr;
    return level1_bank_ < 0 ? levels_.level0_groups().data() : levels_.level1_groups(level1_bank_).data();
  }
  Declarer& declarer_in_force() noexcept { return own_level1_dwell() ? declarer1_ : declarer_; }
  const Declarer& declarer_in_force() const noexcept { return own_level1_dwell() ? declarer1_ : declarer_; }
  static FilterBankOptions with_rate(FilterBankOptions b, double rate_hz) {
    b.adaptation.frame_rate_hz = rate_hz;
    return b;
  }

  HierarchicalBank(const ModelBank& mb, const HierarchicalOptions& options, Built b)
      : options_(in_force(options)),
        bank_(pick(b.models, b.levels.level0()), with_rate(options.bank, mb.frame_rate_hz)),
        declarer_(with_rate(options_.declarer, mb.frame_rate_hz), 0, hypothesis_names(mb)),
        declarer1_(level1_declarer(options_, mb.frame_rate_hz), 0, hypothesis_names(mb)),
        levels_(std::move(b.levels)),
        online_(levels_.level0()),
        air_rates_(mb.frame_rate_hz),
        trim_tracker_(options.trim, mb.frame_rate_hz, mb.nu(), mb.nz(), mb.measurement_names),
        calm_(options.calm_complete, mb.measurement_names, options.bank.adaptation.time_constant_s, mb.frame_rate_hz),
        climb_ref_(options.climb_reference, mb.frame_rate_hz),
        maneuver_dwell_(options.maneuver_dwell, mb.frame_rate_hz),
        maneuver_trim_(options.maneuver_trim, mb.frame_rate_hz),
        maneuver_(options.maneuver, mb.state_names, mb.measurement_names, mb.frame_rate_hz),
        actuators_(options.actuators, mb.hypotheses.at(0).phi, mb.hypotheses.at(0).bd, mb.frame_rate_hz),
        frame_rate_hz_(mb.frame_rate_hz) {
    LevelFloors::check_level1(options.level1_p_min, options.level1_dwell_s, options.declarer.threshold,
                              levels_.size());
    spare_dwell_frames_ = spare_dwell_frames(options, mb.frame_rate_hz);
    if (!options.declarer.rough_dwell_s_per_hypothesis.empty() && !options.bank.adaptation.enabled)
      throw std::invalid_argument("hierarchical bank: rough_dwell_s_per_hypothesis applies while the turbulence "
                                  "adaptation's scale is at least rough_scale; it needs adapt_turbulence on");
    if (options.history_capacity < 1)
      throw std::invalid_argument("hierarchical bank: history_capacity must be >= 1, got " +
                                  std::to_string(options.history_capacity));
    for (const auto& h : mb.hypotheses) names_.push_back(h.name);
    Level1Allowance::check(options.level1_allowance);
    build_allowances();
    p_allow_ = bank_.probabilities();
    LevelFloors::check_partial(options.partial_p_min, levels_.partial_count(), levels_.size(), options.bank.p_min,
                               options.declarer.threshold);
    RoughAirFloor::check(options.rough_floor, levels_.size(), options.bank.adaptation.enabled);
    if (maneuver_dwell_.enabled()) {
      const auto& m = mb.measurement_names;
      const auto it = std::find(m.begin(), m.end(), "AZ");
      if (it == m.end())
        throw std::invalid_argument("hierarchical bank: the maneuver dwell reads the load factor, measurement 'AZ', "
                                    "which this bank does not have");
      maneuver_dwell_az_ = static_cast<int>(it - m.begin());
    }
    departure_ = DepartureHold(options.departure, mb.measurement_names, names_, mb.frame_rate_hz);
    storage_.reserve(b.models.size());
    for (std::size_t i = 0; i < b.models.size(); ++i)
      storage_.emplace_back(b.models[i], "hypothesis '" + names_[i] + "'");
    trim_hold_ = CompleteTrimHold<NZ>(options.complete_trim_hold, mb.nz(), mb.frame_rate_hz);
    trim_in_force_ = ZVector::Zero(mb.nz());
    for (const auto& h : mb.hypotheses) held_of_.push_back(CompleteTrimHold<NZ>::channels_of(h));
    set_held_channels();
    bank_.set_h_output(mb.h_output);
    z_trim_ = mb.z_trim;
    u_trim_ = mb.u_trim;
    design_air_data_ = AirData{mb.mach, mb.alt_ft};
    air_data_ = design_air_data_;
    z_pert_ = z_trim_;
    u_pert_ = u_trim_;
    du_ = UVector::Zero(u_trim_.size());
    dz_ = ZVector::Zero(z_trim_.size());
    z_shift_ = dz_;
    scratch_ = storage_[0];
    x_shift_ = XVector::Zero(mb.nx());
    x_force_ = XVector::Zero(mb.nx());
    if (calm_.enabled() && !options.bank.adaptation.enabled)
      throw std::invalid_argument("hierarchical bank: the calm-air complete model reads the turbulence adaptation's "
                                  "measured power ratio; turn the adaptation on");
    bank_.set_complete_channels(calm_.calm());
    u_eff_ = UVector::Zero(mb.nu());
    mt_dx_ = XVector::Zero(mb.nx());
    mt_shift_ = mt_dx_;
    mt_du_ = UVector::Zero(mb.nu());
    mt_dz_ = ZVector::Zero(mb.nz());
    base_u_trim_ = u_trim_;
    base_z_trim_ = z_trim_;
    if (maneuver_trim_.enabled()) build_maneuver_trim(mb);
    if (mb.schedule) {
      sched_ = Schedule(*mb.schedule, options.schedule, design_air_data_, mb.frame_rate_hz);
      if (sched_.node_filter(0, 0).nx() != mb.nx() ||
          static_cast<int>(mb.schedule->nodes[0].bank.hypotheses.size()) != hypothesis_count())
        throw std::invalid_argument("hierarchical bank: the schedule's nodes do not have this bank's sizes");
      for (int i = 0; i < hypothesis_count(); ++i)
        if (mb.schedule->nodes[0].bank.hypotheses[i].name != names_[i])
          throw std::invalid_argument("hierarchical bank: schedule hypothesis " + std::to_string(i) + " is '" +
                                      mb.schedule->nodes[0].bank.hypotheses[i].name + "', the bank's is '" +
                                      names_[i] + "'");
      if (options.schedule.gust_airspeed) {   // a bank without the gust state or VEL: the measured Mach
        const auto& xs = mb.state_names;
        const auto& m = mb.measurement_names;
        const auto ug = std::find(xs.begin(), xs.end(), "u_g_fps");
        const auto vel = std::find(m.begin(), m.end(), "VEL");
        if (ug != xs.end() && vel != m.end()) {
          gust_u_ = static_cast<int>(ug - xs.begin());
          gust_vel_ = static_cast<int>(vel - m.begin());
        }
      }
      load_scheduled();
      apply_trims();
      bank_.reset_adaptation();   // rho = the node reference in force
      bank_.presume(0);           // with the node floor in force
    }
    history_.reserve(static_cast<std::size_t>(options.history_capacity));
    if (options_.partial_p_min > 0.0) {
      set_floors();
      bank_.presume(0);   // NONE presumed with the partial hypotheses' floor
    }
  }

  // Each on-line filter's held complete channels (complete_trim_hold.h; none when off).
  void set_held_channels() noexcept {
    for (int k = 0; k < size(); ++k)
      bank_.set_held_channels(k, trim_hold_.enabled() ? held_of_[static_cast<std::size_t>(online_[k])] : 0u);
  }
  // The trim tracker's freeze condition on this frame (trim_tracker.h): level 1, a failure
  // declared, or a failure hypothesis on line above freeze_probability.
  bool trim_freezing() const noexcept { return failure_suspected_at(trim_tracker_.options().freeze_probability); }
  // A failure presumed: level 1, or a declared failure current.
  bool failure_declared() const noexcept { return level_ != 0 || online_[declarer_in_force().current()] != 0; }
  // A failure presumed (level 1, or a declared failure current) or rising (an on-line failure
  // hypothesis above `freeze_probability`): the trim tracker's and the calm-air rule's hold.
  bool failure_suspected_at(double freeze_probability) const noexcept {
    if (failure_declared()) return true;
    const PVector& p = bank_.probabilities();
    for (int k = 1; k < size(); ++k)
      if (p(k) > freeze_probability) return true;
    return false;
  }

  void record(int hypothesis, std::int64_t frame) noexcept {
    if (history_.size() >= history_.capacity()) {
      ++dropped_;
      return;
    }
    Declaration d;
    d.hypothesis = hypothesis;
    d.level = level_;
    d.frame = frame;
    d.time_s = static_cast<double>(frame) / frame_rate_hz_;
    history_.push_back(d);  // within the reserved capacity: no allocation
  }

  // Bring `next` on line; every new filter starts from the declared filter's x⁺ (x⁻ and r
  // zero until the propagate) and the declared hypothesis (at `declared`, its position in
  // the current bank) is presumed. A scheduled bank loads the filters in force.
  void switch_to(const Indices& next, int declared, int level, const Indices* live = nullptr) noexcept {
    const XVector x0 = bank_.posterior(declared);
    const int presumed = level == 1 ? 1 : 0;
    if (levels_.partial())   // spare slots off line at level 1, every slot on line at level 0 (hierarchy_levels.h)
      for (int k = 1; k < size(); ++k) bank_.set_live(k, live == nullptr || (*live)[k] != 0);
    for (int k = 0; k < size(); ++k) {
      if (sched_.active()) {
        sched_.filter(next[k], scratch_);
        bank_.load_filter(k, scratch_);
      } else {
        bank_.load_filter(k, storage_[next[k]]);
      }
      bank_.set_posterior(k, x0);
    }
    online_ = next;
    set_held_channels();
    level_ = level;
    departure_.release();
    set_floors();
    bank_.presume(presumed);
    declarer_in_force().reset(presumed);
  }
  // The level-0 floor (a scheduled bank's node floor in force with node_p_min, else p_min, moved
  // towards the rough-air floor as the air roughens: rough_air_floor.h), and the floors for the
  // level on line (level_floors.h).
  double level0_floor() const noexcept {
    const double f0 = sched_.active() && options_.schedule.node_p_min ? sched_.p_min() : options_.bank.p_min;
    return options_.rough_floor.enabled() ? RoughAirFloor::floor(options_.rough_floor, f0, air_ratio()) : f0;
  }
  // The air's power ratio in calm-air units (rough_air_floor.h): the adaptation's air_power_ratio()
  // over a scheduled bank's calm-air reference in force (1 without one).
  double air_ratio() const noexcept {
    const double calm = sched_.active() && sched_.has_calm_reference() ? sched_.calm_reference() : 1.0;
    return bank_.adaptation().air_power_ratio() / calm;
  }
  void set_floors() noexcept {
    LevelFloors::apply(bank_, level_, level0_floor(), options_.level1_p_min, options_.partial_p_min,
                       levels_.level0_partial());
  }
  // allowances_[f][s]: the allowance of the dual in slot s of level-1 bank f (level1_allowance.h):
  // options.level1_allowance_pairs["F>C"] (F the bank's single, C the dual's other one,
  // hierarchy_levels.h), else options.level1_allowance; 0 for a slot that holds no dual.
  // allowance_on_[f]: some dual of bank f has one.
  void build_allowances() {
    std::vector<std::string> singles;
    for (int i : levels_.singles()) singles.push_back(names_[static_cast<std::size_t>(i)]);
    for (const auto& [key, k] : options_.level1_allowance_pairs) Level1Allowance::check_pair(key, k, singles);
    for (int f = 0; f + 1 < size(); ++f) {
      std::vector<double> k_of(static_cast<std::size_t>(size()), 0.0);
      const std::string& single = names_[static_cast<std::size_t>(levels_.level1_single(f))];
      for (int slot = 0; slot < size(); ++slot) {
        const int other = levels_.level1_partner(f)[slot];
        if (other < 0) continue;
        const auto it = options_.level1_allowance_pairs.find(single + ">" + names_[static_cast<std::size_t>(other)]);
        k_of[static_cast<std::size_t>(slot)] =
            it != options_.level1_allowance_pairs.end() ? it->second : options_.level1_allowance;
      }
      allowance_on_.push_back(std::any_of(k_of.begin(), k_of.end(), [](double k) { return k > 0.0; }) ? 1 : 0);
      allowances_.push_back(std::move(k_of));
    }
  }

  // The on-line filters as the schedule has them in force (states kept).
  void load_scheduled() noexcept {
    bank_.replace_filters([&](int k, Hypothesis& h) { sched_.filter(online_[k], h); },
                          [&](auto& h_out) { sched_.h_output(h_out); });
    if (sched_.has_reference_scale()) bank_.set_adapt_power_scale(sched_.reference_scale());
    if ((sched_.has_adapt_reference() && options_.schedule.node_adapt_reference) || climb_ref_.enabled() ||
        maneuver_dwell_.options().has_reference())
      bank_.set_adapt_reference(adapt_reference_in_force());
    set_floors();   // (unchanged unless node_p_min or level1_p_min)
  }
  // The adaptation's reference in force: the climb reference while climbing (climb_reference.h),
  // else the maneuver reference while maneuvering (maneuver_dwell.h), else a scheduled bank's
  // node reference (node_adapt_reference), else the option's.
  double adapt_reference_in_force() const noexcept {
    const double base = base_adapt_reference();
    return climb_ref_.climbing() ? climb_ref_.reference(base) : maneuver_dwell_.reference(base);
  }
  // The reference without the flight phases': a scheduled bank's node reference
  // (node_adapt_reference), else the option's.
  double base_adapt_reference() const noexcept {
    return sched_.has_adapt_reference() && options_.schedule.node_adapt_reference ? sched_.adapt_reference()
                                                                                    : options_.bank.adaptation.reference;
  }
  // The air-data gates' threshold factor (header): sqrt(s_c) with options.gates_calm_scaled,
  // sqrt(s_b) with options.rate_gates_gust_scaled, else 1.
  double rate_gate_scale() const noexcept {
    if (options_.gates_calm_scaled) return std::sqrt(bank_.adaptation().scale_at(gate_calm_reference()));
    return options_.rate_gates_gust_scaled ? std::sqrt(bank_.adaptation().scale_at(base_adapt_reference())) : 1.0;
  }
  // s_c's reference (header): the schedule's calm-air reference in force, else the base reference.
  // The calm-air reference is a power ratio of the node's own bank: read in the references'
  // units, divided by the adaptation's power scale (turbulence_adaptation.h).
  double gate_calm_reference() const noexcept {
    return sched_.active() && sched_.has_calm_reference() ? sched_.calm_reference() / bank_.adaptation().power_scale()
                                                          : base_adapt_reference();
  }
  // Every on-line filter's states move by dx (a change of the scheduled trim state).
  void shift_states(const XVector& dx) noexcept {
    if (dx.isZero(0.0)) return;
    for (int k = 0; k < size(); ++k) {
      const bool corrected = bank_.corrected(k);
      x_shift_ = bank_.prior(k);
      x_shift_ += dx;
      bank_.set_prior(k, x_shift_);
      if (corrected) {
        x_shift_ = bank_.posterior(k);
        x_shift_ += dx;
        bank_.set_posterior(k, x_shift_);
      }
    }
    bank_.refresh_blend();
  }
  // The speed of sound of the scheduled trims in force: their VEL (measurement `vel`) over the
  // schedule's low-passed Mach; 0 before a positive Mach.
  double scheduled_sound_fps(int vel) const noexcept {
    const double m = sched_.filtered_air_data().mach;
    return m > 0.0 ? sched_.z_trim()(vel) / m : 0.0;
  }
  // The air data the schedule follows: `a`, with options.schedule.gust_airspeed its Mach less
  // the estimated along-track gust's (header).
  AirData gust_free(const AirData& a) const noexcept {
    if (gust_u_ < 0 || frame_ == 0) return a;
    const double c = scheduled_sound_fps(gust_vel_);
    const double ug = bank_.blended_state()(gust_u_);
    if (!(c > 0.0) || !std::isfinite(ug)) return a;
    return AirData{a.mach + ug / c, a.pressure_altitude_ft};
  }
  // The scheduled trims in force (a scheduled bank only).
  // With the maneuver trim, its offsets on top (also for a bank of one design).
  void apply_trims() noexcept {
    if (sched_.active()) {
      u_trim_ = sched_.u_trim();
      z_trim_ = sched_.z_trim();
    } else {
      u_trim_ = base_u_trim_;
      z_trim_ = base_z_trim_;
    }
    if (maneuver_trim_.enabled()) {
      u_trim_ += mt_du_;
      z_trim_ += mt_dz_;
    }
  }
  // The sensitivities of every node (a bank of one design: its own) from its NONE filter
  // (maneuver_trim.h); throws std::invalid_argument naming what is missing.
  void build_maneuver_trim(const ModelBank& mb) {
    const auto& m = mb.measurement_names;
    const auto vel = std::find(m.begin(), m.end(), "VEL"), aoa = std::find(m.begin(), m.end(), "AOA");
    if (vel == m.end() || aoa == m.end())
      throw std::invalid_argument("hierarchical bank: the maneuver trim needs the measurements 'VEL' and 'AOA'");
    mt_vel_ = static_cast<int>(vel - m.begin());
    const int ia = static_cast<int>(aoa - m.begin());
    if (options_.maneuver_trim.inertial) {   // q, p, r, alpha of z (inertial_flight_path.h)
      const char* need[3] = {"PIT", "ROL", "YAW"};
      for (int k = 0; k < 3; ++k) {
        const auto it = std::find(m.begin(), m.end(), need[k]);
        if (it == m.end())
          throw std::invalid_argument(std::string("hierarchical bank: the maneuver trim's inertial rates need the "
                                                  "measurement '") + need[k] + "'");
        mt_z_[k] = static_cast<int>(it - m.begin());
      }
    }
    if (options_.maneuver_trim.gamma_load_factor) {   // n, p, r of z (maneuver_trim.h, ClimbAngleComplement)
      const char* need[3] = {"AZ", "ROL", "YAW"};
      const int slot[3] = {4, 1, 2};
      for (int k = 0; k < 3; ++k) {
        const auto it = std::find(m.begin(), m.end(), need[k]);
        if (it == m.end())
          throw std::invalid_argument(std::string("hierarchical bank: the maneuver trim's load-factor climb angle "
                                                  "needs the measurement '") + need[k] + "'");
        mt_z_[slot[k]] = static_cast<int>(it - m.begin());
      }
    }
    mt_z_[3] = ia;   // AOA: the inertial rates and the airspeed's acceleration
    auto add = [&](const ModelBank& node) {
      const HypothesisModel& h = node.hypotheses.at(0);
      const TrimSensitivity s = trim_sensitivity(h.phi, h.bd, h.h, mb.state_names, mb.input_names, mb.frame_rate_hz,
                                                 node.z_trim(mt_vel_), node.z_trim(ia));
      mt_sx_.push_back(s.x);
      mt_su_.push_back(s.u);
      mt_sz_.push_back(s.z);
    };
    if (mb.schedule)
      for (const ScheduleNode& n : mb.schedule->nodes) add(n.bank);
    else
      add(mb);
    if (!(mb.mach > 0.0))
      throw std::invalid_argument("hierarchical bank: the maneuver trim needs the bank's design Mach > 0");
    mt_sound_fps_ = mb.z_trim(mt_vel_) / mb.mach;
  }
  // (dx_m, du_m, dz_m) = sum_c w_c S_c (gamma, a) over the nodes `corners` with `weights`.
  template <class C, class W>
  void blend_maneuver_trim(const C& corners, const W& weights) noexcept {
    const double g = maneuver_trim_.gamma(), acc = maneuver_trim_.accel();
    mt_dx_.setZero();
    mt_du_.setZero();
    mt_dz_.setZero();
    for (std::size_t c = 0; c < corners.size(); ++c) {
      const double w = weights[c];
      if (w == 0.0) continue;
      const Eigen::MatrixXd &sx = mt_sx_[corners[c]], &su = mt_su_[corners[c]], &sz = mt_sz_[corners[c]];
      for (Eigen::Index i = 0; i < mt_dx_.size(); ++i) mt_dx_(i) += w * (sx(i, 0) * g + sx(i, 1) * acc);
      for (Eigen::Index i = 0; i < mt_du_.size(); ++i) mt_du_(i) += w * (su(i, 0) * g + su(i, 1) * acc);
      for (Eigen::Index i = 0; i < mt_dz_.size(); ++i) mt_dz_(i) += w * (sz(i, 0) * g + sz(i, 1) * acc);
    }
  }

  HierarchicalOptions options_;
  Bank bank_;
  Declarer declarer_;    // level 0 (and level 1 without level1_dwell_s)
  Declarer declarer1_;   // level 1 with level1_dwell_s
  int spare_dwell_frames_ = 0;   // spare_dwell_s in frames (0: off)
  std::vector<Hypothesis> storage_;   // every hypothesis filter of the ModelBank, in its order
  std::vector<std::string> names_;
  std::vector<std::vector<double>> allowances_;   // per level-1 bank, per slot: its dual's allowance (build_allowances)
  std::vector<char> allowance_on_;                // per level-1 bank: some dual has one
  PVector p_allow_;             // the probabilities with the allowance (level1_allowance.h)
  Levels levels_;         // the hypotheses on line at each level (hierarchy_levels.h)
  int level1_bank_ = -1;  // the level-1 bank on line (levels_.level1(f)), -1 at level 0
  Indices online_;
  ZVector z_trim_, z_pert_, dz_, z_shift_;
  UVector u_trim_, u_pert_, du_;
  AirDataRates air_rates_;   // the phase gates' climb and Mach rates (air_data_rates.h)
  TrimTracker<NU, NZ> trim_tracker_;
  CalmAirComplete calm_;   // calm_air_complete.h
  CompleteTrimHold<NZ> trim_hold_;        // complete_trim_hold.h
  std::vector<std::uint32_t> held_of_;    // per ModelBank hypothesis: its complete channels
  ZVector trim_in_force_;                 // z_trim + dz, the hold's input (no temporary per frame)
  ClimbReference climb_ref_;
  ManeuverDwell maneuver_dwell_;
  int maneuver_dwell_az_ = 0;   // AZ in z (the maneuver dwell's load factor)
  ManeuverTrim maneuver_trim_;
  int mt_z_[5] = {0, 0, 0, 0, 0};   // PIT, ROL, YAW, AOA, AZ in z (the maneuver trim's readers)
  std::vector<Eigen::MatrixXd> mt_sx_, mt_su_, mt_sz_;   // per node: d(x, u, z)_trim / d(gamma, a)
  XVector mt_dx_, mt_shift_;
  UVector mt_du_, base_u_trim_;
  ZVector mt_dz_, base_z_trim_;
  int mt_vel_ = 0;
  double mt_sound_fps_ = 0.0;   // a bank of one design: its VEL trim over its Mach
  int gust_u_ = -1;     // options.schedule.gust_airspeed: the state u_g_fps (-1: off)
  int gust_vel_ = 0;    // and the measurement VEL
  static constexpr std::array<int, 4> kOneNode{{0, 0, 0, 0}};
  static constexpr std::array<double, 4> kOneWeight{{1.0, 0.0, 0.0, 0.0}};
  ManeuverKinematics maneuver_;
  ActuatorLimits<NU> actuators_;
  UVector u_eff_;
  XVector x_shift_, x_force_;
  Schedule sched_;
  Hypothesis scratch_;   // a scheduled filter on its way on line at a hierarchical switch
  std::vector<Declaration> history_;
  std::int64_t dropped_ = 0;
  AirData design_air_data_, air_data_;
  std::int64_t air_data_rejected_ = 0;
  std::int64_t frame_ = 0;
  DepartureHold departure_;   // level 1 (departure_hold.h)
  double frame_rate_hz_ = 0.0;
  int level_ = 0;
};

using F16HierarchicalBank = HierarchicalBank<13, 13, 5, 7>;
using F16GustHierarchicalBank = HierarchicalBank<13, 19, 5, 7>;
using F16ThrottleHierarchicalBank = HierarchicalBank<13, 13, 6, 7>;
using F16GustThrottleHierarchicalBank = HierarchicalBank<13, 19, 6, 7>;
// The 13-state bank with one partial hypothesis per surface (`f16mmae design --partial-loss F`):
// 18 filters on line at level 0 (header).
using F16PartialHierarchicalBank = HierarchicalBank<18, 13, 5, 7>;
using DynamicHierarchicalBank =
    HierarchicalBank<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;

}  // namespace f16mmae
