// RoughAirFloor — the level-0 probability floor that follows the air (hierarchical_bank.h:
// options.rough_floor). Std only; throws only from check(); the floor is computed without
// allocation.
//
// The level-0 floor f_0 (the bank's p_min, or a scheduled bank's node floor in force,
// level_floors.h) is the prior of "a failure may have begun now". A scheduled bank's node floors
// are chosen on calibration flights in light air (design/calibrate.py bounded_settings): the
// largest floor whose failure-free log-odds stay below the threshold there. In rougher air the
// same floor lets gust-driven flaperon and rudder excursions reach the threshold (10-h moderate-air
// soaks at 15,000 ft with the nodes' 1e-5: 18-102 false declarations against 1-4 at 1e-9;
// docs/results/envelope_scheduled.md, round 45), while the least floor everywhere costs the light
// air the chosen floors' faster climb. With a rough-air floor f_r (p_min > 0) the floor in force
// moves from f_0 to f_r as the air roughens:
//
//     x = max(ρ̄, ρ_L) / ρ_c                       the air's residual power in calm-air units
//     w = clamp((x − x_a) / (x_b − x_a), 0, 1),  rounded to a multiple of 1/100
//     ln f = (1 − w) ln f_0 + w ln f_r            (bit for bit f_0 at w = 0 and where f_0 = f_r,
//                                                  f_r at w = 1; f_0 = 0, no floor: f = 0 while
//                                                  w < 1)
//
//   ρ̄: the turbulence adaptation's measured power ratio (turbulence_adaptation.h: the minimum over
//     the hypotheses on line of q_k / m averaged over τ, so a failure, which its own hypothesis
//     fits, does not raise it); ρ_L: the lull floor's longer average (τ_L), in x once it is in
//     force (τ_L / 2 after the start), so a lull of the gusts over τ does not lift the floor back
//     to the calm-air one while the air mass is rough; 0 before the first update (x = 0: f_0).
//     Over a flight's first frames ρ̄ is the plain mean of a few frames, and the filters' start
//     from x⁻ = 0 can read as rough air: the start-up (start_up_s, filter_bank.h: no hypothesis
//     weighed) covers them (light air at Mach 0.45, 15,000 ft: the first 0.4 s).
//   ρ_c: a scheduled bank's calm-air reference in force (bank_schedule.h: each node's ρ̄ in its
//     calibration's calm air, blended over the cell), 1 for a bank without one. In its units the
//     air reads alike over the envelope (ρ̄ / ρ_c: none 0.7-1.0, light 1.0-1.3, moderate 1.6-3.4,
//     severe 5 and up, 180-s flights at eleven points from 5,000 to 34,000 ft;
//     docs/results/envelope_scheduled.md, round 46), where the adaptation's scale s does not: it
//     stays at 1 in moderate air at 15,000 ft, whose ρ lies below the node's reference ρ_0.
//   x_a, x_b (from, to; defaults 1.3 and 1.5): between light air's upper reach and moderate air's
//     lower one.
//   w's rounding: the floors are set anew only when w moves by a step (set_p_min is a no-op
//     otherwise), not on every frame inside the band.
//
// Off (p_min = 0, the default): f = f_0 bit for bit. Refused (check): p_min < 0 or not below
// 1/K, x_a < 0, x_b <= x_a or either not finite or above 1000, and p_min > 0 without the
// turbulence adaptation (ρ̄ is its measure).
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "f16mmae/estimator_settings.h"

namespace f16mmae {

struct RoughAirFloorOptions {
  double p_min = 0.0;   // f_r, the floor in rough air; 0: off (the level-0 floor everywhere)
  double from = 1.3;    // x_a: below it the level-0 floor f_0 (calm-air units, header)
  double to = 1.5;      // x_b: above it f_r
  bool enabled() const noexcept { return p_min > 0.0; }
};

struct RoughAirFloor {
  static constexpr double kMaxRatio = 1000.0;
  static constexpr double kSteps = 100.0;   // w's rounding (header)

  static void check(const RoughAirFloorOptions& o, int k, bool adaptation_on) {
    if (!(o.p_min >= 0.0) || !(o.p_min * k < 1.0))
      throw std::invalid_argument("hierarchical bank: rough_p_min must lie in [0, 1/K) with K = " + std::to_string(k) +
                                  " hypotheses (0: off), got " + format_value(o.p_min));
    if (!(o.from >= 0.0 && o.from < kMaxRatio) || !(o.to > o.from && o.to <= kMaxRatio))
      throw std::invalid_argument("hierarchical bank: the rough-air floor's band needs 0 <= rough_p_min_from < "
                                  "rough_p_min_to <= " + format_value(kMaxRatio) + " (calm-air units), got " +
                                  format_value(o.from) + " and " + format_value(o.to));
    if (o.enabled() && !adaptation_on)
      throw std::invalid_argument("hierarchical bank: rough_p_min reads the air from the turbulence adaptation's "
                                  "measured power ratio; it needs adapt_turbulence on");
  }

  // w of the header for air ratio x (rounded to a multiple of 1 / kSteps).
  static double weight(const RoughAirFloorOptions& o, double x) noexcept {
    const double w = (x - o.from) / (o.to - o.from);
    if (!(w > 0.0)) return 0.0;   // NaN too: the level-0 floor
    if (w >= 1.0) return 1.0;
    return std::round(w * kSteps) / kSteps;
  }

  // The floor in force from the level-0 floor f0 and the air ratio x (header).
  static double floor(const RoughAirFloorOptions& o, double f0, double x) noexcept {
    if (!o.enabled() || f0 == o.p_min) return f0;
    const double w = weight(o, x);
    if (w == 0.0) return f0;
    if (w == 1.0) return o.p_min;
    if (f0 <= 0.0) return 0.0;
    return std::exp((1.0 - w) * std::log(f0) + w * std::log(o.p_min));
  }
};

}  // namespace f16mmae
