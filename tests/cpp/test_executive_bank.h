// A small synthetic F-16-sized model bank for the daemon's tests (13 states, or 19 with six
// gust-like states appended, 5 inputs, or 6 with a throttle-like input THR that drives the
// first state and is never a failure, 7 measurements, the 13 level-0 hypotheses then the 66
// duals, names of f16mmae/names.py):
// stable Phi, hypothesis k differs from NONE by the removed Bd column (actuators) or H row
// (sensors), as the design makes them. Passes ModelBank::validate().
#pragma once

#include "f16mmae/model_bank.h"

#include <string>
#include <vector>

namespace f16mmae::test_support {

inline ModelBank synthetic_bank(int nx = 13, int nu = 5) {
  const std::vector<std::string> actuators = {"LS", "RS", "LF", "RF", "RUD"};
  const std::vector<std::string> sensors = {"VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY"};
  ModelBank b;
  b.state_names = {"u_fps", "alpha_rad", "q_rad_s", "theta_rad", "beta_rad", "p_rad_s", "r_rad_s",
                   "phi_rad", "d_ls_rad", "d_rs_rad", "d_lf_rad", "d_rf_rad", "d_rud_rad"};
  const std::vector<std::string> gusts = {"u_g_fps", "v_g_fps", "w_g_fps", "p_g_rad_s", "q_g_rad_s", "r_g_rad_s"};
  for (int i = 13; i < nx; ++i) b.state_names.push_back(gusts.at(i - 13));
  b.input_names = actuators;
  if (nu == 6) b.input_names.push_back("THR");
  b.measurement_names = sensors;
  const int nz = 7;
  Eigen::MatrixXd phi = 0.9 * Eigen::MatrixXd::Identity(nx, nx);
  for (int i = 0; i + 1 < nx; ++i) phi(i, i + 1) = 0.05;
  Eigen::MatrixXd bd = Eigen::MatrixXd::Zero(nx, nu);
  for (int j = 0; j < 5; ++j) {
    bd(8 + j, j) = 0.3;
    bd(j, j) = 0.1 * (j + 1);
  }
  if (nu == 6) bd(0, 5) = 2.0;  // the throttle drives the forward speed
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(nz, nx);
  for (int i = 0; i < nz; ++i) {
    h(i, i) = 1.0;
    h(i, (i + 3) % nx) += 0.2;
  }
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(nz, nz) * 0.04;
  for (int i = 0; i + 1 < nz; ++i) a(i, i + 1) = a(i + 1, i) = 0.005;
  auto make = [&](const std::string& name, const std::vector<std::string>& failed) {
    HypothesisModel m{name, phi, bd, h, Eigen::MatrixXd::Zero(nx, nz), a};
    for (const auto& f : failed) {
      for (int j = 0; j < 5; ++j)
        if (actuators[j] == f) m.bd.col(j).setZero();
      for (int i = 0; i < nz; ++i)
        if (sensors[i] == f) m.h.row(i).setZero();
    }
    m.k = 0.3 * m.h.transpose();  // Phi (I - K H) stays stable
    return m;
  };
  b.hypotheses.push_back(make("NONE", {}));
  std::vector<std::string> components = actuators;
  components.insert(components.end(), sensors.begin(), sensors.end());
  for (const auto& c : components) b.hypotheses.push_back(make(c, {c}));
  for (std::size_t i = 0; i < components.size(); ++i)
    for (std::size_t j = i + 1; j < components.size(); ++j)
      b.hypotheses.push_back(make(components[i] + "+" + components[j], {components[i], components[j]}));
  b.u_trim = Eigen::VectorXd::LinSpaced(nu, -0.04, 0.03);
  if (nu == 6) b.u_trim(5) = 0.25;  // the trim throttle
  b.z_trim.resize(nz);
  b.z_trim << 414.8, 0.1417, 0.0, 1.0, 0.0, 0.0, 0.0;
  b.h_output = h;
  b.frame_rate_hz = 64.0;
  b.mach = 0.4;
  b.alt_ft = 20000.0;
  b.tuning = "synthetic";
  b.metadata = "{}";
  b.content_hash = nx == 13 && nu == 5 ? "synthetic-bank" : "synthetic-bank-" + std::to_string(nx) + "-" + std::to_string(nu);
  b.validate();
  return b;
}

}  // namespace f16mmae::test_support
