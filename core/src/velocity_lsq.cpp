#include "fmcw/core/velocity_lsq.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "fmcw/core/median.hpp"
#include "vector_clones.hpp"

namespace fmcw::core {

namespace {
Eigen::Vector3d unit_beam(const Scan& scan, const std::vector<Eigen::Vector3d>& col_origin, std::uint32_t i) {
  const Eigen::Vector3d d =
      scan.position(i) - col_origin[i % static_cast<std::uint32_t>(scan.cols)];
  return d / d.norm();
}

// 1.4826 times the median absolute residual (a Gaussian's sigma), at least floor_sigma. Of a
// large set, the median of every k-th residual (at most kScaleSamples of them): its relative
// error is about 1/sqrt(kScaleSamples), a few percent, and a bus's cluster has tens of
// thousands of rows.
constexpr std::size_t kScaleSamples = 4096;
struct ScaleScratch {
  std::vector<double> magnitude;
  std::vector<std::uint64_t> keys;
};
double robust_scale(const std::vector<double>& residual, double floor_sigma, ScaleScratch& scratch) {
  const std::size_t stride = std::max<std::size_t>(1, (residual.size() + kScaleSamples - 1) / kScaleSamples);
  std::vector<double>& m = scratch.magnitude;
  m.resize((residual.size() + stride - 1) / stride);
  for (std::size_t k = 0, j = 0; k < residual.size(); k += stride, ++j) m[j] = std::abs(residual[k]);
  return std::max(floor_sigma, 1.4826 * upper_median_of_magnitudes(m, scratch.keys));
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

namespace {
// The weighted sums of a planar fit, N = sum w a a^T and g = sum w t a, in scalars (registers,
// not matrices in memory: a store-to-load chain per row) and entry by entry as Eigen's
// (w a) a^T and (w t) a add them, N's two off-diagonal entries each their own sum.
struct PlanarSums {
  double n00 = 0.0, n01 = 0.0, n10 = 0.0, n11 = 0.0, g0 = 0.0, g1 = 0.0;
  void add(double w, const Eigen::Vector3d& a, double t) {
    const double wa0 = w * a.x(), wa1 = w * a.y(), wt = w * t;
    n00 += wa0 * a.x();
    n10 += wa1 * a.x();
    n01 += wa0 * a.y();
    n11 += wa1 * a.y();
    g0 += wt * a.x();
    g1 += wt * a.y();
  }
  Eigen::Matrix2d N() const { return (Eigen::Matrix2d() << n00, n01, n10, n11).finished(); }
  Eigen::Vector2d g() const { return {g0, g1}; }
};

// solve_velocity_planar, also handing back the rows' information N = sum a a^T (zero with fewer
// than two rows), which the robust fit starts from.
VelocityEstimate fit_planar(const VelocityRows& rows, Eigen::Matrix2d& N) {
  VelocityEstimate est;
  est.num_points = static_cast<int>(rows.size());
  N.setZero();
  if (rows.size() < 2) return est;
  PlanarSums sums;
  double yty = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    sums.add(1.0, rows.directions[k], rows.targets_mps[k]);  // w = 1 multiplies exactly
    yty += rows.targets_mps[k] * rows.targets_mps[k];
  }
  N = sums.N();
  const Eigen::Vector2d g = sums.g();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(N);
  const double lmin = eig.eigenvalues()(0);
  est.information_eigenvalues = Eigen::Vector3d(0.0, eig.eigenvalues()(0), eig.eigenvalues()(1));
  est.condition_number = lmin > 0.0 ? eig.eigenvalues()(1) / lmin : std::numeric_limits<double>::infinity();
  if (!(lmin > 0.0)) return est;
  const Eigen::Vector2d v = N.ldlt().solve(g);
  est.velocity_mps = Eigen::Vector3d(v.x(), v.y(), 0.0);
  const double rss = std::max(0.0, yty - 2.0 * v.dot(g) + v.dot(N * v));
  est.residual_rms_mps = std::sqrt(rss / static_cast<double>(rows.size()));
  est.covariance.setZero();
  if (rows.size() > 2) est.covariance.topLeftCorner<2, 2>() = rss / static_cast<double>(rows.size() - 2) * N.inverse();
  est.valid = v.allFinite();
  return est;
}
}  // namespace

VelocityEstimate solve_velocity_planar(const VelocityRows& rows) {
  Eigen::Matrix2d N;
  return fit_planar(rows, N);
}

namespace {
// Tukey's biweight of each residual at c: (1 - u^2)^2 with u = r / c, 0 where |u| >= 1. A row
// of weight 0 adds +0 or -0 to the sums, which leaves them as skipping it would (a sum that
// starts at +0 is never -0, and the rows are finite): the divisions run in vectors here, and
// the sums without a branch per row.
FMCW_VECTOR_CLONES void tukey_weights(const double* __restrict residual, std::size_t n, double c,
                                      double* __restrict weight) {
  for (std::size_t k = 0; k < n; ++k) {
    const double u = residual[k] / c;
    const double w = (1.0 - u * u) * (1.0 - u * u);
    weight[k] = std::abs(u) >= 1.0 ? 0.0 : w;
  }
}
}  // namespace

VelocityEstimate solve_velocity_planar_robust(const VelocityRows& rows, double noise_sigma_mps, int iterations) {
  Eigen::Matrix2d N_used;  // the weighted information behind v: at first every row's
  VelocityEstimate est = fit_planar(rows, N_used);
  if (!est.valid) return est;
  const std::size_t n = rows.size();
  std::vector<double> residual(n), weight(n);
  ScaleScratch scratch;
  Eigen::Vector2d v = est.velocity_mps.head<2>();
  Eigen::Matrix2d N = Eigen::Matrix2d::Zero();
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t k = 0; k < n; ++k) residual[k] = rows.targets_mps[k] - rows.directions[k].head<2>().dot(v);
    // Tukey's biweight with c = 4.685 robust standard deviations (1.4826 MAD).
    const double scale = robust_scale(residual, noise_sigma_mps, scratch);
    const double c = 4.685 * scale;
    tukey_weights(residual.data(), n, c, weight.data());
    PlanarSums sums;
    for (std::size_t k = 0; k < n; ++k) sums.add(weight[k], rows.directions[k], rows.targets_mps[k]);
    N = sums.N();
    const Eigen::Vector2d g = sums.g();
    const Eigen::Vector2d next = N.ldlt().solve(g);
    if (!next.allFinite() || N.determinant() <= 0.0) break;
    const bool converged = (next - v).norm() < 1e-6;
    v = next;
    N_used = N;
    if (converged) break;
  }
  est.velocity_mps = Eigen::Vector3d(v.x(), v.y(), 0.0);
  // Covariance of the robust fit: the residuals' robust scale (at least the noise) over the
  // information of the rows it kept. The plain fit's would count every wheel and limb row.
  for (std::size_t k = 0; k < n; ++k) residual[k] = rows.targets_mps[k] - rows.directions[k].head<2>().dot(v);
  const double scale = robust_scale(residual, noise_sigma_mps, scratch);
  if (N_used.determinant() > 0.0) {
    est.covariance.setZero();
    est.covariance.topLeftCorner<2, 2>() = scale * scale * N_used.inverse();
  }
  return est;
}

void zero_unobserved_direction(VelocityEstimate& estimate, double noise_sigma_mps, double max_weak_sigma_mps,
                               double unobserved_speed_sigma_mps) {
  if (!estimate.valid || !estimate.covariance.allFinite() || !estimate.velocity_mps.allFinite()) return;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(estimate.covariance.topLeftCorner<2, 2>());
  const double weakest_information = estimate.information_eigenvalues(1);  // planar: (0, min, max)
  const double weak_var =
      std::max(eig.eigenvalues()(1), weakest_information > 0.0
                                         ? noise_sigma_mps * noise_sigma_mps / weakest_information
                                         : std::numeric_limits<double>::infinity());
  if (!(weak_var > max_weak_sigma_mps * max_weak_sigma_mps)) return;
  const Eigen::Vector2d strong = eig.eigenvectors().col(0);
  const Eigen::Vector2d weak = eig.eigenvectors().col(1);
  estimate.velocity_mps.head<2>() = estimate.velocity_mps.head<2>().dot(strong) * strong;
  estimate.covariance.topLeftCorner<2, 2>() =
      eig.eigenvalues()(0) * strong * strong.transpose() +
      std::max(weak_var, unobserved_speed_sigma_mps * unobserved_speed_sigma_mps) * weak * weak.transpose();
}

VelocityEstimate solve_velocity_closed_form(const VelocityRows& rows, double qr_condition_threshold) {
  return solve_normal_equations(NormalEquations::of(rows), qr_condition_threshold, [&rows] { return rows; });
}

void flag_meaningless(VelocityEstimate& estimate, double max_sigma_mps) {
  if (!estimate.valid) return;
  if (!estimate.covariance.allFinite() || !estimate.velocity_mps.allFinite() ||
      estimate.velocity_mps.norm() > kMaxPlausibleSpeedMps) {
    estimate.valid = false;
    return;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(estimate.covariance, Eigen::EigenvaluesOnly);
  if (!(eig.eigenvalues().maxCoeff() <= max_sigma_mps * max_sigma_mps)) estimate.valid = false;
}

}  // namespace fmcw::core
