// Test helper: small and F-16-sized synthetic hypothesis banks built the way the design
// builds them (actuator failure = B column removed, sensor failure = H row removed), with
// steady-state gains from a plain Riccati iteration, and a linear truth to fly them against.
#pragma once

#include "f16mmae/model_bank.h"

#include <Eigen/Dense>

#include <random>
#include <string>
#include <vector>

namespace f16mmae::test {

struct Plant {
  Eigen::MatrixXd phi, bd, h, q, r;  // Qd and R of the design model
};

struct Gains {
  Eigen::MatrixXd k, a, p_prior;
};

// Steady-state Kalman gain by iterating the discrete Riccati equation to convergence.
inline Gains steady_state_gains(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& h, const Eigen::MatrixXd& q,
                                const Eigen::MatrixXd& r) {
  const int n = static_cast<int>(phi.rows());
  Eigen::MatrixXd p = Eigen::MatrixXd::Identity(n, n);
  for (int it = 0; it < 20000; ++it) {
    const Eigen::MatrixXd a = h * p * h.transpose() + r;
    const Eigen::MatrixXd k = p * h.transpose() * a.inverse();
    const Eigen::MatrixXd p_post = (Eigen::MatrixXd::Identity(n, n) - k * h) * p;
    Eigen::MatrixXd next = phi * p_post * phi.transpose() + q;
    next = 0.5 * (next + next.transpose()).eval();
    const double change = (next - p).cwiseAbs().maxCoeff();
    p = next;
    if (change < 1e-14) break;
  }
  Gains g;
  g.p_prior = p;
  g.a = h * p * h.transpose() + r;
  g.a = 0.5 * (g.a + g.a.transpose()).eval();
  g.k = p * h.transpose() * g.a.inverse();
  return g;
}

// A stable random plant: Phi = rotation-ish blocks scaled below 1, dense B and H.
inline Plant random_plant(int nx, int nu, int nz, unsigned seed, double q_var = 1e-3, double r_var = 1e-3) {
  std::mt19937 g(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto rnd = [&](int r, int c) { return Eigen::MatrixXd(Eigen::MatrixXd::NullaryExpr(r, c, [&] { return n01(g); })); };
  Plant p;
  Eigen::MatrixXd m = rnd(nx, nx);
  const double rho = f16mmae::spectral_radius(m);
  p.phi = 0.95 / rho * m;
  p.bd = rnd(nx, nu);
  p.h = rnd(nz, nx);
  p.q = q_var * Eigen::MatrixXd::Identity(nx, nx);
  p.r = r_var * Eigen::MatrixXd::Identity(nz, nz);
  return p;
}

// Components a hypothesis fails, from its name ("NONE", "c", "a+b").
inline std::vector<std::string> failed_components(const std::string& name) {
  std::vector<std::string> out;
  if (name == "NONE") return out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t plus = name.find('+', start);
    out.push_back(name.substr(start, plus - start));
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
  return out;
}

// Design-model matrices of a hypothesis: failed actuators' B columns and failed sensors'
// H rows set to zero.
inline void hypothesis_matrices(const Plant& p, const std::vector<std::string>& actuators,
                                const std::vector<std::string>& sensors, const std::vector<std::string>& failed,
                                Eigen::MatrixXd& bd, Eigen::MatrixXd& h) {
  bd = p.bd;
  h = p.h;
  for (const auto& c : failed) {
    for (std::size_t j = 0; j < actuators.size(); ++j)
      if (actuators[j] == c) bd.col(static_cast<Eigen::Index>(j)).setZero();
    for (std::size_t j = 0; j < sensors.size(); ++j)
      if (sensors[j] == c) h.row(static_cast<Eigen::Index>(j)).setZero();
  }
}

// NONE, singles in component order, then duals "a+b" in combination order (names.py).
inline std::vector<std::string> hypothesis_names(const std::vector<std::string>& components) {
  std::vector<std::string> names{"NONE"};
  for (const auto& c : components) names.push_back(c);
  for (std::size_t i = 0; i < components.size(); ++i)
    for (std::size_t j = i + 1; j < components.size(); ++j) names.push_back(components[i] + "+" + components[j]);
  return names;
}

inline ModelBank make_bank(const Plant& p, const std::vector<std::string>& actuators,
                           const std::vector<std::string>& sensors, const Eigen::VectorXd& u_trim,
                           const Eigen::VectorXd& z_trim, double frame_rate_hz = 64.0) {
  ModelBank b;
  for (int i = 0; i < p.phi.rows(); ++i) b.state_names.push_back("x" + std::to_string(i));
  b.input_names = actuators;
  b.measurement_names = sensors;
  std::vector<std::string> components = actuators;
  components.insert(components.end(), sensors.begin(), sensors.end());
  for (const auto& name : hypothesis_names(components)) {
    HypothesisModel m;
    m.name = name;
    m.phi = p.phi;
    hypothesis_matrices(p, actuators, sensors, failed_components(name), m.bd, m.h);
    const Gains g = steady_state_gains(m.phi, m.h, p.q, p.r);
    m.k = g.k;
    m.a = g.a;
    b.hypotheses.push_back(m);
  }
  b.u_trim = u_trim;
  b.z_trim = z_trim;
  b.h_output = p.h;
  b.frame_rate_hz = frame_rate_hz;
  b.tuning = "synthetic";
  return b;
}

// An F-16-sized ModelBank (13 states; actuators LS RS LF RF RUD, sensors VEL AOA PIT AZ
// ROL YAW AY: 79 hypotheses) on random_plant(13, 5, 7, seed, 1e-3, 1e-3), with fixed trims.
inline const std::vector<std::string> kF16Actuators{"LS", "RS", "LF", "RF", "RUD"};
inline const std::vector<std::string> kF16Sensors{"VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY"};
inline ModelBank f16_model_bank(unsigned seed) {
  const Plant plant = random_plant(13, 5, 7, seed, 1e-3, 1e-3);
  Eigen::VectorXd u_trim = Eigen::VectorXd::Constant(5, 0.02), z_trim(7);
  z_trim << 400.0, 0.1, 0.0, 1.0, 0.0, 0.0, 0.0;
  return make_bank(plant, kF16Actuators, kF16Sensors, u_trim, z_trim);
}

// A sensor failure read as a tracked level: the hypothesis, its channel, the range W and the
// level's walk q per frame.
struct TrackedLevel {
  std::string hypothesis;
  int channel;
  double width, q;
};
// The first `count` hypotheses of mb (its level 0: NONE and the singles) as a filter bank's
// Model (e.g. F16FilterBank::Model), the `levels`' failures read as tracked levels.
template <class Model>
std::vector<Model> level_models(const ModelBank& mb, int count, const std::vector<TrackedLevel>& levels) {
  std::vector<Model> models;
  for (int k = 0; k < count; ++k) {
    const auto& h = mb.hypotheses[static_cast<std::size_t>(k)];
    Eigen::VectorXd width = Eigen::VectorXd::Zero(h.h.rows()), q = Eigen::VectorXd::Zero(h.h.rows());
    for (const auto& l : levels)
      if (h.name == l.hypothesis) width(l.channel) = l.width, q(l.channel) = l.q;
    models.push_back(Model::from_matrices(h.phi, h.bd, h.h, h.k, h.a, width, q));
  }
  return models;
}

// The truth: the plant with some components failed (actuator: no response to its
// command; sensor: reads noise only), process and measurement noise.
struct Truth {
  Plant plant;
  std::vector<std::string> actuators, sensors;
  Eigen::VectorXd x;
  std::mt19937 rng;
  std::normal_distribution<double> n01{0.0, 1.0};
  Truth(const Plant& p, std::vector<std::string> a, std::vector<std::string> s, unsigned seed)
      : plant(p), actuators(std::move(a)), sensors(std::move(s)), x(Eigen::VectorXd::Zero(p.phi.rows())), rng(seed) {}
  Eigen::VectorXd noise(const Eigen::MatrixXd& cov) {
    Eigen::VectorXd e(cov.rows());
    for (int i = 0; i < e.size(); ++i) e(i) = n01(rng);
    return Eigen::LLT<Eigen::MatrixXd>(cov).matrixL() * e;
  }
  Eigen::VectorXd measure(const std::vector<std::string>& failed) {
    Eigen::MatrixXd bd, h;
    hypothesis_matrices(plant, actuators, sensors, failed, bd, h);
    return h * x + noise(plant.r);
  }
  void advance(const Eigen::VectorXd& u, const std::vector<std::string>& failed) {
    Eigen::MatrixXd bd, h;
    hypothesis_matrices(plant, actuators, sensors, failed, bd, h);
    x = plant.phi * x + bd * u + noise(plant.q);
  }
};

// Dither: one sinusoid per input, distinct frequencies, unit amplitude.
inline Eigen::VectorXd dither(int nu, int frame, double rate_hz) {
  Eigen::VectorXd u(nu);
  for (int j = 0; j < nu; ++j) u(j) = std::sin(2.0 * 3.14159265358979323846 * (0.7 + 0.37 * j) * frame / rate_hz + j);
  return u;
}

// One flight for bit-for-bit comparisons of banks built from mb (f16_model_bank(seed) or the
// same plant with named states): `frames` frames of that plant with LF failed from frame 100,
// every bank stepped with the same absolute z and u (about mb's trims), then
// after_frame(frame); it stops once after_frame returns false.
template <class AfterFrame, class... Banks>
void fly_alike(const ModelBank& mb, unsigned seed, unsigned noise_seed, int frames, AfterFrame&& after_frame,
               Banks&... banks) {
  Truth truth(random_plant(13, 5, 7, seed, 1e-3, 1e-3), kF16Actuators, kF16Sensors, noise_seed);
  for (int i = 0; i < frames; ++i) {
    const std::vector<std::string> failed = i >= 100 ? std::vector<std::string>{"LF"} : std::vector<std::string>{};
    const Eigen::Matrix<double, 7, 1> z = truth.measure(failed) + mb.z_trim;
    const Eigen::VectorXd du = dither(5, i, 64.0);
    const Eigen::Matrix<double, 5, 1> u = du + mb.u_trim;
    (banks.step(z, u), ...);
    truth.advance(du, failed);
    if (!after_frame(i)) return;
  }
}

}  // namespace f16mmae::test
