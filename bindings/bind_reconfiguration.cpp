// f16mmae.core.SensorReconfiguration (cpp/f16mmae/sensor_reconfiguration.h): the control
// law's feedback in the "reconfigure" mode -- raw z, with the bank's estimate on the channels
// of the sensors the current hypothesis has failed. The frame-by-frame loop (loop/flight.py,
// hil) calls apply() with the estimator's declared name; the C++ closed loop
// (TruthFrames.fly_closed_loop) takes the same object and applies it by hypothesis index.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "core_convert.h"
#include "f16mmae/model_bank.h"
#include "f16mmae/sensor_reconfiguration.h"

namespace py = pybind11;

namespace f16mmae::bindings {

void bind_reconfiguration(py::module_& m) {
  py::class_<SensorReconfiguration>(m, "SensorReconfiguration", R"doc(
The control law's feedback when it is reconfigured only on a declaration:
z_feedback[j] = z_hat[j] for every sensor j that the hypothesis names (its name split at '+'),
z[j] otherwise. With NONE (or an actuator failure) current it is z itself.

SensorReconfiguration(model_bank); apply(hypothesis, z, z_hat) -> z_feedback (nz,);
failed_sensors(hypothesis) -> the names of the sensors it replaces. ValueError for an unknown
hypothesis name or arrays of the wrong shape.)doc")
      .def(py::init([](const ModelBank& bank) {
             try {
               return new SensorReconfiguration(bank);
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());
             }
           }),
           py::arg("model_bank"))
      .def(
          "apply",
          [](const SensorReconfiguration& r, const std::string& hypothesis, py::handle z, py::handle z_hat) {
            int k = 0;
            try {
              k = r.index(hypothesis);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
            py::array_t<double> keep_z, keep_zh;
            const double* zp = convert::vector_data(z, r.nz(), "z", keep_z);
            const double* zhp = convert::vector_data(z_hat, r.nz(), "z_hat", keep_zh);
            py::array_t<double> out(r.nz());
            r.apply(k, zp, zhp, out.mutable_data());
            return out;
          },
          py::arg("hypothesis"), py::arg("z"), py::arg("z_hat"),
          "z with z_hat on the channels of the sensors failed under `hypothesis` (a name).")
      .def(
          "failed_sensors",
          [](const SensorReconfiguration& r, const std::string& hypothesis) {
            int k = 0;
            try {
              k = r.index(hypothesis);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
            std::vector<std::string> out;
            for (int j = 0; j < r.nz(); ++j)
              if (r.failed(k, j)) out.push_back(r.sensor_name(j));
            return out;
          },
          py::arg("hypothesis"), "The measurement names whose channel takes z_hat under `hypothesis`.");
}

}  // namespace f16mmae::bindings
