// ScheduledFilters — the hypothesis filters and trims of a BankSchedule (bank_schedule.h),
// selected on measured air data. Eigen and std only. HierarchicalBank owns one when its
// ModelBank carries a schedule, and asks it, frame by frame, which filters and trims are in
// force.
//
// Two ways to schedule (ScheduleOptions::mode):
//   interpolate  bilinear on the grid cell holding the air data (weights w of
//                bank_schedule.h, corners c):
//                  u_trim = sum_c w_c u_trim_c,  z_trim = sum_c w_c z_trim_c,
//                  x_trim = sum_c w_c x_trim_c                         (every frame)
//                  Phi, Bd, H, K, A, A⁻¹, ln|A| = sum_c w_c (that of corner c)
//                  (HypothesisFilter::assign_blend), re-blended when the air data has moved
//                  blend_step_cells or more (in s or t) since the last blend; at a node the
//                  filters are that node's, bit for bit. A cell with an uncovered corner uses
//                  the nearest covered node instead (counted in fallback_frames()).
//   nearest      the nearest covered node's filters and trims, switched with hysteresis: the
//                node in force changes only when another is nearer by hysteresis_cells
//                (distance in cell units); the trims switch with it.
// Air data outside the axes is clamped to them (counted in outside_frames()).
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
#include "f16mmae/steady_state_filter.h"

#include <Eigen/Dense>

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
  double hysteresis_cells = 0.1;       // nearest: margin before switching node, cell units, >= 0
  double blend_step_cells = 1.0 / 16;  // interpolate: air-data move that re-blends, cell units, >= 0
};

inline void check_schedule_options(const ScheduleOptions& o) {
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
  static constexpr int kCorners = 4;

  ScheduledFilters() = default;

  // Every node's filters (validated) and trims; starts at the air data `start`.
  ScheduledFilters(const BankSchedule& schedule, const ScheduleOptions& options, const AirData& start)
      : options_(options) {
    schedule.validate();
    check_schedule_options(options);
    axes_.mach = schedule.mach;
    axes_.alt_ft = schedule.alt_ft;
    hypotheses_ = static_cast<int>(schedule.nodes[0].bank.hypotheses.size());
    const int n_nodes = static_cast<int>(schedule.nodes.size());
    filters_.reserve(static_cast<std::size_t>(n_nodes) * hypotheses_);
    for (const ScheduleNode& node : schedule.nodes) {
      ScheduleNode geometry;  // the axes' geometry only; banks stay in filters_ and the trims
      geometry.i_mach = node.i_mach;
      geometry.i_alt = node.i_alt;
      axes_.nodes.push_back(std::move(geometry));
      const std::string where = "schedule node (Mach " + std::to_string(schedule.mach[node.i_mach]) + ", " +
                                std::to_string(schedule.alt_ft[node.i_alt]) + " ft) ";
      for (const HypothesisModel& h : node.bank.hypotheses)
        filters_.emplace_back(Model::from_matrices(h.phi, h.bd, h.h, h.k, h.a, where + "hypothesis '" + h.name + "'"),
                              where + "hypothesis '" + h.name + "'");
      u_trim_.push_back(node.bank.u_trim);
      z_trim_.push_back(node.bank.z_trim);
      x_trim_.push_back(node.x_trim);
    }
    reset(start);
  }

  bool active() const noexcept { return !filters_.empty(); }

  // Back to the air data `start`, counters zeroed.
  void reset(const AirData& start) noexcept {
    outside_ = fallback_ = switches_ = blends_ = 0;
    const GridPoint g = axes_.locate(start);
    node_ = axes_.nearest(g);
    choose(g);
    blend_trims();
    last_s_ = g.s, last_t_ = g.t;
  }

  // Selects what is in force for air data `a` (finite). Returns true when the filters
  // changed (the caller reloads its on-line filters through filter()); the trims are
  // recomputed every call (u_trim(), z_trim(), x_trim()).
  bool select(const AirData& a) noexcept {
    const GridPoint g = axes_.locate(a);
    if (g.outside) ++outside_;
    bool changed = false;
    if (options_.mode == ScheduleMode::kNearest) {
      const int best = axes_.nearest(g);
      if (best != node_ && axes_.distance(g, node_) - axes_.distance(g, best) > options_.hysteresis_cells) {
        node_ = best;
        choose_node(node_);
        ++switches_;
        changed = true;
      }
    } else {
      const bool moved = std::abs(g.s - last_s_) >= options_.blend_step_cells ||
                         std::abs(g.t - last_t_) >= options_.blend_step_cells;
      const std::array<int, kCorners> before = corners_;
      const std::array<double, kCorners> w_before = weights_;
      choose(g);
      if (fallback_now_) ++fallback_;
      if (corners_ != before || (moved && weights_ != w_before)) {
        last_s_ = g.s, last_t_ = g.t;
        ++blends_;
        changed = true;
      } else {
        corners_ = before;  // filters stay those of the last blend; trims follow the air data
        trim_weights_ = weights_;
        weights_ = w_before;
      }
    }
    blend_trims();
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

  const UVector& u_trim() const noexcept { return u_now_; }
  const ZVector& z_trim() const noexcept { return z_now_; }
  const XVector& x_trim() const noexcept { return x_now_; }
  // The nodes and weights of the filters in force (weights 1, 0, 0, 0 at one node).
  const std::array<int, kCorners>& corners() const noexcept { return corners_; }
  const std::array<double, kCorners>& weights() const noexcept { return weights_; }
  const BankSchedule& axes() const noexcept { return axes_; }   // axes and node indices only
  int node_count() const noexcept { return static_cast<int>(axes_.nodes.size()); }
  const ScheduleOptions& options() const noexcept { return options_; }
  std::int64_t outside_frames() const noexcept { return outside_; }
  std::int64_t fallback_frames() const noexcept { return fallback_; }
  std::int64_t switches() const noexcept { return switches_; }
  std::int64_t blends() const noexcept { return blends_; }

 private:
  // Interpolate mode: the cell's corners and weights if all four are covered, else the
  // nearest node (fallback_now_). Nearest mode: node_ alone.
  void choose(const GridPoint& g) noexcept {
    fallback_now_ = false;
    if (options_.mode == ScheduleMode::kNearest) return choose_node(node_);
    const int ni = static_cast<int>(axes_.mach.size()), nj = static_cast<int>(axes_.alt_ft.size());
    const int i = std::min(static_cast<int>(std::floor(g.s)), ni > 1 ? ni - 2 : 0);
    const int j = std::min(static_cast<int>(std::floor(g.t)), nj > 1 ? nj - 2 : 0);
    const double a = ni > 1 ? g.s - i : 0.0, b = nj > 1 ? g.t - j : 0.0;
    const int i1 = ni > 1 ? i + 1 : i, j1 = nj > 1 ? j + 1 : j;
    const std::array<int, kCorners> c = {axes_.node_index(i, j), axes_.node_index(i1, j), axes_.node_index(i, j1),
                                         axes_.node_index(i1, j1)};
    const std::array<double, kCorners> w = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
    for (int k = 0; k < kCorners; ++k) {
      if (c[k] < 0 && w[k] != 0.0) {
        fallback_now_ = true;
        return choose_node(axes_.nearest(g));
      }
    }
    for (int k = 0; k < kCorners; ++k) {
      corners_[k] = c[k] >= 0 ? c[k] : first_covered(c);  // weight 0 where uncovered
      weights_[k] = w[k];
    }
    trim_weights_ = weights_;
  }
  static int first_covered(const std::array<int, kCorners>& c) noexcept {
    for (int k : c)
      if (k >= 0) return k;
    return 0;
  }
  void choose_node(int n) noexcept {
    corners_ = {n, n, n, n};
    weights_ = {1.0, 0.0, 0.0, 0.0};
    trim_weights_ = weights_;
  }
  void blend_trims() noexcept {
    const std::array<int, kCorners>& c = corners_;
    const std::array<double, kCorners>& w = trim_weights_;
    u_now_ = w[0] * u_trim_[c[0]];
    z_now_ = w[0] * z_trim_[c[0]];
    x_now_ = w[0] * x_trim_[c[0]];
    for (int k = 1; k < kCorners; ++k) {
      if (w[k] == 0.0) continue;
      u_now_ += w[k] * u_trim_[c[k]];
      z_now_ += w[k] * z_trim_[c[k]];
      x_now_ += w[k] * x_trim_[c[k]];
    }
  }

  ScheduleOptions options_;
  BankSchedule axes_;                 // axes and node grid indices (no banks)
  std::vector<Hypothesis> filters_;   // node n, hypothesis h at n * hypotheses_ + h
  std::vector<UVector> u_trim_;
  std::vector<ZVector> z_trim_;
  std::vector<XVector> x_trim_;
  int hypotheses_ = 0;
  int node_ = 0;                      // nearest mode: the node in force
  std::array<int, kCorners> corners_{};
  std::array<double, kCorners> weights_{};       // of the filters in force
  std::array<double, kCorners> trim_weights_{};  // of the trims in force (the air data now)
  double last_s_ = 0.0, last_t_ = 0.0;           // air data at the last blend
  bool fallback_now_ = false;
  UVector u_now_;
  ZVector z_now_;
  XVector x_now_;
  std::int64_t outside_ = 0, fallback_ = 0, switches_ = 0, blends_ = 0;
};

}  // namespace f16mmae
