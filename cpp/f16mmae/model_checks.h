// Checks of one hypothesis filter's matrices, shared by FilterModel::validate and
// ModelBank::validate and compiled once (cpp/f16mmae/model_checks.cpp: the eigenvalue solver
// is heavy to instantiate, so it lives in one translation unit).
//
// check_filter_matrices(phi, bd, h, k, a, nx, nu, nz, who) throws std::invalid_argument
// "<who>: <problem>" when a shape differs from Phi (nx,nx), Bd (nx,nu), H (nz,nx), K (nx,nz),
// A (nz,nz), an entry is not finite, A is not symmetric positive definite, or the filter's
// error dynamics Phi (I - K H) are not stable (spectral radius >= 1).
//
// check_uninformative_width(h, a, width, level_q, nz, who) throws "<who>: <problem>" unless
// `width` is empty or has nz finite entries >= 0, `level_q` is empty or has nz finite entries
// >= 0 (non-zero only where width_j > 0), and every channel j with width_j > 0 (a reading that
// carries no information under the hypothesis, steady_state_filter.h) has a zero H row j and
// a zero row/column j of A off the diagonal, so its residual is independent of the others.
#pragma once

#include <Eigen/Dense>

#include <string>

namespace f16mmae {

// Largest |eigenvalue| of a square matrix.
double spectral_radius(const Eigen::MatrixXd& m);

void check_filter_matrices(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& bd,
                           const Eigen::MatrixXd& h, const Eigen::MatrixXd& k,
                           const Eigen::MatrixXd& a, Eigen::Index nx, Eigen::Index nu,
                           Eigen::Index nz, const std::string& who);

void check_uninformative_width(const Eigen::MatrixXd& h, const Eigen::MatrixXd& a,
                               const Eigen::VectorXd& width, const Eigen::VectorXd& level_q,
                               Eigen::Index nz, const std::string& who);

}  // namespace f16mmae
