// f16mmae.core.TruthFrames: the truth model's per-step path in C++.
//
// TruthFrames steps the frame on a JSBSimExec (bindings/jsbsim_exec.h): sensors
// (cpp/truth/truth_frame.h) on cached property nodes, the flight control law, the actuators at
// the JSBSim rate and JSBSim itself, with no Python in between; it records the truth log into
// buffers sized at construction, and can fly a whole closed-loop flight with the core's
// estimator in the loop (fly_closed_loop).
//
// Frame i (docs in truth/model.py): z_i = measure(); u_i = FCS(z_feedback, t_i);
// advance(u_i) = SIM/FRAME JSBSim steps, each: due actuator failures, actuator step, surfaces
// written, Run().  Sensor failures act from their frame, actuator failures from their step.
// measure() also samples the air-data sensor (cpp/truth/air_data_sensor.h; normals from their
// own array, the air-data stream), which fly_closed_loop hands to the estimator's schedule()
// before each update.  A bank with the throttle as its sixth input (F16ThrottleHierarchicalBank)
// propagates u_i = (the five surface commands, the throttle command of frame i): the throttle
// dither's command (set_throttle_dither, required for such a bank), about the trim throttle, or
// in maneuvers about the outer loop's throttle command of frame i (computed with the control law).
// The truth log (log(): time, z, ideal z, air data, states, commands, surfaces of every frame)
// is recorded unless the frames are built with record_log=False (a closed-loop flight whose
// caller never reads it: its frames then write nothing but what they fly); the counters
// (measured, step_count) and the track (track(): time, Mach and pressure altitude of the ideal
// air data at every whole second, buffered at construction) are kept either way.
// Throws ValueError for bad arguments (names the field), RuntimeError when JSBSim stops.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "f16mmae/sensor_reconfiguration.h"
#include "hierarchical_access.h"
#include "jsbsim_exec.h"
#include "tick_clock.h"
#include "truth/air_data_sensor.h"
#include "truth/truth_frame.h"

namespace py = pybind11;
using namespace f16mmae::truth;

namespace f16mmae::bindings {
namespace {

template <std::size_t N>
std::array<double, N> arr(const py::dict& d, const char* key) {
  if (!d.contains(key)) throw py::value_error(std::string("TruthFrames: missing field '") + key + "'");
  const auto v = d[key].cast<std::vector<double>>();
  if (v.size() != N)
    throw py::value_error(std::string("TruthFrames: field '") + key + "' needs " + std::to_string(N) +
                          " values, got " + std::to_string(v.size()));
  std::array<double, N> a{};
  std::copy(v.begin(), v.end(), a.begin());
  return a;
}

double num(const py::dict& d, const char* key) {
  if (!d.contains(key)) throw py::value_error(std::string("TruthFrames: missing field '") + key + "'");
  return d[key].cast<double>();
}

struct ScheduledFailure {
  long long at;  // step (actuators) or frame (sensors) from which it acts
  int index, mode;
  double value;
};

std::vector<ScheduledFailure> schedule(const py::list& items, int n_components, int n_modes, const char* what) {
  std::vector<ScheduledFailure> out;
  for (auto item : items) {
    auto t = item.cast<py::tuple>();
    if (t.size() != 4) throw py::value_error(std::string(what) + " entries are (at, index, mode, value)");
    ScheduledFailure f{t[0].cast<long long>(), t[1].cast<int>(), t[2].cast<int>(), t[3].cast<double>()};
    if (f.index < 0 || f.index >= n_components || f.mode < 1 || f.mode >= n_modes)
      throw py::value_error(std::string(what) + ": index " + std::to_string(f.index) + " or mode " +
                            std::to_string(f.mode) + " out of range");
    out.push_back(f);
  }
  std::stable_sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.at < b.at; });
  return out;
}

Reference reference(const py::dict& d, const char* key) {
  if (!d.contains(key)) throw py::value_error(std::string("TruthFrames: missing field '") + key + "'");
  const auto r = d[key].cast<py::dict>();
  Reference out;
  out.start = num(r, "start");
  const auto segs = r["segments"].cast<std::vector<std::vector<double>>>();
  if (segs.size() > static_cast<std::size_t>(kMaxSegments))
    throw py::value_error(std::string("TruthFrames: ") + key + " has more than " + std::to_string(kMaxSegments) +
                          " segments");
  for (const auto& seg : segs) {
    if (seg.size() != 4) throw py::value_error(std::string("TruthFrames: ") + key + " segments are (t0, v0, v1, slope)");
    out.t0[out.n] = seg[0], out.v0[out.n] = seg[1], out.v1[out.n] = seg[2], out.slope[out.n] = seg[3];
    ++out.n;
  }
  return out;
}

class Frames {
 public:
  Frames(std::shared_ptr<Exec> exec, const std::vector<std::string>& surface_properties,
         const std::vector<std::string>& sensor_properties, const std::string& weight_property,
         const std::vector<std::string>& state_properties, const py::dict& actuator, const py::dict& sensor,
         const py::list& actuator_failures, const py::list& sensor_failures, py::array_t<double> noise,
         const std::vector<std::string>& air_data_properties, const py::dict& air_data,
         py::array_t<double> air_data_noise, int steps_per_frame, double frame_rate_hz, double sim_rate_hz,
         long long capacity, bool record_log)
      : exec_(std::move(exec)), record_log_(record_log), steps_per_frame_(steps_per_frame),
        frame_rate_hz_(frame_rate_hz), sim_rate_hz_(sim_rate_hz) {
    if (surface_properties.size() != kSurfaces || sensor_properties.size() != kSensors)
      throw py::value_error("TruthFrames needs 5 surface and 7 sensor properties");
    for (int i = 0; i < kSurfaces; ++i) surface_[i] = exec_->node(surface_properties[i]);
    for (int i = 0; i < kSensors; ++i) sensor_[i] = exec_->node(sensor_properties[i]);
    weight_ = exec_->node(weight_property);
    if (air_data_properties.size() != kAirData)
      throw py::value_error("TruthFrames needs 2 air-data properties (Mach, pressure altitude)");
    for (int j = 0; j < kAirData; ++j) air_node_[j] = exec_->node(air_data_properties[j]);
    air_.decay = num(air_data, "decay");
    air_.sigma = arr<kAirData>(air_data, "sigma");
    air_.reset();
    for (auto& p : state_properties) state_.push_back(exec_->node(p));
    act_.trim_rad = arr<kSurfaces>(actuator, "trim_rad");
    act_.limit_rad = arr<kSurfaces>(actuator, "limit_rad");
    act_.decay = arr<kSurfaces>(actuator, "decay");
    act_.max_step_rad = arr<kSurfaces>(actuator, "max_step_rad");
    act_.reset();
    sen_.z_trim = arr<kSensors>(sensor, "z_trim");
    sen_.sigma = arr<kSensors>(sensor, "sigma");
    sen_.full_scale_low = arr<kSensors>(sensor, "full_scale_low");
    sen_.full_scale_high = arr<kSensors>(sensor, "full_scale_high");
    sen_.reset();
    act_fail_ = schedule(actuator_failures, kSurfaces, 5, "actuator_failures");
    sen_fail_ = schedule(sensor_failures, kSensors, 7, "sensor_failures");
    set_noise(noise);
    set_air_data_noise(air_data_noise);
    const std::size_t cap = static_cast<std::size_t>(capacity > 0 ? capacity : 1);
    track_every_ = std::max(1LL, std::llround(frame_rate_hz));
    track_.reserve(kTrack * (cap / static_cast<std::size_t>(track_every_) + 2));
    if (!record_log_) return;
    log_time_.reserve(cap);
    log_z_.reserve(cap * kSensors);
    log_ideal_.reserve(cap * kSensors);
    log_air_.reserve(cap * kAirData);
    log_air_ideal_.reserve(cap * kAirData);
    log_state_.reserve(cap * state_.size());
    log_u_.reserve(cap * kSurfaces);
    log_surface_.reserve(cap * kSurfaces);
  }

  void set_fcs(const py::dict& d) {
    FcsCoefficients c;
    c.u_trim = arr<kSurfaces>(d, "u_trim");
    c.limit_rad = arr<kSurfaces>(d, "limit_rad");
    c.z_trim = arr<kSensors>(d, "z_trim");
    c.kq = num(d, "kq"), c.kn = num(d, "kn"), c.ki = num(d, "ki"), c.kp = num(d, "kp");
    c.kpff = num(d, "kpff"), c.kr = num(d, "kr"), c.kay = num(d, "kay"), c.kari = num(d, "kari");
    c.k_c = num(d, "k_c"), c.k_v = num(d, "k_v"), c.k_d = num(d, "k_d");
    c.speed_filter_s = num(d, "speed_filter_s"), c.washout_s = num(d, "washout_s"), c.g_dt = num(d, "g_dt");
    c.xi_max = num(d, "xi_max"), c.dt_s = num(d, "dt_s");
    c.dither_enabled = d["dither_enabled"].cast<bool>();
    c.dither_amplitude_rad = arr<kSurfaces>(d, "dither_amplitude_rad");
    c.dither_omega_rad_s = arr<kSurfaces>(d, "dither_omega_rad_s");
    c.dither_phase_rad = arr<kSurfaces>(d, "dither_phase_rad");
    if (d.contains("dither_gain")) c.dither_gain = dither_gain(arr<kSurfaces>(d, "dither_gain"));
    if (d.contains("dither_gain2")) {
      c.dither2_gain = dither_gain(arr<kSurfaces>(d, "dither_gain2"));
      c.dither2_amplitude_rad = arr<kSurfaces>(d, "dither2_amplitude_rad");
      c.dither2_omega_rad_s = arr<kSurfaces>(d, "dither2_omega_rad_s");
      c.dither2_phase_rad = arr<kSurfaces>(d, "dither2_phase_rad");
    }
    fcs_.c = c;
    fcs_.x_int = num(d, "x_int"), fcs_.x_wash = num(d, "x_wash"), fcs_.x_vel = num(d, "x_vel");
    has_fcs_ = true;
  }

  // The adaptive dither's gains per surface (truth/dither.py adaptive_gains): 5 finite values >= 0.
  static Surfaces dither_gain(const Surfaces& g) {
    for (double x : g)
      if (!(std::isfinite(x) && x >= 0.0))
        throw py::value_error("TruthFrames: a dither gain needs 5 finite values >= 0 (LS RS LF RF RUD)");
    return g;
  }
  static Surfaces dither_gain(const std::vector<double>& g) {
    if (g.size() != kSurfaces) throw py::value_error("TruthFrames: a dither gain needs 5 values (LS RS LF RF RUD)");
    Surfaces s{};
    std::copy(g.begin(), g.end(), s.begin());
    return dither_gain(s);
  }
  // A (Mach, altitude) table (AirDataTable) from its grid and rows (one per Mach, one value per
  // altitude); `what` names it in the refusals: 2 to 16 finite increasing points per axis, every
  // value positive and finite.
  static AirDataTable air_data_table(const std::vector<double>& mach, const std::vector<double>& alt_ft,
                                     const std::vector<std::vector<double>>& rows, const std::string& what) {
    const auto grid = [&](const std::vector<double>& g, const char* axis) {
      if (g.size() < 2 || g.size() > static_cast<std::size_t>(AirDataTable::kMaxGrid))
        throw py::value_error("TruthFrames: " + what + ": the " + axis + " grid needs 2 to " +
                              std::to_string(AirDataTable::kMaxGrid) + " points, got " + std::to_string(g.size()));
      for (std::size_t k = 0; k < g.size(); ++k)
        if (!std::isfinite(g[k]) || (k > 0 && !(g[k] > g[k - 1])))
          throw py::value_error("TruthFrames: " + what + ": the " + axis + " grid must be finite and increasing");
    };
    grid(mach, "Mach"), grid(alt_ft, "altitude");
    if (rows.size() != mach.size())
      throw py::value_error("TruthFrames: " + what + ": needs one row per Mach (" + std::to_string(mach.size()) +
                            "), got " + std::to_string(rows.size()));
    AirDataTable t;
    t.n_mach = static_cast<int>(mach.size()), t.n_alt = static_cast<int>(alt_ft.size());
    std::copy(mach.begin(), mach.end(), t.mach.begin());
    std::copy(alt_ft.begin(), alt_ft.end(), t.alt_ft.begin());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i].size() != alt_ft.size())
        throw py::value_error("TruthFrames: " + what + ": needs one value per altitude in every row");
      for (std::size_t j = 0; j < alt_ft.size(); ++j) {
        if (!(std::isfinite(rows[i][j]) && rows[i][j] > 0.0))
          throw py::value_error("TruthFrames: " + what + ": every value must be positive and finite");
        t.value[i * alt_ft.size() + j] = rows[i][j];
      }
    }
    return t;
  }

  // The adaptive dither's rule for one adapted bank, flown by fly_closed_loop (AdaptedDither):
  // the reference table on the grid (mach, alt_ft), rows Mach, the full ratio, and the rudder's
  // reference and gain bound.
  void set_adapted_dither(const std::vector<double>& mach, const std::vector<double>& alt_ft,
                          const std::vector<std::vector<double>>& reference, double full_ratio,
                          double rudder_reference, double rudder_bound) {
    if (!(std::isfinite(full_ratio) && full_ratio > 1.0))
      throw py::value_error("TruthFrames: the adapted dither's full ratio must be finite and > 1");
    if (!(std::isfinite(rudder_reference) && rudder_reference > 0.0))
      throw py::value_error("TruthFrames: the adapted dither's rudder reference must be positive and finite");
    if (!(std::isfinite(rudder_bound) && rudder_bound >= 1.0))
      throw py::value_error("TruthFrames: the adapted dither's rudder gain bound must be finite and >= 1");
    AdaptedDither a;
    a.on = true, a.full_ratio = full_ratio;
    a.rudder_reference = rudder_reference, a.rudder_bound = rudder_bound;
    a.reference = air_data_table(mach, alt_ft, reference, "the adapted dither's reference");
    adapted_ = a;
  }

  // g_j of the calm line, h_j of the turbulence line (set_fcs gave its terms).
  void set_dither_gain(const std::vector<double>& g, const std::vector<double>& h) {
    const Surfaces gs = dither_gain(g), hs = dither_gain(h);
    fcs_.c.dither_gain = gs;
    fcs_.c.dither2_gain = hs;
  }

  // The outer loop (truth/outer_loop.py OuterLoop.coefficients()) on the instruments
  // `instruments` (h, hdot, Mach, phi) and the throttle property: it flies with the control law.
  void set_outer_loop(const py::dict& d, const std::vector<std::string>& instruments, const std::string& throttle) {
    if (instruments.size() != 4) throw py::value_error("TruthFrames: the outer loop reads 4 instruments (h, hdot, M, phi)");
    OuterLoopCoefficients c;
    c.k_h = num(d, "k_h"), c.k_hd = num(d, "k_hd"), c.k_hi = num(d, "k_hi");
    c.nz_min_g = num(d, "nz_min_g"), c.nz_max_g = num(d, "nz_max_g");
    c.k_phi = num(d, "k_phi"), c.k_phi_i = num(d, "k_phi_i"), c.p_max_rad_s = num(d, "p_max_rad_s");
    c.k_m = num(d, "k_m"), c.k_mi = num(d, "k_mi"), c.dt_s = num(d, "dt_s"), c.throttle_0 = num(d, "throttle_0");
    c.h_ref = reference(d, "h_ref"), c.m_ref = reference(d, "m_ref"), c.phi_ref = reference(d, "phi_ref");
    outer_.c = c;
    outer_.x_h = num(d, "x_h"), outer_.x_m = num(d, "x_m"), outer_.x_phi = num(d, "x_phi");
    for (int i = 0; i < 4; ++i) instrument_[i] = exec_->node(instruments[i]);
    throttle_ = exec_->node(throttle);
    has_outer_ = true;
  }
  py::tuple outer_state() const { return py::make_tuple(outer_.x_h, outer_.x_m, outer_.x_phi); }

  void set_noise(py::array_t<double> noise) {
    if (noise.ndim() != 2 || noise.shape(1) != kSensors)
      throw py::value_error("TruthFrames: noise must be an (n, 7) array of standard normals");
    noise_ = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(noise);
    noise_rows_ = noise_.shape(0);
    noise_row_ = 0;
  }
  py::ssize_t noise_left() const { return noise_rows_ - noise_row_; }

  void set_air_data_noise(py::array_t<double> noise) {
    if (noise.ndim() != 2 || noise.shape(1) != kAirData)
      throw py::value_error("TruthFrames: air_data_noise must be an (n, 2) array of standard normals");
    air_noise_ = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(noise);
    air_noise_rows_ = air_noise_.shape(0);
    air_noise_row_ = 0;
  }
  py::ssize_t air_data_noise_left() const { return air_noise_rows_ - air_noise_row_; }
  const AirDataValues& air_data() const { return air_last_; }

  Sensors measure_frame() {
    const double t = static_cast<double>(frame_) / frame_rate_hz_;
    while (next_sen_ < sen_fail_.size() && sen_fail_[next_sen_].at <= frame_) {
      const auto& f = sen_fail_[next_sen_++];
      sen_.fail(f.index, static_cast<SensorMode>(f.mode), f.value, t);
    }
    if (noise_row_ >= noise_rows_) throw py::value_error("TruthFrames: noise exhausted (call set_noise)");
    if (air_noise_row_ >= air_noise_rows_)
      throw py::value_error("TruthFrames: air-data noise exhausted (call set_air_data_noise)");
    Sensors ideal;
    for (int i = 0; i < kSensors; ++i) ideal[i] = sensor_[i]->getDoubleValue();
    const double w = weight_->getDoubleValue();
    ideal[3] = -ideal[3] / w;
    ideal[6] = ideal[6] / w;
    const Sensors z = sen_.measure(ideal, noise_.data(noise_row_++, 0), t);
    AirDataValues air_ideal;
    for (int j = 0; j < kAirData; ++j) air_ideal[j] = air_node_[j]->getDoubleValue();
    air_last_ = air_.measure(air_ideal, air_noise_.data(air_noise_row_++, 0));
    if (frame_ % track_every_ == 0) track_.insert(track_.end(), {t, air_ideal[0], air_ideal[1]});
    ++measured_;
    if (!record_log_) return z;
    log_air_.insert(log_air_.end(), air_last_.begin(), air_last_.end());
    log_air_ideal_.insert(log_air_ideal_.end(), air_ideal.begin(), air_ideal.end());
    log_time_.push_back(t);
    log_z_.insert(log_z_.end(), z.begin(), z.end());
    log_ideal_.insert(log_ideal_.end(), ideal.begin(), ideal.end());
    for (auto* n : state_) log_state_.push_back(n->getDoubleValue());
    return z;
  }

  // The throttle dither written at the start of every frame (truth/model.py advance); with a
  // schedule dict {target_fps2, mach, alt_ft, accel_fps2 (rows mach)} its amplitude follows the
  // air data measured with the frame's z.
  void set_throttle_dither(const std::string& property, double trim, double amplitude, double omega_rad_s,
                           const py::object& schedule) {
    ThrottleDither d;
    d.trim = trim, d.amplitude = amplitude, d.omega_rad_s = omega_rad_s;
    if (!schedule.is_none()) {
      const py::dict s = schedule.cast<py::dict>();
      d.scheduled = true;
      d.target_fps2 = s["target_fps2"].cast<double>();
      d.thrust_accel_fps2 = air_data_table(s["mach"].cast<std::vector<double>>(), s["alt_ft"].cast<std::vector<double>>(),
                                           s["accel_fps2"].cast<std::vector<std::vector<double>>>(),
                                           "the throttle schedule's accel_fps2");
    }
    throttle_dither_node_ = exec_->node(property);
    throttle_dither_ = d;
    throttle_base_ = trim;
  }

  // The throttle command of the current frame (written by advance_frame; the sixth input of a
  // throttle bank): the dither's, on the air data measured with the frame's z, about the trim or,
  // in maneuvers, about the outer loop's throttle of this frame (so: after command()).
  double throttle_command() const {
    const bool measured = measured_ > 0;
    return throttle_dither_.command_about(throttle_base_, static_cast<double>(frame_) / frame_rate_hz_,
                                          measured ? air_last_[0] : std::nan(""),
                                          measured ? air_last_[1] : std::nan(""));
  }
  // The throttle the dither rides on from now on (a pilot flown outside these frames).
  void set_throttle_base(double base) { throttle_base_ = base; }
  // The throttle command the last advance_frame wrote (NaN without a throttle dither).
  double last_throttle() const { return last_throttle_; }

  void advance_frame(const Surfaces& u) { advance_frame(u, throttle_dither_node_ != nullptr ? throttle_command() : 0.0); }
  // The same with the frame's throttle command already computed (written with a throttle dither).
  void advance_frame(const Surfaces& u, double throttle) {
    if (throttle_dither_node_ != nullptr) {
      throttle_dither_node_->setDoubleValue(throttle);
      last_throttle_ = throttle;
    }
    Surfaces eff = u;
    for (int k = 0; k < steps_per_frame_; ++k) {
      while (next_act_ < act_fail_.size() && act_fail_[next_act_].at <= step_) {
        const auto& f = act_fail_[next_act_++];
        act_.fail(f.index, static_cast<ActuatorMode>(f.mode), f.value);
      }
      eff = act_.step(u);
      for (int i = 0; i < kSurfaces; ++i) surface_[i]->setDoubleValue(eff[i]);
      const bool ok = guarded([&] { return exec_->fdm().Run(); });
      if (!ok)
        throw std::runtime_error("JSBSim stopped at t = " + std::to_string(step_ / sim_rate_hz_) + " s");
      ++step_;
    }
    if (record_log_) {
      log_u_.insert(log_u_.end(), u.begin(), u.end());
      log_surface_.insert(log_surface_.end(), eff.begin(), eff.end());
    }
    ++frame_;
  }

  Surfaces command(const Sensors& zf) {
    if (!has_fcs_) throw py::value_error("TruthFrames: no flight control law (call set_fcs)");
    const double t = static_cast<double>(frame_) / frame_rate_hz_;
    if (!has_outer_) return fcs_.command(zf, t);
    double nz_cmd, p_cmd, throttle;
    outer_.command(t, instrument_[0]->getDoubleValue(), instrument_[1]->getDoubleValue(),
                   instrument_[2]->getDoubleValue(), instrument_[3]->getDoubleValue(), nz_cmd, p_cmd, throttle);
    throttle_->setDoubleValue(throttle);
    throttle_base_ = throttle;  // a throttle dither rides on it (advance_frame)
    return fcs_.command(zf, t, nz_cmd, p_cmd);
  }

  // n closed-loop frames with the estimator est in the loop (see the binding's docstring).
  // Bank: a fixed-size F-16 bank (hierarchical_access.h); with 6 inputs the sixth is the
  // throttle command.
  // recon (with use_mmae false): the "reconfigure" feedback, raw z with z_hat on the sensors
  // failed under the current hypothesis (sensor_reconfiguration.h); null: raw z.
  template <class Bank>
  py::dict fly_closed_loop(Bank& est, long long n, bool use_mmae, bool record,
                           const SensorReconfiguration* recon = nullptr) {
    using ZV = typename Bank::ZVector;
    using UV = typename Bank::UVector;
    using Ticks = TickClock::Ticks;
    constexpr py::ssize_t K = Bank::PVector::RowsAtCompileTime;
    constexpr int kInputs = UV::RowsAtCompileTime;
    static_assert(kInputs == kSurfaces || kInputs == kSurfaces + 1, "u: the surfaces, and the throttle");
    if (kInputs > kSurfaces && throttle_dither_node_ == nullptr)
      throw py::value_error("a bank with the throttle as its sixth input flies with the throttle dither set "
                            "(set_throttle_dither, amplitude 0 for the trim throttle)");
    if (adapted_.on && !est.bank().adaptation().enabled())
      throw py::value_error("the adapted dither reads the bank's turbulence adaptation: the bank has none "
                            "(--adapt-turbulence)");
    UV u_est = UV::Zero();
    py::array_t<double> probs({static_cast<py::ssize_t>(record ? n : 0), K});
    py::array_t<double> scale(static_cast<py::ssize_t>(record ? n : 0));
    py::array_t<int> dwell_in_force(static_cast<py::ssize_t>(record ? n : 0));
    double* row = probs.mutable_data();
    double* scale_row = scale.mutable_data();
    int* dwell_row = dwell_in_force.mutable_data();
    py::list events;
    Ticks truth_ticks = 0, est_ticks = 0;   // the frames' parts, in TickClock ticks (tick_clock.h)
    bool declared_last = false;
    TickClock clock;
    clock.start();
    const Ticks t0 = TickClock::now();
    Sensors z = measure_frame();
    truth_ticks += TickClock::now() - t0;
    for (long long i = 0; i < n; ++i) {
      const Ticks a = TickClock::now();
      est.schedule(AirData{air_last_[0], air_last_[1]});
      const int d = est.update(Eigen::Map<const ZV>(z.data()));
      if (adapted_.on) {   // the gains for u_i from the estimator's own rho-bar (loop/flight.py)
        const double rho = est.bank().adaptation().measured_power_ratio();
        const double h = adapted_.mix(rho, air_last_[0], air_last_[1]);
        fcs_.c.dither_gain[2] = fcs_.c.dither_gain[3] = 1.0 - h;
        fcs_.c.dither2_gain[2] = fcs_.c.dither2_gain[3] = h;
        fcs_.c.dither_gain[4] = adapted_.rudder_gain(rho);
      }
      Sensors zf = z;
      if (use_mmae) {
        const ZV zh = est.z_hat();
        for (int k = 0; k < kSensors; ++k) zf[k] = zh[k];
      } else if (recon) {
        const ZV zh = est.z_hat();
        recon->apply(est.current_hypothesis(), z.data(), zh.data(), zf.data());
      }
      const Ticks b = TickClock::now();
      const Surfaces u = command(zf);
      const Ticks c = TickClock::now();
      const double throttle = throttle_dither_node_ != nullptr ? throttle_command() : 0.0;  // once a frame
      for (int j = 0; j < kSurfaces; ++j) u_est[j] = u[j];
      if constexpr (kInputs > kSurfaces) u_est[kSurfaces] = throttle;
      est.propagate(u_est);
      const Ticks e = TickClock::now();
      advance_frame(u, throttle);
      if (i + 1 < n) z = measure_frame();
      const Ticks f = TickClock::now();
      est_ticks += (b - a) + (e - c);
      truth_ticks += (c - b) + (f - e);
      declared_last = d >= 0;
      if (declared_last) events.append(py::make_tuple(i, est.name(d), py::cast(est.online_names())));
      if (record) {
        const auto& p = est.probabilities();
        for (py::ssize_t k = 0; k < K; ++k) row[k] = p[k];
        row += K;
        *scale_row++ = est.turbulence_scale();
        *dwell_row++ = est.declarer().dwell_frames_in_force();
      }
    }
    clock.stop();
    const double truth_s = clock.seconds(truth_ticks), est_s = clock.seconds(est_ticks);
    py::dict out;
    out["probabilities"] = probs;
    out["turbulence_scale"] = scale;
    out["dwell_frames_in_force"] = dwell_in_force;
    out["events"] = events;
    out["truth_s"] = truth_s;
    out["estimator_s"] = est_s;
    out["declared_last_frame"] = declared_last;
    return out;
  }

  long long frame() const { return frame_; }
  long long step() const { return step_; }
  long long measured() const { return measured_; }
  bool records_log() const { return record_log_; }
  py::tuple fcs_state() const { return py::make_tuple(fcs_.x_int, fcs_.x_wash, fcs_.x_vel); }
  py::tuple actuator_positions() const { return py::cast(act_.position_rad); }

  // The track: (time s, Mach, pressure altitude ft) of the ideal air data, one row a second.
  py::array_t<double> track() const {
    py::array_t<double> a({static_cast<py::ssize_t>(track_.size() / kTrack), static_cast<py::ssize_t>(kTrack)});
    std::copy(track_.begin(), track_.end(), a.mutable_data());
    return a;
  }

  py::dict log() const {
    if (!record_log_) throw py::value_error("TruthFrames: these frames keep no log (built with record_log=False)");
    auto mat = [](const std::vector<double>& v, std::size_t cols) {
      const std::size_t rows = cols ? v.size() / cols : 0;
      py::array_t<double> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
      std::copy(v.begin(), v.end(), a.mutable_data());
      return a;
    };
    py::dict d;
    py::array_t<double> t(static_cast<py::ssize_t>(log_time_.size()));
    std::copy(log_time_.begin(), log_time_.end(), t.mutable_data());
    d["time_s"] = t;
    d["z"] = mat(log_z_, kSensors);
    d["z_ideal"] = mat(log_ideal_, kSensors);
    d["air_data"] = mat(log_air_, kAirData);
    d["air_data_ideal"] = mat(log_air_ideal_, kAirData);
    d["state"] = mat(log_state_, state_.size());
    d["u_cmd_rad"] = mat(log_u_, kSurfaces);
    d["surface_rad"] = mat(log_surface_, kSurfaces);
    return d;
  }

 private:
  std::shared_ptr<Exec> exec_;
  bool record_log_ = true;
  std::array<SGPropertyNode*, kSurfaces> surface_{};
  std::array<SGPropertyNode*, kSensors> sensor_{};
  SGPropertyNode* weight_ = nullptr;
  std::array<SGPropertyNode*, kAirData> air_node_{};
  AirDataSensor air_;
  AirDataValues air_last_{};
  AdaptedDither adapted_;
  py::array_t<double, py::array::c_style | py::array::forcecast> air_noise_;
  py::ssize_t air_noise_rows_ = 0, air_noise_row_ = 0;
  std::vector<SGPropertyNode*> state_;
  ActuatorBank act_;
  SensorSet sen_;
  FlightControlLaw fcs_;
  bool has_fcs_ = false;
  OuterLoopLaw outer_;
  bool has_outer_ = false;
  std::array<SGPropertyNode*, 4> instrument_{};
  SGPropertyNode* throttle_ = nullptr;
  SGPropertyNode* throttle_dither_node_ = nullptr;
  ThrottleDither throttle_dither_{};
  double throttle_base_ = 0.0;                                   // trim, or the outer loop's
  double last_throttle_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<ScheduledFailure> act_fail_, sen_fail_;
  std::size_t next_act_ = 0, next_sen_ = 0;
  py::array_t<double, py::array::c_style | py::array::forcecast> noise_;
  py::ssize_t noise_rows_ = 0, noise_row_ = 0;
  int steps_per_frame_;
  double frame_rate_hz_, sim_rate_hz_;
  long long frame_ = 0, step_ = 0, measured_ = 0;
  std::vector<double> log_time_, log_z_, log_ideal_, log_air_, log_air_ideal_, log_state_, log_u_, log_surface_;
  static constexpr std::size_t kTrack = 3;   // track row: time s, Mach, pressure altitude ft
  long long track_every_ = 1;                // frames a second
  std::vector<double> track_;
};

template <std::size_t N>
std::array<double, N> vec(py::handle obj, const char* what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 1 || a.shape(0) != static_cast<py::ssize_t>(N))
    throw py::value_error(std::string(what) + " needs " + std::to_string(N) + " values");
  std::array<double, N> out{};
  std::copy(a.data(), a.data() + N, out.begin());
  return out;
}

template <std::size_t N>
py::array_t<double> to_numpy(const std::array<double, N>& a) {
  py::array_t<double> out(static_cast<py::ssize_t>(N));
  std::copy(a.begin(), a.end(), out.mutable_data());
  return out;
}

}  // namespace

void bind_truth(py::module_& m) {
  py::class_<Frames>(m, "TruthFrames", R"doc(
    The truth model's frames in C++ (see truth/model.py, which builds it): measure() -> z (7,),
    advance(u), step(z_feedback) -> (u, z_next) = FCS command, advance, next measurement;
    fly(n) flies n frames on raw feedback then measures once more.  log() returns the record
    (record_log=False: none is kept, log() raises ValueError).)doc")
      .def(py::init<std::shared_ptr<Exec>, const std::vector<std::string>&, const std::vector<std::string>&,
                    const std::string&, const std::vector<std::string>&, const py::dict&, const py::dict&,
                    const py::list&, const py::list&, py::array_t<double>, const std::vector<std::string>&,
                    const py::dict&, py::array_t<double>, int, double, double, long long, bool>(),
           py::arg("exec"), py::arg("surface_properties"), py::arg("sensor_properties"),
           py::arg("weight_property"), py::arg("state_properties"), py::arg("actuator"), py::arg("sensor"),
           py::arg("actuator_failures"), py::arg("sensor_failures"), py::arg("noise"),
           py::arg("air_data_properties"), py::arg("air_data"), py::arg("air_data_noise"),
           py::arg("steps_per_frame"), py::arg("frame_rate_hz"), py::arg("sim_rate_hz"), py::arg("capacity"),
           py::arg("record_log") = true)
      .def("set_fcs", &Frames::set_fcs, py::arg("coefficients"))
      .def("set_dither_gain", &Frames::set_dither_gain, py::arg("gain"), py::arg("gain2"),
           "The adaptive dither's gains per surface, of the calm and of the turbulence line (5 values >= 0 each;\n"
           "truth/dither.py adaptive_gains), from the next frame on.")
      .def("set_outer_loop", &Frames::set_outer_loop, py::arg("coefficients"), py::arg("instruments"),
           py::arg("throttle_property"))
      .def_property_readonly("outer_state", &Frames::outer_state)
      .def("throttle_command", &Frames::throttle_command,
           "The throttle command of the current frame (the dither's, about the trim or, in maneuvers,\n"
           "about the outer loop's throttle of the frame; advance writes it).")
      .def("set_throttle_base", &Frames::set_throttle_base, py::arg("base"),
           "The throttle the dither rides on (a pilot flown in Python sets its command here).")
      .def_property_readonly("last_throttle", &Frames::last_throttle,
                             "The throttle command the last advance wrote (NaN without a throttle dither).")
      .def("set_throttle_dither", &Frames::set_throttle_dither, py::arg("property"), py::arg("trim"),
           py::arg("amplitude"), py::arg("omega_rad_s"), py::arg("schedule") = py::none(),
           "Write trim + amplitude sin(omega_rad_s t) to the throttle property before each frame; with\n"
           "schedule {target_fps2, mach, alt_ft, accel_fps2}, amplitude = target_fps2 / the table bilinear\n"
           "at the air data measured with the frame's z (truth/dither.py).")
      .def("set_noise", &Frames::set_noise, py::arg("noise"))
      .def_property_readonly("noise_left", &Frames::noise_left)
      .def("set_air_data_noise", &Frames::set_air_data_noise, py::arg("noise"))
      .def_property_readonly("air_data_noise_left", &Frames::air_data_noise_left)
      .def_property_readonly("air_data", [](const Frames& f) { return to_numpy(f.air_data()); },
                             "(Mach, pressure altitude ft) as measured at the last measure()")
      .def("measure", [](Frames& f) { return to_numpy(f.measure_frame()); })
      .def("advance", [](Frames& f, py::handle u) { f.advance_frame(vec<kSurfaces>(u, "u")); }, py::arg("u"))
      .def("command", [](Frames& f, py::handle z) { return to_numpy(f.command(vec<kSensors>(z, "z_feedback"))); },
           py::arg("z_feedback"))
      .def("step", [](Frames& f, py::handle z, bool measure_next) {
             const Surfaces u = f.command(vec<kSensors>(z, "z_feedback"));
             f.advance_frame(u);
             return py::make_tuple(to_numpy(u), measure_next ? py::object(to_numpy(f.measure_frame())) : py::none());
           }, py::arg("z_feedback"), py::arg("measure_next") = true)
      .def("fly", [](Frames& f, long long n) {
             for (long long i = 0; i < n; ++i) f.advance_frame(f.command(f.measure_frame()));
             f.measure_frame();
           }, py::arg("n_frames"))
      .def("fly_closed_loop", [](Frames& f, py::handle bank, long long n, bool use_mmae, bool record,
                                 const SensorReconfiguration* recon) {
             if (use_mmae && recon)
               throw py::value_error("fly_closed_loop: use_mmae feeds back z_hat on every channel; a reconfiguration "
                                     "applies only with use_mmae=False");
             if (recon && recon->nz() != kSensors)
               throw py::value_error("fly_closed_loop: the reconfiguration has " + std::to_string(recon->nz()) +
                                     " sensors, the truth model " + std::to_string(kSensors));
             return std::visit(
                 [&](auto est) -> py::dict {
                   if constexpr (std::is_same_v<decltype(est), std::monostate>)
                     throw py::value_error("fly_closed_loop flies a fixed-size F-16 bank only (13 or 19 states, "
                                           "5 or 6 inputs)");
                   else {
                     if (recon && recon->hypothesis_count() != est->hypothesis_count())
                       throw py::value_error("fly_closed_loop: the reconfiguration was built from another bank (" +
                                             std::to_string(recon->hypothesis_count()) + " hypotheses, the bank " +
                                             std::to_string(est->hypothesis_count()) + ")");
                     return f.fly_closed_loop(*est, n, use_mmae, record, recon);
                   }
                 },
                 fixed_hierarchical_bank(bank));
           }, py::arg("bank"), py::arg("n_frames"), py::arg("use_mmae"), py::arg("record_probabilities"),
           py::arg("reconfiguration") = nullptr,
           R"doc(
    n closed-loop frames with a core.HierarchicalBank in the loop, all in C++ (loop/flight.py
    describes the frame): z = measure(); then per frame: bank.schedule(the air data measured with
    z), bank.update(z), u = FCS(z_hat if use_mmae, else reconfiguration.apply(current hypothesis,
    z, z_hat) if a core.SensorReconfiguration is given, else z), bank.propagate(u), advance(u),
    the next z (not after the last frame).
    Returns {'probabilities': (n, 13) the probabilities on line after each frame (or (0, 13)),
    'turbulence_scale': (n,) the bank's turbulence_scale after each frame (or (0,)),
    'dwell_frames_in_force': (n,) its dwell_frames_in_force after each frame (or (0,)),
    'events': [(frame, declared name, names on line after it)], 'truth_s', 'estimator_s'
    (seconds spent in each), 'declared_last_frame'}.)doc")
      .def("set_adapted_dither", &Frames::set_adapted_dither, py::arg("mach"), py::arg("alt_ft"),
           py::arg("reference"), py::arg("full_ratio"), py::arg("rudder_reference"), py::arg("rudder_bound"),
           "fly_closed_loop flies the adaptive dither of one adapted bank (truth/dither.py "
           "adapted_dither_reference, adaptive_rudder_gain): the reference table on the grid (rows Mach), "
           "the full ratio, the rudder's reference rho_r and its gain bound (Dither.rudder_gain_bound)")
      .def_property_readonly("frame", &Frames::frame)
      .def_property_readonly("step_count", &Frames::step)
      .def_property_readonly("measured", &Frames::measured)
      .def_property_readonly("track", &Frames::track,
                             "(n, 3): time s, Mach and pressure altitude ft of the ideal air data at every whole "
                             "second measured (kept with or without the log)")
      .def_property_readonly("records_log", &Frames::records_log)
      .def_property_readonly("fcs_state", &Frames::fcs_state)
      .def_property_readonly("actuator_positions", &Frames::actuator_positions)
      .def("log", &Frames::log);
}

}  // namespace f16mmae::bindings
