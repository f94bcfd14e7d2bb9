// f16mmae.core.HierarchicalBank: the hierarchical MMAE of paper Fig. 2
// (cpp/f16mmae/hierarchical_bank.h) built from a core.ModelBank. An F-16 bank (5 inputs,
// 7 measurements, 12 single failures) of 13 states runs in the fixed-size
// F16HierarchicalBank, of 19 states (the six Dryden gust states) in F16GustHierarchicalBank,
// of 13 states and 6 inputs (the throttle command last) in F16ThrottleHierarchicalBank, of 19
// states and 6 inputs in F16GustThrottleHierarchicalBank:
// the bank's nx and nu select it; any other bank runs in the dynamic one. Signals are ABSOLUTE here: the bank subtracts its own u_trim / z_trim and
// z_hat comes back absolute.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core_convert.h"
#include "estimator_init.h"
#include "hierarchical_access.h"
#include "tick_clock.h"
#include "f16mmae/cache_warm.h"
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/model_bank.h"

namespace py = pybind11;

namespace f16mmae::bindings {
namespace {

namespace cv = convert;

class PyHierarchicalBank {
 public:
  // options: estimator_init.h (the keyword arguments, shared with core.Executive)
  PyHierarchicalBank(const ModelBank& bank, const HierarchicalOptions& o) {
    int singles = 0;
    for (std::size_t i = 1; i < bank.hypotheses.size(); ++i)
      singles += bank.hypotheses[i].name.find('+') == std::string::npos ? 1 : 0;
    if (fits<F16HierarchicalBank>(bank, singles))
      bank_ = std::make_unique<F16HierarchicalBank>(bank, o);
    else if (fits<F16GustHierarchicalBank>(bank, singles))
      bank_ = std::make_unique<F16GustHierarchicalBank>(bank, o);
    else if (fits<F16ThrottleHierarchicalBank>(bank, singles))
      bank_ = std::make_unique<F16ThrottleHierarchicalBank>(bank, o);
    else if (fits<F16GustThrottleHierarchicalBank>(bank, singles))
      bank_ = std::make_unique<F16GustThrottleHierarchicalBank>(bank, o);
    else
      bank_ = std::make_unique<DynamicHierarchicalBank>(bank, o);
    nu_ = bank.nu();
    nz_ = bank.nz();
  }

  template <class F>
  decltype(auto) visit(F&& f) {
    return std::visit([&](auto& p) -> decltype(auto) { return f(*p); }, bank_);
  }
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(
        [&](const auto& p) -> decltype(auto) {
          return f(static_cast<const typename std::decay_t<decltype(p)>::element_type&>(*p));
        },
        bank_);
  }

  py::object update(py::handle z) {
    return visit([&](auto& b) -> py::object {
      const int d = b.update(cv::to_vector<typename std::decay_t<decltype(b)>::ZVector>(z, nz_, "z"));
      return d < 0 ? py::object(py::none()) : py::object(py::str(b.name(d)));
    });
  }
  void schedule(double mach, double pressure_altitude_ft) {
    visit([&](auto& b) { b.schedule(AirData{mach, pressure_altitude_ft}); });
  }
  void set_trim_offset(py::handle du, py::handle dz) {
    visit([&](auto& b) {
      using B = std::decay_t<decltype(b)>;
      b.set_trim_offset(cv::to_vector<typename B::UVector>(du, nu_, "du"),
                        cv::to_vector<typename B::ZVector>(dz, nz_, "dz"));
    });
  }
  py::object schedule_state() const {
    return visit([](const auto& b) -> py::object {
      const auto& s = b.scheduled();
      if (!s.active()) return py::none();
      py::dict d;
      d["mode"] = s.options().mode == ScheduleMode::kNearest ? "nearest" : "interpolate";
      py::list nodes, weights;
      for (int c = 0; c < 4; ++c) {
        if (s.weights()[c] == 0.0) continue;
        const auto& n = s.axes().nodes[s.corners()[c]];
        nodes.append(py::make_tuple(s.axes().mach[n.i_mach], s.axes().alt_ft[n.i_alt]));
        weights.append(s.weights()[c]);
      }
      d["nodes"] = nodes;
      d["weights"] = weights;
      d["switches"] = s.switches();
      d["blends"] = s.blends();
      d["outside_frames"] = s.outside_frames();
      d["fallback_frames"] = s.fallback_frames();
      d["x_trim"] = cv::to_numpy(s.x_trim());
      d["layer"] = s.layer();
      d["air_data"] = py::make_tuple(s.filtered_air_data().mach, s.filtered_air_data().pressure_altitude_ft);
      return d;
    });
  }
  void propagate(py::handle u) {
    visit([&](auto& b) { b.propagate(cv::to_vector<typename std::decay_t<decltype(b)>::UVector>(u, nu_, "u")); });
  }
  py::object step(py::handle z, py::handle u) {
    py::array_t<double> keep_u;
    cv::vector_data(u, nu_, "u", keep_u);  // check u before the frame is applied
    py::object d = update(z);
    propagate(u);
    return d;
  }
  py::list declarations() const {
    return visit([](auto& b) {
      py::list out;
      for (const auto& d : b.declarations()) {
        py::dict e;
        e["hypothesis"] = b.name(d.hypothesis);
        e["level"] = d.level;
        e["frame"] = d.frame;
        e["time_s"] = d.time_s;
        out.append(e);
      }
      return out;
    });
  }
  bool fixed() const { return !std::holds_alternative<std::unique_ptr<DynamicHierarchicalBank>>(bank_); }
  FixedHierarchicalBank fixed_bank() {
    if (auto* p = std::get_if<std::unique_ptr<F16HierarchicalBank>>(&bank_)) return p->get();
    if (auto* p = std::get_if<std::unique_ptr<F16GustHierarchicalBank>>(&bank_)) return p->get();
    if (auto* p = std::get_if<std::unique_ptr<F16ThrottleHierarchicalBank>>(&bank_)) return p->get();
    if (auto* p = std::get_if<std::unique_ptr<F16GustThrottleHierarchicalBank>>(&bank_)) return p->get();
    return std::monostate{};
  }

 private:
  // The fixed-size instantiation whose sizes the bank has (K = 1 + singles, NX, NU, NZ).
  template <class B>
  static bool fits(const ModelBank& bank, int singles) {
    return bank.nx() == B::XVector::RowsAtCompileTime && bank.nu() == B::UVector::RowsAtCompileTime &&
           bank.nz() == B::ZVector::RowsAtCompileTime && singles + 1 == B::PVector::RowsAtCompileTime;
  }

  std::variant<std::unique_ptr<F16HierarchicalBank>, std::unique_ptr<F16GustHierarchicalBank>,
               std::unique_ptr<F16ThrottleHierarchicalBank>, std::unique_ptr<F16GustThrottleHierarchicalBank>,
               std::unique_ptr<DynamicHierarchicalBank>>
      bank_;
  int nu_ = 0, nz_ = 0;
};

template <class F>
auto prop(F f) {
  return [f](const PyHierarchicalBank& b) { return b.visit(f); };
}

}  // namespace

// Benchmark (f16mmae.bench): the fixed-size F-16 bank of the model bank's nx and nu
// (F16HierarchicalBank, F16GustHierarchicalBank for 19 states, F16ThrottleHierarchicalBank for
// 6 inputs) over frames z (N,7), u (N,nu)
// and, if given, air data (N,2) handed to schedule() before each frame; the frames replayed
// from reset() pass after pass for at least min_time_s and 3 passes, timed in C++. Returns
// (seconds per frame of the fastest pass, slowest single frame of the last pass in seconds).
// evict_bytes > 0: a cold cache before every frame, as in a closed loop where the truth model
// runs between two frames: a buffer of evict_bytes is read line by line (untimed) before each
// frame, which evicts the bank from the caches smaller than the buffer, and each frame is
// timed alone (TickClock ticks: a few ns a read); a pass's figure is then its median frame, as
// a frame the scheduler preempted (milliseconds) would otherwise weigh on the pass's mean.
template <class Bank>
py::tuple bench_fixed_loop(const ModelBank& bank, py::handle z_frames, py::handle u_frames, py::handle air,
                           double min_time_s, HierarchicalOptions o, long long evict_bytes) {
  o.bank.p_min = bank.estimator.p_min;
  o.declarer.threshold = bank.estimator.threshold;
  o.declarer.dwell_s = bank.estimator.dwell_s;
  const auto hb = std::make_unique<Bank>(bank, o);
  const Eigen::MatrixXd z = cv::to_matrix(z_frames, -1, 7, "z", "(N, 7)");
  const Eigen::Index n = z.rows();
  constexpr int nu = Bank::UVector::RowsAtCompileTime;
  const Eigen::MatrixXd u = cv::to_matrix(u_frames, n, nu, "u",
                                          "(N, " + std::to_string(nu) + ") with N the frames of z");
  const bool scheduled = !air.is_none();
  const Eigen::MatrixXd a =
      scheduled ? cv::to_matrix(air, n, 2, "air_data", "(N, 2) with N the frames of z") : Eigen::MatrixXd();
  if (n == 0) throw py::value_error("the benchmark needs at least one frame");
  if (evict_bytes < 0) throw py::value_error("evict_bytes must be >= 0, got " + std::to_string(evict_bytes));
  std::vector<typename Bank::ZVector> zs(n);
  std::vector<typename Bank::UVector> us(n);
  std::vector<AirData> as(scheduled ? n : 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    zs[i] = z.row(i).transpose();
    us[i] = u.row(i).transpose();
    if (scheduled) as[i] = AirData{a(i, 0), a(i, 1)};
  }
  std::vector<unsigned char> evict(static_cast<std::size_t>(evict_bytes), 1);
  std::vector<TickClock::Ticks> frame_ticks(evict.empty() ? 0 : n);
  const auto frame = [&](Eigen::Index i) {
    if (scheduled) hb->schedule(as[i]);
    hb->step(zs[i], us[i]);
  };
  using Clock = std::chrono::steady_clock;
  double best_s = std::numeric_limits<double>::infinity(), worst_frame_s = 0.0;
  {
    py::gil_scoped_release release;
    const Clock::time_point start = Clock::now();
    for (int pass = 0; pass < 3 || std::chrono::duration<double>(Clock::now() - start).count() < min_time_s; ++pass) {
      hb->reset();
      if (evict.empty()) {
        const Clock::time_point t0 = Clock::now();
        for (Eigen::Index i = 0; i < n; ++i) frame(i);
        best_s = std::min(best_s, std::chrono::duration<double>(Clock::now() - t0).count());
      } else {
        TickClock clock;
        clock.start();
        for (Eigen::Index i = 0; i < n; ++i) {
          touch_lines(evict.data(), evict.size());
          const TickClock::Ticks t0 = TickClock::now();
          frame(i);
          frame_ticks[i] = TickClock::now() - t0;
        }
        clock.stop();
        std::nth_element(frame_ticks.begin(), frame_ticks.begin() + n / 2, frame_ticks.end());
        best_s = std::min(best_s, clock.seconds(frame_ticks[n / 2]) * static_cast<double>(n));
      }
    }
    hb->reset();
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!evict.empty()) touch_lines(evict.data(), evict.size());
      const Clock::time_point t0 = Clock::now();
      frame(i);
      worst_frame_s = std::max(worst_frame_s, std::chrono::duration<double>(Clock::now() - t0).count());
    }
  }  // the GIL is held again: Python objects may be made
  return py::make_tuple(best_s / static_cast<double>(n), worst_frame_s);
}

py::tuple bench_hierarchical_loop(const ModelBank& bank, py::handle z_frames, py::handle u_frames, py::handle air,
                                  double min_time_s, long long evict_bytes, const py::kwargs& estimator) {
  const HierarchicalOptions o = estimator_options(estimator);   // core.HierarchicalBank's keywords
  int level0 = 0;   // NONE and the hypotheses without '+': the singles and any partial ones
  for (const auto& h : bank.hypotheses) level0 += h.name.find('+') == std::string::npos ? 1 : 0;
  if (level0 == 18 && bank.nx() == 13 && bank.nu() == 5)   // a partial hypothesis per surface
    return bench_fixed_loop<F16PartialHierarchicalBank>(bank, z_frames, u_frames, air, min_time_s, o, evict_bytes);
  if (bank.nx() == F16GustHierarchicalBank::XVector::RowsAtCompileTime)
    return bench_fixed_loop<F16GustHierarchicalBank>(bank, z_frames, u_frames, air, min_time_s, o, evict_bytes);
  if (bank.nu() == F16ThrottleHierarchicalBank::UVector::RowsAtCompileTime)
    return bench_fixed_loop<F16ThrottleHierarchicalBank>(bank, z_frames, u_frames, air, min_time_s, o, evict_bytes);
  return bench_fixed_loop<F16HierarchicalBank>(bank, z_frames, u_frames, air, min_time_s, o, evict_bytes);
}

FixedHierarchicalBank fixed_hierarchical_bank(py::handle hierarchical_bank) {
  return hierarchical_bank.cast<PyHierarchicalBank&>().fixed_bank();
}

// The climb and acceleration sensitivities (maneuver_trim.h) of every node of a model bank
// (one for a bank of one design): a list of dicts mach, alt_ft, x (nx,2), u (nu,2), z (nz,2),
// thrust (2,).
py::list maneuver_trim_sensitivities(const ModelBank& mb) {
  const auto& m = mb.measurement_names;
  const auto vel = std::find(m.begin(), m.end(), "VEL"), aoa = std::find(m.begin(), m.end(), "AOA");
  if (vel == m.end() || aoa == m.end()) throw py::value_error("maneuver trim: the bank has no VEL or AOA measurement");
  py::list out;
  auto add = [&](const ModelBank& node, double mach, double alt_ft) {
    const HypothesisModel& h = node.hypotheses.at(0);
    const TrimSensitivity s = trim_sensitivity(h.phi, h.bd, h.h, mb.state_names, mb.input_names, mb.frame_rate_hz,
                                               node.z_trim(vel - m.begin()), node.z_trim(aoa - m.begin()));
    py::dict d;
    d["mach"] = mach;
    d["alt_ft"] = alt_ft;
    d["x"] = cv::to_numpy(Eigen::MatrixXd(s.x));
    d["u"] = cv::to_numpy(Eigen::MatrixXd(s.u));
    d["z"] = cv::to_numpy(Eigen::MatrixXd(s.z));
    d["thrust"] = py::make_tuple(s.thrust(0), s.thrust(1));
    out.append(d);
  };
  if (mb.schedule)
    for (const ScheduleNode& n : mb.schedule->nodes)
      add(n.bank, mb.schedule->mach[n.i_mach], mb.schedule->alt_ft[n.i_alt]);
  else
    add(mb, mb.mach, mb.alt_ft);
  return out;
}

void bind_hierarchical(py::module_& m) {
  m.def("parse_calm_complete", &parse_calm_complete, py::arg("text"),
        "The calm-air bounds of 'NAME=RHO[,NAME=RHO...]', {measurement: rho} (cpp/f16mmae/\n"
        "calm_air_complete.h; rho in [0, 100], 0: off). ValueError naming the entry.");
  m.def("maneuver_trim_sensitivities", &maneuver_trim_sensitivities, py::arg("model_bank"),
        "Per node of the bank (one for a bank of one design) a dict: mach, alt_ft and the climb and\n"
        "acceleration sensitivities of its NONE filter's trim, d(x, u, z)/d(gamma rad, dV/dt ft/s^2) as\n"
        "x (nx,2), u (nu,2), z (nz,2), and the thrust acceleration of that equilibrium, thrust (2,)\n"
        "(cpp/f16mmae/maneuver_trim.h).");
  m.def("_bench_hierarchical_loop", &bench_hierarchical_loop, py::arg("bank"), py::arg("z"), py::arg("u"),
        py::arg("air_data") = py::none(), py::arg("min_time_s") = 0.2, py::arg("evict_bytes") = 0,
        "Benchmark: (seconds per frame, slowest frame in seconds) of the fixed-size C++ F-16 bank of the\n"
        "model bank's nx and nu (13 states, 19 with gust states; 5 inputs, 6 with the throttle; 18 filters\n"
        "on line with a partial hypothesis per surface)\n"
        "over frames z (N,7), u (N,nu), with schedule(air_data[i]) before each frame when air_data (N,2) is\n"
        "given, timed in C++ (f16mmae.bench); any other keyword is core.HierarchicalBank's (the bank's own\n"
        "p_min, threshold and dwell_s stand);\n"
        "evict_bytes > 0: a buffer of that size read before every frame (a cold cache; frames timed alone,\n"
        "the median frame of a pass counts).");
  m.def("estimator_defaults", &estimator_defaults,
        "Every keyword of core.HierarchicalBank (and core.Executive, core.TurbulenceBankSet) with the core's\n"
        "default when it is left out, {name: default} (bindings/estimator_init.h).");
  py::class_<PyHierarchicalBank> cls(m, "HierarchicalBank", R"doc(
The hierarchical MMAE of paper Fig. 2 over a core.ModelBank.

    HierarchicalBank(model_bank, p_min=0.001, node_p_min=True, strip_leading_term=True, threshold=0.9,
                     dwell_s=0.25, declarer=None, trim_time_constant_s=0.0,
                     trim_freeze_probability=0.05, trim_hold_s=2.0, trim_freeze=True,
                     trim_steady_g=0.0, trim_steady_measurements=['AOA'], trim_steady_roll_rate_rad_s=0.0873,
                     trim_steady_climb_ft_s=5.0,
                     trim_steady_mach_per_s=0.001,
                     schedule_mode="interpolate", hysteresis_cells=..., blend_step_cells=...,
                     air_data_time_constant_s=..., cubic_trims=...,
                     adapt_turbulence=False, adapt_time_constant_s=5.0, adapt_scale_min=1.0,
                     adapt_scale_max=100.0, adapt_gain=20.0, adapt_reference=None,
                     maneuver_kinematics=False, actuator_rate_limits_rad_s=[],
                     actuator_position_limits_rad=[])

Level 0: NONE and every single failure on line, NONE presumed. When single failure f is
declared (p_f > threshold for dwell_s), the level-1 bank {NONE, f, f+c for every other c}
is brought on line from storage; if NONE is then declared the bank backs out to level 0; a
dual declared at level 1 is the final answer (the bank stays at level 1). At a switch every
new filter starts from the declared filter's posterior state and the declared hypothesis is
presumed. Hypotheses are found by name in the model bank. declarer (a core.Declarer), if
given, supplies threshold and dwell_s; the frame rate is the model bank's.

adapt_turbulence: scale every filter's residual covariance by one on-line estimate s of the
residual power against the design's (cpp/f16mmae/turbulence_adaptation.h; rho = the average
over adapt_time_constant_s of min_k q_k / nz, s = clamp(1 + adapt_gain (rho - adapt_reference),
adapt_scale_min, adapt_scale_max)); the likelihoods become -q_k/(2 s). Off: exactly the bank as
designed. adapt_reference None: a scheduled bank whose nodes carry their own reference uses
those (blended with the filters), any other bank 0.6; a number: that reference everywhere. turbulence_scale reads s, turbulence_power_ratio rho. adapt_channel_weight g in (0, 1]: a scale per
measurement channel, s_j = s^(1-g) s'_j^g with s'_j from the best-fitting filter's share of channel j
in its quadratic form, the likelihoods -(D r_k)' A_k^-1 (D r_k) / 2 with D = diag(s_j^-1/2)
(turbulence_channel_scales reads the s_j); 0, the default: the common s. adapt_own_channels: each
filter's quadratic form counts per channel it reads, rho from min_k q_k / m_k (m_k: the channels
filter k reads; a failed sensor's uninformative channel is not one), so that a hypothesis with an
uninformative channel does not read the air calmer than it is; a bank without one is unchanged.
adapt_counted_channels (with adapt_own_channels): a bit per measurement channel j (1 << j, z's order);
an uninformative channel whose bit is set still counts in m_k (0, the default: none does).
adapt_excluded_channels: a bit per measurement channel j (1 << j, z's order); a hypothesis that reads
a set channel as a free level (uninformative there) while the presumed one does not leaves the
adaptation's minimum (it still gets the scale; 0, the default: none leaves it).
adapt_level_scale_channels: a bit per measurement channel j; with the common scale, every hypothesis
that reads a set channel as a free level gains (1/2) ln max(s / s_0, 1) a frame at every level,
s_0 = adapt_level_scale_from (>= 1; 1, the default: (1/2) ln s); adapt_level_scale adds (1/2) ln s
on the presumed failure's own level channels only (cpp/f16mmae/filter_bank.h; 0, the default: none).

calm_complete_rho ({measurement: rho}, with adapt_turbulence; empty, the default, or rho 0: off): while
the adaptation's measured power ratio is below rho times the calm-air reference in force (a scheduled
bank whose nodes carry one, else 1; decided while no failure is presumed or rising),
the hypotheses that read that measurement as a tracked level read it with the paper's complete
model, the trim plus its noise (cpp/f16mmae/calm_air_complete.h); calm_complete_channels reads the
channels in force (a bit per measurement).
calm_measure ('power', the default, 'whiteness' or 'either'; with calm_complete_rho): the air read by
the power ratio (above), by how white the presumed filter's residuals are on VEL, AOA, AZ, AY and ROL
(W-bar, about 1 in the design's gusts, below it in calm air; cpp/f16mmae/residual_whiteness.h) against
calm_whiteness_bound (default 0.78) for every bounded measurement, or calm by either.
complete_trim_hold ('off', the default, 'suspected' or 'declared'): a complete failure's channel (a failed
sensor's H row zero, not read as a level) is read against the trim in force when a failure began to show,
held while one is suspected (declared, or a failure hypothesis rising) or only while one is declared, not
against the trim the schedule and the trim tracker move (cpp/f16mmae/complete_trim_hold.h);
complete_trim_offset reads the held offset.
complete_trim_time_constant_s (0, the default, or T in (0, 3600] s): the reference the trim in force
averaged over T seconds while nothing is held (the flight condition's trim, not the gusts' wander).

node_p_min (a scheduled bank): the probability floor is each node's bank's p_min, blended
geometrically with the filters (cpp/f16mmae/scheduled_filters.h); False: p_min everywhere.
p_min_in_force reads the floor in force.

maneuver_kinematics: add to every filter's propagation the rigid-body kinematic and gravity
terms its wings-level linearization drops (second order; zero in wings-level flight about the
trim), evaluated on the blended state (cpp/f16mmae/maneuver_kinematics.h), so a steady turn or
pull-up is not read as a failure. Off: exactly the bank as designed.

actuator_rate_limits_rad_s, actuator_position_limits_rad (nu values each; empty: off): the
filters see the commands through a copy of the actuators with these limits
(cpp/f16mmae/actuator_limits.h): the command that makes their linear lag follow the limited
actuator, equal to u inside the limits.

SIGNALS ARE ABSOLUTE: update(z (nz,)) subtracts the trim in force, model_bank.z_trim + dz,
propagate(u (nu,)) model_bank.u_trim + du, and z_hat is absolute (z_hat_perturbation is not).
The trim offset (du, dz) is zero unless set_trim_offset sets it or trim tracking
(trim_time_constant_s > 0; cpp/f16mmae/trim_tracker.h) estimates it: a low-pass of u and z
about the trim with that time constant, frozen while a failure hypothesis is above
trim_freeze_probability (and trim_hold_s after), at level 1 or with a failure declared
(trim_freeze=False: never frozen, for comparison only); trim_steady_g > 0: tracked only while
the estimated load factor is within trim_steady_g g of the trim, and of the measurements only
trim_steady_measurements (default ['AOA']), and frozen while the estimated roll rate exceeds
trim_steady_roll_rate_rad_s or the air data handed to schedule climb
faster than trim_steady_climb_ft_s or change Mach faster than trim_steady_mach_per_s. A frame with
a non-finite value is rejected and counted in rejected_frames. Raises ValueError for an invalid
model bank or a missing dual hypothesis.

A SCHEDULED model bank (model_bank.schedule, cpp/f16mmae/scheduled_filters.h) follows the air
data given to schedule(mach, pressure_altitude_ft), low-passed with air_data_time_constant_s: schedule_mode 'interpolate' (bilinear on the
grid cell; matrices re-blended when the air data moved blend_step_cells; trims to third order on
the 4 x 4 nodes around when cubic_trims and covered) or 'nearest' (nearest
node, switched past hysteresis_cells); the states move with the trim state, probabilities,
declarations and the level carry over. schedule_state reports what is in force.)doc");
  def_estimator_init<PyHierarchicalBank>(cls)
      .def("update", &PyHierarchicalBank::update, py::arg("z"),
           "Update with absolute z (nz,); returns the name declared on this frame, or None.")
      .def("propagate", &PyHierarchicalBank::propagate, py::arg("u"), "Propagate with absolute u (nu,).")
      .def("step", &PyHierarchicalBank::step, py::arg("z"), py::arg("u"),
           "update(z) then propagate(u); returns update's result.")
      .def("reset", [](PyHierarchicalBank& b) { b.visit([](auto& x) { x.reset(); }); },
           "Back to level 0, NONE presumed, states zero, history and counters cleared.")
      .def_property_readonly("level", prop([](auto& b) { return b.level(); }), "0 (singles) or 1 (a failure's duals)")
      .def_property_readonly("hypotheses", prop([](auto& b) {
                               py::tuple t(b.size());
                               for (int k = 0; k < b.size(); ++k) t[k] = py::str(b.name(b.online()[k]));
                               return t;
                             }),
                             "names of the hypotheses on line, in the order of probabilities")
      .def_property_readonly("declared", prop([](auto& b) { return b.name(b.current_hypothesis()); }),
                             "the current hypothesis: NONE until a failure is declared, then the last declared")
      .def_property_readonly("level1_failure", prop([](auto& b) -> py::object {
                               const int f = b.level1_failure();
                               return f < 0 ? py::object(py::none()) : py::object(py::str(b.name(f)));
                             }),
                             "the single failure whose level-1 bank is on line, None at level 0")
      .def_property_readonly("declarations", &PyHierarchicalBank::declarations,
                             "list of {'hypothesis', 'level', 'frame', 'time_s'} (time_s = frame / frame rate)")
      .def_property_readonly("probabilities", prop([](auto& b) { return cv::to_numpy(b.probabilities()); }),
                             "(K,) probabilities of the hypotheses on line")
      .def_property_readonly("z_hat", prop([](auto& b) { return cv::to_numpy(b.z_hat()); }),
                             "(nz,) ABSOLUTE measurement estimate h_output @ blended_state + z_trim")
      .def_property_readonly("z_hat_perturbation", prop([](auto& b) { return cv::to_numpy(b.z_hat_perturbation()); }),
                             "(nz,) h_output @ blended_state")
      .def_property_readonly("blended_state", prop([](auto& b) { return cv::to_numpy(b.blended_state()); }),
                             "(nx,) probability-weighted state (perturbation from trim)")
      .def_property_readonly("residuals", prop([](auto& b) { return cv::to_numpy(b.bank().residuals()); }),
                             "(K, nz) residuals of the filters on line at the last update")
      .def_property_readonly("state_estimates", prop([](auto& b) { return cv::to_numpy(b.bank().state_estimates()); }),
                             "(K, nx) posterior states of the filters on line")
      .def_property_readonly("turbulence_scale", prop([](auto& b) { return b.turbulence_scale(); }),
                             "the turbulence adaptation's likelihood scale s in force (1.0 when off)")
      .def_property_readonly("adapt_turbulence", prop([](auto& b) { return b.options().bank.adaptation.enabled; }))
      .def_property_readonly("maneuver_kinematics", prop([](auto& b) { return b.options().maneuver.kinematics; }))
      .def_property_readonly("actuator_limits", prop([](auto& b) { return b.options().actuators.enabled(); }))
      .def_property_readonly("turbulence_power_ratio", prop([](auto& b) { return b.bank().adaptation().power_ratio(); }),
                             "the adaptation's averaged residual power ratio rho (1.0 when off)")
      .def_property_readonly("measured_power_ratio",
                             prop([](auto& b) { return b.bank().adaptation().measured_power_ratio(); }),
                             "the adaptation's measured rho-bar (0.0 before the first update; the calm-air "
                             "complete model's and the turbulence bank set's measure of the air)")
      .def_property_readonly("air_power_ratio", prop([](auto& b) { return b.bank().adaptation().air_power_ratio(); }),
                             "the air's power ratio: rho-bar, or the lull floor's long average once in force "
                             "when larger (the rough-air floor's and the rough-air full tempering's measure)")
      .def_property_readonly("power_scale", prop([](auto& b) { return b.bank().adaptation().power_scale(); }),
                             "the adaptation's power scale sigma in force (a scheduled bank's node reference "
                             "scale, blended; 1 otherwise): its rho-bar over sigma is what the references read")
      .def_property_readonly("fully_tempered",
                             prop([](auto& b) { return b.bank().adaptation().fully_tempered(); }),
                             "the per-hypothesis tempering's fully tempered hypotheses for the next frame, "
                             "a bit per level-0 hypothesis (full_tempering, with rough_tempering in rough air)")
      .def_property_readonly("calm_complete_channels", prop([](auto& b) { return b.bank().complete_channels(); }),
                             "the channels read with the complete model from the next update on, a bit per "
                             "measurement (calm_complete_rho)")
      .def_property_readonly("calm_whiteness", prop([](auto& b) { return b.calm_whiteness(); }),
                             "the calm-air rule's residual whiteness W-bar (calm_measure 'whiteness' or 'either'; "
                             "NaN otherwise or before its first block of residuals)")
      .def_property_readonly("complete_trim_offset",
                             prop([](auto& b) { return cv::to_numpy(b.complete_trim_offset()); }),
                             "the complete channels' held offset (trim in force minus the held trim) of the "
                             "last update: zero while nothing is held or complete_trim_hold is off")
      .def_property_readonly("adapt_reference", prop([](auto& b) { return b.bank().adaptation().options().reference; }),
                             "the turbulence adaptation's reference rho_0 in force (the node's, the climb's, the "
                             "maneuver's or the option's; hierarchical_bank.h)")
      .def_property_readonly("reference_scale", prop([](auto& b) {
                               return b.scheduled().active() ? b.scheduled().reference_scale() : 1.0;
                             }),
                             "the scheduled reference scale sigma in force (1.0 without one; bank_schedule.h): the "
                             "adaptation reads its power ratio divided by it (turbulence_adaptation.h)")
      .def_property_readonly("calm_reference", prop([](auto& b) {
                               return b.scheduled().active() ? b.scheduled().calm_reference() : 1.0;
                             }),
                             "the scheduled calm-air reference in force, calm_complete_rho's unit (1.0 without one)")
      .def_property_readonly("log_likelihoods", prop([](auto& b) { return cv::to_numpy(b.bank().log_likelihoods()); }),
                             "(K,) the log-likelihoods l_k (eq. 2, tempered) of the filters on line at the last update")
      .def_property_readonly("turbulence_channel_scales", prop([](auto& b) {
                               const auto d = b.bank().adaptation().channel_inverse_sqrt_scales();
                               return cv::to_numpy(Eigen::VectorXd(d.array().square().inverse()));
                             }),
                             "(nz,) the per-channel scales s_j in force (adapt_channel_weight > 0; ones otherwise)")
      .def_property_readonly("rejected_frames", prop([](auto& b) { return b.rejected_frames(); }))
      .def_property_readonly("departure_frames", prop([](auto& b) { return b.departure_frames(); }),
                             "frames on which the departure hold kept the level-1 bank from declaring")
      .def("schedule", &PyHierarchicalBank::schedule, py::arg("mach"), py::arg("pressure_altitude_ft"),
           "Measured air data for the coming frames (scheduling only). A non-finite value is counted\n"
           "in air_data_rejected and the last usable one stays in force.")
      .def_property_readonly("air_data", prop([](auto& b) {
                               return py::make_tuple(b.air_data().mach, b.air_data().pressure_altitude_ft);
                             }),
                             "(mach, pressure_altitude_ft) in force: the design condition until schedule()")
      .def_property_readonly("air_data_rejected", prop([](auto& b) { return b.air_data_rejected(); }),
                             "schedule() calls with a non-finite value")
      .def_property_readonly("schedule_state", &PyHierarchicalBank::schedule_state,
                             "None for a bank designed at one flight condition; for a scheduled bank a dict:\n"
                             "mode, nodes ((mach, alt_ft) of the filters in force) and their weights, switches\n"
                             "(nearest), blends (interpolate), outside_frames (air data clamped to the grid),\n"
                             "fallback_frames (a cell with an uncovered corner: nearest node), x_trim, layer (configuration), air_data\n"
                             "(the low-passed air data the schedule follows)")
      .def("set_trim_offset", &PyHierarchicalBank::set_trim_offset, py::arg("du"), py::arg("dz"),
           "The trim offset in force from the next frame: subtract u_trim + du and z_trim + dz.")
      .def_property_readonly("trim_offset", prop([](auto& b) {
                               return py::make_tuple(cv::to_numpy(b.u_trim_offset()), cv::to_numpy(b.z_trim_offset()));
                             }),
                             "(du (nu,), dz (nz,)) in force")
      .def_property_readonly("trim_frozen", prop([](auto& b) { return b.trim_tracker().frozen(); }),
                             "trim tracking held its estimate on the last frame")
      .def_property_readonly("trim_frozen_frames", prop([](auto& b) { return b.trim_tracker().frozen_frames(); }),
                             "frames on which trim tracking held its estimate, since reset")
      .def_property_readonly("maneuvering", prop([](auto& b) { return b.maneuver_dwell().maneuvering(); }),
                             "the maneuver dwell's gate on this frame (maneuver_dwell.h; False when it is off)")
      .def_property_readonly("maneuver_load_factor", prop([](auto& b) { return b.maneuver_dwell().load_factor_lp(); }),
                             "the maneuver dwell's low-passed estimated load factor off the trim, g (maneuver_dwell.h; "
                             "0 when it is off)")
      .def_property_readonly("maneuver_trim", prop([](auto& b) {
                               return py::make_tuple(b.maneuver_trim().gamma(), b.maneuver_trim().accel(),
                                                     cv::to_numpy(b.maneuver_trim_du()),
                                                     cv::to_numpy(b.maneuver_trim_dz()));
                             }),
                             "(gamma rad, dV/dt ft/s^2, du (nu,), dz (nz,)) of the maneuver trim in force "
                             "(maneuver_trim.h; zeros when it is off)")
      .def_property_readonly("frames", prop([](auto& b) { return b.frames(); }), "update calls so far")
      .def_property_readonly("frame_rate_hz", prop([](auto& b) { return b.frame_rate_hz(); }))
      .def_property_readonly("u_trim", prop([](auto& b) { return cv::to_numpy(b.u_trim()); }))
      .def_property_readonly("z_trim", prop([](auto& b) { return cv::to_numpy(b.z_trim()); }))
      .def_property_readonly("p_min", prop([](auto& b) { return b.options().bank.p_min; }))
      .def_property_readonly("p_min_in_force", prop([](auto& b) { return b.bank().options().p_min; }),
                             "the floor in force: p_min, or a scheduled bank's node floors blended (node_p_min)")
      .def_property_readonly("threshold", prop([](auto& b) { return b.declarer().options().threshold; }))
      .def_property_readonly("dwell_s", prop([](auto& b) { return b.declarer().options().dwell_s; }))
      .def_property_readonly("dwell_frames", prop([](auto& b) { return b.declarer().dwell_frames(); }))
      .def_property_readonly("dwell_frames_in_force", prop([](auto& b) { return b.declarer().dwell_frames_in_force(); }),
                             "the dwell in frames in force for the declarer's candidate on the last update (0: no "
                             "hypothesis above the threshold): the phase's dwell or the candidate's least dwell, "
                             "rough air's in rough air, the longer (declarer.h); its evidence dwell asks N_k times "
                             "this over dwell_frames")
      .def_property_readonly("declarer_rough", prop([](auto& b) { return b.declarer().rough(); }),
                             "the rough-air least dwell in force (declarer.h): on the last accepted update the "
                             "adaptation's scale s_b was at least rough_scale")
      .def_property_readonly("fixed_size", &PyHierarchicalBank::fixed,
                             "True when a fixed-size F-16 bank (13 states, 19 with gust states; 5 inputs, 6 with\n"
                             "the throttle) runs inside");
}

}  // namespace f16mmae::bindings
