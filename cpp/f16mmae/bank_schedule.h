// BankSchedule — a scheduled model bank: model banks designed on a grid over the flight
// envelope (Mach x pressure altitude), and the geometry that maps measured air data onto the
// grid. Eigen and std only; the file format lives in cpp/bankfile/schedule_file.h.
//
// Grid: strictly ascending axes mach[0..I-1] and alt_ft[0..J-1]; node (i, j) sits at
// (mach[i], alt_ft[j]). A node is *covered* when a bank was designed there (points that do not
// trim are left out). Each covered node carries its ModelBank (every hypothesis filter, u_trim,
// z_trim) and x_trim (nx), the trim state the filters' perturbation states are taken from
// (the absolute state estimate is x_trim + x). A node may also carry its own adaptation
// reference (adapt_reference, the turbulence adaptation's rho_0 at that node,
// turbulence_adaptation.h), chosen by the design so that the node's estimator keeps its
// no-failure calibration flights a set distance from a declaration (the design states its
// rule and records it in the metadata). Either every
// node carries one or none does (NaN: not carried, the estimator's own option applies).
// A node may also carry its calm-air reference (calm_reference: the turbulence adaptation's
// measured power ratio ρ̄ midway between the node's calm air and light turbulence, which
// calm_air_complete.h's bounds are relative to); every node or none, as the adaptation
// reference. A node may also carry its reference scale (reference_scale, sigma > 0: its bank's
// measured power ratio over that of the node's bank of another failure model, the one its
// adaptation references and the estimator's climb and maneuver references were chosen on, on the
// same calibration flights; design/schedule.py): the turbulence adaptation reads its power ratio
// divided by sigma (turbulence_adaptation.h's power scale, hierarchical_bank.h); every node or
// none, as the adaptation reference.
// Each node's bank also recommends its own estimator settings (EstimatorSettings, checked by
// ModelBank::validate); its p_min is the node's probability floor, which the core blends
// with the filters (scheduled_filters.h). The primary node's settings are those the schedule
// as a whole reports. The schedule as a whole also recommends the estimator's start-up
// (start_up_s, filter_bank.h; 0: none): the design bounds the nodes' floors and references
// on flights flown with it, so the file is to be flown with it (the scheduled-bank file
// reports it as its ModelBank's estimator.start_up_s).
//
// Configuration layers (an aircraft whose configuration switches with the flight condition,
// e.g. the F-16's leading-edge flap, scheduled on trim alpha): a node also has a layer l
// (0 .. L-1), the configuration its bank was designed in; a grid point may be covered in
// several layers (its own configuration and, near a switch, the neighbouring one).
// switch_state (an index into x_trim) and the ascending switch_thresholds (L - 1 values)
// state the configuration law: at a point whose trim state component is v, the layer is
// the number of thresholds below v,  l(v) = #{k : v > switch_thresholds[k]}.
// switch_state = -1 (no thresholds): one layer, every node in layer 0.
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
// or not strictly ascending; switch_state and switch_thresholds not given together, thresholds
// not ascending; a node layer outside the layers; a node index outside the axes or covered
// twice in one layer; an x_trim of the
// wrong size or not finite; an adapt_reference outside [0, 100] or a calm_reference outside
// (0, 100], a reference_scale outside (0, 100], either carried by some nodes and not by others; a start_up_s outside [0, kMaxStartUpS]; a primary node that is not one of the nodes; node banks whose names, sizes, frame rate or tuning differ from
// node 0's (each node bank is validated by ModelBank::validate on load).
#pragma once

#include "f16mmae/air_data.h"
#include "f16mmae/model_bank.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct ScheduleNode {
  int i_mach = 0;          // index on BankSchedule::mach
  int i_alt = 0;           // index on BankSchedule::alt_ft
  int layer = 0;           // configuration layer (header comment)
  ModelBank bank;          // the bank designed at (mach[i_mach], alt_ft[i_alt])
  Eigen::VectorXd x_trim;  // (nx) trim state of that design
  double adapt_reference = std::numeric_limits<double>::quiet_NaN();  // rho_0 at the node, or NaN
  double calm_reference = std::numeric_limits<double>::quiet_NaN();   // ρ̄ between calm and light air, or NaN
  double reference_scale = std::numeric_limits<double>::quiet_NaN();  // sigma (header), or NaN
};

// Where air data falls on the grid (see the header comment).
struct GridPoint {
  double s = 0.0, t = 0.0;  // fractional coordinates, clamped to the axes
  bool outside = false;     // some coordinate was clamped
};

struct BankSchedule {
  // 2: per-node adapt_reference; 3: start_up_s; 4: calm_reference; 5: reference_scale
  static constexpr std::uint32_t kFormatVersion = 5;

  // Whether the nodes carry their own adaptation reference (validate: all or none).
  bool has_adapt_reference() const noexcept { return !nodes.empty() && !std::isnan(nodes[0].adapt_reference); }
  // Whether the nodes carry their calm-air reference (validate: all or none).
  bool has_calm_reference() const noexcept { return !nodes.empty() && !std::isnan(nodes[0].calm_reference); }
  // Whether the nodes carry their reference scale (validate: all or none).
  bool has_reference_scale() const noexcept { return !nodes.empty() && !std::isnan(nodes[0].reference_scale); }

  std::vector<double> mach;    // ascending Mach axis
  std::vector<double> alt_ft;  // ascending pressure-altitude axis, ft
  std::vector<ScheduleNode> nodes;
  int primary = 0;             // the node in force before air data arrives (nodes index)
  int switch_state = -1;       // x_trim index of the configuration law, -1: one layer
  std::vector<double> switch_thresholds;   // ascending; layers = size + 1
  std::string metadata;        // JSON text: how the schedule was made (provenance only)
  // The estimator start-up the design recommends for the whole schedule, s (filter_bank.h's
  // start_up_s: its nodes' floors and references were bounded on flights flown with it);
  // 0: none. In [0, kMaxStartUpS].
  double start_up_s = 0.0;

  int layers() const noexcept { return static_cast<int>(switch_thresholds.size()) + 1; }
  // The node at grid index (i, j) in `layer`, or -1.
  int node_index(int i, int j, int layer = 0) const noexcept {
    for (std::size_t n = 0; n < nodes.size(); ++n)
      if (nodes[n].i_mach == i && nodes[n].i_alt == j && nodes[n].layer == layer) return static_cast<int>(n);
    return -1;
  }
  // The node at (i, j) in `layer` if covered there, else the one of the lowest layer, or -1.
  int node_index_any(int i, int j, int layer) const noexcept {
    const int n = node_index(i, j, layer);
    if (n >= 0) return n;
    for (int l = 0; l < layers(); ++l) {
      const int m = node_index(i, j, l);
      if (m >= 0) return m;
    }
    return -1;
  }
  // The layer of the configuration law for a trim state component v.
  int layer_of(double v) const noexcept {
    int l = 0;
    for (double t : switch_thresholds) l += v > t ? 1 : 0;
    return l;
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

  // The covered node nearest to g (cell units) in `layer` (any layer when -1 or when the
  // layer has no node), ties to the lower index.
  int nearest(const GridPoint& g, int layer = -1) const noexcept {
    int best = -1;
    double best_d = 0.0;
    for (int n = 0; n < static_cast<int>(nodes.size()); ++n) {
      if (layer >= 0 && nodes[n].layer != layer) continue;
      const double d = distance(g, n);
      if (best < 0 || d < best_d) best = n, best_d = d;
    }
    return best >= 0 ? best : nearest(g, -1);
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
    if (switch_state < -1 || (switch_state == -1) != switch_thresholds.empty())
      fail("switch_state = " + std::to_string(switch_state) + " with " + std::to_string(switch_thresholds.size()) +
           " switch_thresholds: give both (a state index >= 0 and ascending thresholds) or neither (-1, none)");
    for (std::size_t k = 0; k < switch_thresholds.size(); ++k)
      if (!std::isfinite(switch_thresholds[k]) || (k > 0 && !(switch_thresholds[k] > switch_thresholds[k - 1])))
        fail("switch_thresholds must be finite and strictly ascending: switch_thresholds[" + std::to_string(k) +
             "] = " + std::to_string(switch_thresholds[k]));
    if (!(start_up_s >= 0.0 && start_up_s <= kMaxStartUpS))
      fail("start_up_s = " + format_value(start_up_s) + " must be in [0, " + format_value(kMaxStartUpS) + "] s");
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
      if (node.layer < 0 || node.layer >= layers())
        fail(who + ".layer = " + std::to_string(node.layer) + " is outside [0, " + std::to_string(layers() - 1) +
             "] (the layers of " + std::to_string(switch_thresholds.size()) + " switch_thresholds)");
      if (node_index(node.i_mach, node.i_alt, node.layer) != static_cast<int>(n))
        fail(who + " covers grid index (" + std::to_string(node.i_mach) + ", " + std::to_string(node.i_alt) +
             ") in layer " + std::to_string(node.layer) + " a second time");
      if (switch_state >= node.x_trim.size())
        fail("switch_state = " + std::to_string(switch_state) + " is not an index of " + who + ".x_trim (" +
             std::to_string(node.x_trim.size()) + " values)");
      const ModelBank& b = node.bank;
      if (node.x_trim.size() != b.nx() || !node.x_trim.allFinite())
        fail(who + ".x_trim must hold " + std::to_string(b.nx()) + " finite values, it has " +
             std::to_string(node.x_trim.size()));
      // a per-node value every node carries or none does (NaN: not carried), in its range when carried
      const auto carried = [&](const char* field, double value, double first_value, bool zero_allowed) {
        if (std::isnan(value) != std::isnan(first_value))
          fail(who + "." + field + " is " + (std::isnan(value) ? "missing" : "given") + " but nodes[0]'s is " +
               (std::isnan(first_value) ? "missing" : "given") + ": every node carries one or none does");
        if (!std::isnan(value) && !((zero_allowed ? value >= 0.0 : value > 0.0) && value <= 100.0))
          fail(who + "." + field + " must be in " + (zero_allowed ? "[0" : "(0") + ", 100], got " + std::to_string(value));
      };
      carried("adapt_reference", node.adapt_reference, nodes[0].adapt_reference, true);
      carried("calm_reference", node.calm_reference, nodes[0].calm_reference, false);
      carried("reference_scale", node.reference_scale, nodes[0].reference_scale, false);
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
