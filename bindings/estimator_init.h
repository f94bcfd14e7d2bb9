// The estimator's settings as Python keyword arguments: ONE table, shared by every binding that
// builds the hierarchical MMAE from a core.ModelBank (core.HierarchicalBank and core.Executive)
// or from a core.TurbulenceSetFile (core.Executive, core.TurbulenceBankSet), so that a setting the
// in-process estimator takes, the daemon's in-process executive (and so `f16mmae replay`) takes
// too, with the same name, default and check.
//
//   def_estimator_init<T>(cls)   cls.def(py::init(...)): T(model_bank, HierarchicalOptions) from
//                                model_bank and keyword arguments, each a row of kKeywords below
//   def_estimator_init<T, Source>(cls)   the same from another source (the set's members,
//                                cpp/executive/turbulence_set_bank.h)
//   estimator_options(kwargs)    the HierarchicalOptions those keywords give
//
// A row names a keyword and the option field it sets; field<&A::b, &B::c>("name") is the plain
// row: the value cast to the field's type, and its default read from a default-constructed
// HierarchicalOptions. A keyword left out is the core's own default, so the bank as designed.
// Adding a setting is one row here and one row of the harness's option table
// (loop/estimator_options.py; or named in CORE_ONLY with its reason: tests/python/
// test_hil_daemon_cli.py checks the two against each other). The constructor's docstring lists
// every keyword with its default.
//
// Where each row's field lives: the floor, likelihoods and adaptation in filter_bank.h and
// turbulence_adaptation.h; the declaration rule in declarer.h; the levels in hierarchical_bank.h,
// level_floors.h, level1_allowance.h, departure_hold.h; trim tracking in trim_tracker.h; the
// schedule in scheduled_filters.h; the climb reference in climb_reference.h; the maneuver options
// in maneuver_dwell.h, maneuver_kinematics.h, maneuver_trim.h; the limits in actuator_limits.h.
//
// Errors name the keyword: an unknown keyword or a value of the wrong type raises TypeError, a
// bad choice ('on'|'off', schedule_mode, ...) ValueError. `declarer`, a core.Declarer, supplies
// threshold, dwell_s and dwell_nats in place of those keywords whatever their order.
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "f16mmae/declarer.h"
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/model_bank.h"

namespace f16mmae::bindings {

namespace py = pybind11;

struct EstimatorKeyword {
  const char* name;
  std::string kind;                                                // what the value must be, for errors
  std::function<void(HierarchicalOptions&, py::handle)> set;       // may throw py::cast_error or ValueError
  std::function<py::object(const HierarchicalOptions&)> default_of;  // the core's default, for the docstring
};

template <class V>
constexpr const char* kind_of() {
  if constexpr (std::is_same_v<V, bool>) return "True or False";
  else if constexpr (std::is_same_v<V, std::string>) return "a string";
  else if constexpr (std::is_arithmetic_v<V>) return "a number";
  else if constexpr (std::is_same_v<V, std::vector<double>>) return "a list of numbers";
  else if constexpr (std::is_same_v<V, std::vector<std::string>>) return "a list of strings";
  else return "a dict of strings to numbers";
}

// A plain row: HierarchicalOptions' field at the end of the member path Path.
template <auto... Path>
EstimatorKeyword field(const char* name) {
  using V = std::decay_t<decltype((std::declval<HierarchicalOptions&>().*....*Path))>;
  return {name, kind_of<V>(),
          [](HierarchicalOptions& o, py::handle v) { (o.*....*Path) = v.cast<V>(); },
          [](const HierarchicalOptions& o) { return py::cast((o.*....*Path)); }};
}

// A choice of two words stored as a bool (true: `yes`).
inline bool choice(const char* name, py::handle v, const char* yes, const char* no) {
  const auto s = v.cast<std::string>();
  if (s != yes && s != no)
    throw py::value_error(std::string(name) + " must be '" + yes + "' or '" + no + "', got '" + s + "'");
  return s == yes;
}

// A row of two words, `first` or `second`, for the bool field at Path; the field is true for
// `first` unless first_is is false (then for `second`).
template <auto... Path>
EstimatorKeyword two_words(const char* name, const char* first, const char* second, bool first_is = true) {
  return {name, std::string("'") + first + "' or '" + second + "'",
          [=](HierarchicalOptions& o, py::handle v) { (o.*....*Path) = choice(name, v, first, second) == first_is; },
          [=](const HierarchicalOptions& o) { return py::cast((o.*....*Path) == first_is ? first : second); }};
}

// A row for the enumerated field at Path, given as one of its words: Parse(word) (throws
// std::invalid_argument naming a word it does not know) and Name(value) back.
template <auto Parse, auto Name, auto... Path>
EstimatorKeyword words(const char* name, const char* expected) {
  return {name, expected,
          [](HierarchicalOptions& o, py::handle v) {
            try {
              (o.*....*Path) = Parse(py::cast<std::string>(py::str(v)));
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
          },
          [](const HierarchicalOptions& o) { return py::cast(Name((o.*....*Path))); }};
}

// A row for a reference that NaN turns off at Path, given as a number or None (None: off).
template <auto... Path>
EstimatorKeyword optional_number(const char* name) {
  return {name, "a number or None",
          [](HierarchicalOptions& o, py::handle v) {
            if (!v.is_none()) (o.*....*Path) = v.cast<double>();
          },
          [](const HierarchicalOptions& o) {
            const double x = (o.*....*Path);
            return std::isnan(x) ? py::object(py::none()) : py::cast(x);
          }};
}

using O = HierarchicalOptions;

inline const std::vector<EstimatorKeyword>& estimator_keywords() {
  static const std::vector<EstimatorKeyword> kKeywords = {
      // the bank: floor, likelihoods, start
      field<&O::bank, &FilterBankOptions::p_min>("p_min"),
      field<&O::bank, &FilterBankOptions::strip_leading_term>("strip_leading_term"),
      field<&O::bank, &FilterBankOptions::start_up_s>("start_up_s"),
      field<&O::bank, &FilterBankOptions::fresh_floor_levels>("fresh_floor_levels"),
      field<&O::schedule, &ScheduleOptions::node_p_min>("node_p_min"),
      // the levels
      field<&O::level1_p_min>("level1_p_min"),
      field<&O::level1_dwell_s>("level1_dwell_s"),
      field<&O::level1_allowance>("level1_allowance"),
      field<&O::level1_allowance_pairs>("level1_allowance_pairs"),
      two_words<&O::departure, &DepartureOptions::enabled>("departure_hold", "on", "off"),
      field<&O::declare_components>("declare_components"),
      field<&O::partial_p_min>("partial_p_min"),
      field<&O::rough_floor, &RoughAirFloorOptions::p_min>("rough_p_min"),
      field<&O::rough_floor, &RoughAirFloorOptions::from>("rough_p_min_from"),
      field<&O::rough_floor, &RoughAirFloorOptions::to>("rough_p_min_to"),
      // the declaration rule (`declarer`, handled after the others, overrides these three)
      field<&O::declarer, &DeclarerOptions::threshold>("threshold"),
      field<&O::declarer, &DeclarerOptions::dwell_s>("dwell_s"),
      field<&O::declarer, &DeclarerOptions::dwell_nats>("dwell_nats"),
      field<&O::declarer, &DeclarerOptions::dwell_nats_per_hypothesis>("dwell_nats_per_hypothesis"),  // {name: N_k}
      field<&O::declarer, &DeclarerOptions::dwell_s_per_hypothesis>("dwell_s_per_hypothesis"),  // {name: D_k s}
      field<&O::declarer, &DeclarerOptions::rough_dwell_s_per_hypothesis>("rough_dwell_s_per_hypothesis"),  // {name: R_k s}
      field<&O::declarer, &DeclarerOptions::rough_scale>("rough_scale"),
      {"declarer", "a core.Declarer or None", [](O&, py::handle) {},
       [](const O&) { return py::object(py::none()); }},
      // the calm-air complete model (calm_air_complete.h)
      field<&O::calm_complete, &CalmAirCompleteOptions::rho>("calm_complete_rho"),  // {measurement: rho_j}
      words<&parse_calm_measure, &calm_measure_name, &O::calm_complete, &CalmAirCompleteOptions::measure>(
          "calm_measure", "'power', 'whiteness' or 'either'"),
      field<&O::calm_complete, &CalmAirCompleteOptions::whiteness_bound>("calm_whiteness_bound"),
      // the complete failures' held trim (complete_trim_hold.h)
      words<&parse_trim_hold, &trim_hold_name, &O::complete_trim_hold, &CompleteTrimHoldOptions::hold>(
          "complete_trim_hold", "'off', 'suspected' or 'declared'"),
      field<&O::complete_trim_hold, &CompleteTrimHoldOptions::time_constant_s>("complete_trim_time_constant_s"),
      // trim tracking
      field<&O::trim, &TrimTrackingOptions::time_constant_s>("trim_time_constant_s"),
      field<&O::trim, &TrimTrackingOptions::freeze_probability>("trim_freeze_probability"),
      field<&O::trim, &TrimTrackingOptions::hold_s>("trim_hold_s"),
      field<&O::trim, &TrimTrackingOptions::freeze>("trim_freeze"),
      field<&O::trim, &TrimTrackingOptions::steady_g>("trim_steady_g"),
      field<&O::trim, &TrimTrackingOptions::steady_measurements>("trim_steady_measurements"),
      field<&O::trim, &TrimTrackingOptions::steady_roll_rate_rad_s>("trim_steady_roll_rate_rad_s"),
      field<&O::trim, &TrimTrackingOptions::steady_climb_ft_s>("trim_steady_climb_ft_s"),
      field<&O::trim, &TrimTrackingOptions::steady_mach_per_s>("trim_steady_mach_per_s"),
      two_words<&O::trim, &TrimTrackingOptions::load_factor>("trim_load_factor", "on", "off"),
      // the schedule
      {"schedule_mode", "'interpolate' or 'nearest'",
       [](O& o, py::handle v) {
         o.schedule.mode = choice("schedule_mode", v, "interpolate", "nearest") ? ScheduleMode::kInterpolate
                                                                                : ScheduleMode::kNearest;
       },
       [](const O& o) { return py::cast(o.schedule.mode == ScheduleMode::kInterpolate ? "interpolate" : "nearest"); }},
      field<&O::schedule, &ScheduleOptions::hysteresis_cells>("hysteresis_cells"),
      field<&O::schedule, &ScheduleOptions::blend_step_cells>("blend_step_cells"),
      field<&O::schedule, &ScheduleOptions::air_data_time_constant_s>("air_data_time_constant_s"),
      field<&O::schedule, &ScheduleOptions::cubic_trims>("cubic_trims"),
      field<&O::schedule, &ScheduleOptions::plane_trims>("plane_trims"),
      field<&O::schedule, &ScheduleOptions::row_trims>("row_trims"),
      field<&O::schedule, &ScheduleOptions::neighbour_trims>("neighbour_trims"),
      field<&O::schedule, &ScheduleOptions::lift_trims>("lift_trims"),
      field<&O::schedule, &ScheduleOptions::stabilator_trims>("stabilator_trims"),
      field<&O::schedule, &ScheduleOptions::gust_airspeed>("gust_airspeed"),
      // the turbulence adaptation
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::enabled>("adapt_turbulence"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::time_constant_s>(
          "adapt_time_constant_s"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::scale_min>("adapt_scale_min"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::scale_max>("adapt_scale_max"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::gain>("adapt_gain"),
      {"adapt_reference", "a number or None",  // None: a schedule's per-node references, else the core's
       [](O& o, py::handle v) {
         if (v.is_none()) return;
         o.bank.adaptation.reference = v.cast<double>();
         o.schedule.node_adapt_reference = false;
       },
       [](const O&) { return py::object(py::none()); }},
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::channel_weight>(
          "adapt_channel_weight"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::own_channels>(
          "adapt_own_channels"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::running_start>(
          "adapt_running_start"),
      two_words<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::level_scale>(
          "adapt_level_scale", "on", "off"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::counted_channels>(
          "adapt_counted_channels"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::excluded_channels>(
          "adapt_excluded_channels"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::level_scale_channels>(
          "adapt_level_scale_channels"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::hypothesis_weight>(
          "adapt_hypothesis_weight"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::full_tempering>(
          "adapt_full_tempering"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::spare_margin>("adapt_spare_margin"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::spare_margin_over>(
          "adapt_spare_margin_over"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::spare_rho>("adapt_spare_rho"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::level_scale_from>(
          "adapt_level_scale_from"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::floor_time_constant_s>(
          "adapt_floor_time_constant_s"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::rough_tempering>(
          "adapt_rough_tempering"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::rough_rho>("adapt_rough_rho"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::rough_weight>("adapt_rough_weight"),
      field<&O::bank, &FilterBankOptions::adaptation, &TurbulenceAdaptationOptions::scale_max_from>(
          "adapt_scale_max_from"),
      field<&O::spare_dwell_s>("spare_dwell_s"),
      field<&O::evidence_dwell_in_phases>("evidence_dwell_in_phases"),
      // the climb reference
      optional_number<&O::climb_reference, &ClimbReferenceOptions::reference>("adapt_reference_climb"),
      field<&O::climb_reference, &ClimbReferenceOptions::hold_s>("adapt_reference_climb_hold_s"),
      field<&O::climb_reference, &ClimbReferenceOptions::dwell_s>("adapt_reference_climb_dwell_s"),
      // the maneuver dwell and its gates
      field<&O::maneuver_dwell, &ManeuverDwellOptions::dwell_s>("maneuver_dwell_s"),
      optional_number<&O::maneuver_dwell, &ManeuverDwellOptions::reference>("maneuver_reference"),
      field<&O::maneuver_dwell, &ManeuverDwellOptions::hold_s>("maneuver_dwell_hold_s"),
      field<&O::maneuver_dwell, &ManeuverDwellOptions::g>("maneuver_dwell_g"),
      field<&O::maneuver_dwell, &ManeuverDwellOptions::time_constant_s>("maneuver_dwell_time_constant_s"),
      {"maneuver_mach_per_s", "a number",  // one gate for the maneuver dwell and the climb reference
       [](O& o, py::handle v) { o.maneuver_dwell.mach_per_s = o.climb_reference.mach_per_s = v.cast<double>(); },
       [](const O& o) { return py::cast(o.maneuver_dwell.mach_per_s); }},
      field<&O::rate_gates_gust_scaled>("maneuver_rate_gust_scaled"),
      field<&O::gates_calm_scaled>("maneuver_gates_calm_scaled"),
      {"maneuver_climb_ft_s", "a number",  // one gate for the maneuver dwell and the climb reference
       [](O& o, py::handle v) { o.maneuver_dwell.climb_ft_s = o.climb_reference.climb_ft_s = v.cast<double>(); },
       [](const O& o) { return py::cast(o.maneuver_dwell.climb_ft_s); }},
      // the maneuver's kinematics, tempering and trim
      field<&O::maneuver, &ManeuverOptions::kinematics>("maneuver_kinematics"),
      field<&O::maneuver, &ManeuverOptions::tempering_g>("maneuver_tempering_g"),
      field<&O::maneuver, &ManeuverOptions::tempering_deadband_g>("maneuver_tempering_deadband_g"),
      field<&O::maneuver, &ManeuverOptions::tempering_alpha_deg>("maneuver_tempering_alpha_deg"),
      field<&O::maneuver, &ManeuverOptions::tempering_alpha_deadband_deg>("maneuver_tempering_alpha_deadband_deg"),
      field<&O::maneuver, &ManeuverOptions::tempering_alpha_trim_deg>("maneuver_tempering_alpha_trim_deg"),
      field<&O::maneuver, &ManeuverOptions::tempering_added_g>("maneuver_tempering_added_g"),
      field<&O::maneuver, &ManeuverOptions::tempering_added_deadband_g>("maneuver_tempering_added_deadband_g"),
      field<&O::maneuver, &ManeuverOptions::tempering_added_spread>("maneuver_tempering_added_spread"),
      field<&O::maneuver_trim, &ManeuverTrimOptions::enabled>("maneuver_trim"),
      field<&O::maneuver_trim, &ManeuverTrimOptions::time_constant_s>("maneuver_trim_time_constant_s"),
      two_words<&O::maneuver_trim, &ManeuverTrimOptions::accel>("maneuver_trim_accel", "on", "off"),
      two_words<&O::maneuver_trim, &ManeuverTrimOptions::inertial>("maneuver_trim_rates", "air", "inertial", false),
      field<&O::maneuver_trim, &ManeuverTrimOptions::inertial_path, &InertialFlightPathOptions::blend_time_constant_s>(
          "maneuver_trim_blend_s"),
      field<&O::maneuver_trim, &ManeuverTrimOptions::accel_airspeed_rad_s>("maneuver_trim_accel_airspeed_rad_s"),
      two_words<&O::maneuver_trim, &ManeuverTrimOptions::gamma_load_factor>("maneuver_trim_gamma_load_factor", "on",
                                                                            "off"),
      // the actuators' limits (nu each; empty: off)
      field<&O::actuators, &ActuatorLimitOptions::rate_limit_rad_s>("actuator_rate_limits_rad_s"),
      field<&O::actuators, &ActuatorLimitOptions::position_limit_rad>("actuator_position_limits_rad"),
  };
  return kKeywords;
}

inline HierarchicalOptions estimator_options(const py::kwargs& kwargs) {
  HierarchicalOptions o;
  const auto& table = estimator_keywords();
  for (const auto& [key, value] : kwargs) {
    const auto name = key.cast<std::string>();
    const auto row = std::find_if(table.begin(), table.end(), [&](const auto& k) { return name == k.name; });
    if (row == table.end()) throw py::type_error("unexpected estimator keyword argument '" + name + "'");
    try {
      row->set(o, value);
    } catch (const py::cast_error&) {
      throw py::type_error(name + " must be " + row->kind + ", got " +
                           std::string(py::str(py::type::handle_of(value).attr("__name__"))));
    }
  }
  if (kwargs.contains("declarer") && !kwargs["declarer"].is_none()) {
    const py::handle declarer = kwargs["declarer"];
    if (!py::isinstance<Declarer>(declarer))
      throw py::value_error("declarer must be a core.Declarer (its threshold, dwell_s and dwell_nats are used), got " +
                            std::string(py::str(py::type::handle_of(declarer).attr("__name__"))));
    const DeclarerOptions& d = declarer.cast<const Declarer&>().options();
    o.declarer.threshold = d.threshold;
    o.declarer.dwell_s = d.dwell_s;
    o.declarer.dwell_nats = d.dwell_nats;
  }
  return o;
}

// The constructor's docstring: every keyword with the core's default, one a line
// ("  p_min: float = 0.001"), the type as Python names it.
inline std::string estimator_keywords_doc() {
  const HierarchicalOptions core;
  std::string doc = "Keyword arguments (bindings/estimator_init.h), each the core's default when left out:\n";
  for (const auto& k : estimator_keywords()) {
    const py::object d = k.default_of(core);
    doc += std::string("  ") + k.name + ": " + k.kind + " = " + std::string(py::repr(d)) + "\n";
  }
  return doc;
}

// Every keyword with the core's default, {name: default}: the harness checks a setting that
// depends on another keyword's default (e.g. the lull floor's τ_L against the averaging time τ)
// before any work, from this one source.
inline py::dict estimator_defaults() {
  const HierarchicalOptions core;
  py::dict out;
  for (const auto& k : estimator_keywords()) out[py::str(k.name)] = k.default_of(core);
  return out;
}

template <class T, class Source = ModelBank, class Class>
Class& def_estimator_init(Class& cls) {
  return cls.def(py::init([](const Source& bank, const py::kwargs& kwargs) {
                   return new T(bank, estimator_options(kwargs));
                 }),
                 py::arg("model_bank"), estimator_keywords_doc().c_str());
}

}  // namespace f16mmae::bindings
