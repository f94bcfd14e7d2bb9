// Calls every bind_* function. Add one line per binding file.
#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace f16mmae::bindings {
void bind_model_bank(py::module_& m);  // bind_model_bank.cpp
void bind_filter(py::module_& m);        // bind_filter.cpp: FilterModel
void bind_bank(py::module_& m);          // bind_bank.cpp: FilterBank
void bind_declarer(py::module_& m);      // bind_declarer.cpp: Declarer
void bind_hierarchical(py::module_& m);  // bind_hierarchical.cpp: HierarchicalBank
void bind_monitor(py::module_& m);       // bind_monitor.cpp: ResidualMonitor
void bind_jsbsim(py::module_& m);        // bind_jsbsim.cpp: JSBSimExec, JSBSimProperty
void bind_truth(py::module_& m);         // bind_truth.cpp: TruthFrames
void bind_executive(py::module_& m);     // bind_executive.cpp: Executive
void bind_frame_auth(py::module_& m);    // bind_frame_auth.cpp: FrameAuth
void bind_reconfiguration(py::module_& m);  // bind_reconfiguration.cpp: SensorReconfiguration
void bind_bank_set(py::module_& m);      // bind_bank_set.cpp: TurbulenceBankSet
void bind_turbulence_set_file(py::module_& m);  // bind_bank_set.cpp: TurbulenceSetFile
void register_all(py::module_& m) {
  bind_filter(m);
  bind_bank(m);
  bind_declarer(m);
  bind_model_bank(m);
  bind_hierarchical(m);
  bind_monitor(m);
  bind_jsbsim(m);
  bind_truth(m);
  bind_turbulence_set_file(m);
  bind_executive(m);
  bind_frame_auth(m);
  bind_reconfiguration(m);
  bind_bank_set(m);
}
}  // namespace f16mmae::bindings
