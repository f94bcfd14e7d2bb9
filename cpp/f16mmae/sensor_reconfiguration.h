// SensorReconfiguration — what the flight control law feeds back in the "reconfigure" mode:
// the raw measurements, except the channels of the sensors that the estimator's current
// (declared) hypothesis says have failed, which take the bank's estimate:
//
//   z_fb[j] = z_hat[j]   if sensor j is a component of the current hypothesis h
//   z_fb[j] = z[j]       otherwise (NONE, an actuator failure, the other sensors)
//
// The current hypothesis is the one the declarer has declared (dwell passed); it changes only
// on a declaration, so the control law is reconfigured only on a confirmed decision and
// never by the probabilities moving between declarations. With NONE current the law flies on
// exactly the raw sensors. (The "mmae" mode, the paper's, feeds back the blended z_hat on
// every channel at every frame.) A hypothesis's components are its name split at '+'
// ("AOA", "LF+AOA"), each without a partial failure's ":MODE" ("LS:loss=0.5" is surface LS,
// hierarchy_levels.h); sensors are the ModelBank's measurement names.
// Construction throws std::invalid_argument when a hypothesis names a component that is
// neither an input nor a measurement of the bank; apply() is noexcept and allocates nothing.
#pragma once

#include "f16mmae/model_bank.h"

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

class SensorReconfiguration {
 public:
  explicit SensorReconfiguration(const ModelBank& bank) : nz_(bank.nz()), sensors_(bank.measurement_names) {
    for (const auto& h : bank.hypotheses) {
      names_.push_back(h.name);
      std::vector<unsigned char> failed(static_cast<std::size_t>(nz_), 0);
      if (h.name != "NONE") {
        std::size_t start = 0;
        while (start <= h.name.size()) {
          const std::size_t plus = h.name.find('+', start);
          const std::string c = h.name.substr(start, plus == std::string::npos ? std::string::npos : plus - start);
          mark(c, bank, failed, h.name);
          if (plus == std::string::npos) break;
          start = plus + 1;
        }
      }
      failed_.push_back(std::move(failed));
    }
  }

  int nz() const noexcept { return nz_; }
  const std::string& sensor_name(int j) const { return sensors_.at(static_cast<std::size_t>(j)); }
  int hypothesis_count() const noexcept { return static_cast<int>(names_.size()); }
  // The index of a hypothesis by name; std::invalid_argument naming it if the bank has none.
  int index(const std::string& name) const {
    for (std::size_t k = 0; k < names_.size(); ++k)
      if (names_[k] == name) return static_cast<int>(k);
    throw std::invalid_argument("SensorReconfiguration: the bank has no hypothesis '" + name + "'");
  }
  // True when sensor j has failed under hypothesis k (0 <= k < hypothesis_count()).
  bool failed(int k, int j) const noexcept { return failed_[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] != 0; }

  // out = z with z_hat on the channels failed under hypothesis k (arrays of nz() values;
  // out may alias z).
  void apply(int k, const double* z, const double* z_hat, double* out) const noexcept {
    const auto& f = failed_[static_cast<std::size_t>(k)];
    for (int j = 0; j < nz_; ++j) out[j] = f[static_cast<std::size_t>(j)] ? z_hat[j] : z[j];
  }

 private:
  static void mark(const std::string& component, const ModelBank& bank, std::vector<unsigned char>& failed,
                   const std::string& hypothesis) {
    const std::string c = component.substr(0, component.find(':'));
    for (std::size_t j = 0; j < bank.measurement_names.size(); ++j)
      if (bank.measurement_names[j] == c) {
        failed[j] = 1;
        return;
      }
    for (const auto& u : bank.input_names)
      if (u == c) return;
    throw std::invalid_argument("SensorReconfiguration: hypothesis '" + hypothesis + "' names '" + c +
                                "', neither an input nor a measurement of the bank");
  }

  int nz_ = 0;
  std::vector<std::string> sensors_;
  std::vector<std::string> names_;
  std::vector<std::vector<unsigned char>> failed_;
};

}  // namespace f16mmae
