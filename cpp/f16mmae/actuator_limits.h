// ActuatorLimits — the surface actuators' rate and position limits, which the filters'
// linear actuator model lacks, applied to the commands before the filters see them.
// Eigen and std only; nothing allocates per frame.
//
// Why: each filter models actuator j as a first-order lag of its command, per frame
//   d_j(i+1) = a_j d_j(i) + b_j u_j(i)       (the bank's Phi(s_j, s_j) = a_j, Bd(s_j, j) = b_j)
// while the real actuator is that lag with its rate limited to R_j and its position to
// +-L_j. In level flight the commands stay well inside both limits and the two agree. At
// a maneuver's entry (a roll-in to a turn, a pull-up) the flight control law can command a
// surface tens of degrees in one frame: the real surface moves at R_j, the model's lag at
// up to 27 % of the step per frame (at 64 Hz and 20.2 rad/s), and the filters read the
// difference as a failure of that surface.
//
// What the bank does (HierarchicalBank, HierarchicalOptions::actuators): it steps its own
// copy of each actuator on the commands, as the aircraft's actuator is specified (lag
// a_j = exp(-lambda_j / f) over the frame, f the frame rate, in `substeps` equal steps of a
// zero-order-held command):
//   c = clip(u_j, -L_j, L_j);   target = c + (delta_j - c) a_j^(1/substeps);
//   delta_j += clip(target - delta_j, -R_j / (f substeps), R_j / (f substeps))
// and hands the filters the command that makes their linear lag reproduce that step exactly:
//   u_eff_j = (delta_j(i+1) - a_j delta_j(i)) / b_j.
// Inside the limits (no clip active) u_eff_j = u_j to rounding, since b_j = 1 - a_j (the
// lag's unit DC gain; checked at construction). delta starts at the first frame's clipped
// command (the aircraft in flight at its trim); reset() forgets it.
//
// Why it cannot absorb a failure: u_eff is a function of the commands only (u, never z);
// it knows nothing of what the surfaces or the aircraft did. A failed actuator's hypothesis
// has its Bd column zero and ignores u_j either way.
//
// Options: empty limits = off (the bank without it, bit for bit); else nu rate limits
// (rad/s) and nu position limits (rad), each finite and > 0, and substeps >= 1. An input
// whose two limits are both +inf has no actuator here (the throttle command of a bank that
// models it, `f16mmae design --throttle-input`): it is handed to the filters unchanged and
// needs no lag state.
// The constructor throws std::invalid_argument naming the field, or the input j whose
// model in the bank has no first-order lag of unit gain: exactly one state s_j driven by
// input j alone (Bd row s_j zero but for b_j) whose Phi row is zero but for a_j, and
// b_j = 1 - a_j. (Bd column j has other entries too: the airframe's response within the
// frame to the lagged surface; the filters keep them.)
#pragma once

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct ActuatorLimitOptions {
  std::vector<double> rate_limit_rad_s;     // nu values; empty = off
  std::vector<double> position_limit_rad;   // nu values (|delta| <= L)
  int substeps = 2;                         // actuator integration steps per frame

  bool enabled() const noexcept { return !rate_limit_rad_s.empty(); }
};

template <int NU>
class ActuatorLimits {
 public:
  using UVector = Eigen::Matrix<double, NU, 1>;

  ActuatorLimits() = default;
  // phi, bd: the no-failure hypothesis' matrices; frame_rate_hz: the bank's.
  ActuatorLimits(const ActuatorLimitOptions& options, const Eigen::MatrixXd& phi, const Eigen::MatrixXd& bd,
                 double frame_rate_hz)
      : enabled_(options.enabled()) {
    const int nu = static_cast<int>(bd.cols());
    delta_ = UVector::Zero(nu);
    decay_ = UVector::Zero(nu);
    max_step_ = UVector::Zero(nu);
    limit_ = UVector::Zero(nu);
    a_ = UVector::Zero(nu);
    b_ = UVector::Zero(nu);
    if (!enabled_) return;
    auto fail = [](const std::string& what) { throw std::invalid_argument("actuator limits: " + what); };
    if (static_cast<int>(options.rate_limit_rad_s.size()) != nu ||
        static_cast<int>(options.position_limit_rad.size()) != nu)
      fail("rate_limit_rad_s and position_limit_rad need " + std::to_string(nu) + " values each (one per input), got " +
           std::to_string(options.rate_limit_rad_s.size()) + " and " + std::to_string(options.position_limit_rad.size()));
    if (options.substeps < 1) fail("substeps must be >= 1, got " + std::to_string(options.substeps));
    const int n = options.substeps;
    for (int j = 0; j < nu; ++j) {
      const double r = options.rate_limit_rad_s[j], l = options.position_limit_rad[j];
      if (std::isinf(r) && r > 0.0 && std::isinf(l) && l > 0.0) {  // no actuator: passed through
        limit_(j) = r;
        continue;
      }
      if (!(std::isfinite(r) && r > 0.0))
        fail("rate_limit_rad_s[" + std::to_string(j) + "] = " + std::to_string(r) +
             " must be finite and > 0 (or +inf with its position limit: an input without actuator)");
      if (!(std::isfinite(l) && l > 0.0))
        fail("position_limit_rad[" + std::to_string(j) + "] = " + std::to_string(l) +
             " must be finite and > 0 (or +inf with its rate limit: an input without actuator)");
      // The lag state of input j: driven by input j alone, its Phi row zero but for the diagonal.
      int s = -1;
      for (int i = 0; i < bd.rows(); ++i) {
        bool lag = bd(i, j) != 0.0;
        for (int c = 0; lag && c < bd.cols(); ++c) lag = c == j || bd(i, c) == 0.0;
        for (int c = 0; lag && c < phi.cols(); ++c) lag = c == i || phi(i, c) == 0.0;
        if (!lag) continue;
        if (s >= 0) fail("input " + std::to_string(j) + " drives two lag states (" + std::to_string(s) + ", " +
                         std::to_string(i) + ")");
        s = i;
      }
      if (s < 0) fail("input " + std::to_string(j) + " drives no first-order lag state");
      a_(j) = phi(s, s);
      b_(j) = bd(s, j);
      if (!(a_(j) > 0.0 && a_(j) < 1.0 && std::abs(a_(j) + b_(j) - 1.0) < 1e-9))
        fail("input " + std::to_string(j) + ": lag a = " + std::to_string(a_(j)) + ", gain b = " +
             std::to_string(b_(j)) + " is not a stable lag of unit gain (b = 1 - a)");
      decay_(j) = std::pow(a_(j), 1.0 / n);
      max_step_(j) = r / (frame_rate_hz * n);
      limit_(j) = l;
    }
    substeps_ = n;
  }

  bool enabled() const noexcept { return enabled_; }
  void reset() noexcept { started_ = false; }
  // Carry over `from`'s modelled surface positions (the same actuators, another bank's copy;
  // turbulence_bank_set.h). noexcept.
  void carry_over(const ActuatorLimits& from) noexcept {
    started_ = from.started_;
    delta_ = from.delta_;
  }
  const UVector& position() const noexcept { return delta_; }   // the modelled surfaces, rad

  // The command the filters see for this frame's commands u (absolute); u itself when off
  // or not finite (the bank then rejects the frame and nothing here moves).
  template <class U>
  void effective(const U& u, UVector& u_eff) noexcept {
    u_eff = u;
    if (!enabled_ || !u.allFinite()) return;
    const int nu = static_cast<int>(u.size());
    if (!started_) {
      for (int j = 0; j < nu; ++j) delta_(j) = std::clamp(u(j), -limit_(j), limit_(j));
      started_ = true;
    }
    for (int j = 0; j < nu; ++j) {
      if (std::isinf(limit_(j))) continue;  // no actuator: u_eff_j = u_j
      const double c = std::clamp(u(j), -limit_(j), limit_(j));
      const double start = delta_(j);
      double d = start;
      for (int k = 0; k < substeps_; ++k) {
        const double target = c + (d - c) * decay_(j);
        d += std::clamp(target - d, -max_step_(j), max_step_(j));
      }
      delta_(j) = d;
      u_eff(j) = (d - a_(j) * start) / b_(j);
    }
  }

 private:
  bool enabled_ = false, started_ = false;
  int substeps_ = 1;
  UVector delta_, decay_, max_step_, limit_, a_, b_;
};

}  // namespace f16mmae
