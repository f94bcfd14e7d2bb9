#include "f16mmae/model_checks.h"

#include <Eigen/Eigenvalues>

#include <sstream>
#include <stdexcept>

namespace f16mmae {

double spectral_radius(const Eigen::MatrixXd& m) {
  return m.size() == 0 ? 0.0 : m.eigenvalues().cwiseAbs().maxCoeff();
}

void check_filter_matrices(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& bd,
                           const Eigen::MatrixXd& h, const Eigen::MatrixXd& k,
                           const Eigen::MatrixXd& a, Eigen::Index nx, Eigen::Index nu,
                           Eigen::Index nz, const std::string& who) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument(who + ": " + what); };
  auto check = [&](const char* name, const Eigen::MatrixXd& x, Eigen::Index r, Eigen::Index c) {
    if (x.rows() != r || x.cols() != c) {
      std::ostringstream s;
      s << name << " is " << x.rows() << "x" << x.cols() << ", expected " << r << "x" << c;
      fail(s.str());
    }
    if (!x.allFinite()) fail(std::string(name) + " has a non-finite entry");
  };
  if (nx == 0 || nu == 0 || nz == 0) fail("phi, bd and h must be non-empty");
  check("phi", phi, nx, nx);
  check("bd", bd, nx, nu);
  check("h", h, nz, nx);
  check("k", k, nx, nz);
  check("a", a, nz, nz);
  const double asym = (a - a.transpose()).cwiseAbs().maxCoeff();
  if (asym > 1e-9 * (1.0 + a.cwiseAbs().maxCoeff())) fail("residual covariance A is not symmetric");
  if (Eigen::LLT<Eigen::MatrixXd>(a).info() != Eigen::Success)
    fail("residual covariance A is not positive definite");
  const double rho = spectral_radius(phi * (Eigen::MatrixXd::Identity(nx, nx) - k * h));
  if (!(rho < 1.0)) {
    std::ostringstream s;
    s << "error dynamics Phi (I - K H) is unstable (spectral radius " << rho << " >= 1)";
    fail(s.str());
  }
}

}  // namespace f16mmae
