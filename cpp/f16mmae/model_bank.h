// ModelBank — the in-memory model bank: every hypothesis filter's matrices, the trim the
// estimator subtracts, and the flight condition it was designed at. Eigen and std only;
// the file format lives in cpp/bankfile (LCM-encoded), this header knows nothing of it.
//
// Each hypothesis k is a steady-state discrete Kalman filter (paper Sec. III-IV):
//   x(t_{i+1}) = Phi_k x(t_i) + Bd_k u(t_i) + w,     z(t_i) = H_k x(t_i) + v      (eqs. 3-4)
//   A_k = H_k P_k^- H_k^T + R_k                                                    (eq. 5)
// with sizes Phi (nx,nx), Bd (nx,nu), H (nz,nx), K (nx,nz), A (nz,nz). Quantities are
// perturbations from the trim (u_trim, z_trim). A hypothesis may mark channels whose reading
// is uninformative under it (uninformative_width_j > 0, the width of the range its unknown
// level lies in, and uninformative_level_q_j, the level's random walk per frame;
// steady_state_filter.h derives the likelihood); empty or zeros for the paper's models.
//
// The bank also carries the estimator settings its design recommends (EstimatorSettings:
// p_min, threshold, dwell_s; estimator_settings.h gives their ranges) and, per hypothesis, the
// recommended evidence dwell N_k (HypothesisModel::dwell_nats, nats, declarer.h's
// dwell_nats_per_hypothesis; 0: the frame dwell alone).
//
// validate() throws std::invalid_argument with a sentence naming the field (or hypothesis)
// and the value: names that are empty, duplicated, hold a NUL or are not UTF-8; a
// hypothesis whose name says it fails input j (measurement i) while its Bd column j (H row
// i) is not zero, which is how names permuted against the matrices show; a frame rate, Mach
// or altitude that is not finite and >= 0 (rate > 0, at most kMaxFrameRateHz); estimator
// settings or a hypothesis' dwell_nats out of range; a wrong shape, a non-finite entry, an A_k that is not symmetric
// positive definite, an unstable error dynamics Phi_k (I - K_k H_k) (spectral radius >= 1),
// uninformative widths that are not 0 or nz finite values >= 0, or that mark a channel whose
// H row is not zero or whose A row couples it to another channel.
#pragma once

#include <Eigen/Dense>

#include "f16mmae/estimator_settings.h"
#include "f16mmae/model_checks.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct BankSchedule;  // bank_schedule.h

struct HypothesisModel {
  std::string name;  // "NONE", "LS", ..., "AY", duals "LS+PIT" (f16mmae/names.py order)
  Eigen::MatrixXd phi, bd, h, k, a;
  Eigen::VectorXd uninformative_width;  // (nz) or empty: 0 = informative channel
  Eigen::VectorXd uninformative_level_q;  // (nz) or empty: level random walk per frame
  double dwell_nats = 0.0;  // recommended evidence dwell N_k, [0, kMaxDwellNats] nats; 0: frame dwell alone
};

struct ModelBank {
  static constexpr std::uint32_t kFormatVersion = 4;
  static constexpr double kMaxFrameRateHz = 10000.0;

  std::vector<std::string> state_names;        // nx
  std::vector<std::string> input_names;        // nu: LS RS LF RF RUD
  std::vector<std::string> measurement_names;  // nz: VEL AOA PIT AZ ROL YAW AY
  std::vector<HypothesisModel> hypotheses;     // [0] is NONE, then singles, then duals
  Eigen::VectorXd u_trim;    // (nu) absolute trim commands, subtracted from u
  Eigen::VectorXd z_trim;    // (nz) absolute trim measurements, subtracted from z
  Eigen::MatrixXd h_output;  // (nz,nx) blended state -> z_hat (the unfailed H)
  double frame_rate_hz = 0.0;
  double mach = 0.0;
  double alt_ft = 0.0;
  std::string tuning;    // name of the pseudonoise tuning ("untuned", "tuned", ...)
  EstimatorSettings estimator;  // the settings the design recommends (p_min, threshold, dwell_s)
  std::string metadata;  // JSON text describing the design (provenance; nothing reads settings from it)
  std::string content_hash;  // hex SHA-256 of the encoded payload (set by the bank file)
  // A scheduled bank (bank_schedule.h): banks designed on a Mach x altitude grid. This bank
  // is then one of its nodes (the one in force until air data arrives) and content_hash is
  // the schedule file's. Empty for a bank designed at one flight condition.
  std::shared_ptr<const BankSchedule> schedule;

  int nx() const { return static_cast<int>(state_names.size()); }
  int nu() const { return static_cast<int>(input_names.size()); }
  int nz() const { return static_cast<int>(measurement_names.size()); }

  // Index of a hypothesis by name, or -1.
  int find(const std::string& name) const {
    for (std::size_t i = 0; i < hypotheses.size(); ++i)
      if (hypotheses[i].name == name) return static_cast<int>(i);
    return -1;
  }

  void validate() const {
    auto fail = [](const std::string& what) { throw std::invalid_argument("model bank: " + what); };
    const int nx_ = nx(), nu_ = nu(), nz_ = nz();
    if (nx_ == 0 || nu_ == 0 || nz_ == 0) fail("state, input and measurement names must be non-empty");
    check_names("state_names", state_names);
    check_names("input_names", input_names);
    check_names("measurement_names", measurement_names);
    check_text("tuning", tuning);
    check_text("metadata", metadata);
    if (hypotheses.empty()) fail("no hypotheses");
    for (std::size_t i = 0; i < hypotheses.size(); ++i)  // before any message quotes a name
      check_text("hypotheses[" + std::to_string(i) + "].name", hypotheses[i].name);
    if (hypotheses[0].name != "NONE") fail("hypothesis 0 must be NONE, got '" + hypotheses[0].name + "'");
    auto check_number = [&](const char* what, double v, bool positive, double upper) {
      if (!std::isfinite(v) || v < 0.0 || (positive && v == 0.0) || v > upper)
        fail(std::string(what) + " must be finite, " + (positive ? "> 0" : ">= 0") + " and <= " +
             format_value(upper) + ", got " + format_value(v));
    };
    check_number("frame_rate_hz", frame_rate_hz, true, kMaxFrameRateHz);
    check_number("mach", mach, false, 10.0);
    check_number("alt_ft", alt_ft, false, 1.0e6);
    check_settings(estimator, static_cast<int>(hypotheses.size()), frame_rate_hz, "model bank: estimator");
    auto check_vec = [&](const char* what, const Eigen::VectorXd& v, int n) {
      if (v.size() != n) {
        std::ostringstream s;
        s << what << " has size " << v.size() << ", expected " << n;
        fail(s.str());
      }
      if (!v.allFinite()) fail(std::string(what) + " has a non-finite entry");
    };
    check_vec("u_trim", u_trim, nu_);
    check_vec("z_trim", z_trim, nz_);
    if (h_output.rows() != nz_ || h_output.cols() != nx_ || !h_output.allFinite()) {
      std::ostringstream s;
      s << "h_output is " << h_output.rows() << "x" << h_output.cols() << ", expected " << nz_
        << "x" << nx_ << " with finite entries";
      fail(s.str());
    }
    for (std::size_t i = 0; i < hypotheses.size(); ++i) {
      const HypothesisModel& m = hypotheses[i];
      const std::string who = "hypothesis " + std::to_string(i) + " '" + m.name + "'";
      for (std::size_t j = 0; j < i; ++j)
        if (hypotheses[j].name == m.name) fail(who + ": duplicate name");
      check_filter_matrices(m.phi, m.bd, m.h, m.k, m.a, nx_, nu_, nz_, "model bank: " + who);
      check_uninformative_width(m.h, m.a, m.uninformative_width, m.uninformative_level_q, nz_,
                                "model bank: " + who);
      check_failed_components(m, who);
      check_dwell_nats(m.dwell_nats, "model bank: " + who);
    }
  }

 private:
  // A name is non-empty, unique in its list, and valid text (check_text).
  static void check_names(const std::string& field, const std::vector<std::string>& names) {
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string where = field + "[" + std::to_string(i) + "]";
      if (names[i].empty()) throw std::invalid_argument("model bank: " + where + " is empty");
      check_text(where, names[i]);
      for (std::size_t j = 0; j < i; ++j)
        if (names[j] == names[i])
          throw std::invalid_argument("model bank: " + where + " '" + names[i] + "' duplicates " + field + "[" +
                                      std::to_string(j) + "]");
    }
  }

  // Text holds no NUL and is valid UTF-8 (RFC 3629: no overlong forms, no surrogates, <= U+10FFFF).
  static void check_text(const std::string& field, const std::string& text) {
    auto fail = [&](std::size_t at, const char* what) {
      throw std::invalid_argument("model bank: " + field + " " + what + " at byte " + std::to_string(at));
    };
    const auto* b = reinterpret_cast<const unsigned char*>(text.data());
    const std::size_t n = text.size();
    for (std::size_t i = 0; i < n;) {
      const unsigned c = b[i];
      if (c == 0) fail(i, "holds a NUL character");
      int extra = 0;
      unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the first continuation byte
      if (c < 0x80) {
        ++i;
        continue;
      } else if (c >= 0xC2 && c <= 0xDF) {
        extra = 1;
      } else if (c >= 0xE0 && c <= 0xEF) {
        extra = 2;
        if (c == 0xE0) lo = 0xA0;
        if (c == 0xED) hi = 0x9F;
      } else if (c >= 0xF0 && c <= 0xF4) {
        extra = 3;
        if (c == 0xF0) lo = 0x90;
        if (c == 0xF4) hi = 0x8F;
      } else {
        fail(i, "is not valid UTF-8");
      }
      if (i + static_cast<std::size_t>(extra) >= n) fail(i, "is not valid UTF-8 (a truncated sequence)");
      for (int k = 1; k <= extra; ++k) {
        const unsigned cc = b[i + k];
        if (cc < (k == 1 ? lo : 0x80u) || cc > (k == 1 ? hi : 0xBFu)) fail(i, "is not valid UTF-8");
      }
      i += static_cast<std::size_t>(extra) + 1;
    }
  }

  // Hypothesis "a+b" fails components a and b: a failed input j has a zero Bd column j, a
  // failed measurement i a zero H row i (the design's rule). A name that is neither is left
  // to the banks that use it (HierarchicalBank looks hypotheses up by name).
  void check_failed_components(const HypothesisModel& m, const std::string& who) const {
    if (m.name == "NONE") return;
    std::size_t start = 0;
    for (;;) {
      const std::size_t plus = m.name.find('+', start);
      const std::string c = m.name.substr(start, plus == std::string::npos ? std::string::npos : plus - start);
      for (std::size_t j = 0; j < input_names.size(); ++j)
        if (input_names[j] == c && !m.bd.col(static_cast<Eigen::Index>(j)).isZero(0.0))
          throw std::invalid_argument("model bank: " + who + " fails input '" + c + "' but its bd column " +
                                      std::to_string(j) + " (input_names[" + std::to_string(j) +
                                      "]) is not zero: input_names do not match the matrices");
      for (std::size_t i = 0; i < measurement_names.size(); ++i)
        if (measurement_names[i] == c && !m.h.row(static_cast<Eigen::Index>(i)).isZero(0.0))
          throw std::invalid_argument("model bank: " + who + " fails measurement '" + c + "' but its h row " +
                                      std::to_string(i) + " (measurement_names[" + std::to_string(i) +
                                      "]) is not zero: measurement_names do not match the matrices");
      if (plus == std::string::npos) break;
      start = plus + 1;
    }
  }
};

}  // namespace f16mmae
