// ModelBank — the in-memory model bank: every hypothesis filter's matrices, the trim the
// estimator subtracts, and the flight condition it was designed at. Eigen and std only;
// the file format lives in cpp/bankfile (LCM-encoded), this header knows nothing of it.
//
// Each hypothesis k is a steady-state discrete Kalman filter (paper Sec. III-IV):
//   x(t_{i+1}) = Phi_k x(t_i) + Bd_k u(t_i) + w,     z(t_i) = H_k x(t_i) + v      (eqs. 3-4)
//   A_k = H_k P_k^- H_k^T + R_k                                                    (eq. 5)
// with sizes Phi (nx,nx), Bd (nx,nu), H (nz,nx), K (nx,nz), A (nz,nz). Quantities are
// perturbations from the trim (u_trim, z_trim).
//
// validate() throws std::invalid_argument with a sentence naming the hypothesis and the
// problem: a wrong shape, a non-finite entry, an A_k that is not symmetric positive
// definite, an unstable error dynamics Phi_k (I - K_k H_k) (spectral radius >= 1).
#pragma once

#include <Eigen/Dense>

#include "f16mmae/model_checks.h"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct HypothesisModel {
  std::string name;  // "NONE", "LS", ..., "AY", duals "LS+PIT" (f16mmae/names.py order)
  Eigen::MatrixXd phi, bd, h, k, a;
};

struct ModelBank {
  static constexpr std::uint32_t kFormatVersion = 1;

  std::vector<std::string> state_names;        // nx
  std::vector<std::string> input_names;        // nu: LS RS LF RF RUD
  std::vector<std::string> measurement_names;  // nz: VEL AOA PIT AZ ROL YAW AY
  std::vector<HypothesisModel> hypotheses;     // [0] is NONE, then singles, then duals
  Eigen::VectorXd u_trim;    // (nu) absolute trim commands, subtracted from u
  Eigen::VectorXd z_trim;    // (nz) absolute trim measurements, subtracted from z
  Eigen::MatrixXd h_output;  // (nz,nx) blended state -> z_hat (the unfailed H)
  double frame_rate_hz = 0.0;
  double mach = 0.0;
  double alt_ft = 0.0;
  std::string tuning;    // name of the pseudonoise tuning ("untuned", "tuned", ...)
  std::string metadata;  // free JSON text: design options, generator version
  std::string content_hash;  // hex SHA-256 of the encoded payload (set by the bank file)

  int nx() const { return static_cast<int>(state_names.size()); }
  int nu() const { return static_cast<int>(input_names.size()); }
  int nz() const { return static_cast<int>(measurement_names.size()); }

  // Index of a hypothesis by name, or -1.
  int find(const std::string& name) const {
    for (std::size_t i = 0; i < hypotheses.size(); ++i)
      if (hypotheses[i].name == name) return static_cast<int>(i);
    return -1;
  }

  void validate() const {
    auto fail = [](const std::string& what) { throw std::invalid_argument("model bank: " + what); };
    const int nx_ = nx(), nu_ = nu(), nz_ = nz();
    if (nx_ == 0 || nu_ == 0 || nz_ == 0) fail("state, input and measurement names must be non-empty");
    if (hypotheses.empty()) fail("no hypotheses");
    if (hypotheses[0].name != "NONE") fail("hypothesis 0 must be NONE, got '" + hypotheses[0].name + "'");
    if (!(frame_rate_hz > 0.0) || !std::isfinite(frame_rate_hz)) fail("frame_rate_hz must be positive and finite");
    auto check_vec = [&](const char* what, const Eigen::VectorXd& v, int n) {
      if (v.size() != n) {
        std::ostringstream s;
        s << what << " has size " << v.size() << ", expected " << n;
        fail(s.str());
      }
      if (!v.allFinite()) fail(std::string(what) + " has a non-finite entry");
    };
    check_vec("u_trim", u_trim, nu_);
    check_vec("z_trim", z_trim, nz_);
    if (h_output.rows() != nz_ || h_output.cols() != nx_ || !h_output.allFinite()) {
      std::ostringstream s;
      s << "h_output is " << h_output.rows() << "x" << h_output.cols() << ", expected " << nz_
        << "x" << nx_ << " with finite entries";
      fail(s.str());
    }
    for (std::size_t i = 0; i < hypotheses.size(); ++i) {
      const HypothesisModel& m = hypotheses[i];
      const std::string who = "hypothesis " + std::to_string(i) + " '" + m.name + "'";
      for (std::size_t j = 0; j < i; ++j)
        if (hypotheses[j].name == m.name) fail(who + ": duplicate name");
      check_filter_matrices(m.phi, m.bd, m.h, m.k, m.a, nx_, nu_, nz_, "model bank: " + who);
    }
  }
};

}  // namespace f16mmae
