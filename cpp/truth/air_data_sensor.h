// f16mmae truth model: the air-data sensor's per-frame arithmetic (measured Mach number and
// pressure altitude, the air data the estimator may schedule on).
//
// The C++ twin of python/harness/f16mmae/truth/air_data.py, which is the reference and holds
// the constants and their sources; they come in through the fields below.  Per channel j
// (0 = Mach, 1 = pressure altitude ft), once per frame, with n_j a standard normal drawn by
// the caller from the air-data stream:
//   first frame:  y_j = ideal_j                        (an aircraft already in flight)
//   every frame:  y_j = ideal_j + (y_j - ideal_j) * decay     decay = exp(-dt / tau)
//                 m_j = y_j + n_j * sigma_j
// written in the Python code's order of operations so both give the same doubles.
// Standard library only; nothing here allocates.
#pragma once

#include <array>

namespace f16mmae::truth {

inline constexpr int kAirData = 2;  // Mach, pressure altitude (ft)
using AirDataValues = std::array<double, kAirData>;

struct AirDataSensor {
  double decay = 0.0;
  AirDataValues sigma{};
  AirDataValues lag{};
  bool started = false;

  void reset() { started = false; }

  /// The measured values from the ideal ones and the standard normals normal[0..1].
  AirDataValues measure(const AirDataValues& ideal, const double* normal) {
    if (!started) {
      lag = ideal;
      started = true;
    }
    AirDataValues out{};
    for (int j = 0; j < kAirData; ++j) {
      lag[j] = ideal[j] + (lag[j] - ideal[j]) * decay;
      out[j] = lag[j] + normal[j] * sigma[j];
    }
    return out;
  }
};

}  // namespace f16mmae::truth
