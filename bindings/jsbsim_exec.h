// f16mmae.core.JSBSimExec: a JSBSim FGFDMExec made and driven from C++ through the library
// inside the installed `jsbsim` Python package (its _jsbsim.so exports JSBSim's C++ API; the
// headers of the same release are fetched at configure time, cmake/jsbsim_cxx.cmake).  It
// offers the part of jsbsim.FGFDMExec that truth/aircraft.py uses to load, trim and restart
// (properties, run, run_ic, paths), so the set-up is one Python procedure for both truth
// engines and the same compiled JSBSim code flies both; TruthFrames (bind_truth.cpp) steps it.
// Throws KeyError for an unknown property and jsbsim.TrimFailureError / jsbsim.BaseError for
// JSBSim's exceptions, as jsbsim.FGFDMExec does.
#pragma once

#include <pybind11/pybind11.h>

#include <FGFDMExec.h>
#include <input_output/FGPropertyManager.h>
#include <models/FGPropulsion.h>
#include <models/propulsion/FGEngine.h>

#include <memory>
#include <string>
#include <vector>

namespace f16mmae::bindings {

namespace py = pybind11;

// Translate JSBSim's exceptions as the jsbsim package does.
template <class F>
auto guarded(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const JSBSim::TrimFailureException& e) {
    PyErr_SetString(py::module_::import("jsbsim").attr("TrimFailureError").ptr(), e.what());
    throw py::error_already_set();
  } catch (const JSBSim::BaseException& e) {
    PyErr_SetString(py::module_::import("jsbsim").attr("BaseError").ptr(), e.what());
    throw py::error_already_set();
  }
}

inline std::string strip(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// FGEngine::FuelFlow_pph is state (the turbine seeks it towards thrust x TSFC at a limited
// rate) but no writable property: reached through a member pointer of a derived class.
struct EngineAccess : JSBSim::FGEngine {
  static double& fuel_flow_pph(JSBSim::FGEngine& e) { return e.*(&EngineAccess::FuelFlow_pph); }
};

class Exec {
 public:
  explicit Exec(const std::string& root_dir) : fdm_(std::make_unique<JSBSim::FGFDMExec>(nullptr, nullptr)) {
    // The same start as jsbsim.FGFDMExec(root_dir): root, output ".", engine, aircraft, systems.
    fdm_->SetRootDir(SGPath(root_dir));
    fdm_->SetOutputPath(SGPath("."));
    fdm_->SetEnginePath(SGPath("engine"));
    fdm_->SetAircraftPath(SGPath("aircraft"));
    fdm_->SetSystemsPath(SGPath("systems"));
  }
  JSBSim::FGFDMExec& fdm() { return *fdm_; }
  SGPropertyNode* node(const std::string& path) {
    SGPropertyNode* n = fdm_->GetPropertyManager()->GetNode(path);
    if (!n) throw py::key_error("no JSBSim property '" + path + "'");
    return n;
  }
  std::vector<double> fuel_flow_pph() const {
    std::vector<double> out;
    auto prop = fdm_->GetPropulsion();
    for (unsigned i = 0; i < prop->GetNumEngines(); ++i) out.push_back(EngineAccess::fuel_flow_pph(*prop->GetEngine(i)));
    return out;
  }
  void set_fuel_flow_pph(const std::vector<double>& v) {
    auto prop = fdm_->GetPropulsion();
    if (v.size() != prop->GetNumEngines())
      throw py::value_error("set_fuel_flow_pph needs one value per engine (" +
                            std::to_string(prop->GetNumEngines()) + "), got " + std::to_string(v.size()));
    for (unsigned i = 0; i < v.size(); ++i) EngineAccess::fuel_flow_pph(*prop->GetEngine(i)) = v[i];
  }
  double get(const std::string& key) { return node(strip(key))->getDoubleValue(); }
  void set(const std::string& key, double v) {
    guarded([&] { fdm_->SetPropertyValue(strip(key), v); return 0; });
  }

 private:
  std::unique_ptr<JSBSim::FGFDMExec> fdm_;
};

}  // namespace f16mmae::bindings
