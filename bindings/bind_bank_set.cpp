// f16mmae.core.TurbulenceBankSet: one estimator over hierarchical banks designed for rising
// turbulence intensities, the running one chosen on line by its own measured intensity
// (cpp/f16mmae/turbulence_bank_set.h). Built either from core.HierarchicalBank members of one
// fixed-size F-16 type (hierarchical_access.h), each built with the turbulence adaptation on,
// which the set keeps alive; or from a set file (core.TurbulenceSetFile) and the estimator's
// keyword arguments (estimator_init.h), its members made by the executive's rule
// (cpp/executive/turbulence_set_bank.h, the one place it is written: what mmae-daemon
// --turbulence-banks runs). Signals are ABSOLUTE, as core.HierarchicalBank's.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "core_convert.h"
#include "estimator_init.h"
#include "hierarchical_access.h"
#include "bankfile/turbulence_set_file.h"
#include "executive/turbulence_set_bank.h"
#include "f16mmae/model_bank.h"
#include "f16mmae/turbulence_bank_set.h"

namespace py = pybind11;

namespace f16mmae::bindings {
namespace {

namespace cv = convert;

class PyTurbulenceBankSet {
 public:
  PyTurbulenceBankSet(const py::list& members, const std::vector<double>& bounds, const std::vector<double>& typical,
                      double hold_s, double warm_up_s, double warm_down_s, double settle_s, double freeze_probability,
                      int start, int start_standby, bool calmer_own_rho, double floor_rho,
                      const std::vector<double>& floor_p_min)
      : members_(members) {
    TurbulenceBankSetOptions o;
    o.bounds = bounds;
    o.typical = typical;
    o.hold_s = hold_s;
    o.warm_up_s = warm_up_s;
    o.warm_down_s = warm_down_s;
    o.start_standby = start_standby;
    o.settle_s = settle_s;
    o.freeze_probability = freeze_probability;
    o.start = start;
    o.calmer_own_rho = calmer_own_rho;
    o.floor_rho = floor_rho;
    o.floor_p_min = floor_p_min;
    std::vector<FixedHierarchicalBank> fixed;
    for (py::handle m : members) {
      FixedHierarchicalBank f = fixed_hierarchical_bank(m);   // TypeError if not a core.HierarchicalBank
      if (std::holds_alternative<std::monostate>(f))
        throw py::value_error("turbulence bank set: every member must be a fixed-size F-16 bank; one runs the dynamic-size bank");
      if (!fixed.empty() && f.index() != fixed[0].index())
        throw py::value_error("turbulence bank set: the members must be banks of one kind (states and inputs); "
                              "they differ");
      fixed.push_back(f);
    }
    if (fixed.empty()) throw py::value_error("turbulence bank set: needs at least 2 member banks, got 0");
    std::visit(
        [&](auto first) {
          using P = decltype(first);
          if constexpr (!std::is_same_v<P, std::monostate>) {
            using B = std::remove_pointer_t<P>;
            std::vector<B*> ptrs;
            for (const auto& f : fixed) ptrs.push_back(std::get<P>(f));
            set_ = std::make_shared<TurbulenceBankSet<B>>(std::move(ptrs), o);
          }
        },
        fixed[0]);
  }

  // The set of `file`'s members, each HierarchicalBank(member, the executive's rule applied to
  // `options`): TurbulenceSetBank owns them, the set points into it. ValueError for a set of
  // other sizes than the executive runs (19 states, 6 inputs, 7 measurements) or one it refuses.
  PyTurbulenceBankSet(const TurbulenceSetFile& file, const HierarchicalOptions& options) {
    using B = F16GustThrottleHierarchicalBank;
    file.validate();
    const ModelBank& b = file.members.front();
    if (b.nx() != 19 || b.nu() != 6 || b.nz() != 7)
      throw py::value_error("turbulence bank set: a set file's members must have 19 states, 6 inputs and 7 "
                            "measurements (the executive's set), got (" + std::to_string(b.nx()) + ", " +
                            std::to_string(b.nu()) + ", " + std::to_string(b.nz()) + ")");
    auto owner = std::make_shared<executive::TurbulenceSetBank<B>>(file, options);
    set_ = std::shared_ptr<TurbulenceBankSet<B>>(owner, &owner->set());   // keeps `owner` alive
  }

  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(
        [&](const auto& p) -> decltype(auto) {
          using S = typename std::decay_t<decltype(p)>::element_type;
          if (!p) throw py::value_error("turbulence bank set: not constructed");
          return f(const_cast<S&>(*p));
        },
        set_);
  }

  py::object update(py::handle z) {
    return visit([&](auto& s) -> py::object {
      using B = std::decay_t<decltype(s.running())>;
      const int d = s.update(cv::to_vector<typename B::ZVector>(z, 7, "z"));
      return d < 0 ? py::object(py::none()) : py::object(py::str(s.running().name(d)));
    });
  }
  void propagate(py::handle u) {
    visit([&](auto& s) {
      using B = std::decay_t<decltype(s.running())>;
      constexpr int nu = B::UVector::RowsAtCompileTime;
      s.propagate(cv::to_vector<typename B::UVector>(u, nu, "u"));
    });
  }

  py::list members_;   // keeps the member banks alive (empty: a set file's, owned by set_)

 private:
  std::variant<std::shared_ptr<TurbulenceBankSet<F16HierarchicalBank>>,
               std::shared_ptr<TurbulenceBankSet<F16GustHierarchicalBank>>,
               std::shared_ptr<TurbulenceBankSet<F16ThrottleHierarchicalBank>>,
               std::shared_ptr<TurbulenceBankSet<F16GustThrottleHierarchicalBank>>>
      set_;
};

template <class F>
auto prop(F f) {
  return [f](const PyTurbulenceBankSet& s) { return s.visit(f); };
}

// Benchmark (f16mmae.bench): a set of the model banks as the set's members are (19 states,
// 6 inputs: F16GustThrottleHierarchicalBank), each with the adaptation on, over frames z (N,7),
// u (N,6), replayed pass after pass from reset() for at least min_time_s and 3 passes, timed in
// C++; member 0 in force at the start, no start standby. Returns (seconds per frame of the
// fastest pass, handovers in the last pass, frames with a standby in the last pass).
py::tuple bench_bank_set_loop(const std::vector<ModelBank>& banks, py::handle z_frames, py::handle u_frames,
                              const std::vector<double>& bounds, const std::vector<double>& typical,
                              double hold_s, double min_time_s) {
  using Bank = F16GustThrottleHierarchicalBank;
  HierarchicalOptions o;
  o.bank.adaptation.enabled = true;
  o.bank.adaptation.reference = 1.0;
  std::vector<std::unique_ptr<Bank>> owned;
  std::vector<Bank*> members;
  for (const ModelBank& b : banks) {
    o.bank.p_min = b.estimator.p_min;
    o.declarer.threshold = b.estimator.threshold;
    o.declarer.dwell_s = b.estimator.dwell_s;
    owned.push_back(std::make_unique<Bank>(b, o));
    members.push_back(owned.back().get());
  }
  TurbulenceBankSetOptions so;
  so.bounds = bounds;
  so.typical = typical;
  so.hold_s = hold_s;
  so.start = 0;
  so.start_standby = -1;
  TurbulenceBankSet<Bank> set(members, so);
  const Eigen::MatrixXd z = cv::to_matrix(z_frames, -1, 7, "z", "(N, 7)");
  const Eigen::Index n = z.rows();
  const Eigen::MatrixXd u = cv::to_matrix(u_frames, n, 6, "u", "(N, 6) with N the frames of z");
  for (const ModelBank& b : banks)
    if (b.nx() != 19 || b.nu() != 6) throw py::value_error("the benchmark's banks must have 19 states and 6 inputs");
  if (n == 0) throw py::value_error("the benchmark needs at least one frame");
  std::vector<Bank::ZVector> zs(n);
  std::vector<Bank::UVector> us(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    zs[i] = z.row(i).transpose();
    us[i] = u.row(i).transpose();
  }
  using Clock = std::chrono::steady_clock;
  double best_s = std::numeric_limits<double>::infinity();
  {
    py::gil_scoped_release release;
    const Clock::time_point start = Clock::now();
    for (int pass = 0; pass < 3 || std::chrono::duration<double>(Clock::now() - start).count() < min_time_s; ++pass) {
      set.reset();
      const Clock::time_point t0 = Clock::now();
      for (Eigen::Index i = 0; i < n; ++i) set.step(zs[i], us[i]);
      best_s = std::min(best_s, std::chrono::duration<double>(Clock::now() - t0).count());
    }
  }
  return py::make_tuple(best_s / static_cast<double>(n), set.switches(), set.standby_frames());
}

std::string fspath(py::handle path) { return py::str(py::module_::import("os").attr("fspath")(path)); }

// The selector's settings by name (core.TurbulenceBankSet's keyword arguments): f(name, field)
// for each, the one list both directions use.
template <class F>
void for_each_setting(TurbulenceBankSetOptions& s, F&& f) {
  f("bounds", s.bounds), f("typical", s.typical), f("hold_s", s.hold_s), f("warm_up_s", s.warm_up_s);
  f("warm_down_s", s.warm_down_s), f("settle_s", s.settle_s), f("freeze_probability", s.freeze_probability);
  f("start", s.start), f("start_standby", s.start_standby), f("calmer_own_rho", s.calmer_own_rho);
  f("floor_rho", s.floor_rho), f("floor_p_min", s.floor_p_min);
}

py::dict selector_dict(TurbulenceBankSetOptions s) {
  py::dict d;
  for_each_setting(s, [&](const char* name, const auto& value) { d[name] = value; });
  return d;
}

// The set file's content from Python values (the selector: core.TurbulenceBankSet's keywords;
// one left out keeps the core's default).
TurbulenceSetFile make_set_file(const std::vector<ModelBank>& members, const std::vector<std::string>& levels,
                                const std::vector<double>& adapt_reference, const std::vector<double>& trim_time_constant_s,
                                const py::dict& selector, double maneuver_tempering_g,
                                const std::optional<std::vector<double>>& adapt_gain) {
  TurbulenceSetFile f;
  f.maneuver_tempering_g = maneuver_tempering_g;
  f.adapt_gain = adapt_gain ? *adapt_gain : std::vector<double>(members.size(), TurbulenceAdaptationOptions{}.gain);
  f.members = members;
  f.levels = levels;
  f.adapt_reference = adapt_reference;
  f.trim_time_constant_s = trim_time_constant_s;
  const py::dict known = selector_dict(f.selector);
  for (const auto& item : selector)
    if (!known.contains(item.first))
      throw py::value_error("turbulence bank set: unknown selector setting '" + std::string(py::str(item.first)) +
                            "'; valid: " + std::string(py::str(py::str(", ").attr("join")(known))));
  for_each_setting(f.selector, [&](const char* name, auto& value) {
    if (selector.contains(name)) value = selector[name].cast<std::decay_t<decltype(value)>>();
  });
  return f;
}

}  // namespace

void bind_turbulence_set_file(py::module_& m) {
  py::class_<TurbulenceSetFile>(m, "TurbulenceSetFile", R"doc(
A turbulence bank set file (cpp/bankfile/turbulence_set_file.h), loaded and validated: the member
banks (rising intensity), their design levels, adaptation references and trim tracking time
constants (0: off), adaptation gains (adapt_gain), the load-factor tempering the set is flown with (maneuver_tempering_g, g; 0:
off; a --maneuver-tempering given overrides it), the selector's settings
(core.TurbulenceBankSet's keyword arguments) and content_hash (hex SHA-256 of the payload: the
set's name in mmae-daemon's status). core.Executive(set_file, ...) runs the set as mmae-daemon
--turbulence-banks does.)doc")
      .def_property_readonly("members", [](const TurbulenceSetFile& f) { return f.members; })
      .def_property_readonly("levels", [](const TurbulenceSetFile& f) { return f.levels; })
      .def_property_readonly("adapt_reference", [](const TurbulenceSetFile& f) { return f.adapt_reference; })
      .def_property_readonly("trim_time_constant_s", [](const TurbulenceSetFile& f) { return f.trim_time_constant_s; })
      .def_property_readonly("maneuver_tempering_g", [](const TurbulenceSetFile& f) { return f.maneuver_tempering_g; })
      .def_property_readonly("adapt_gain", [](const TurbulenceSetFile& f) { return f.adapt_gain; })
      .def_property_readonly("selector", [](const TurbulenceSetFile& f) { return selector_dict(f.selector); })
      .def_property_readonly("content_hash", [](const TurbulenceSetFile& f) { return f.content_hash; });
  m.def(
      "load_turbulence_set", [](py::handle path) { return load_turbulence_set(fspath(path)); }, py::arg("path"),
      "Read a turbulence bank set file: magic, version, size and SHA-256, every member bank as a bank\n"
      "file, then the set's checks. FileNotFoundError if absent, OSError if unreadable, ValueError naming\n"
      "the field.");
  m.def(
      "save_turbulence_set",
      [](py::handle path, const std::vector<ModelBank>& members, const std::vector<std::string>& levels,
         const std::vector<double>& adapt_reference, const std::vector<double>& trim_time_constant_s,
         const py::dict& selector, double maneuver_tempering_g, const std::optional<std::vector<double>>& adapt_gain) {
        return save_turbulence_set(make_set_file(members, levels, adapt_reference, trim_time_constant_s, selector,
                                                 maneuver_tempering_g, adapt_gain),
                                   fspath(path));
      },
      py::arg("path"), py::arg("members"), py::kw_only(), py::arg("levels"), py::arg("adapt_reference"),
      py::arg("trim_time_constant_s"), py::arg("selector"), py::arg("maneuver_tempering_g") = 0.0,
      py::arg("adapt_gain") = py::none(),
      "Validate and write a turbulence bank set file atomically; returns its content hash. selector: a dict\n"
      "of core.TurbulenceBankSet's settings (bounds, typical, hold_s, ...; left out: the core's defaults);\n"
      "maneuver_tempering_g: the load-factor tempering the set is flown with (g; 0: off); adapt_gain: each\n"
      "member's adaptation gain (None: the core's default, 20, for every member). ValueError naming the field.");
}

void bind_bank_set(py::module_& m) {
  m.def("_bench_bank_set_loop", &bench_bank_set_loop, py::arg("banks"), py::arg("z"), py::arg("u"), py::arg("bounds"),
        py::arg("typical"), py::arg("hold_s") = 1.0, py::arg("min_time_s") = 0.2,
        "Benchmark: (seconds per frame, handovers, frames with a standby) of a core.TurbulenceBankSet over\n"
        "19-state 6-input members built from the model banks (adaptation on), frames z (N,7), u (N,6), in C++.");
  py::class_<PyTurbulenceBankSet> cls(m, "TurbulenceBankSet", R"doc(
One estimator over banks designed for rising turbulence intensities (cpp/f16mmae/turbulence_bank_set.h).

    TurbulenceBankSet(members, bounds, typical, hold_s=1.0, warm_up_s=1.0, warm_down_s=5.0,
                      settle_s=1.0, freeze_probability=0.05, start=1, start_standby=0,
                      calmer_own_rho=False, floor_rho=0.0, floor_p_min=[])
    TurbulenceBankSet(set_file, *, p_min=..., ...)   # core.HierarchicalBank's keywords

The second form runs a core.TurbulenceSetFile as mmae-daemon --turbulence-banks does: member i
is core.HierarchicalBank(set_file.members[i], the keywords) with the turbulence adaptation on,
each filter's power per channel it reads (adapt_own_channels), the file's adapt_reference[i]
unless adapt_reference is given, its trim_time_constant_s[i] unless trim_time_constant_s is, and
its maneuver_tempering_g unless maneuver_tempering_g is (cpp/executive/turbulence_set_bank.h);
the selector is the file's; members is then empty.

members: core.HierarchicalBank objects of one fixed-size kind, each with adapt_turbulence=True,
in order of rising design intensity (n of them). One member a is in force (start at first,
start_standby running beside it from frame 0). After each update the selector's rho of member
a (min_k q_k / nz averaged as the adaptation does, a plain mean at first) is classified by
bounds (n x (n-1), row a: member a's rho between level i and i+1, rising) into a level L;
member L, if not a, runs beside it as a standby (started in flight as a's copy, its
adaptation's rho at typical[L]) and takes over once wanted for hold_s and, a copy, run for
warm_up_s (L > a) or warm_down_s (L < a): level, hypotheses on line, probabilities, declarer
state, declarations; its own filter states and rho. Nothing is decided within settle_s of a
switch or the start, and the standby is dropped while the member in force is at level 1, has
a failure declared, or a failure hypothesis is above freeze_probability. calmer_own_rho: while
a calmer member c runs as the standby, c's own rho against its own row of bounds decides
whether it is wanted (the header's rule). floor_rho > 0 with floor_p_min (one per member, 0: its
own): after settle_s and while not frozen, member a's level-0 floor is floor_p_min[a] while its rho
<= floor_rho, else its own (the header's floor by rho). Outputs are the member in force's. Raises ValueError for invalid members or settings (naming them).)doc");
  cls.def(py::init<const py::list&, const std::vector<double>&, const std::vector<double>&, double, double, double,
                    double, double, int, int, bool, double, const std::vector<double>&>(),
           py::arg("members"), py::arg("bounds"), py::arg("typical"), py::kw_only(), py::arg("hold_s") = 1.0,
           py::arg("warm_up_s") = 1.0, py::arg("warm_down_s") = 5.0, py::arg("settle_s") = 1.0,
           py::arg("freeze_probability") = 0.05, py::arg("start") = 1, py::arg("start_standby") = 0,
           py::arg("calmer_own_rho") = false, py::arg("floor_rho") = 0.0,
           py::arg("floor_p_min") = std::vector<double>{});
  def_estimator_init<PyTurbulenceBankSet, TurbulenceSetFile>(cls)
      .def("update", &PyTurbulenceBankSet::update, py::arg("z"),
           "Update the running member with absolute z (7,); then the selector. Returns the name declared, or None.")
      .def("propagate", &PyTurbulenceBankSet::propagate, py::arg("u"), "Propagate the running member with absolute u.")
      .def("schedule", [](PyTurbulenceBankSet& s, double mach, double alt) {
             s.visit([&](auto& x) { x.schedule(AirData{mach, alt}); });
           }, py::arg("mach"), py::arg("pressure_altitude_ft"))
      .def("reset", [](PyTurbulenceBankSet& s) { s.visit([](auto& x) { x.reset(); }); },
           "Every member back to its start; the start member runs.")
      .def_property_readonly("members", [](const PyTurbulenceBankSet& s) { return s.members_; })
      .def_property_readonly("active", prop([](auto& s) { return s.active(); }), "index of the member in force")
      .def_property_readonly("standby", prop([](auto& s) { return s.standby(); }), "index of the member warming up, or -1")
      .def_property_readonly("standby_frames", prop([](auto& s) { return s.standby_frames(); }),
                             "frames on which a standby ran beside the member in force, since reset")
      .def_property_readonly("switches", prop([](auto& s) { return s.switches(); }), "handovers since reset")
      .def_property_readonly("frozen_frames", prop([](auto& s) { return s.frozen_frames(); }),
                             "frames on which a failure hypothesis froze the selector, since reset")
      .def_property_readonly("turbulence_power_ratio", prop([](auto& s) { return s.power_ratio(); }),
                             "the selector's rho of the member in force")
      .def_property_readonly("turbulence_scale", prop([](auto& s) { return s.running().turbulence_scale(); }))
      .def_property_readonly("dwell_frames_in_force",
                             prop([](auto& s) { return s.running().declarer().dwell_frames_in_force(); }),
                             "the member in force's declarer: its candidate's dwell in frames on the last "
                             "update (0: none above the threshold; declarer.h)")
      .def_property_readonly("level", prop([](auto& s) { return s.running().level(); }))
      .def_property_readonly("dwell_s", prop([](auto& s) { return s.running().declarer().options().dwell_s; }),
                             "the member in force's declaration dwell, s")
      .def_property_readonly("hypotheses", prop([](auto& s) {
                               const auto& b = s.running();
                               py::tuple t(b.size());
                               for (int k = 0; k < b.size(); ++k) t[k] = py::str(b.name(b.online()[k]));
                               return t;
                             }))
      .def_property_readonly("declared", prop([](auto& s) { return s.running().name(s.running().current_hypothesis()); }))
      .def_property_readonly("probabilities", prop([](auto& s) { return cv::to_numpy(s.running().probabilities()); }))
      .def_property_readonly("residuals", prop([](auto& s) { return cv::to_numpy(s.running().bank().residuals()); }),
                             "(K, nz) residuals of the member in force's filters on line at the last update")
      .def_property_readonly("log_likelihoods",
                             prop([](auto& s) { return cv::to_numpy(s.running().bank().log_likelihoods()); }),
                             "(K,) the member in force's log-likelihoods l_k (eq. 2, tempered) at the last update")
      .def_property_readonly("z_hat", prop([](auto& s) { return cv::to_numpy(s.running().z_hat()); }))
      .def_property_readonly("blended_state", prop([](auto& s) { return cv::to_numpy(s.running().blended_state()); }))
      .def_property_readonly("frames", prop([](auto& s) { return s.running().frames(); }))
      .def_property_readonly("air_data", prop([](auto& s) {
                               return py::make_tuple(s.running().air_data().mach,
                                                     s.running().air_data().pressure_altitude_ft);
                             }))
      .def_property_readonly("air_data_rejected", prop([](auto& s) { return s.running().air_data_rejected(); }))
      .def_property_readonly("declarations", prop([](auto& s) {
                               py::list out;
                               for (const auto& d : s.running().declarations()) {
                                 py::dict e;
                                 e["hypothesis"] = s.running().name(d.hypothesis);
                                 e["level"] = d.level;
                                 e["frame"] = d.frame;
                                 e["time_s"] = d.time_s;
                                 out.append(e);
                               }
                               return out;
                             }))
      .def_property_readonly("fixed_size", [](const PyTurbulenceBankSet&) { return false; },
                             "False: a set is flown frame by frame (not the one-call C++ closed loop)");
}

}  // namespace f16mmae::bindings
