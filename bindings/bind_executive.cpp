// f16mmae.core.Executive: the MMAE executive of mmae-daemon (cpp/executive/executive.h) in
// process -- the one implementation of the frame rules (frame_sequencer.h), used by
// `f16mmae replay` and the in-process LCM executive. Frames go in as numbers and arrays
// (checked here: shapes, frame counters that fit int64); the status comes out LCM-encoded,
// byte for byte what mmae-daemon publishes (decode it with f16mmae.lcmt_mmae_status).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core_convert.h"
#include "estimator_init.h"
#include "bankfile/turbulence_set_file.h"
#include "executive/executive.h"
#include "f16mmae/model_bank.h"

namespace py = pybind11;

namespace f16mmae::bindings {
namespace {

namespace cv = convert;
using executive::Executive;
using executive::MmaeEstimator;

std::string on_sensor(Executive& ex, std::int64_t frame, py::handle z, const std::optional<std::vector<bool>>& valid,
                      std::int64_t utime, const std::optional<std::vector<double>>& air_data) {
  const auto zv = cv::to_vector<MmaeEstimator::ZVector>(z, MmaeEstimator::kNz, "z");
  if (valid && valid->size() != static_cast<std::size_t>(MmaeEstimator::kNz))
    throw py::value_error("valid must hold " + std::to_string(MmaeEstimator::kNz) + " flags, got " +
                          std::to_string(valid->size()));
  if (air_data && air_data->size() != 2)
    throw py::value_error("air_data must be (mach, pressure_altitude_ft), got " + std::to_string(air_data->size()) +
                          " values");
  lcmt_sensor_frame f{};
  f.utime = utime;
  f.frame = frame;
  f.mach = air_data ? (*air_data)[0] : std::nan("");
  f.pressure_altitude_ft = air_data ? (*air_data)[1] : std::nan("");
  for (int j = 0; j < MmaeEstimator::kNz; ++j) {
    f.z[j] = zv(j);
    f.valid[j] = valid ? (*valid)[j] : true;
  }
  return executive::fate_name(ex.on_sensor(f));
}

// u: the five surface commands, then the throttle command (required by a throttle bank; a
// 5-element u sends a NaN throttle, as a sender without one).
std::string on_command(Executive& ex, std::int64_t frame, py::handle u, std::int64_t utime) {
  const auto n = static_cast<int>(py::len(u));
  const bool throttle = ex.estimator().models_throttle();
  if (throttle && n != MmaeEstimator::kNuThrottle)
    throw py::value_error("u: this bank models the throttle: u must hold the 5 surface commands and the throttle "
                          "command (6 values), got " + std::to_string(n));
  const auto uv = cv::to_vector<Eigen::VectorXd>(u, n == MmaeEstimator::kNuThrottle ? n : MmaeEstimator::kNu, "u");
  lcmt_command_frame f{};
  f.utime = utime;
  f.frame = frame;
  for (int j = 0; j < MmaeEstimator::kNu; ++j) f.u_rad[j] = uv(j);
  f.throttle = n == MmaeEstimator::kNuThrottle ? uv(MmaeEstimator::kNu) : std::nan("");
  return executive::fate_name(ex.on_command(f));
}

py::dict counters(const Executive& ex) {
  const auto& c = ex.counters();
  py::dict d;
  d["frames_updated"] = c.frames_updated;
  d["commands_applied"] = c.commands_applied;
  d["frames_rejected"] = c.frames_rejected;
  d["dropped_duplicate"] = c.dropped_duplicate;
  d["dropped_out_of_order"] = c.dropped_out_of_order;
  d["frames_resynchronised"] = c.frames_resynchronised;
  d["frames_stale"] = c.frames_stale;
  d["commands_missed"] = c.commands_missed;
  d["air_data_rejected"] = ex.air_data_rejected();
  return d;
}

}  // namespace

void bind_executive(py::module_& m) {
  py::class_<Executive> cls(m, "Executive", R"doc(
The MMAE executive of mmae-daemon, in process: the F-16 hierarchical bank of a ModelBank
behind the daemon's frame rules (duplicates and late frames dropped, lost frames propagated
with the held command, non-finite or invalid frames rejected, a counter more than one second
of frames from the sequence re-synchronised from the stale state).

Executive(model_bank, *, p_min, threshold, dwell_s, ..., adapt_turbulence, adapt_reference,
trim_time_constant_s, schedule_mode, maneuver_kinematics, actuator_rate_limits_rad_s, ...): the
estimator settings in force, the same keyword arguments as core.HierarchicalBank (callers pass
the bank's recommended ones with their overrides; mmae-daemon's flags set the same options).
on_sensor(frame, z, valid=None, utime=0, air_data=None) and on_command(frame, u, utime=0) take
absolute z (7,) and u (5,) or (6,): the surface commands, then the throttle command (a bank that
models the throttle needs all six; five send a NaN throttle, which a 5-input bank ignores) (and the frame's measured air data (mach, pressure_altitude_ft); None
sends NaN, as a sender without air data: the schedule stays, the frame is counted in
counters['air_data_rejected']) and return the frame's fate: "used", "rejected", "duplicate", "out-of-order" or
"resynchronised". A used or resynchronised sensor frame leaves its status in encoded_status.
Raises ValueError for a bank other than the F-16's (13 states and 5 inputs, 19 states with the
gust states, or 6 inputs with the throttle; 7 measurements)
and for arrays of the wrong shape.

Executive(set_file, *, ...) with a core.TurbulenceSetFile runs its turbulence bank set as
mmae-daemon --turbulence-banks does: the settings apply to every member, each with the
turbulence adaptation on at the set's reference for it unless adapt_reference is given; the
status carries the set's content_hash.)doc");
  def_estimator_init<Executive, TurbulenceSetFile>(cls);
  def_estimator_init<Executive>(cls)
      .def("on_sensor", &on_sensor, py::arg("frame"), py::arg("z"), py::arg("valid") = py::none(),
           py::arg("utime") = 0, py::arg("air_data") = py::none(), "Sensor frame: returns its fate.")
      .def("on_command", &on_command, py::arg("frame"), py::arg("u"), py::arg("utime") = 0,
           "Command frame: returns its fate.")
      .def("on_reset", &Executive::on_reset, "A new flight: estimator and frame sequence restart.")
      .def_property_readonly(
          "encoded_status",
          [](const Executive& ex) {
            return py::bytes(reinterpret_cast<const char*>(ex.encoded_status()),
                             static_cast<std::size_t>(ex.encoded_status_size()));
          },
          "The last status, LCM-encoded (lcmt_mmae_status); b'' before the first.")
      .def_property_readonly("counters", &counters, "The frame counters since construction (a dict).")
      .def_property_readonly("max_gap_frames", &Executive::max_gap_frames,
                             "The largest gap caught up frame by frame (one second of frames).")
      .def_property_readonly("statuses", &Executive::statuses, "Statuses produced since construction.")
      .def_property_readonly(
          "nu", [](const Executive& ex) { return ex.estimator().nu(); },
          "The bank's input size: 5, or 6 when it models the throttle (the command frame's throttle).");
}

}  // namespace f16mmae::bindings
