// running_mean.h — a plain mean that hands over to a first-order low-pass, without a division
// per sample once it has handed over.
//
//   m_1 = x_1,   m_i = m_{i-1} + a_i (x_i - m_{i-1}),   a_i = max(1/i, alpha)   (i = 2, 3, ...)
//
// i.e. the mean of the first samples while 1/i >= alpha (right within the low-pass' time
// constant of a start), then the low-pass of gain alpha. running_mean_length(alpha) is n, the
// largest i with 1.0/i >= alpha in double arithmetic (n >= 1): taking a_i = 1.0/i for i <= n
// and alpha from i = n + 1 on gives max(1.0/i, alpha) bit for bit (where 1.0/i == alpha the two
// are the same number), so a caller counts samples up to n and divides no more after that.
// Users: the scheduled filters' air-data low-pass (scheduled_filters.h), the turbulence
// adaptation's measured power ratio and its lull floor's long average
// (turbulence_adaptation.h), the residual whiteness
// (residual_whiteness.h) and the load factor's spread (maneuver_kinematics.h). std only.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace f16mmae {

// n of the header for a gain alpha in (0, 1]; alpha <= 0 (no low-pass to hand over to): the
// largest int64, a mean forever.
inline std::int64_t running_mean_length(double alpha) noexcept {
  constexpr auto kForever = std::numeric_limits<std::int64_t>::max();
  if (!(alpha > 0.0)) return kForever;
  const double guess = std::floor(1.0 / alpha);
  if (!(guess < 9.0e18)) return kForever;
  auto n = static_cast<std::int64_t>(guess);
  if (n < 1) n = 1;
  while (n > 1 && 1.0 / static_cast<double>(n) < alpha) --n;   // the rounding of 1 / alpha
  while (1.0 / static_cast<double>(n + 1) >= alpha) ++n;
  return n;
}

}  // namespace f16mmae
