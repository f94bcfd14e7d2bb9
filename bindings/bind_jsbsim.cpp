// Registers f16mmae.core.JSBSimExec and JSBSimProperty (bindings/jsbsim_exec.h).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <models/atmosphere/FGWinds.h>

#include "jsbsim_exec.h"

namespace f16mmae::bindings {
namespace {

// One property node of a JSBSimExec (as jsbsim.FGPropertyNode): get_double_value, set_double_value.
struct Node {
  std::shared_ptr<Exec> owner;
  SGPropertyNode* node;
};

}  // namespace

void bind_jsbsim(py::module_& m) {
  m.attr("JSBSIM_VERSION") = F16MMAE_JSBSIM_VERSION;  // the jsbsim release whose API this was built against
  py::class_<Exec, std::shared_ptr<Exec>>(m, "JSBSimExec", R"doc(
    JSBSimExec(root_dir): a JSBSim FGFDMExec made in C++ (the jsbsim package's library), for
    TruthFrames.  Offers the subset of jsbsim.FGFDMExec that the truth model's set-up uses:
    fdm[prop], fdm[prop] = value, run(), run_ic(), load_model(), set_dt(), set_debug_level(),
    set_engine_path(), set_systems_path(), reset_to_initial_conditions(), get_sim_time(),
    set_sim_time(), get_delta_t(), get_property_manager().get_node(path); and reset_winds(),
    fuel_flow_pph(), set_fuel_flow_pph() for a restart (truth/aircraft.py).)doc")
      .def(py::init<const std::string&>(), py::arg("root_dir"))
      .def("set_debug_level", [](Exec& e, int level) { e.fdm().SetDebugLevel(level); }, py::arg("level"))
      .def("set_engine_path", [](Exec& e, const std::string& p) { return e.fdm().SetEnginePath(SGPath(p)); })
      .def("set_systems_path", [](Exec& e, const std::string& p) { return e.fdm().SetSystemsPath(SGPath(p)); })
      .def("load_model", [](Exec& e, const std::string& model, bool add) {
             return guarded([&] { return e.fdm().LoadModel(model, add); });
           }, py::arg("model"), py::arg("add_model_to_path") = true)
      .def("set_dt", [](Exec& e, double dt) { e.fdm().Setdt(dt); }, py::arg("dt"))
      .def("run", [](Exec& e) { return guarded([&] { return e.fdm().Run(); }); })
      .def("run_ic", [](Exec& e) { return guarded([&] { return e.fdm().RunIC(); }); })
      .def("reset_to_initial_conditions", [](Exec& e, int mode) {
             guarded([&] { e.fdm().ResetToInitialConditions(mode); return 0; });
           }, py::arg("mode"))
      .def("reset_winds", [](Exec& e) { e.fdm().GetWinds()->InitModel(); },
           "Zero the turbulence model's states (FGWinds::InitModel), as after loading.")
      .def("fuel_flow_pph", &Exec::fuel_flow_pph, "Each engine's fuel flow state (lbs/h).")
      .def("set_fuel_flow_pph", &Exec::set_fuel_flow_pph, py::arg("values"))
      .def("set_sim_time", [](Exec& e, double t) { return e.fdm().Setsim_time(t); }, py::arg("time"))
      .def("get_property_manager", [](std::shared_ptr<Exec> e) { return e; },
           "This object: get_node(path) is here, as on jsbsim's FGPropertyManager.")
      .def("get_node", [](std::shared_ptr<Exec> e, const std::string& path) { return Node{e, e->node(path)}; },
           py::arg("path"))
      .def("get_sim_time", [](Exec& e) { return e.fdm().GetSimTime(); })
      .def("get_delta_t", [](Exec& e) { return e.fdm().GetDeltaT(); })
      .def("__getitem__", &Exec::get, py::arg("key"))
      .def("__setitem__", &Exec::set, py::arg("key"), py::arg("value"));

  py::class_<Node>(m, "JSBSimProperty", "A property node of a JSBSimExec (JSBSimExec.get_node(path)).")
      .def("get_double_value", [](const Node& n) { return n.node->getDoubleValue(); })
      .def("set_double_value", [](Node& n, double v) { return n.node->setDoubleValue(v); }, py::arg("value"));
}

}  // namespace f16mmae::bindings
