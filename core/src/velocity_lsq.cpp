#include "fmcw/core/velocity_lsq.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>

namespace fmcw::core {

namespace {
Eigen::Vector3d unit_beam(const Scan& scan, const std::vector<Eigen::Vector3d>& col_origin, std::uint32_t i) {
  const Eigen::Vector3d d =
      scan.position(i) - col_origin[i % static_cast<std::uint32_t>(scan.cols)];
  return d / d.norm();
}
}  // namespace

NormalEquations NormalEquations::of(const VelocityRows& rows) {
  NormalEquations ne;
  for (std::size_t k = 0; k < rows.size(); ++k) ne.add(rows.directions[k], rows.targets_mps[k]);
  return ne;
}

std::vector<Eigen::Vector3d> column_origins(const Scan& scan) {
  std::vector<Eigen::Vector3d> origins(static_cast<std::size_t>(scan.cols));
  for (const auto& head : scan.heads) {
    for (int c = head.col_begin; c < head.col_end; ++c) origins[static_cast<std::size_t>(c)] = head.origin_m();
  }
  return origins;
}

void build_ego_rows(const Scan& scan, const std::vector<Eigen::Vector3d>& col_origin,
                    const std::vector<std::uint32_t>& pixels, VelocityRows& rows) {
  rows.clear();
  rows.directions.reserve(pixels.size());
  rows.targets_mps.reserve(pixels.size());
  for (const std::uint32_t i : pixels) {
    rows.directions.push_back(unit_beam(scan, col_origin, i));
    rows.targets_mps.push_back(-static_cast<double>(scan.radial_velocity_mps[i]));
  }
}

void build_object_rows(const Scan& scan, const std::vector<Eigen::Vector3d>& col_origin,
                       const std::vector<std::uint32_t>& pixels, const Eigen::Vector3d& ego_velocity_mps,
                       VelocityRows& rows) {
  rows.clear();
  rows.directions.reserve(pixels.size());
  rows.targets_mps.reserve(pixels.size());
  for (const std::uint32_t i : pixels) {
    const Eigen::Vector3d e = unit_beam(scan, col_origin, i);
    rows.directions.push_back(e);
    rows.targets_mps.push_back(static_cast<double>(scan.radial_velocity_mps[i]) + e.dot(ego_velocity_mps));
  }
}

void fill_statistics(const NormalEquations& ne, VelocityEstimate& estimate) {
  estimate.num_points = ne.n;
  const Eigen::Matrix3d AtA = ne.AtA;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(AtA);
  estimate.information_eigenvalues = eig.eigenvalues();
  const double lmin = eig.eigenvalues()(0);
  const double lmax = eig.eigenvalues()(2);
  estimate.condition_number = lmin > 0.0 ? lmax / lmin : std::numeric_limits<double>::infinity();
  const Eigen::Vector3d& x = estimate.velocity_mps;
  const double rss = std::max(0.0, ne.yty - 2.0 * x.dot(ne.Aty) + x.dot(AtA * x));
  estimate.residual_rms_mps = ne.n > 0 ? std::sqrt(rss / ne.n) : VelocityEstimate::kNaN;
  if (ne.n > 3 && lmin > 0.0) {
    const double sigma2 = rss / (ne.n - 3);
    const Eigen::Vector3d inv = eig.eigenvalues().cwiseInverse();
    estimate.covariance = sigma2 * eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
  } else {
    estimate.covariance.setConstant(VelocityEstimate::kNaN);
  }
}

VelocityEstimate solve_normal_equations(const NormalEquations& ne, double qr_condition_threshold,
                                        const std::function<VelocityRows()>& rows_for_qr) {
  VelocityEstimate est;
  est.num_points = ne.n;
  if (ne.n < 3) return est;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(ne.AtA, Eigen::EigenvaluesOnly);
  const double lmin = eig.eigenvalues()(0);
  const double cond = lmin > 0.0 ? eig.eigenvalues()(2) / lmin : std::numeric_limits<double>::infinity();
  bool full_rank = true;
  if (cond <= qr_condition_threshold) {
    est.velocity_mps = ne.AtA.ldlt().solve(ne.Aty);  // Eq. 21 minimised: (A^T A) V = A^T y
  } else {
    const VelocityRows rows = rows_for_qr();
    Eigen::MatrixX3d A(static_cast<Eigen::Index>(rows.size()), 3);
    Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k) {
      A.row(static_cast<Eigen::Index>(k)) = rows.directions[k].transpose();
      b(static_cast<Eigen::Index>(k)) = rows.targets_mps[k];
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixX3d> qr(A);
    est.velocity_mps = qr.solve(b);
    est.used_qr = true;
    full_rank = qr.rank() == 3;
  }
  fill_statistics(ne, est);
  est.valid = full_rank && est.velocity_mps.allFinite();
  return est;
}

VelocityEstimate solve_velocity_closed_form(const VelocityRows& rows, double qr_condition_threshold) {
  return solve_normal_equations(NormalEquations::of(rows), qr_condition_threshold, [&rows] { return rows; });
}

}  // namespace fmcw::core
