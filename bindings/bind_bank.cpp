// f16mmae.core.FilterBank: the MMAE bank (cpp/f16mmae/filter_bank.h) behind one Python
// class. F-16-sized models (13 filters of 13 states, 5 inputs, 7 measurements) run in the
// fixed-size F16FilterBank (no heap, no exceptions per frame); any other sizes in the
// dynamic-size bank. Signals are perturbations from trim. Shapes are checked here
// (ValueError naming the expected shape); a frame with a non-finite value is rejected and
// counted in rejected_frames, never raised.
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "core_convert.h"
#include "f16mmae/filter_bank.h"

namespace py = pybind11;

namespace f16mmae::bindings {
namespace {

namespace cv = convert;

class PyFilterBank {
 public:
  template <class F>
  decltype(auto) visit(F&& f) {
    return fixed_ ? f(*fixed_) : f(*dyn_);
  }
  template <class F>
  decltype(auto) visit(F&& f) const {
    return fixed_ ? f(static_cast<const F16FilterBank&>(*fixed_)) : f(static_cast<const DynamicFilterBank&>(*dyn_));
  }

  PyFilterBank(const py::sequence& models, double p_min, bool strip_leading_term, const py::object& initial,
               const py::object& h_output, bool fresh_floor_levels) {
    std::vector<DynamicFilterModel> dyn;
    for (std::size_t i = 0; i < py::len(models); ++i) {
      const py::object item = models[i];
      if (!py::isinstance<DynamicFilterModel>(item))
        throw py::value_error("models[" + std::to_string(i) + "] must be a core.FilterModel, got " +
                              std::string(py::str(py::type::handle_of(item).attr("__name__"))));
      dyn.push_back(item.cast<DynamicFilterModel>());
    }
    if (dyn.empty()) throw py::value_error("models must hold at least one core.FilterModel");
    FilterBankOptions opt;
    opt.p_min = p_min;
    opt.strip_leading_term = strip_leading_term;
    opt.fresh_floor_levels = fresh_floor_levels;
    const bool f16 = dyn.size() == 13 && dyn[0].nx() == 13 && dyn[0].nu() == 5 && dyn[0].nz() == 7;
    bool same = true;
    for (const auto& d : dyn) same = same && d.nx() == dyn[0].nx() && d.nu() == dyn[0].nu() && d.nz() == dyn[0].nz();
    if (f16 && same) {
      std::vector<F16FilterModel> fixed;
      for (std::size_t i = 0; i < dyn.size(); ++i)
        fixed.push_back(F16FilterModel::from_matrices(dyn[i].phi, dyn[i].bd, dyn[i].h, dyn[i].k, dyn[i].a,
                                                      Eigen::VectorXd(dyn[i].uninformative_width),
                                                      Eigen::VectorXd(dyn[i].uninformative_level_q),
                                                      "model " + std::to_string(i)));
      fixed_ = std::make_unique<F16FilterBank>(fixed, opt);
    } else {
      dyn_ = std::make_unique<DynamicFilterBank>(dyn, opt);
    }
    k_ = static_cast<int>(dyn.size());
    nx_ = dyn[0].nx();
    nu_ = dyn[0].nu();
    nz_ = dyn[0].nz();
    if (!h_output.is_none()) {
      const std::string shape = "(" + std::to_string(nz_) + ", " + std::to_string(nx_) + ")";
      const Eigen::MatrixXd h = cv::to_matrix(h_output, nz_, nx_, "h_output", shape);
      visit([&](auto& b) { b.set_h_output(h); });
    }
    if (!initial.is_none()) {
      const Eigen::VectorXd p = cv::to_vector(initial, k_, "initial_probabilities");
      visit([&](auto& b) { b.set_probabilities(p); });
      initial_ = p;
    }
  }

  py::array_t<double> update(py::handle z) {
    return visit([&](auto& b) {
      using B = std::decay_t<decltype(b)>;
      b.update(cv::to_vector<typename B::ZVector>(z, nz_, "z"));
      return cv::to_numpy(b.probabilities());
    });
  }
  void propagate(py::handle u) {
    visit([&](auto& b) { b.propagate(cv::to_vector<typename std::decay_t<decltype(b)>::UVector>(u, nu_, "u")); });
  }
  py::array_t<double> step(py::handle z, py::handle u) {
    return visit([&](auto& b) {
      using B = std::decay_t<decltype(b)>;
      const auto zv = cv::to_vector<typename B::ZVector>(z, nz_, "z");  // both checked before the frame
      const auto uv = cv::to_vector<typename B::UVector>(u, nu_, "u");
      b.step(zv, uv);
      return cv::to_numpy(b.probabilities());
    });
  }
  // step() over N frames in C++; returns the (N, K) probabilities after each frame.
  py::array_t<double> step_frames(py::handle z, py::handle u) {
    const Eigen::MatrixXd zs = cv::to_matrix(z, -1, nz_, "z", "(N, " + std::to_string(nz_) + ")");
    const Eigen::MatrixXd us = cv::to_matrix(u, zs.rows(), nu_, "u",
                                             "(" + std::to_string(zs.rows()) + ", " + std::to_string(nu_) + ")");
    Eigen::MatrixXd out(zs.rows(), k_);
    visit([&](auto& b) {
      using B = std::decay_t<decltype(b)>;
      for (Eigen::Index i = 0; i < zs.rows(); ++i) {
        b.step(typename B::ZVector(zs.row(i).transpose()), typename B::UVector(us.row(i).transpose()));
        out.row(i) = b.probabilities().transpose();
      }
    });
    return cv::to_numpy(out);
  }
  void reset() {
    visit([&](auto& b) {
      b.reset();
      if (initial_.size() > 0) b.set_probabilities(initial_);
    });
  }

  int k_ = 0, nx_ = 0, nu_ = 0, nz_ = 0;
  bool fixed() const { return static_cast<bool>(fixed_); }

 private:
  std::unique_ptr<F16FilterBank> fixed_;
  std::unique_ptr<DynamicFilterBank> dyn_;
  Eigen::VectorXd initial_;
};

}  // namespace

void bind_bank(py::module_& m) {
  py::class_<PyFilterBank>(m, "FilterBank", R"doc(
The MMAE filter bank with its hypothesis probability evaluator (paper Sec. III, eqs. 1-2).

    FilterBank(models, p_min=0.001, strip_leading_term=True, initial_probabilities=None,
               h_output=None, fresh_floor_levels=False)

models: a sequence of K core.FilterModel of equal sizes (n states, p inputs, m measurements);
models[0] is the no-failure hypothesis, presumed at start (p_0 = 1 - (K-1) p_min, others p_min)
unless initial_probabilities (K,) is given (it must sum to 1; it is floored at p_min).
Per frame, signals are perturbations from trim:
  update(z (m,))   residuals r_k = z - H_k x-_k, log-likelihoods (eq. 2, the leading term
                   1/((2 pi)^(m/2) |A_k|^(1/2)) stripped by default), Bayes update (eq. 1) in the log
                   domain, then the floor: every p_k >= p_min, sum 1, ratios above the floor as Bayes.
  propagate(u (p,)) x-_k = Phi_k x+_k + Bd_k u.
  step(z, u)       update then propagate.
h_output (m, n) maps the blended state to z_hat (default: models[0].h, the unfailed H).
fresh_floor_levels: a hypothesis on its floor restarts its failed sensors' tracked levels at
the frame's reading (cpp/f16mmae/filter_bank.h; False: they keep tracking on the floor).
A frame with a non-finite value is applied to no filter and counted in rejected_frames.
13 F-16-sized models (13, 5, 7) run in the fixed-size C++ bank (fixed_size is True).)doc")
      .def(py::init<const py::sequence&, double, bool, const py::object&, const py::object&, bool>(),
           py::arg("models"), py::kw_only(), py::arg("p_min") = 0.001, py::arg("strip_leading_term") = true,
           py::arg("initial_probabilities") = py::none(), py::arg("h_output") = py::none(),
           py::arg("fresh_floor_levels") = false)
      .def("update", &PyFilterBank::update, py::arg("z"), "Update with z (m,); returns the probabilities (K,).")
      .def("propagate", &PyFilterBank::propagate, py::arg("u"), "Propagate every filter with u (p,).")
      .def("step", &PyFilterBank::step, py::arg("z"), py::arg("u"),
           "update(z) then propagate(u); returns the probabilities (K,) after the update.")
      .def("step_frames", &PyFilterBank::step_frames, py::arg("z"), py::arg("u"),
           "step() over N frames z (N, m), u (N, p) in C++; returns the (N, K) probabilities after each.")
      .def("reset", &PyFilterBank::reset,
           "States back to zero, the start probabilities again, rejected_frames zeroed.")
      .def(
          "set_live",
          [](PyFilterBank& b, int k, bool live) {
            if (k <= 0 || k >= b.k_)
              throw py::value_error("set_live: filter " + std::to_string(k) + " must be in [1, " +
                                    std::to_string(b.k_) + ") (filter 0 stays live)");
            b.visit([&](auto& x) { x.set_live(k, live); });
          },
          py::arg("k"), py::arg("live"),
          "Filter k (>= 1) on or off line: off, p_k = 0 and the others conditioned on 'not k' (filter_bank.h).")
      .def("live", [](const PyFilterBank& b, int k) { return b.visit([&](auto& x) { return x.live(k); }); },
           py::arg("k"), "Whether filter k is on line.")
      .def_property_readonly("probabilities",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.probabilities()); }); },
                             "(K,) hypothesis probabilities p_k")
      .def_property_readonly("log_likelihoods",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.log_likelihoods()); }); },
                             "(K,) log-likelihoods l_k of the last update (eq. 2, as configured)")
      .def_property_readonly("quadratic_forms",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.quadratic_forms()); }); },
                             "(K,) r_k^T A_k^-1 r_k of the last update")
      .def_property_readonly("residuals",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.residuals()); }); },
                             "(K, m) residuals r_k of the last update")
      .def_property_readonly("state_estimates",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.state_estimates()); }); },
                             "(K, n) posterior state estimates x+_k of the last update")
      .def_property_readonly("prior_states",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.prior_states()); }); },
                             "(K, n) predictions x-_k for the next update")
      .def_property_readonly("blended_state",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.blended_state()); }); },
                             "(n,) probability-weighted state sum_k p_k x+_k")
      .def_property_readonly("z_hat",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return convert::to_numpy(x.z_hat()); }); },
                             "(m,) measurement estimate h_output @ blended_state (perturbation)")
      .def_property_readonly("rejected_frames",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return x.rejected_frames(); }); },
                             "number of update/propagate calls rejected for a non-finite value")
      .def_property_readonly("size", [](const PyFilterBank& b) { return b.k_; }, "K, filters in the bank")
      .def_property_readonly("nx", [](const PyFilterBank& b) { return b.nx_; })
      .def_property_readonly("nu", [](const PyFilterBank& b) { return b.nu_; })
      .def_property_readonly("nz", [](const PyFilterBank& b) { return b.nz_; })
      .def_property_readonly("fixed_size", &PyFilterBank::fixed,
                             "True when the fixed-size F-16 bank (13 filters, 13/5/7) runs inside")
      .def_property_readonly("p_min",
                             [](const PyFilterBank& b) { return b.visit([](auto& x) { return x.options().p_min; }); })
      .def_property_readonly("strip_leading_term", [](const PyFilterBank& b) {
        return b.visit([](auto& x) { return x.options().strip_leading_term; });
      })
      .def_property_readonly("fresh_floor_levels", [](const PyFilterBank& b) {
        return b.visit([](auto& x) { return x.options().fresh_floor_levels; });
      });
}

}  // namespace f16mmae::bindings
