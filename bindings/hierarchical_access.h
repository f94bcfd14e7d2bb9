// Access to the C++ estimator inside a core.HierarchicalBank, for bindings that fly it from
// C++ (bind_truth.cpp: a whole closed-loop flight without crossing to Python per frame).
#pragma once

#include <pybind11/pybind11.h>

#include <variant>

#include "f16mmae/hierarchical_bank.h"

namespace f16mmae::bindings {

/// A fixed-size F-16 bank: 13 states, 19 with the Dryden gust states, either with the
/// throttle as the sixth input; monostate: none.
using FixedHierarchicalBank = std::variant<std::monostate, F16HierarchicalBank*, F16GustHierarchicalBank*,
                                           F16ThrottleHierarchicalBank*, F16GustThrottleHierarchicalBank*>;

/// The fixed-size F-16 bank inside ``hierarchical_bank`` (a core.HierarchicalBank), or
/// monostate when it runs the dynamic-size bank.  TypeError if it is not a core.HierarchicalBank.
FixedHierarchicalBank fixed_hierarchical_bank(pybind11::handle hierarchical_bank);

}  // namespace f16mmae::bindings
