// f16mmae.core — the pybind11 module over the C++ core (cpp/f16mmae) and the bank file
// (cpp/bankfile). Each bind_*.cpp file binds one idea and registers it here.
#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace f16mmae::bindings {
void register_all(py::module_& m);  // bindings/registry.cpp
}

PYBIND11_MODULE(core, m) {
  m.doc() = "f16mmae.core: the C++ MMAE estimator (steady-state Kalman filter bank, "
            "hypothesis probabilities, declarer, hierarchical bank, residual monitors, "
            "model-bank file).";
  m.attr("__version__") = F16MMAE_VERSION;
  f16mmae::bindings::register_all(m);
}
