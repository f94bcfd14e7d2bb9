// Calls every bind_* function. Add one line per binding file.
#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace f16mmae::bindings {
void register_all(py::module_& m) {
  (void)m;
}
}  // namespace f16mmae::bindings
