// AirData — the measured air data the estimator may schedule on (and nothing else): Mach
// number and pressure altitude as the F-16's air data system delivers them to the flight
// control computer, with that system's noise and lag. Never the truth state: the truth model's
// air-data sensor produces it (docs/INTERFACES.md). Air data is not a failure hypothesis and
// carries no failure truth; air-data failures are out of scope.
//
// A value is usable when both fields are finite; a bank given one that is not keeps its
// schedule at the last usable value and counts the frame (HierarchicalBank::schedule).
#pragma once

#include <cmath>

namespace f16mmae {

struct AirData {
  double mach = 0.0;
  double pressure_altitude_ft = 0.0;

  bool finite() const noexcept { return std::isfinite(mach) && std::isfinite(pressure_altitude_ft); }
};

}  // namespace f16mmae
