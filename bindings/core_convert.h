// numpy <-> Eigen at the boundary of the estimator bindings (bind_filter.cpp, bind_bank.cpp,
// bind_hierarchical.cpp, bind_monitor.cpp): shapes are checked here and refused with a
// ValueError naming the argument, the expected shape and the shape received.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Dense>

#include <string>

namespace f16mmae::bindings::convert {

namespace py = pybind11;
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

inline std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// obj as a C-contiguous float64 array; ValueError unless it holds real numbers.
inline py::array_t<double> as_array(py::handle obj, const char* what) {
  const py::array raw = py::array::ensure(obj);
  const char kind = raw ? raw.dtype().kind() : 'O';
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    throw py::value_error(std::string(what) + " must be an array of real numbers, got " +
                          (raw ? "dtype " + std::string(py::str(raw.dtype()))
                               : std::string(py::str(py::type::handle_of(obj).attr("__name__")))));
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(raw);
}

// A 1-D array of exactly n entries (n < 0: any length), as a pointer valid while `keep` lives.
inline const double* vector_data(py::handle obj, Eigen::Index n, const char* what, py::array_t<double>& keep) {
  keep = as_array(obj, what);
  if (keep.ndim() != 1 || (n >= 0 && keep.shape(0) != n)) {
    throw py::value_error(std::string(what) + " must have shape (" + (n >= 0 ? std::to_string(n) : "n") +
                          ",), got " + shape_text(keep));
  }
  return keep.data();
}

// A copy as the vector type V (a bank's fixed- or dynamic-size ZVector / UVector, by default
// Eigen::VectorXd), checked as vector_data checks it.
template <class V = Eigen::VectorXd>
V to_vector(py::handle obj, Eigen::Index n, const char* what) {
  py::array_t<double> keep;
  const double* p = vector_data(obj, n, what, keep);
  return V(Eigen::Map<const V>(p, keep.shape(0)));
}

// A 2-D array; rows/cols < 0 accept any extent; `expected` spells the shape for messages.
inline Eigen::MatrixXd to_matrix(py::handle obj, Eigen::Index rows, Eigen::Index cols, const char* what,
                                 const std::string& expected) {
  const py::array_t<double> a = as_array(obj, what);
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || (cols >= 0 && a.shape(1) != cols))
    throw py::value_error(std::string(what) + " must have shape " + expected + ", got " + shape_text(a));
  return Eigen::Map<const RowMajorMatrix>(a.data(), a.shape(0), a.shape(1));
}

// numpy copies (writeable; they are snapshots, changing them changes nothing in the core).
template <class Derived>
py::array_t<double> to_numpy(const Eigen::MatrixBase<Derived>& m) {
  if (Derived::ColsAtCompileTime == 1) {
    py::array_t<double> out(m.rows());
    for (Eigen::Index i = 0; i < m.rows(); ++i) out.mutable_at(i) = m(i, 0);
    return out;
  }
  py::array_t<double> out({m.rows(), m.cols()});
  Eigen::Map<RowMajorMatrix>(out.mutable_data(), m.rows(), m.cols()) = m;
  return out;
}

}  // namespace f16mmae::bindings::convert
