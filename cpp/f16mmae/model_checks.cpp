#include "f16mmae/model_checks.h"

#include <Eigen/Eigenvalues>

#include <cmath>
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

void check_uninformative_width(const Eigen::MatrixXd& h, const Eigen::MatrixXd& a,
                               const Eigen::VectorXd& width, const Eigen::VectorXd& level_q,
                               Eigen::Index nz, const std::string& who) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument(who + ": " + what); };
  if (level_q.size() != 0) {
    if (level_q.size() != nz) {
      std::ostringstream s;
      s << "uninformative_level_q has size " << level_q.size() << ", expected 0 or " << nz;
      fail(s.str());
    }
    for (Eigen::Index j = 0; j < nz; ++j) {
      const double w = level_q(j);
      const bool marked = width.size() == nz && width(j) > 0.0;
      if (!(std::isfinite(w) && w >= 0.0) || (w != 0.0 && !marked)) {
        std::ostringstream s;
        s << "uninformative_level_q[" << j << "] must be finite and >= 0, and 0 unless the channel is "
          << "uninformative (width > 0), got " << w;
        fail(s.str());
      }
    }
  }
  if (width.size() == 0) return;
  if (width.size() != nz) {
    std::ostringstream s;
    s << "uninformative_width has size " << width.size() << ", expected 0 or " << nz;
    fail(s.str());
  }
  for (Eigen::Index j = 0; j < nz; ++j) {
    const double w = width(j);
    if (!std::isfinite(w) || w < 0.0) {
      std::ostringstream s;
      s << "uninformative_width[" << j << "] must be finite and >= 0, got " << w;
      fail(s.str());
    }
    if (w == 0.0) continue;
    const std::string at = "channel " + std::to_string(j) + " is uninformative (width " + std::to_string(w) + ")";
    if (!h.row(j).isZero(0.0)) fail(at + " but its h row is not zero");
    for (Eigen::Index i = 0; i < nz; ++i)
      if (i != j && (a(i, j) != 0.0 || a(j, i) != 0.0))
        fail(at + " but A couples it to channel " + std::to_string(i) + " (A is not block diagonal there)");
  }
}

}  // namespace f16mmae
