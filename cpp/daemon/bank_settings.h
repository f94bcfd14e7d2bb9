// Estimator settings recommended by a model bank: its metadata JSON's top-level "estimator"
// object, e.g. {"estimator": {"p_min": 1e-09, "threshold": 0.9, "dwell_s": 0.25}, ...},
// written by `f16mmae design` from the tuning. The in-process closed loop applies the same
// rule (f16mmae.closedloop.bank_estimator_settings): the bank's recommendation, missing keys
// at the core's defaults, command-line overrides last. So mmae-daemon and `f16mmae run` run
// the same estimator on the same bank; tests/python/test_daemon_settings_agree.py holds the
// two implementations to each other on banks that differ only in their metadata.
//
// A metadata text that is empty, or not a JSON object, or without an "estimator" object,
// recommends nothing (the core's defaults), as in Python. An "estimator" entry p_min,
// threshold or dwell_s that is not a number throws std::invalid_argument naming it; other
// keys are ignored.
#pragma once

#include "f16mmae/hierarchical_bank.h"

#include <optional>
#include <string>

namespace f16mmae::daemon {

struct EstimatorSettings {
  std::optional<double> p_min, threshold, dwell_s;
  // Applies the set fields over `base`.
  HierarchicalOptions apply(HierarchicalOptions base) const {
    if (p_min) base.bank.p_min = *p_min;
    if (threshold) base.declarer.threshold = *threshold;
    if (dwell_s) base.declarer.dwell_s = *dwell_s;
    return base;
  }
};

EstimatorSettings bank_estimator_settings(const std::string& metadata_json);

}  // namespace f16mmae::daemon
