// BankSchedule — a scheduled model bank: model banks designed on a grid over the flight
// envelope (Mach x pressure altitude), and the geometry that maps measured air data onto the
// grid. Eigen and std only; the file format lives in cpp/bankfile/schedule_file.h.
//
// Grid: strictly ascending axes mach[0..I-1] and alt_ft[0..J-1]; node (i, j) sits at
// (mach[i], alt_ft[j]). A node is *covered* when a bank was designed there (points that do not
// trim are left out). Each covered node carries its ModelBank (every hypothesis filter, u_trim,
// z_trim) and x_trim (nx), the trim state the filters' perturbation states are taken from
// (the absolute state estimate is x_trim + x).
//
// Fractional grid coordinates of air data a = (M, h), clamped to the axes:
//   s = i + (M - mach[i]) / (mach[i+1] - mach[i])          for mach[i] <= M <= mach[i+1]
//   t = j + (h - alt[j]) / (alt[j+1] - alt[j])              likewise in altitude
// A value outside an axis is clamped to its end and the frame is counted as outside the grid.
// Distances between air data and nodes are measured in these cell units.
//
// Bilinear weights on the cell (i, j) = (floor s, floor t), with a = s - i, b = t - j:
//   w00 = (1-a)(1-b), w10 = a(1-b), w01 = (1-a) b, w11 = a b
// for the corners (i, j), (i+1, j), (i, j+1), (i+1, j+1). At a node the weights are exactly
// (1, 0, 0, 0). A cell with an uncovered corner cannot be interpolated bilinearly: the schedule
// uses linear weights on the triangle of its three covered corners where the point lies in
// it, else the nearest covered node (counted; scheduled_filters.h).
//
// validate() throws std::invalid_argument naming the field: axes that are empty, not finite
// or not strictly ascending; a node index outside the axes or covered twice; an x_trim of the
// wrong size or not finite; a primary node that is not one of the nodes; node banks whose names, sizes, frame rate or tuning differ from
// node 0's (each node bank is validated by ModelBank::validate on load).
#pragma once

#include "f16mmae/air_data.h"
#include "f16mmae/model_bank.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct ScheduleNode {
  int i_mach = 0;          // index on BankSchedule::mach
  int i_alt = 0;           // index on BankSchedule::alt_ft
  ModelBank bank;          // the bank designed at (mach[i_mach], alt_ft[i_alt])
  Eigen::VectorXd x_trim;  // (nx) trim state of that design
};

// Where air data falls on the grid (see the header comment).
struct GridPoint {
  double s = 0.0, t = 0.0;  // fractional coordinates, clamped to the axes
  bool outside = false;     // some coordinate was clamped
};

struct BankSchedule {
  static constexpr std::uint32_t kFormatVersion = 1;

  std::vector<double> mach;    // ascending Mach axis
  std::vector<double> alt_ft;  // ascending pressure-altitude axis, ft
  std::vector<ScheduleNode> nodes;
  int primary = 0;             // the node in force before air data arrives (nodes index)
  std::string metadata;        // JSON text: how the schedule was made (provenance only)

  int node_index(int i, int j) const noexcept {
    for (std::size_t n = 0; n < nodes.size(); ++n)
      if (nodes[n].i_mach == i && nodes[n].i_alt == j) return static_cast<int>(n);
    return -1;
  }

  // Fractional coordinate of v on an ascending axis (clamped; `outside` set when clamped).
  static double coordinate(const std::vector<double>& axis, double v, bool& outside) noexcept {
    const int n = static_cast<int>(axis.size());
    if (n == 1 || v <= axis.front()) {
      outside = outside || v < axis.front() || (n == 1 && v > axis.front());
      return 0.0;
    }
    if (v >= axis.back()) {
      outside = outside || v > axis.back();
      return n - 1.0;
    }
    const int i = static_cast<int>(std::upper_bound(axis.begin(), axis.end(), v) - axis.begin()) - 1;
    return i + (v - axis[i]) / (axis[i + 1] - axis[i]);
  }

  GridPoint locate(const AirData& a) const noexcept {
    GridPoint g;
    g.s = coordinate(mach, a.mach, g.outside);
    g.t = coordinate(alt_ft, a.pressure_altitude_ft, g.outside);
    return g;
  }

  // The covered node nearest to g (cell units), ties to the lower index.
  int nearest(const GridPoint& g) const noexcept {
    int best = 0;
    double best_d = distance(g, 0);
    for (int n = 1; n < static_cast<int>(nodes.size()); ++n) {
      const double d = distance(g, n);
      if (d < best_d) best = n, best_d = d;
    }
    return best;
  }
  double distance(const GridPoint& g, int n) const noexcept {
    const double ds = g.s - nodes[n].i_mach, dt = g.t - nodes[n].i_alt;
    return std::sqrt(ds * ds + dt * dt);
  }

  void validate() const {
    auto fail = [](const std::string& what) { throw std::invalid_argument("bank schedule: " + what); };
    auto check_axis = [&](const char* name, const std::vector<double>& axis) {
      if (axis.empty()) fail(std::string(name) + " axis is empty");
      for (std::size_t i = 0; i < axis.size(); ++i) {
        if (!std::isfinite(axis[i]) || axis[i] < 0.0)
          fail(std::string(name) + "[" + std::to_string(i) + "] = " + std::to_string(axis[i]) +
               " must be finite and >= 0");
        if (i > 0 && !(axis[i] > axis[i - 1]))
          fail(std::string(name) + " axis must be strictly ascending: " + name + "[" + std::to_string(i) +
               "] = " + std::to_string(axis[i]) + " after " + std::to_string(axis[i - 1]));
      }
    };
    check_axis("mach", mach);
    check_axis("alt_ft", alt_ft);
    if (nodes.empty()) fail("no covered node");
    if (primary < 0 || primary >= static_cast<int>(nodes.size()))
      fail("primary = " + std::to_string(primary) + " is not one of its " + std::to_string(nodes.size()) + " nodes");
    const ModelBank& first = nodes[0].bank;
    for (std::size_t n = 0; n < nodes.size(); ++n) {
      const ScheduleNode& node = nodes[n];
      const std::string who = "nodes[" + std::to_string(n) + "]";
      if (node.i_mach < 0 || node.i_mach >= static_cast<int>(mach.size()) || node.i_alt < 0 ||
          node.i_alt >= static_cast<int>(alt_ft.size()))
        fail(who + " at grid index (" + std::to_string(node.i_mach) + ", " + std::to_string(node.i_alt) +
             ") is outside the " + std::to_string(mach.size()) + " x " + std::to_string(alt_ft.size()) + " grid");
      if (node_index(node.i_mach, node.i_alt) != static_cast<int>(n))
        fail(who + " covers grid index (" + std::to_string(node.i_mach) + ", " + std::to_string(node.i_alt) +
             ") a second time");
      const ModelBank& b = node.bank;
      if (node.x_trim.size() != b.nx() || !node.x_trim.allFinite())
        fail(who + ".x_trim must hold " + std::to_string(b.nx()) + " finite values, it has " +
             std::to_string(node.x_trim.size()));
      if (b.state_names != first.state_names || b.input_names != first.input_names ||
          b.measurement_names != first.measurement_names)
        fail(who + ".bank has other state, input or measurement names than nodes[0]");
      if (b.hypotheses.size() != first.hypotheses.size())
        fail(who + ".bank has " + std::to_string(b.hypotheses.size()) + " hypotheses, nodes[0] has " +
             std::to_string(first.hypotheses.size()));
      for (std::size_t k = 0; k < b.hypotheses.size(); ++k)
        if (b.hypotheses[k].name != first.hypotheses[k].name)
          fail(who + ".bank hypothesis " + std::to_string(k) + " is '" + b.hypotheses[k].name +
               "', nodes[0] has '" + first.hypotheses[k].name + "'");
      if (b.frame_rate_hz != first.frame_rate_hz)
        fail(who + ".bank frame_rate_hz " + std::to_string(b.frame_rate_hz) + " differs from nodes[0]'s " +
             std::to_string(first.frame_rate_hz));
      if (b.tuning != first.tuning)
        fail(who + ".bank tuning '" + b.tuning + "' differs from nodes[0]'s '" + first.tuning + "'");
    }
  }
};

}  // namespace f16mmae
