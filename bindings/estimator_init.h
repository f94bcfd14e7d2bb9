// The estimator's settings as Python keyword arguments: ONE list, shared by every binding
// that builds the hierarchical MMAE from a core.ModelBank (core.HierarchicalBank and
// core.Executive), so that a setting the in-process estimator takes, the daemon's in-process
// executive (and so `f16mmae replay`) takes too, with the same name, default and check.
//
//   def_estimator_init<T>(cls)   cls.def(py::init(...)): T(model_bank, HierarchicalOptions)
//                                from model_bank and the keyword arguments below
//   def_estimator_init<T, Source>(cls)   the same from another source (core.Executive and
//                                core.TurbulenceBankSet from a core.TurbulenceSetFile: the set's
//                                members, cpp/executive/turbulence_set_bank.h)
//
//   p_min, strip_leading_term            the bank's floor and its likelihoods (filter_bank.h)
//   level1_p_min                         the floor while a level-1 bank is on line; 0: p_min
//                                        (hierarchical_bank.h)
//   level1_dwell_s                       the dwell while a level-1 bank is on line; 0: dwell_s
//   level1_allowance                     the duals' drift allowance at level 1, nats a frame; 0:
//                                        none (level1_allowance.h)
//   level1_allowance_pairs               {"F>C": k}: the dual F+C's own allowance in F's level-1
//                                        bank (level1_allowance.h); empty: none
//   departure_hold ('on'|'off')          level 1: no declaration while the measurements leave
//                                        the linearization (hierarchical_bank.h; default on)
//   declare_components                   a partial hypothesis and its single declared as one
//                                        component (hierarchical_bank.h, declarer.h; default off)
//   partial_p_min                        the partial-loss hypotheses' floor at level 0; 0: p_min
//                                        (hierarchical_bank.h)
//   start_up_s                           updates that weigh nothing after a start (filter_bank.h)
//   node_p_min                           a scheduled bank: each node's floor (its bank's p_min,
//                                        blended; scheduled_filters.h) instead of p_min
//   threshold, dwell_s, dwell_nats, declarer  the declaration rule (declarer.h); a core.Declarer
//                                        given as declarer supplies threshold, dwell_s and dwell_nats
//   trim_time_constant_s, trim_freeze_probability, trim_hold_s, trim_freeze,
//   trim_steady_g, trim_steady_measurements, trim_steady_roll_rate_rad_s, trim_steady_climb_ft_s,
//   trim_steady_mach_per_s                                                    trim_tracker.h
//   schedule_mode ('interpolate'|'nearest'),
//   hysteresis_cells, blend_step_cells,
//   air_data_time_constant_s, cubic_trims                                      scheduled_filters.h
//   adapt_turbulence, adapt_time_constant_s, adapt_scale_min, adapt_scale_max, adapt_gain,
//   adapt_reference (None: a schedule's per-node references, else 0.6), adapt_channel_weight,
//   adapt_own_channels, adapt_counted_channels (bit j: z_j),
//   adapt_hypothesis_weight, adapt_full_tempering (bit k: hypothesis k),
//   adapt_spare_own_fit, adapt_spare_rho (0: at any rho-bar),
//   adapt_spare_burst_ratio (0: off)                                   turbulence_adaptation.h
//   adapt_reference_climb (None: off), adapt_reference_climb_hold_s,
//   adapt_reference_climb_dwell_s (0: the declarer's dwell)             climb_reference.h
//   maneuver_dwell_s (0: the declarer's dwell), maneuver_reference (None: off),
//   maneuver_dwell_hold_s, maneuver_dwell_g, maneuver_dwell_time_constant_s  maneuver_dwell.h
//   maneuver_mach_per_s: the air data's |M_dot| above which the maneuver dwell's and the
//   climb reference's gates call the aircraft maneuvering      maneuver_dwell.h, climb_reference.h
//   maneuver_kinematics, maneuver_tempering_g,
//   maneuver_tempering_deadband_g (0: none)                             maneuver_kinematics.h
//   maneuver_trim, maneuver_trim_time_constant_s, maneuver_trim_accel ('on'|'off'),
//   maneuver_trim_rates ('air'|'inertial'), maneuver_trim_blend_s                   maneuver_trim.h
//   actuator_rate_limits_rad_s, actuator_position_limits_rad (nu each; empty: off)
//                                                                       actuator_limits.h
// Every default is the core's own (the option structs' initialisers), so a keyword left out
// means the bank as designed. Each keyword is a row of the harness's option table
// (loop/estimator_options.py) or named there in CORE_ONLY with its reason. A bad schedule_mode or declarer raises ValueError naming it.
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "f16mmae/declarer.h"
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/model_bank.h"

namespace f16mmae::bindings {

namespace py = pybind11;

inline HierarchicalOptions estimator_options(double p_min, double level1_p_min, double level1_dwell_s, double level1_allowance,
                                             const std::map<std::string, double>& level1_allowance_pairs,
                                             const std::string& departure_hold, bool declare_components, double partial_p_min, bool node_p_min, bool strip_leading_term, double start_up_s,
                                             double threshold, double dwell_s, double dwell_nats,
                                             const py::object& declarer, double trim_time_constant_s,
                                             double trim_freeze_probability, double trim_hold_s, bool trim_freeze,
                                             double trim_steady_g,
                                             const std::vector<std::string>& trim_steady_measurements,
                                             double trim_steady_roll_rate_rad_s, double trim_steady_climb_ft_s,
                                             double trim_steady_mach_per_s, const std::string& schedule_mode,
                                             double hysteresis_cells,
                                             double blend_step_cells, double air_data_time_constant_s,
                                             bool cubic_trims, bool adapt_turbulence, double adapt_time_constant_s,
                                             double adapt_scale_min, double adapt_scale_max, double adapt_gain,
                                             const std::optional<double>& adapt_reference, double adapt_channel_weight, bool adapt_own_channels,
                                             std::uint32_t adapt_counted_channels, double adapt_hypothesis_weight, std::uint32_t adapt_full_tempering,
                                             bool adapt_spare_own_fit, double adapt_spare_rho, double adapt_spare_burst_ratio,
                                             const std::optional<double>& adapt_reference_climb,
                                             double adapt_reference_climb_hold_s,
                                             double adapt_reference_climb_dwell_s,
                                             double maneuver_dwell_s, const std::optional<double>& maneuver_reference,
                                             double maneuver_dwell_hold_s, double maneuver_dwell_g,
                                             double maneuver_dwell_time_constant_s, double maneuver_mach_per_s,
                                             bool maneuver_kinematics, double maneuver_tempering_g,
                                             double maneuver_tempering_deadband_g,
                                             bool maneuver_trim, double maneuver_trim_time_constant_s, const std::string& maneuver_trim_accel,
                                             const std::string& maneuver_trim_rates, double maneuver_trim_blend_s,
                                             const std::vector<double>& actuator_rate_limits_rad_s,
                                             const std::vector<double>& actuator_position_limits_rad) {
  HierarchicalOptions o;
  o.maneuver.kinematics = maneuver_kinematics;
  o.maneuver.tempering_g = maneuver_tempering_g;
  o.maneuver.tempering_deadband_g = maneuver_tempering_deadband_g;
  o.maneuver_trim.enabled = maneuver_trim;
  o.maneuver_trim.time_constant_s = maneuver_trim_time_constant_s;
  if (maneuver_trim_accel != "on" && maneuver_trim_accel != "off")
    throw py::value_error("maneuver_trim_accel must be 'on' or 'off', got '" + maneuver_trim_accel + "'");
  o.maneuver_trim.accel = maneuver_trim_accel == "on";
  if (maneuver_trim_rates != "air" && maneuver_trim_rates != "inertial")
    throw py::value_error("maneuver_trim_rates must be 'air' or 'inertial', got '" + maneuver_trim_rates + "'");
  o.maneuver_trim.inertial = maneuver_trim_rates == "inertial";
  o.maneuver_trim.inertial_path.blend_time_constant_s = maneuver_trim_blend_s;
  o.actuators.rate_limit_rad_s = actuator_rate_limits_rad_s;
  o.actuators.position_limit_rad = actuator_position_limits_rad;
  o.trim.time_constant_s = trim_time_constant_s;
  o.trim.freeze_probability = trim_freeze_probability;
  o.trim.hold_s = trim_hold_s;
  o.trim.freeze = trim_freeze;
  o.trim.steady_g = trim_steady_g;
  o.trim.steady_measurements = trim_steady_measurements;
  o.trim.steady_roll_rate_rad_s = trim_steady_roll_rate_rad_s;
  o.trim.steady_climb_ft_s = trim_steady_climb_ft_s;
  o.trim.steady_mach_per_s = trim_steady_mach_per_s;
  if (schedule_mode == "interpolate")
    o.schedule.mode = ScheduleMode::kInterpolate;
  else if (schedule_mode == "nearest")
    o.schedule.mode = ScheduleMode::kNearest;
  else
    throw py::value_error("schedule_mode must be 'interpolate' or 'nearest', got '" + schedule_mode + "'");
  o.schedule.hysteresis_cells = hysteresis_cells;
  o.schedule.blend_step_cells = blend_step_cells;
  o.schedule.air_data_time_constant_s = air_data_time_constant_s;
  o.schedule.cubic_trims = cubic_trims;
  o.bank.p_min = p_min;
  o.level1_p_min = level1_p_min;
  o.level1_dwell_s = level1_dwell_s;
  o.level1_allowance = level1_allowance;
  o.level1_allowance_pairs = level1_allowance_pairs;
  if (departure_hold != "on" && departure_hold != "off")
    throw py::value_error("departure_hold must be 'on' or 'off', got '" + departure_hold + "'");
  o.departure.enabled = departure_hold == "on";
  o.declare_components = declare_components;
  o.partial_p_min = partial_p_min;
  o.schedule.node_p_min = node_p_min;
  o.bank.strip_leading_term = strip_leading_term;
  o.bank.start_up_s = start_up_s;
  o.bank.adaptation.enabled = adapt_turbulence;
  o.bank.adaptation.time_constant_s = adapt_time_constant_s;
  o.bank.adaptation.scale_min = adapt_scale_min;
  o.bank.adaptation.scale_max = adapt_scale_max;
  o.bank.adaptation.gain = adapt_gain;
  o.bank.adaptation.channel_weight = adapt_channel_weight;
  o.bank.adaptation.own_channels = adapt_own_channels;
  o.bank.adaptation.counted_channels = adapt_counted_channels;
  o.bank.adaptation.hypothesis_weight = adapt_hypothesis_weight;
  o.bank.adaptation.full_tempering = adapt_full_tempering;
  o.bank.adaptation.spare_own_fit = adapt_spare_own_fit;
  o.bank.adaptation.spare_rho = adapt_spare_rho;
  o.bank.adaptation.spare_burst_ratio = adapt_spare_burst_ratio;
  if (adapt_reference) {  // one reference everywhere; else a schedule's per-node ones, if it has them
    o.bank.adaptation.reference = *adapt_reference;
    o.schedule.node_adapt_reference = false;
  }
  if (adapt_reference_climb) o.climb_reference.reference = *adapt_reference_climb;
  o.climb_reference.hold_s = adapt_reference_climb_hold_s;
  o.climb_reference.dwell_s = adapt_reference_climb_dwell_s;
  o.maneuver_dwell.dwell_s = maneuver_dwell_s;
  if (maneuver_reference) o.maneuver_dwell.reference = *maneuver_reference;
  o.maneuver_dwell.hold_s = maneuver_dwell_hold_s;
  o.maneuver_dwell.g = maneuver_dwell_g;
  o.maneuver_dwell.time_constant_s = maneuver_dwell_time_constant_s;
  o.maneuver_dwell.mach_per_s = maneuver_mach_per_s;
  o.climb_reference.mach_per_s = maneuver_mach_per_s;
  o.declarer.threshold = threshold;
  o.declarer.dwell_s = dwell_s;
  o.declarer.dwell_nats = dwell_nats;
  if (!declarer.is_none()) {
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

template <class T, class Source = ModelBank, class Class>
Class& def_estimator_init(Class& cls) {
  const HierarchicalOptions core;  // the defaults
  return cls.def(
      py::init([](const Source& bank, double p_min, double level1_p_min, double level1_dwell_s, double level1_allowance,
                  const std::map<std::string, double>& level1_allowance_pairs,
                  const std::string& departure_hold, bool declare_components, double partial_p_min, bool node_p_min, bool strip_leading_term, double start_up_s,
                  double threshold, double dwell_s, double dwell_nats,
                  const py::object& declarer, double trim_time_constant_s, double trim_freeze_probability,
                  double trim_hold_s, bool trim_freeze, double trim_steady_g,
                  const std::vector<std::string>& trim_steady_measurements, double trim_steady_roll_rate_rad_s,
                  double trim_steady_climb_ft_s,
                  double trim_steady_mach_per_s, const std::string& schedule_mode,
                  double hysteresis_cells,
                  double blend_step_cells, double air_data_time_constant_s, bool cubic_trims, bool adapt_turbulence,
                  double adapt_time_constant_s, double adapt_scale_min, double adapt_scale_max, double adapt_gain,
                  const std::optional<double>& adapt_reference, double adapt_channel_weight, bool adapt_own_channels,
                                             std::uint32_t adapt_counted_channels, double adapt_hypothesis_weight, std::uint32_t adapt_full_tempering,
                                             bool adapt_spare_own_fit, double adapt_spare_rho, double adapt_spare_burst_ratio,
                  const std::optional<double>& adapt_reference_climb,
                  double adapt_reference_climb_hold_s, double adapt_reference_climb_dwell_s,
                  double maneuver_dwell_s, const std::optional<double>& maneuver_reference,
                  double maneuver_dwell_hold_s, double maneuver_dwell_g, double maneuver_dwell_time_constant_s,
                  double maneuver_mach_per_s, bool maneuver_kinematics,
                  double maneuver_tempering_g, double maneuver_tempering_deadband_g,
                  bool maneuver_trim, double maneuver_trim_time_constant_s, const std::string& maneuver_trim_accel,
                  const std::string& maneuver_trim_rates, double maneuver_trim_blend_s,
                  const std::vector<double>& actuator_rate_limits_rad_s,
                  const std::vector<double>& actuator_position_limits_rad) {
        return new T(bank, estimator_options(p_min, level1_p_min, level1_dwell_s, level1_allowance, level1_allowance_pairs, departure_hold, declare_components, partial_p_min, node_p_min, strip_leading_term, start_up_s, threshold, dwell_s, dwell_nats,
                                             declarer,
                                             trim_time_constant_s, trim_freeze_probability, trim_hold_s, trim_freeze,
                                             trim_steady_g, trim_steady_measurements, trim_steady_roll_rate_rad_s, trim_steady_climb_ft_s,
                                             trim_steady_mach_per_s, schedule_mode, hysteresis_cells, blend_step_cells,
                                             air_data_time_constant_s, cubic_trims, adapt_turbulence,
                                             adapt_time_constant_s, adapt_scale_min, adapt_scale_max, adapt_gain,
                                             adapt_reference, adapt_channel_weight, adapt_own_channels, adapt_counted_channels, adapt_hypothesis_weight, adapt_full_tempering, adapt_spare_own_fit, adapt_spare_rho, adapt_spare_burst_ratio, adapt_reference_climb, adapt_reference_climb_hold_s,
                                             adapt_reference_climb_dwell_s, maneuver_dwell_s, maneuver_reference,
                                             maneuver_dwell_hold_s, maneuver_dwell_g, maneuver_dwell_time_constant_s,
                                             maneuver_mach_per_s, maneuver_kinematics, maneuver_tempering_g,
                                             maneuver_tempering_deadband_g, maneuver_trim, maneuver_trim_time_constant_s,
                                             maneuver_trim_accel, maneuver_trim_rates, maneuver_trim_blend_s,
                                             actuator_rate_limits_rad_s, actuator_position_limits_rad));
      }),
      py::arg("model_bank"), py::kw_only(), py::arg("p_min") = core.bank.p_min,
      py::arg("level1_p_min") = core.level1_p_min, py::arg("level1_dwell_s") = core.level1_dwell_s,
      py::arg("level1_allowance") = core.level1_allowance,
      py::arg("level1_allowance_pairs") = std::map<std::string, double>{},
      py::arg("departure_hold") = core.departure.enabled ? "on" : "off",
      py::arg("declare_components") = core.declare_components, py::arg("partial_p_min") = core.partial_p_min,
      py::arg("node_p_min") = core.schedule.node_p_min,
      py::arg("strip_leading_term") = core.bank.strip_leading_term, py::arg("start_up_s") = core.bank.start_up_s,
      py::arg("threshold") = core.declarer.threshold,
      py::arg("dwell_s") = core.declarer.dwell_s,
      py::arg("dwell_nats") = core.declarer.dwell_nats, py::arg("declarer") = py::none(),
      py::arg("trim_time_constant_s") = core.trim.time_constant_s,
      py::arg("trim_freeze_probability") = core.trim.freeze_probability, py::arg("trim_hold_s") = core.trim.hold_s,
      py::arg("trim_freeze") = core.trim.freeze, py::arg("trim_steady_g") = core.trim.steady_g,
      py::arg("trim_steady_measurements") = core.trim.steady_measurements,
      py::arg("trim_steady_roll_rate_rad_s") = core.trim.steady_roll_rate_rad_s,
      py::arg("trim_steady_climb_ft_s") = core.trim.steady_climb_ft_s,
      py::arg("trim_steady_mach_per_s") = core.trim.steady_mach_per_s, py::arg("schedule_mode") = "interpolate",
      py::arg("hysteresis_cells") = core.schedule.hysteresis_cells,
      py::arg("blend_step_cells") = core.schedule.blend_step_cells,
      py::arg("air_data_time_constant_s") = core.schedule.air_data_time_constant_s,
      py::arg("cubic_trims") = core.schedule.cubic_trims, py::arg("adapt_turbulence") = core.bank.adaptation.enabled,
      py::arg("adapt_time_constant_s") = core.bank.adaptation.time_constant_s,
      py::arg("adapt_scale_min") = core.bank.adaptation.scale_min,
      py::arg("adapt_scale_max") = core.bank.adaptation.scale_max, py::arg("adapt_gain") = core.bank.adaptation.gain,
      py::arg("adapt_reference") = py::none(), py::arg("adapt_channel_weight") = core.bank.adaptation.channel_weight,
      py::arg("adapt_own_channels") = core.bank.adaptation.own_channels,
      py::arg("adapt_counted_channels") = core.bank.adaptation.counted_channels,
      py::arg("adapt_hypothesis_weight") = core.bank.adaptation.hypothesis_weight,
      py::arg("adapt_full_tempering") = core.bank.adaptation.full_tempering,
      py::arg("adapt_spare_own_fit") = core.bank.adaptation.spare_own_fit,
      py::arg("adapt_spare_rho") = core.bank.adaptation.spare_rho,
      py::arg("adapt_spare_burst_ratio") = core.bank.adaptation.spare_burst_ratio,
      py::arg("adapt_reference_climb") = py::none(),
      py::arg("adapt_reference_climb_hold_s") = core.climb_reference.hold_s,
      py::arg("adapt_reference_climb_dwell_s") = core.climb_reference.dwell_s,
      py::arg("maneuver_dwell_s") = core.maneuver_dwell.dwell_s, py::arg("maneuver_reference") = py::none(),
      py::arg("maneuver_dwell_hold_s") = core.maneuver_dwell.hold_s,
      py::arg("maneuver_dwell_g") = core.maneuver_dwell.g,
      py::arg("maneuver_dwell_time_constant_s") = core.maneuver_dwell.time_constant_s,
      py::arg("maneuver_mach_per_s") = core.maneuver_dwell.mach_per_s,
      py::arg("maneuver_kinematics") = core.maneuver.kinematics,
      py::arg("maneuver_tempering_g") = core.maneuver.tempering_g,
      py::arg("maneuver_tempering_deadband_g") = core.maneuver.tempering_deadband_g,
      py::arg("maneuver_trim") = core.maneuver_trim.enabled,
      py::arg("maneuver_trim_time_constant_s") = core.maneuver_trim.time_constant_s,
      py::arg("maneuver_trim_accel") = core.maneuver_trim.accel ? "on" : "off",
      py::arg("maneuver_trim_rates") = core.maneuver_trim.inertial ? "inertial" : "air",
      py::arg("maneuver_trim_blend_s") = core.maneuver_trim.inertial_path.blend_time_constant_s,
      py::arg("actuator_rate_limits_rad_s") = std::vector<double>{},
      py::arg("actuator_position_limits_rad") = std::vector<double>{});
}

}  // namespace f16mmae::bindings
