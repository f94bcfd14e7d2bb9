// f16mmae.core.FilterModel: the matrices of one steady-state hypothesis filter
// (cpp/f16mmae/steady_state_filter.h). Validated at construction: shapes, finiteness,
// symmetric positive-definite A, stable Phi (I - K H); a bad model raises ValueError.
#include <pybind11/pybind11.h>

#include "core_convert.h"
#include "f16mmae/steady_state_filter.h"

namespace py = pybind11;

namespace f16mmae::bindings {

void bind_filter(py::module_& m) {
  namespace cv = convert;
  py::class_<DynamicFilterModel>(m, "FilterModel", R"doc(
One hypothesis filter of the MMAE bank: a steady-state discrete Kalman filter (paper eqs. 3-5).

    FilterModel(phi=(n,n), bd=(n,p), h=(m,n), k=(n,m), a=(m,m), uninformative_width=None|(m,),
                uninformative_level_q=None|(m,))

phi: state transition, bd: discrete input matrix, h: measurement matrix, k: steady-state
gain, a: residual covariance A = H P- H^T + R (eq. 5); uninformative_width: W_j > 0 makes
channel j's reading, under this hypothesis, an unknown level anywhere in a range of width W_j,
a random walk of uninformative_level_q_j per frame (0: no memory) (its h row must be
zero; likelihood in cpp/f16mmae/steady_state_filter.h). Quantities are perturbations from
trim. Raises ValueError for a wrong shape, a non-finite entry, an A that is not symmetric
positive definite, or unstable error dynamics Phi (I - K H).)doc")
      .def(py::init([](py::handle phi, py::handle bd, py::handle h, py::handle k, py::handle a, py::handle width,
                       py::handle level_q) {
             const Eigen::MatrixXd phi_m = cv::to_matrix(phi, -1, -1, "phi", "(n, n)");
             const Eigen::Index n = phi_m.rows();
             const std::string ns = std::to_string(n);
             if (phi_m.cols() != n) cv::to_matrix(phi, n, n, "phi", "(n, n)");
             const Eigen::MatrixXd bd_m = cv::to_matrix(bd, n, -1, "bd", "(" + ns + ", p)");
             const Eigen::MatrixXd h_m = cv::to_matrix(h, -1, n, "h", "(m, " + ns + ")");
             const Eigen::Index mz = h_m.rows();
             const std::string ms = std::to_string(mz);
             const Eigen::MatrixXd k_m = cv::to_matrix(k, n, mz, "k", "(" + ns + ", " + ms + ")");
             const Eigen::MatrixXd a_m = cv::to_matrix(a, mz, mz, "a", "(" + ms + ", " + ms + ")");
             const Eigen::VectorXd w =
                 width.is_none() ? Eigen::VectorXd() : cv::to_vector(width, mz, "uninformative_width");
             const Eigen::VectorXd tw = level_q.is_none()
                                            ? Eigen::VectorXd()
                                            : cv::to_vector(level_q, mz, "uninformative_level_q");
             DynamicFilterModel model = DynamicFilterModel::from_matrices(phi_m, bd_m, h_m, k_m, a_m, w, tw);
             model.validate("FilterModel");
             return model;
           }),
           py::kw_only(), py::arg("phi"), py::arg("bd"), py::arg("h"), py::arg("k"), py::arg("a"),
           py::arg("uninformative_width") = py::none(), py::arg("uninformative_level_q") = py::none())
      .def_property_readonly("phi", [](const DynamicFilterModel& f) { return cv::to_numpy(f.phi); }, "(n,n) Phi")
      .def_property_readonly("bd", [](const DynamicFilterModel& f) { return cv::to_numpy(f.bd); }, "(n,p) B_d")
      .def_property_readonly("h", [](const DynamicFilterModel& f) { return cv::to_numpy(f.h); }, "(m,n) H")
      .def_property_readonly("k", [](const DynamicFilterModel& f) { return cv::to_numpy(f.k); }, "(n,m) gain K")
      .def_property_readonly("a", [](const DynamicFilterModel& f) { return cv::to_numpy(f.a); },
                             "(m,m) residual covariance A (eq. 5)")
      .def_property_readonly("uninformative_width",
                             [](const DynamicFilterModel& f) { return cv::to_numpy(f.uninformative_width); },
                             "(m,) width of each uninformative channel's uniform density, 0 = informative")
      .def_property_readonly("uninformative_level_q",
                             [](const DynamicFilterModel& f) { return cv::to_numpy(f.uninformative_level_q); },
                             "(m,) random-walk variance per frame of an uninformative channel's level")
      .def_property_readonly("nx", &DynamicFilterModel::nx, "states n")
      .def_property_readonly("nu", &DynamicFilterModel::nu, "inputs p")
      .def_property_readonly("nz", &DynamicFilterModel::nz, "measurements m")
      .def("__repr__", [](const DynamicFilterModel& f) {
        return "FilterModel(nx=" + std::to_string(f.nx()) + ", nu=" + std::to_string(f.nu()) +
               ", nz=" + std::to_string(f.nz()) + ")";
      });
}

}  // namespace f16mmae::bindings
