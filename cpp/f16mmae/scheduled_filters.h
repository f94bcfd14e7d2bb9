// ScheduledFilters — the hypothesis filters and trims of a BankSchedule (bank_schedule.h),
// selected on measured air data. Eigen and std only. HierarchicalBank owns one when its
// ModelBank carries a schedule, and asks it, frame by frame, which filters and trims are in
// force.
//
// The schedule follows the air data through a first-order low-pass (time constant
// air_data_time_constant_s, frame period dt, alpha = 1 - exp(-dt / tau)), started as the
// running mean of the selections since the last reset (n = 1, 2, ...):
//   a_f,n = a_f,n-1 + max(alpha, 1/n) (a_n - a_f,n-1),   so a_f,1 = a_1,
// i.e. a_f is the mean of a_1..a_n while 1/n > alpha (the first tau of flight) and the
// low-pass after, so measurement noise does not move the trims frame to frame (a trim that
// jitters, with the states moved to follow it, reads to the filters as a kick off equilibrium
// every frame) and the first sample's noise is not held for tau (held, 0.002 Mach of noise
// is a VEL trim 2 ft/s off, 4 sigma of the VEL sensor, that a cover VEL hypothesis explains
// and NONE does not); the flight condition itself changes slowly. Everything below is of a_f.
//
// Two ways to schedule (ScheduleOptions::mode):
//   interpolate  bilinear on the grid cell holding the air data (weights w of
//                bank_schedule.h, corners c):
//                  trims (u_trim, z_trim, x_trim) every frame, to third order when
//                  ScheduleOptions::cubic_trims and the 4 x 4 nodes around the point are
//                  covered: the tensor product of the 4-point Lagrange weights on each axis,
//                    L_j(v) = prod_{k != j} (v - v_k) / (v_j - v_k),  trim = sum_jk L_j(M) L_k(h) trim_jk
//                  (4 nodes of an axis around the cell, fewer on a shorter axis; centred if
//                  covered, else shifted by one or two nodes); else, with row trims
//                  (ScheduleOptions::row_trims, the default) row by row: on an altitude
//                  stencil as above, each row of non-zero weight blended by the Lagrange
//                  weights of its own Mach stencil, 4 nodes, else 3, else 2, all covered in
//                  the layer in force, the one nearest centred on the point among those whose
//                  span reaches within a cell of it,
//                    trim = sum_k L_k(h) sum_j L_kj(M) trim_jk,
//                  (where the trimmable envelope's edge takes a node from the 4 x 4 stencil the
//                  trim's 1/M^2 is still followed: at Mach 0.3453, 26,582 ft AOA 0.0002 rad off
//                  the truth model's trim, bilinearly 0.0024; docs/results/envelope_scheduled.md,
//                  round 37); in a cell with one uncovered corner, within kDiagonalBlendCells of
//                  the diagonal (d its own coordinate there: a - b for a missing (0,1)) they
//                  move linearly to the triangle's trims, (1 - beta) rows + beta linear, beta =
//                  max(0, 1 - d / kDiagonalBlendCells), so they meet the other half's plane on
//                  the diagonal (without the blend, noisy air data crossing it read a 0.004-rad
//                  AOA step as a failure); else bilinearly, trim = sum_c w_c trim_c. The trim
//                  is far from linear in Mach (alpha goes about as 1/M^2), and a trim
//                  interpolated linearly is off the
//                  model's equilibrium enough to be taken for a failure (docs/results/schedule.md).
//                  Phi, Bd, H, K, A, A⁻¹, ln|A|, H_out = sum_c w_c (that of corner c)
//                  (HypothesisFilter::assign_blend), re-blended when the air data has moved
//                  blend_step_cells or more (in s or t) since the last blend (the first
//                  selection after a reset always blends); at a node the filters are that
//                  node's, bit for bit. A cell with one uncovered corner (the trimmable
//                  envelope's edge cuts it) is split along the diagonal that avoids that
//                  corner: in the half of the three covered corners, linear weights there
//                  (corners (0,0) (1,0) (0,1) (1,1) of the cell, uncovered (0,1):
//                  w = (1-a, a-b, 0, b); the others likewise), for filters and trims (third
//                  order or row by row where covered, above); in the other half, or with two
//                  or more corners uncovered, the nearest covered node instead (counted in
//                  fallback_frames()). Plane trims (ScheduleOptions::plane_trims, the default;
//                  off: the nearest node's trims too): in the missing corner's half the trims
//                  are those of the covered triangle's plane, extrapolated, the same linear
//                  weights with one of them negative (uncovered (0,1): w = (1-a, a-b, 0, b),
//                  a - b < 0 there), while the filters stay the nearest node's. The trims are
//                  then continuous across the diagonal, where the nearest node's jumped, and
//                  near the aircraft's where the trimmable envelope's edge cuts the grid: at
//                  Mach 0.32, 29,000 ft VEL 0.1 ft/s and AOA 0.0015 rad off the truth model's
//                  trim, against the nearest node's 31 ft/s and 0.042 rad
//                  (docs/results/envelope_scheduled.md, round 37). Neighbour trims
//                  (ScheduleOptions::neighbour_trims, the default, with plane_trims): in a cell
//                  missing two or more corners the trims are those of its edge-adjacent cells
//                  that miss at most one (bilinear, or the covered triangle's), extended to the
//                  point and blended with weights 1/d, d the distance in cells to each, so they
//                  meet each neighbour's trims on the shared edge (the nearest node's jumped
//                  there, and noisy air data on it crossed back and forth).
//                  Lift trims (ScheduleOptions::lift_trims, the default): in a cut cell the
//                  linear trims (the covered triangle's, the plane's, the neighbours' triangles;
//                  a covered neighbour's stay bilinear) are linear not in (s, t) but in
//                  (lambda, t), lambda the lift coordinate
//                    lambda = (delta(h) M^2)^(-3/4),   delta the standard atmosphere's p / p0,
//                  by barycentric weights on the triangle's nodes (extended outside it); the
//                  airspeed components (measurement VEL, state u_fps) keep the (s, t) weights,
//                  airspeed being a(h) M. In level flight C_L = W / (q S), q = 0.7 p0 delta M^2,
//                  so alpha, the surfaces and the load factor are functions of 1 / (delta M^2)
//                  nearly alone; the exponent 3/4 follows the truth model's trimmed alpha along
//                  the low-speed edge, where C_L(alpha) bends (linear in 1 / (delta M^2) the
//                  planes overshoot by 0.0025 rad, linear in Mach they fall short by 0.005):
//                  there the schedule's AOA trim is within 0.0003 rad of the truth model's
//                  (docs/results/envelope_scheduled.md, round 38).
//                  Stabilator trims (ScheduleOptions::stabilator_trims, the default, with
//                  plane_trims): past the trimmable envelope's edge (a missing half whose missing
//                  corner is covered in no layer; a cell missing two or more corners through its
//                  neighbours' planes) the stabilators' trims (inputs LS, RS; their lag states
//                  d_ls_rad, d_rs_rad) are not the plane's but a curve in the trim alpha: the
//                  layer's edge table, its nodes that are corners of a cell with a corner
//                  covered in no layer, ordered by their trim alpha (state alpha_rad),
//                  piecewise linear between them and extended linearly past its ends, read at
//                  the alpha of the trims in force. Blended with the plane over the first
//                  kDiagonalBlendCells past the diagonal,
//                    stab = (1 - gamma) plane + gamma table(alpha),   gamma = min(1, d / kDiagonalBlendCells),
//                  d the distance past the diagonal (b - a for a missing (0,1)), so the trims
//                  meet the covered half's on it; in a cell missing two or more corners each
//                  neighbour's plane term carries its own gamma at the point (0 for a
//                  neighbour not cut by the edge) and the table the blend of them, so the
//                  trims meet each neighbour's on the shared edge. Why: along the edge alpha is
//                  high and the stabilator trim bends with it (the flap, the pitch break:
//                  -0.0325 rad at alpha 0.265 to -0.0547 at 0.327), which no plane through a
//                  cell's three nodes follows; 0.012 rad off at Mach 0.36, 34,000 ft, read as a
//                  stabilator failure; along the table within 0.0006 rad at 22 edge points
//                  (docs/results/envelope_scheduled.md, round 39).
//   nearest      the nearest covered node's filters and trims, switched with hysteresis: the
//                node in force changes only when another is nearer by hysteresis_cells
//                (distance in cell units); the trims switch with it.
// Air data outside the axes is clamped to them (counted in outside_frames()).
//
// Configuration layers (bank_schedule.h): the layer in force at a point is the
// configuration law applied to the trim state component v = sum_c w_c v_c / sum_c w_c of the
// cell's covered corners (bilinear weights w, each corner's node of the lowest layer), so the
// configuration switches where the schedule's trims cross the threshold. Interpolate: the
// filters are blended from the corners' nodes in that layer (a corner not covered in it
// counts as uncovered: triangle or nearest node in the layer, as above), and re-blended at
// once when the layer changes; the third-order trims take each stencil node in that layer
// where it is covered there, else in its own (the trims change little across a switch, the
// dynamics much). Nearest: the nearest node in the layer, switched at once on a layer change.
//
// Per-node adaptation reference (a schedule whose nodes carry adapt_reference,
// bank_schedule.h): blended with the filters' weights, rho_0 = sum_c w_c rho_0,c, and
// changed with them (adapt_reference()); HierarchicalBank hands it to its turbulence
// adaptation when ScheduleOptions::node_adapt_reference. A schedule whose nodes carry their
// calm-air reference (calm_reference) has it blended alike (calm_reference(); 1 when they
// carry none): calm_air_complete.h's bounds are relative to it; their reference scale
// (reference_scale) alike (reference_scale(); 1 when they carry none).
//
// Per-node probability floor: each node's bank recommends its own p_min (its estimator
// settings, bank_schedule.h). The floor in force is their geometric blend with the filters'
// weights, ln p_min = sum_c w_c ln p_min,c (the floor enters the declaration as ln p_min: the
// climb a failure's log-odds makes from it), exactly the common value when the weighted
// corners agree (a node's own, bit for bit), and 0 if a weighted corner has none (p_min 0);
// changed with the filters (p_min()). HierarchicalBank hands it to its FilterBank when
// ScheduleOptions::node_p_min.
//
// Handover (HierarchicalBank applies it): when x_trim changes from x_old to x_new every
// on-line filter's states move by x_old - x_new, so the absolute state estimate
// x_trim + x is continuous (bumpless); probabilities, declarations and the level are not
// touched by a schedule change.
//
// select() and filter() are noexcept and allocate nothing for fixed sizes.
#pragma once

#include "f16mmae/air_data.h"
#include "f16mmae/bank_schedule.h"
#include "f16mmae/running_mean.h"
#include "f16mmae/steady_state_filter.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

enum class ScheduleMode { kInterpolate, kNearest };

struct ScheduleOptions {
  ScheduleMode mode = ScheduleMode::kInterpolate;
  double air_data_time_constant_s = 2.0;  // low-pass of the air data, s, >= 0 (0: none)
  bool cubic_trims = true;                // interpolate: trims to third order where covered
  bool plane_trims = true;                // interpolate: the missing corner's half takes the plane's trims
  bool row_trims = true;                  // interpolate: where no 4 x 4 stencil is covered, row by row
  bool neighbour_trims = true;            // interpolate, plane_trims: a cell missing 2+ corners, neighbours' planes
  bool lift_trims = true;                 // interpolate: a cut cell's linear trims in the lift coordinate
  bool stabilator_trims = true;           // interpolate, plane_trims: past the edge, stabilators along alpha
  bool gust_airspeed = false;             // HierarchicalBank: the schedule's Mach less the estimated gust's
  double hysteresis_cells = 0.1;       // nearest: margin before switching node, cell units, >= 0
  double blend_step_cells = 1.0 / 16;  // interpolate: air-data move that re-blends, cell units, >= 0
  bool node_adapt_reference = true;    // the nodes' adaptation reference, where they carry one
  bool node_p_min = true;              // the nodes' probability floors (their banks' p_min)
};

inline void check_schedule_options(const ScheduleOptions& o) {
  if (!(std::isfinite(o.air_data_time_constant_s) && o.air_data_time_constant_s >= 0.0))
    throw std::invalid_argument("schedule: air_data_time_constant_s must be finite and >= 0, got " +
                                std::to_string(o.air_data_time_constant_s));
  if (!(std::isfinite(o.hysteresis_cells) && o.hysteresis_cells >= 0.0 && o.hysteresis_cells < 1.0))
    throw std::invalid_argument("schedule: hysteresis_cells must be in [0, 1), got " +
                                std::to_string(o.hysteresis_cells));
  if (!(std::isfinite(o.blend_step_cells) && o.blend_step_cells >= 0.0 && o.blend_step_cells < 1.0))
    throw std::invalid_argument("schedule: blend_step_cells must be in [0, 1), got " +
                                std::to_string(o.blend_step_cells));
}

template <int NX, int NU, int NZ>
class ScheduledFilters {
 public:
  using Hypothesis = HypothesisFilter<NX, NU, NZ>;
  using Model = FilterModel<NX, NU, NZ>;
  using XVector = typename Hypothesis::XVector;
  using UVector = typename Hypothesis::UVector;
  using ZVector = typename Hypothesis::ZVector;
  using OutputMatrix = Eigen::Matrix<double, NZ, NX>;   // H_out: blended state -> z_hat
  static constexpr int kCorners = 4;
  // Row trims in a cut cell's covered half within this many cells of its diagonal (the
  // diagonal's own coordinate, e.g. a - b) move linearly to the triangle's trims on it (header).
  static constexpr double kDiagonalBlendCells = 0.25;
  // The lift coordinate's exponent: lambda = (delta M^2)^(-kLiftExponent) (header).
  static constexpr double kLiftExponent = 0.75;

  ScheduledFilters() = default;

  // Every node's filters (validated) and trims; starts at the air data `start`.
  ScheduledFilters(const BankSchedule& schedule, const ScheduleOptions& options, const AirData& start,
                   double frame_rate_hz)
      : options_(options) {
    schedule.validate();
    check_schedule_options(options);
    alpha_ = options.air_data_time_constant_s > 0.0
                 ? 1.0 - std::exp(-1.0 / (frame_rate_hz * options.air_data_time_constant_s))
                 : 1.0;
    mean_frames_ = running_mean_length(alpha_);
    axes_.mach = schedule.mach;
    axes_.alt_ft = schedule.alt_ft;
    axes_.switch_state = schedule.switch_state;
    axes_.switch_thresholds = schedule.switch_thresholds;
    hypotheses_ = static_cast<int>(schedule.nodes[0].bank.hypotheses.size());
    const int n_nodes = static_cast<int>(schedule.nodes.size());
    filters_.reserve(static_cast<std::size_t>(n_nodes) * hypotheses_);
    for (const ScheduleNode& node : schedule.nodes) {
      ScheduleNode geometry;  // the axes' geometry only; banks stay in filters_ and the trims
      geometry.i_mach = node.i_mach;
      geometry.i_alt = node.i_alt;
      geometry.layer = node.layer;
      axes_.nodes.push_back(std::move(geometry));
      const std::string where = "schedule node (Mach " + std::to_string(schedule.mach[node.i_mach]) + ", " +
                                std::to_string(schedule.alt_ft[node.i_alt]) + " ft) ";
      for (const HypothesisModel& h : node.bank.hypotheses)
        filters_.emplace_back(Model::from_matrices(h.phi, h.bd, h.h, h.k, h.a, h.uninformative_width,
                                                   h.uninformative_level_q, where + "hypothesis '" + h.name + "'"),
                              where + "hypothesis '" + h.name + "'");
      u_trim_.push_back(node.bank.u_trim);
      z_trim_.push_back(node.bank.z_trim);
      x_trim_.push_back(node.x_trim);
      h_out_.push_back(node.bank.h_output);
      reference_.push_back(node.adapt_reference);
      calm_.push_back(node.calm_reference);
      scale_.push_back(node.reference_scale);
      p_min_.push_back(node.bank.estimator.p_min);
      lift_.push_back(lift_coordinate(schedule.mach[node.i_mach], schedule.alt_ft[node.i_alt]));
    }
    const ModelBank& first = schedule.nodes[0].bank;
    z_speed_ = position(first.measurement_names, "VEL");
    x_speed_ = position(first.state_names, "u_fps");
    has_reference_ = schedule.has_adapt_reference();
    has_calm_ = schedule.has_calm_reference();
    has_scale_ = schedule.has_reference_scale();
    const int ni = static_cast<int>(axes_.mach.size()), nj = static_cast<int>(axes_.alt_ft.size());
    lookup_.assign(static_cast<std::size_t>(axes_.layers()) * ni * nj, -1);
    lookup_any_.assign(lookup_.size(), -1);
    for (int l = 0; l < axes_.layers(); ++l)
      for (int i = 0; i < ni; ++i)
        for (int j = 0; j < nj; ++j) {
          lookup_[(static_cast<std::size_t>(l) * ni + i) * nj + j] = axes_.node_index(i, j, l);
          lookup_any_[(static_cast<std::size_t>(l) * ni + i) * nj + j] = axes_.node_index_any(i, j, l);
        }
    build_edge_tables(first);
    if (!u_trim_.empty()) u_lin_ = u_trim_[0], z_lin_ = z_trim_[0], x_lin_ = x_trim_[0];   // sized once
    reset(start);
  }

  bool active() const noexcept { return !filters_.empty(); }

  // Back to the air data `start`, counters zeroed.
  void reset(const AirData& start) noexcept {
    outside_ = fallback_ = switches_ = blends_ = 0;
    rows_key_ = RowKey{};   // the row stencils chosen afresh
    filtered_ = start;
    selections_ = 0;
    const GridPoint g = axes_.locate(start);
    node_ = axes_.nearest(g, layer_at(cell_of(g)));
    choose(g);
    take_filter_weights();
    blend_trims(g);
    last_s_ = g.s, last_t_ = g.t;
  }

  // Selects what is in force for air data `a` (finite). Returns true when the filters
  // changed (the caller reloads its on-line filters through filter()); the trims are
  // recomputed every call (u_trim(), z_trim(), x_trim()).
  bool select(const AirData& a) noexcept {
    const bool primed = selections_ > 0;
    if (primed) {
      // the running mean's gain 1/n while it is at least alpha (n <= mean_frames_), then
      // alpha; n stops counting at mean_frames_
      const bool mean = selections_ < mean_frames_;
      const double gain = mean ? 1.0 / static_cast<double>(selections_ + 1) : alpha_;
      filtered_.mach += gain * (a.mach - filtered_.mach);
      filtered_.pressure_altitude_ft += gain * (a.pressure_altitude_ft - filtered_.pressure_altitude_ft);
      if (mean) ++selections_;
    } else {
      filtered_ = a;
      selections_ = 1;
    }
    const GridPoint g = axes_.locate(filtered_);
    if (g.outside) ++outside_;
    bool changed = false;
    if (options_.mode == ScheduleMode::kNearest) {
      const int best = axes_.nearest(g, layer_at(cell_of(g)));
      const bool other_layer = axes_.nodes[best].layer != axes_.nodes[node_].layer;
      if (best != node_ &&
          (other_layer || axes_.distance(g, node_) - axes_.distance(g, best) > options_.hysteresis_cells)) {
        node_ = best;
        ++switches_;
        changed = true;
      }
      choose(g);
      take_filter_weights();
    } else {
      choose(g);
      if (fallback_now_) ++fallback_;
      if (!primed || layer_now_ != filter_layer_ || std::abs(g.s - last_s_) >= options_.blend_step_cells ||
          std::abs(g.t - last_t_) >= options_.blend_step_cells) {
        take_filter_weights();  // the filters follow: re-blend
        last_s_ = g.s, last_t_ = g.t;
        ++blends_;
        changed = true;
      }
    }
    blend_trims(g);
    return changed;
  }

  // The filter in force for ModelBank hypothesis h, written into `out` (noexcept).
  void filter(int h, Hypothesis& out) const noexcept {
    const Hypothesis* f[kCorners];
    for (int c = 0; c < kCorners; ++c) f[c] = &filters_[static_cast<std::size_t>(corners_[c]) * hypotheses_ + h];
    out.assign_blend(f, weights_.data(), kCorners);
  }
  // The filter of hypothesis h at covered node n (its designed filter, unblended).
  const Hypothesis& node_filter(int n, int h) const noexcept {
    return filters_[static_cast<std::size_t>(n) * hypotheses_ + h];
  }

  // H_out of the filters in force (the blend of the corners' h_output), into `out`.
  void h_output(OutputMatrix& out) const noexcept {
    out = weights_[0] * h_out_[corners_[0]];
    for (int c = 1; c < kCorners; ++c)
      if (weights_[c] != 0.0) out += weights_[c] * h_out_[corners_[c]];
  }
  const UVector& u_trim() const noexcept { return u_now_; }
  const ZVector& z_trim() const noexcept { return z_now_; }
  const XVector& x_trim() const noexcept { return x_now_; }
  // Whether the nodes carry an adaptation reference, and its blend over the filters in force.
  bool has_adapt_reference() const noexcept { return has_reference_; }
  double adapt_reference() const noexcept { return reference_now_; }
  // Whether the nodes carry a calm-air reference, and its blend over the filters in force (1
  // when they carry none).
  bool has_calm_reference() const noexcept { return has_calm_; }
  double calm_reference() const noexcept { return calm_now_; }
  // Whether the nodes carry a reference scale, and its blend over the filters in force (1 when
  // they carry none).
  bool has_reference_scale() const noexcept { return has_scale_; }
  double reference_scale() const noexcept { return scale_now_; }
  // The probability floor of the filters in force (header comment).
  double p_min() const noexcept { return p_min_now_; }
  // The nodes and weights of the filters in force (weights 1, 0, 0, 0 at one node), and
  // the low-passed air data the schedule follows.
  const std::array<int, kCorners>& corners() const noexcept { return corners_; }
  const std::array<double, kCorners>& weights() const noexcept { return weights_; }
  const AirData& filtered_air_data() const noexcept { return filtered_; }
  // The configuration layer of the filters in force (0 for a schedule of one layer).
  int layer() const noexcept { return filter_layer_; }
  const BankSchedule& axes() const noexcept { return axes_; }   // axes and node indices only
  int node_count() const noexcept { return static_cast<int>(axes_.nodes.size()); }
  const ScheduleOptions& options() const noexcept { return options_; }
  std::int64_t outside_frames() const noexcept { return outside_; }
  std::int64_t fallback_frames() const noexcept { return fallback_; }
  std::int64_t switches() const noexcept { return switches_; }
  std::int64_t blends() const noexcept { return blends_; }

 private:
  // What the air data point g calls for, into trim_corners_ / trim_weights_. Interpolate
  // mode: the cell's corners and weights if all four are covered, else the nearest node
  // (fallback_now_). Nearest mode: node_ alone.
  // The grid cell holding g: its lower corner (i, j), upper (i1, j1) and bilinear weights.
  struct Cell {
    int i, j, i1, j1;
    std::array<double, kCorners> w;
  };
  Cell cell_of(const GridPoint& g) const noexcept {
    const int ni = static_cast<int>(axes_.mach.size()), nj = static_cast<int>(axes_.alt_ft.size());
    Cell c;
    c.i = std::min(static_cast<int>(std::floor(g.s)), ni > 1 ? ni - 2 : 0);
    c.j = std::min(static_cast<int>(std::floor(g.t)), nj > 1 ? nj - 2 : 0);
    const double a = ni > 1 ? g.s - c.i : 0.0, b = nj > 1 ? g.t - c.j : 0.0;
    c.i1 = ni > 1 ? c.i + 1 : c.i;
    c.j1 = nj > 1 ? c.j + 1 : c.j;
    c.w = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
    return c;
  }
  // The configuration layer at a cell (header comment): the law on the weighted trim state
  // component of its covered corners; 0 for a schedule of one layer.
  int layer_at(const Cell& cell) const noexcept {
    if (axes_.switch_state < 0) return 0;
    const int ii[kCorners] = {cell.i, cell.i1, cell.i, cell.i1}, jj[kCorners] = {cell.j, cell.j, cell.j1, cell.j1};
    double sum = 0.0, weight = 0.0;
    for (int k = 0; k < kCorners; ++k) {
      if (cell.w[k] == 0.0) continue;
      const int n = index_any(ii[k], jj[k], 0);
      if (n < 0) continue;
      sum += cell.w[k] * x_trim_[n](axes_.switch_state);
      weight += cell.w[k];
    }
    return weight > 0.0 ? axes_.layer_of(sum / weight) : axes_.nodes[node_].layer;
  }
  void choose(const GridPoint& g) noexcept {
    fallback_now_ = plane_now_ = lift_now_ = false;
    diagonal_share_ = edge_share_ = 0.0;
    if (options_.mode == ScheduleMode::kNearest) {
      layer_now_ = axes_.nodes[node_].layer;
      return choose_node(node_);
    }
    const Cell cell = cell_of(g);
    const int i = cell.i, j = cell.j, i1 = cell.i1, j1 = cell.j1;
    const double a = g.s - i, b = g.t - j;
    const int layer = layer_now_ = layer_at(cell);
    const std::array<int, kCorners> c = {index(i, j, layer), index(i1, j, layer), index(i, j1, layer),
                                         index(i1, j1, layer)};
    std::array<double, kCorners> w = cell.w;
    int uncovered = 0, missing = -1;
    for (int k = 0; k < kCorners; ++k)
      if (c[k] < 0 && w[k] != 0.0) ++uncovered, missing = k;
    bool triangle = uncovered == 1;   // its three corners covered (a corner of weight 0 may not be)
    for (int k = 0; k < kCorners && triangle; ++k) triangle = k == missing || c[k] >= 0;
    if (uncovered == 1 && !triangle_weights(missing, a, b, w)) {
      if (options_.plane_trims && triangle) {   // the trims on the covered triangle's plane, extrapolated
        plane_now_ = true;
        lift_now_ = options_.lift_trims;
        std::array<double, kCorners> lw = w;
        if (lift_now_) lift_weights(c, missing, j, point_lift(g), g.t, lw);
        edge_share_ = edge_share(i, j, missing, a, b);
        plane_terms_ = 0;
        for (int k = 0; k < kCorners; ++k)
          if (k != missing) {
            plane_corners_[plane_terms_] = c[k], plane_lift_[plane_terms_] = lw[k];
            plane_keep_[plane_terms_] = 1.0 - edge_share_;
            plane_weights_[plane_terms_++] = w[k];
          }
      }
      uncovered = 2;
    }
    if (uncovered > 1 && options_.plane_trims && options_.neighbour_trims && !plane_now_)
      neighbour_planes(g, cell, layer);
    if (uncovered > 1) {
      fallback_now_ = true;
      return choose_node(axes_.nearest(g, layer));
    }
    if (uncovered == 1) {   // the covered half: how far from the diagonal (0 on it)
      diagonal_share_ = std::max(0.0, 1.0 - covered_side(missing, a, b) / kDiagonalBlendCells);
      lift_now_ = options_.lift_trims && triangle;   // its weights when the linear trims are used (blend_trims)
      lift_missing_ = missing, lift_row_ = j;
    }
    for (int k = 0; k < kCorners; ++k) {
      trim_corners_[k] = c[k] >= 0 ? c[k] : first_covered(c);  // weight 0 where uncovered
      trim_weights_[k] = w[k];
    }
  }
  // The lift coordinate of the air data at g.
  double point_lift(const GridPoint& g) const noexcept {
    return lift_coordinate(axis_value(axes_.mach, g.s), axis_value(axes_.alt_ft, g.t));
  }
  // The lift coordinate at Mach `mach`, pressure altitude `alt_ft` (header): (delta M^2)^(-3/4),
  // delta the standard atmosphere's pressure ratio.
  static double lift_coordinate(double mach, double alt_ft) noexcept {
    const double delta = alt_ft < 36089.24 ? std::pow(1.0 - 6.8755856e-6 * alt_ft, 5.2558797)
                                           : 0.2233609 * std::exp(-4.806346e-5 * (alt_ft - 36089.24));
    return std::pow(delta * mach * mach, -kLiftExponent);
  }
  // The physical value at fractional coordinate x of an axis.
  static double axis_value(const std::vector<double>& axis, double x) noexcept {
    const int i = std::min(static_cast<int>(std::floor(x)), static_cast<int>(axis.size()) - 1);
    const double frac = x - i;
    return frac == 0.0 ? axis[i] : axis[i] + frac * (axis[i + 1] - axis[i]);
  }
  // Linear weights at the point (lambda lp, t) on the triangle of the corners (cell row j) other
  // than `missing` (all three covered, nodes c) in the coordinates (lambda, t), into w (w[missing] =
  // 0): the barycentric coordinates, extended outside the triangle; w unchanged where lambda is not
  // finite or the three are collinear in (lambda, t).
  void lift_weights(const std::array<int, kCorners>& c, int missing, int j, double lp, double tp,
                    std::array<double, kCorners>& w) const noexcept {
    int k3[3], n = 0;
    for (int k = 0; k < kCorners; ++k)
      if (k != missing) k3[n++] = k;
    double l[3], t[3];
    for (int m = 0; m < 3; ++m) l[m] = lift_[c[k3[m]]], t[m] = j + (k3[m] >> 1);
    const double d = (l[1] - l[0]) * (t[2] - t[0]) - (l[2] - l[0]) * (t[1] - t[0]);
    // a Mach axis from 0 gives lambda = inf; collinear nodes d = 0: w as given
    if (!(std::isfinite(lp) && std::isfinite(d) && std::abs(d) > 1e-9 * (std::abs(l[0]) + 1.0))) return;
    const double w1 = ((lp - l[0]) * (t[2] - t[0]) - (l[2] - l[0]) * (tp - t[0])) / d;
    const double w2 = ((l[1] - l[0]) * (tp - t[0]) - (lp - l[0]) * (t[1] - t[0])) / d;
    w = {0.0, 0.0, 0.0, 0.0};
    w[k3[0]] = 1.0 - w1 - w2, w[k3[1]] = w1, w[k3[2]] = w2;
  }
  // A cut cell's diagonal coordinate at (a, b): positive in the covered half, negative past the
  // diagonal, in cells (e.g. a - b for a missing (0,1)).
  static double covered_side(int missing, double a, double b) noexcept {
    return missing == 0 ? a + b - 1 : missing == 1 ? b - a : missing == 2 ? a - b : 1 - a - b;
  }
  // The edge table's share gamma at (a, b) of the cell (i, j) whose corner `missing` is uncovered
  // in the layer in force (header): 0 unless that corner is covered in no layer and the layer has
  // an edge table.
  double edge_share(int i, int j, int missing, double a, double b) const noexcept {
    if (!options_.stabilator_trims || edge_nodes_[static_cast<std::size_t>(layer_now_)].size() < 2) return 0.0;
    if (index_any(i + (missing & 1), j + (missing >> 1), 0) >= 0) return 0.0;
    return std::min(1.0, std::max(0.0, -covered_side(missing, a, b)) / kDiagonalBlendCells);
  }
  // The index of `name` in `names`, or -1.
  static int position(const std::vector<std::string>& names, const char* name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  }
  // Each layer's edge table (header): its nodes that are corners of a cell with a corner covered
  // in no layer, ordered by trim alpha (ties: the first), and the components it sets; none
  // without a state alpha_rad or a stabilator.
  void build_edge_tables(const ModelBank& first) {
    x_alpha_ = position(first.state_names, "alpha_rad");
    u_stab_ = {position(first.input_names, "LS"), position(first.input_names, "RS")};
    x_stab_ = {position(first.state_names, "d_ls_rad"), position(first.state_names, "d_rs_rad")};
    edge_nodes_.assign(static_cast<std::size_t>(axes_.layers()), {});
    edge_alpha_.assign(edge_nodes_.size(), {});
    const bool stabilator = u_stab_[0] >= 0 || u_stab_[1] >= 0 || x_stab_[0] >= 0 || x_stab_[1] >= 0;
    if (x_alpha_ < 0 || !stabilator) return;
    const int ni = static_cast<int>(axes_.mach.size()), nj = static_cast<int>(axes_.alt_ft.size());
    for (int l = 0; l < axes_.layers(); ++l) {
      std::vector<int>& nodes = edge_nodes_[static_cast<std::size_t>(l)];
      for (int i = 0; i + 1 < ni; ++i)
        for (int j = 0; j + 1 < nj; ++j) {
          bool edge = false;
          for (int k = 0; k < kCorners; ++k) edge = edge || index_any(i + (k & 1), j + (k >> 1), 0) < 0;
          if (!edge) continue;
          for (int k = 0; k < kCorners; ++k) {
            const int n = index(i + (k & 1), j + (k >> 1), l);
            if (n >= 0 && std::find(nodes.begin(), nodes.end(), n) == nodes.end()) nodes.push_back(n);
          }
        }
      std::stable_sort(nodes.begin(), nodes.end(),
                       [&](int p, int q) { return x_trim_[p](x_alpha_) < x_trim_[q](x_alpha_); });
      std::vector<double>& alpha = edge_alpha_[static_cast<std::size_t>(l)];
      std::vector<int> distinct;
      for (int n : nodes)
        if (alpha.empty() || x_trim_[n](x_alpha_) > alpha.back()) distinct.push_back(n), alpha.push_back(x_trim_[n](x_alpha_));
      nodes = std::move(distinct);
    }
  }
  // The edge table of the layer in force at trim alpha `alpha`: its two nodes (a segment, the
  // first or last past the ends) and the second's weight f.
  void edge_segment(double alpha, int& n0, int& n1, double& f) const noexcept {
    const std::vector<double>& al = edge_alpha_[static_cast<std::size_t>(layer_now_)];
    const std::vector<int>& nodes = edge_nodes_[static_cast<std::size_t>(layer_now_)];
    std::size_t k = 0;
    while (k + 2 < al.size() && alpha > al[k + 1]) ++k;
    n0 = nodes[k], n1 = nodes[k + 1];
    f = (alpha - al[k]) / (al[k + 1] - al[k]);
  }
  // Trims in a cell with two or more uncovered corners (header comment): each edge-adjacent cell
  // with at most one uncovered corner in the layer, its linear weights (bilinear, or its covered
  // triangle's) extended to g, blended with weights 1 / d, d the distance in cells from g to that
  // cell, into the plane terms; none (plane_now_ false) where no neighbour qualifies.
  void neighbour_planes(const GridPoint& g, const Cell& cell, int layer) noexcept {
    const int ni = static_cast<int>(axes_.mach.size()), nj = static_cast<int>(axes_.alt_ft.size());
    const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
    const double d[4] = {g.s - cell.i, cell.i1 - g.s, g.t - cell.j, cell.j1 - g.t};
    double total = 0.0, lp = 0.0;
    bool lifted = false;   // the point's lift coordinate, computed once
    plane_terms_ = 0;
    for (int side = 0; side < 4; ++side) {
      const int i = cell.i + di[side], j = cell.j + dj[side];
      if (i < 0 || j < 0 || i + 1 >= ni || j + 1 >= nj) continue;
      const std::array<int, kCorners> c = {index(i, j, layer), index(i + 1, j, layer), index(i, j + 1, layer),
                                           index(i + 1, j + 1, layer)};
      int missing = -1, uncovered = 0;
      for (int k = 0; k < kCorners; ++k)
        if (c[k] < 0) ++uncovered, missing = k;
      if (uncovered > 1) continue;
      const double a = g.s - i, b = g.t - j;
      std::array<double, kCorners> w = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
      if (uncovered == 1) triangle_weights(missing, a, b, w);   // extended past the triangle: some negative
      std::array<double, kCorners> lw = w;
      if (uncovered == 1 && options_.lift_trims) {
        if (!lifted) lp = point_lift(g), lifted = true;
        lift_weights(c, missing, j, lp, g.t, lw);
      }
      const double share = 1.0 / std::max(d[side], 1e-12);
      const double gamma = uncovered == 1 ? edge_share(i, j, missing, a, b) : 0.0;
      for (int k = 0; k < kCorners; ++k)
        if (c[k] >= 0) {
          plane_corners_[plane_terms_] = c[k], plane_lift_[plane_terms_] = share * lw[k];
          plane_keep_[plane_terms_] = 1.0 - gamma;
          plane_weights_[plane_terms_++] = share * w[k];
        }
      total += share;
      edge_share_ += share * gamma;
    }
    if (total == 0.0) return;
    for (int k = 0; k < plane_terms_; ++k) plane_weights_[k] /= total, plane_lift_[k] /= total;
    edge_share_ /= total;
    plane_now_ = true;
    lift_now_ = options_.lift_trims;
  }
  // Linear weights on the triangle of the three corners other than `missing` (header
  // comment), into w; false when (a, b) lies outside that triangle (the missing corner's half).
  static bool triangle_weights(int missing, double a, double b, std::array<double, kCorners>& w) noexcept {
    switch (missing) {
      case 0: w = {0.0, 1 - b, 1 - a, a + b - 1}; break;
      case 1: w = {1 - b, 0.0, b - a, a}; break;
      case 2: w = {1 - a, a - b, 0.0, b}; break;
      default: w = {1 - a - b, a, b, 0.0}; break;
    }
    for (double v : w)
      if (v < 0.0) return false;
    return true;
  }
  // BankSchedule::node_index / node_index_any from the tables built at construction (grid
  // indices within the axes).
  int index(int i, int j, int layer) const noexcept {
    return lookup_[(static_cast<std::size_t>(layer) * axes_.mach.size() + i) * axes_.alt_ft.size() + j];
  }
  int index_any(int i, int j, int layer) const noexcept {
    return lookup_any_[(static_cast<std::size_t>(layer) * axes_.mach.size() + i) * axes_.alt_ft.size() + j];
  }
  // The filters in force follow the trims' corners and weights (and the reference with them).
  void take_filter_weights() noexcept {
    corners_ = trim_corners_, weights_ = trim_weights_;
    filter_layer_ = layer_now_;
    blend_p_min();
    if (has_calm_) calm_now_ = blend(calm_);
    if (has_scale_) scale_now_ = blend(scale_);
    if (has_reference_) reference_now_ = blend(reference_);
  }
  // sum_c w_c v_c over the filters' corners (a per-node reference).
  double blend(const std::vector<double>& per_node) const noexcept {
    double v = 0.0;
    for (int c = 0; c < kCorners; ++c)
      if (weights_[c] != 0.0) v += weights_[c] * per_node[corners_[c]];
    return v;
  }
  // p_min_now_ from the filters' corners and weights (header comment).
  void blend_p_min() noexcept {
    double common = -1.0, log_sum = 0.0;
    bool same = true;
    for (int c = 0; c < kCorners; ++c) {
      if (weights_[c] == 0.0) continue;
      const double p = p_min_[corners_[c]];
      same = same && (common < 0.0 || p == common);
      common = p;
      if (p <= 0.0) {
        p_min_now_ = 0.0;
        return;
      }
      log_sum += weights_[c] * std::log(p);
    }
    p_min_now_ = same ? common : std::exp(log_sum);
  }
  static int first_covered(const std::array<int, kCorners>& c) noexcept {
    for (int k : c)
      if (k >= 0) return k;
    return 0;
  }
  void choose_node(int n) noexcept {
    trim_corners_ = {n, n, n, n};
    trim_weights_ = {1.0, 0.0, 0.0, 0.0};
  }
  // The Lagrange weights at fractional coordinate x of an axis on the n = min(4, size) nodes
  // first..first+n-1 (physical values).
  static void lagrange(const std::vector<double>& axis, double x, int first, int n, std::array<double, 4>& w) noexcept {
    const int size = static_cast<int>(axis.size());
    const int i = std::min(static_cast<int>(std::floor(x)), size - 1);
    const double frac = x - i;  // 0 on a node: v is the node's value exactly
    const double v = frac == 0.0 ? axis[i] : axis[i] + frac * (axis[i + 1] - axis[i]);
    for (int j = 0; j < n; ++j) {
      double l = 1.0;
      for (int k = 0; k < n; ++k)
        if (k != j) l *= (v - axis[first + k]) / (axis[first + j] - axis[first + k]);
      w[j] = l;
    }
  }
  // The stencil starts to try on an axis, centred first: the cell's node - 1, then the cell's
  // node, then - 2 (each within the axis); returns how many.
  static int starts(int size, double x, std::array<int, 3>& out) noexcept {
    const int n = size < 4 ? size : 4;
    const int cell = std::min(static_cast<int>(std::floor(x)), size > 1 ? size - 2 : 0);
    int count = 0;
    for (int c : {cell - 1, cell, cell - 2}) {
      const int f = std::max(0, std::min(c, size - n));
      bool seen = false;
      for (int k = 0; k < count; ++k) seen = seen || out[k] == f;
      if (!seen) out[count++] = f;
    }
    return count;
  }
  // Adds w times node n's trims to the trims in force; the first call (first) assigns them.
  void add_trims(double w, int n, bool& first) noexcept {
    if (first) {
      u_now_ = w * u_trim_[n], z_now_ = w * z_trim_[n], x_now_ = w * x_trim_[n];
      first = false;
    } else {
      u_now_ += w * u_trim_[n], z_now_ += w * z_trim_[n], x_now_ += w * x_trim_[n];
    }
  }
  // Third-order trims at g (header comment) on the first stencil whose nodes of non-zero
  // weight are all covered; false, changing nothing, if there is none.
  bool blend_trims_cubic(const GridPoint& g) noexcept {
    const int sm = static_cast<int>(axes_.mach.size()), sa = static_cast<int>(axes_.alt_ft.size());
    const int nm = sm < 4 ? sm : 4, na = sa < 4 ? sa : 4;
    std::array<int, 3> fms{}, fas{};
    const int cm = starts(sm, g.s, fms), ca = starts(sa, g.t, fas);
    for (int a = 0; a < cm * ca; ++a) {
      const int fm = fms[a / ca], fa = fas[a % ca];
      std::array<double, 4> wm{}, wa{};
      lagrange(axes_.mach, g.s, fm, nm, wm);
      lagrange(axes_.alt_ft, g.t, fa, na, wa);
      int nodes[16];
      bool covered = true;
      for (int j = 0; j < nm && covered; ++j)
        for (int k = 0; k < na && covered; ++k) {
          nodes[j * 4 + k] = index_any(fm + j, fa + k, layer_now_);
          covered = nodes[j * 4 + k] >= 0 || wm[j] * wa[k] == 0.0;
        }
      if (!covered) continue;
      bool first = true;
      for (int j = 0; j < nm; ++j)
        for (int k = 0; k < na; ++k) {
          const double w = wm[j] * wa[k];
          if (w != 0.0) add_trims(w, nodes[j * 4 + k], first);
        }
      return !first;
    }
    return false;
  }
  // Row by row: on the first altitude stencil (starts()) each of whose rows of non-zero weight
  // has a Mach stencil of 4, else 3, else 2 nodes all covered in the layer in force whose span
  // reaches within one cell of g.s (the nearest such start), the Lagrange blend of the rows'
  // Lagrange blends; false, changing nothing, if there is none. The stencils chosen are kept while
  // the choice cannot change (RowKey: it changes only where g.s crosses a multiple of 1/2, g.t a
  // node, or the layer), so a frame recomputes only the weights.
  bool blend_trims_rows(const GridPoint& g) noexcept {
    const RowKey key{layer_now_, static_cast<int>(std::floor(2.0 * g.s)), 2.0 * g.s == std::floor(2.0 * g.s),
                     static_cast<int>(std::floor(g.t)), g.t == std::floor(g.t)};
    const int na = static_cast<int>(axes_.alt_ft.size()) < 4 ? static_cast<int>(axes_.alt_ft.size()) : 4;
    std::array<double, 4> wa{}, wm{};
    for (bool fresh = !(key == rows_key_);; fresh = true) {
      if (fresh) {
        rows_key_ = key;
        choose_rows(g);
      }
      if (rows_.fa < 0) return false;
      lagrange(axes_.alt_ft, g.t, rows_.fa, na, wa);
      // every row of non-zero weight has its stencil, else choose afresh (a weight that rounds
      // to 0 just off a node would have left its row out of the kept choice)
      bool weighed = true;
      for (int k = 0; k < na; ++k) weighed = weighed && (wa[k] == 0.0 || rows_.n[k] > 0);
      if (weighed || fresh) break;
    }
    bool first = true;
    for (int k = 0; k < na; ++k) {
      if (wa[k] == 0.0) continue;
      lagrange(axes_.mach, g.s, rows_.f[k], rows_.n[k], wm);
      for (int j = 0; j < rows_.n[k]; ++j)
        add_trims(wa[k] * wm[j], index(rows_.f[k] + j, rows_.fa + k, layer_now_), first);
    }
    return !first;
  }
  // The row stencils blend_trims_rows takes at g, into rows_ (fa -1: none).
  void choose_rows(const GridPoint& g) noexcept {
    const int sm = static_cast<int>(axes_.mach.size()), sa = static_cast<int>(axes_.alt_ft.size());
    const int na = sa < 4 ? sa : 4;
    std::array<int, 3> fas{};
    const int ca = starts(sa, g.t, fas);
    rows_.fa = -1;
    for (int a = 0; a < ca; ++a) {
      std::array<double, 4> wa{};
      lagrange(axes_.alt_ft, g.t, fas[a], na, wa);
      RowStencils r{fas[a], {}, {}};
      bool rows = true;
      for (int k = 0; k < na && rows; ++k) {
        if (wa[k] == 0.0) continue;
        const int row = fas[a] + k;
        for (int n = std::min(4, sm); n >= 2 && r.n[k] == 0; --n) {
          double best = 1e9;   // cells past the stencil's span (at most 1), then off its centre
          for (int f = 0; f + n <= sm; ++f) {
            const double past = std::max({0.0, f - g.s, g.s - (f + n - 1)});
            const double score = 100.0 * past + std::abs(f + 0.5 * (n - 1) - g.s);
            if (past > 1.0 || score >= best) continue;
            bool covered = true;
            for (int j = 0; j < n && covered; ++j) covered = index(f + j, row, layer_now_) >= 0;
            if (!covered) continue;
            best = score;
            r.f[k] = f;
            r.n[k] = n;
          }
        }
        rows = r.n[k] > 0;
      }
      if (!rows) continue;
      rows_ = r;
      return;
    }
  }
  void blend_trims(const GridPoint& g) noexcept {
    if (options_.mode == ScheduleMode::kInterpolate && options_.cubic_trims && !fallback_now_ && blend_trims_cubic(g))
      return;
    if (options_.mode == ScheduleMode::kInterpolate && options_.cubic_trims && options_.row_trims && !fallback_now_ &&
        blend_trims_rows(g)) {
      if (diagonal_share_ > 0.0) {   // near a cut cell's diagonal: toward the linear trims (header)
        take_triangle_lift(g);
        blend_trims_linear(u_lin_, z_lin_, x_lin_);
        u_now_ += diagonal_share_ * (u_lin_ - u_now_);
        z_now_ += diagonal_share_ * (z_lin_ - z_now_);
        x_now_ += diagonal_share_ * (x_lin_ - x_now_);
      }
      return;
    }
    take_triangle_lift(g);
    blend_trims_linear(u_now_, z_now_, x_now_);
  }
  // A cut cell's covered half: the triangle's lift weights, computed only where its linear trims
  // are used (choose() leaves them to here; the missing half's plane has its own).
  void take_triangle_lift(const GridPoint& g) noexcept {
    if (lift_now_ && !plane_now_) lift_weights(trim_corners_, lift_missing_, lift_row_, point_lift(g), g.t, trim_lift_);
  }
  // The corners' linear blend (bilinear, the triangle's, or the plane terms) into (u, z, x); in a
  // cut cell with lift trims, the lift weights but for the airspeed components (header).
  void blend_trims_linear(UVector& u, ZVector& z, XVector& x) const noexcept {
    const int* c = plane_now_ ? plane_corners_.data() : trim_corners_.data();
    const double* w = plane_now_ ? plane_weights_.data() : trim_weights_.data();
    const double* l = !lift_now_ ? w : plane_now_ ? plane_lift_.data() : trim_lift_.data();
    const int n = plane_now_ ? plane_terms_ : kCorners;
    u = l[0] * u_trim_[c[0]];
    z = l[0] * z_trim_[c[0]];
    x = l[0] * x_trim_[c[0]];
    for (int k = 1; k < n; ++k) {
      if (l[k] == 0.0) continue;
      u += l[k] * u_trim_[c[k]];
      z += l[k] * z_trim_[c[k]];
      x += l[k] * x_trim_[c[k]];
    }
    if (l != w) {
      if (z_speed_ >= 0) {
        z(z_speed_) = 0.0;
        for (int k = 0; k < n; ++k) z(z_speed_) += w[k] * z_trim_[c[k]](z_speed_);
      }
      if (x_speed_ >= 0) {
        x(x_speed_) = 0.0;
        for (int k = 0; k < n; ++k) x(x_speed_) += w[k] * x_trim_[c[k]](x_speed_);
      }
    }
    if (edge_share_ > 0.0) blend_stabilators(c, l, n, u, x);
  }
  // Past the trimmable edge (edge_share_ > 0): the stabilators' trims, the plane terms' (c, l, n)
  // kept shares and the edge table at the trims' alpha (header).
  void blend_stabilators(const int* c, const double* l, int n, UVector& u, XVector& x) const noexcept {
    int n0 = 0, n1 = 0;
    double f = 0.0;
    edge_segment(x(x_alpha_), n0, n1, f);
    const double t0 = edge_share_ * (1.0 - f), t1 = edge_share_ * f;
    for (int s = 0; s < 2; ++s) {
      if (u_stab_[s] >= 0) {
        double v = t0 * u_trim_[n0](u_stab_[s]) + t1 * u_trim_[n1](u_stab_[s]);
        for (int k = 0; k < n; ++k) v += l[k] * plane_keep_[k] * u_trim_[c[k]](u_stab_[s]);
        u(u_stab_[s]) = v;
      }
      if (x_stab_[s] >= 0) {
        double v = t0 * x_trim_[n0](x_stab_[s]) + t1 * x_trim_[n1](x_stab_[s]);
        for (int k = 0; k < n; ++k) v += l[k] * plane_keep_[k] * x_trim_[c[k]](x_stab_[s]);
        x(x_stab_[s]) = v;
      }
    }
  }

  ScheduleOptions options_;
  BankSchedule axes_;                 // axes and node grid indices (no banks)
  std::vector<Hypothesis> filters_;   // node n, hypothesis h at n * hypotheses_ + h
  std::vector<UVector> u_trim_;
  std::vector<ZVector> z_trim_;
  std::vector<XVector> x_trim_;
  std::vector<OutputMatrix> h_out_;
  std::vector<double> reference_;     // per node adapt_reference (NaN: not carried)
  std::vector<double> calm_;          // per node calm_reference (NaN: not carried)
  std::vector<double> scale_;         // per node reference_scale (NaN: not carried)
  std::vector<double> p_min_;         // per node p_min (its bank's estimator settings)
  std::vector<int> lookup_, lookup_any_;   // (layer, i, j) -> node_index, node_index_any
  bool has_reference_ = false;
  double reference_now_ = 0.0;        // blend of the filters in force
  bool has_calm_ = false;
  double calm_now_ = 1.0;             // blend of the filters in force (1: not carried)
  bool has_scale_ = false;
  double scale_now_ = 1.0;            // blend of the filters in force (1: not carried)
  double p_min_now_ = 0.0;            // blend of the filters in force
  int hypotheses_ = 0;
  int node_ = 0;                      // nearest mode: the node in force
  std::array<int, kCorners> corners_{};          // of the filters in force (the last blend)
  std::array<double, kCorners> weights_{};
  std::array<int, kCorners> trim_corners_{};     // of the trims in force (the air data now)
  std::array<double, kCorners> trim_weights_{};
  // plane_trims (plane_now_): the covered triangle's corners and weights, or the neighbours' terms
  static constexpr int kPlaneTerms = 4 * kCorners;
  std::array<int, kPlaneTerms> plane_corners_{};
  std::array<double, kPlaneTerms> plane_weights_{};
  std::array<double, kPlaneTerms> plane_lift_{};   // lift_trims: the same terms' weights in (lambda, t)
  std::array<double, kPlaneTerms> plane_keep_{};   // stabilator_trims: each term's share kept, 1 - gamma
  int plane_terms_ = 0;
  double edge_share_ = 0.0;                        // stabilator_trims: the edge table's share (0: none)
  std::vector<std::vector<int>> edge_nodes_;       // per layer its edge table's nodes by trim alpha
  std::vector<std::vector<double>> edge_alpha_;    // ... and their trim alphas, ascending
  int x_alpha_ = -1;                               // the state alpha_rad (-1: none)
  std::array<int, 2> u_stab_{-1, -1}, x_stab_{-1, -1};   // LS, RS: inputs and lag states (-1: none)
  std::array<double, kCorners> trim_lift_{};       // lift_trims: the covered triangle's in (lambda, t)
  int lift_missing_ = 0, lift_row_ = 0;            // ... its missing corner and cell row
  bool lift_now_ = false;                          // a cut cell's lift weights are in force
  std::vector<double> lift_;                       // per node its lift coordinate
  int z_speed_ = -1, x_speed_ = -1;                // the airspeed components (VEL, u_fps; -1: none)
  bool plane_now_ = false;
  AirData filtered_;                             // the low-passed air data
  double alpha_ = 1.0;
  std::int64_t selections_ = 0;                  // selections since the last reset, up to mean_frames_
  std::int64_t mean_frames_ = 1;                 // running_mean_length(alpha_) (running_mean.h)
  double last_s_ = 0.0, last_t_ = 0.0;           // air data at the last blend
  bool fallback_now_ = false;
  int layer_now_ = 0;                            // the layer the air data now calls for
  int filter_layer_ = 0;                         // the layer of the filters in force
  // The row stencils in force (blend_trims_rows) and what they were chosen for.
  struct RowStencils {
    int fa = -1;                          // the altitude stencil's first row (-1: none)
    std::array<int, 4> f{}, n{};          // each row's Mach stencil: first node and count (0: weight 0)
  };
  struct RowKey {
    int layer = -1, half_s = 0;
    bool on_half = false;
    int cell_t = 0;
    bool on_node = false;
    bool operator==(const RowKey& o) const noexcept {
      return layer == o.layer && half_s == o.half_s && on_half == o.on_half && cell_t == o.cell_t && on_node == o.on_node;
    }
  };
  RowStencils rows_;
  RowKey rows_key_;                       // layer -1: nothing chosen yet
  UVector u_now_, u_lin_;
  ZVector z_now_, z_lin_;
  XVector x_now_, x_lin_;
  double diagonal_share_ = 0.0;   // row trims near a cut cell's diagonal: the linear trims' share
  std::int64_t outside_ = 0, fallback_ = 0, switches_ = 0, blends_ = 0;
};

}  // namespace f16mmae
