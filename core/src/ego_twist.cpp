#include "fmcw/core/ego_twist.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <array>
#include <bitset>
#include <cmath>

#include "fmcw/core/check.hpp"
#include "fmcw/core/random.hpp"

namespace fmcw::core {

namespace {

constexpr int kCellCols = 24;  // coverage grid over the image
constexpr int kCellRows = 6;
using Coverage = std::bitset<kCellCols * kCellRows>;

// The valid points as rows of the twist problem: a = [e, (r x e)_z], target -v.
struct TwistRows {
  std::vector<Eigen::Vector4d> a;
  std::vector<double> v;
  std::vector<std::uint16_t> cell;
};

TwistRows gather_rows(const Scan& scan) {
  TwistRows rows;
  const std::vector<Eigen::Vector3d> origin = column_origins(scan);
  rows.a.reserve(scan.size());
  for (int r = 0; r < scan.rows; ++r) {
    for (int c = 0; c < scan.cols; ++c) {
      const std::size_t i = scan.index(r, c);
      if (!scan.valid[i]) continue;
      const Eigen::Vector3d& o = origin[static_cast<std::size_t>(c)];
      const Eigen::Vector3d e = (scan.position(i) - o).normalized();
      // Yaw rate term: e . (omega_z z x o) = omega_z (o_x e_y - o_y e_x).
      rows.a.emplace_back(e.x(), e.y(), e.z(), o.x() * e.y() - o.y() * e.x());
      rows.v.push_back(scan.radial_velocity_mps[i]);
      const int cell = (r * kCellRows / scan.rows) * kCellCols + c * kCellCols / scan.cols;
      rows.cell.push_back(static_cast<std::uint16_t>(cell));
    }
  }
  return rows;
}

struct Score {
  int columns = -1;   // azimuth columns of the grid holding inliers
  int coverage = -1;  // cells of the grid holding inliers
  int inliers = 0;
  double cost = 0.0;
  // The static world shows in nearly every azimuth (ground below, buildings above), a vehicle
  // in a band of them: more columns first, then more cells, then lower truncated cost.
  bool better_than(const Score& o) const {
    if (columns != o.columns) return columns > o.columns;
    return coverage != o.coverage ? coverage > o.coverage : cost < o.cost;
  }
};

Score score(const TwistRows& rows, const std::vector<std::uint32_t>& subset, const std::vector<int>& column_points,
            const Eigen::Vector4d& p, double threshold) {
  Score s;
  Coverage covered;
  std::array<int, kCellCols * kCellRows> per_cell{};
  const double t2 = threshold * threshold;
  for (const std::uint32_t k : subset) {
    const double res = rows.v[k] + rows.a[k].dot(p);
    const double r2 = res * res;
    if (r2 < t2) {
      ++s.inliers;
      // A cell counts once it holds a few inliers: single stray points do not make coverage.
      if (++per_cell[rows.cell[k]] == 3) covered.set(rows.cell[k]);
      s.cost += r2;
    } else {
      s.cost += t2;
    }
  }
  s.coverage = static_cast<int>(covered.count());
  // A column counts when its inliers are a real share of its points, not a thin band.
  s.columns = 0;
  for (int c = 0; c < kCellCols; ++c) {
    int in_column = 0;
    for (int r = 0; r < kCellRows; ++r) in_column += per_cell[static_cast<std::size_t>(r * kCellCols + c)];
    s.columns += in_column >= 3 && in_column * 10 >= column_points[static_cast<std::size_t>(c)] ? 1 : 0;
  }
  return s;
}

}  // namespace

void EgoTwistParams::validate() const {
  FMCW_CHECK_ARG(noise_sigma_mps > 0.0 && inlier_threshold_mps > 0.0, "ego twist: noise_sigma_mps and inlier_threshold_mps must be > 0");
  FMCW_CHECK_ARG(ransac_iterations >= 1 && sample_points >= 8, "ego twist: ransac_iterations >= 1 and sample_points >= 8 required");
  FMCW_CHECK_ARG(huber_k_sigma > 0.0 && refine_iterations >= 1, "ego twist: huber_k_sigma > 0 and refine_iterations >= 1 required");
  FMCW_CHECK_ARG(max_yaw_rate_rps > 0.0, "ego twist: max_yaw_rate_rps must be > 0");
  FMCW_CHECK_ARG(lateral_velocity_sigma_mps >= 0.0, "ego twist: lateral_velocity_sigma_mps must be >= 0, got ",
                 lateral_velocity_sigma_mps);
  FMCW_CHECK_ARG(min_inliers >= 4, "ego twist: min_inliers must be >= 4, got ", min_inliers);
  FMCW_CHECK_ARG(standing_coverage_fraction > 0.0 && standing_coverage_fraction <= 1.0,
                 "ego twist: standing_coverage_fraction must be in (0, 1]");
}

EgoTwistEstimate estimate_ego_twist(const Scan& scan, const EgoTwistParams& params, std::uint64_t seed,
                                    const TwistPrior* prior) {
  EgoTwistEstimate out;
  const TwistRows rows = gather_rows(scan);
  const auto n = static_cast<std::uint32_t>(rows.v.size());
  if (n < 4) return out;

  // The yaw rate is observable only when heads sit at different points.
  bool distinct_mounts = false;
  for (const auto& h : scan.heads) distinct_mounts |= (h.origin_m() - scan.heads.front().origin_m()).norm() > 0.01;
  const bool with_yaw = params.estimate_yaw_rate && distinct_mounts;
  const int dof = with_yaw ? 4 : 3;

  // MSAC on a seeded subset of the points.
  const std::vector<std::uint32_t> subset = subsample_indices(n, static_cast<std::uint32_t>(params.sample_points), seed);
  std::vector<int> column_points(kCellCols, 0);
  for (const std::uint32_t k : subset) ++column_points[rows.cell[k] % kCellCols];
  Rng rng(mix_seed(seed, 1));
  const auto admissible = [&](const Eigen::Vector4d& q) {
    if (prior == nullptr) return true;
    return (q.head<3>() - prior->velocity_mps).norm() <= prior->max_velocity_change_mps &&
           std::abs(q(3) - prior->yaw_rate_rps) <= prior->max_yaw_rate_change_rps;
  };
  Eigen::Vector4d best_p = Eigen::Vector4d::Zero();
  Score best;
  if (prior != nullptr) {  // the previous twist is the first hypothesis
    best_p << prior->velocity_mps, with_yaw ? prior->yaw_rate_rps : 0.0;
    best = score(rows, subset, column_points, best_p, params.inlier_threshold_mps);
  }
  for (int it = 0; it < params.ransac_iterations; ++it) {
    Eigen::Matrix4d A = Eigen::Matrix4d::Identity();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    std::array<std::uint32_t, 4> pick{};
    for (int j = 0; j < dof; ++j) {
      bool fresh = false;
      while (!fresh) {
        pick[static_cast<std::size_t>(j)] = subset[rng.uniform_below(subset.size())];
        fresh = true;
        for (int q = 0; q < j; ++q) fresh &= pick[static_cast<std::size_t>(q)] != pick[static_cast<std::size_t>(j)];
      }
      A.row(j) = rows.a[pick[static_cast<std::size_t>(j)]].transpose();
      b(j) = -rows.v[pick[static_cast<std::size_t>(j)]];
    }
    if (!with_yaw) {
      A.col(3).setZero();
      A(3, 3) = 1.0;
    }
    const Eigen::FullPivLU<Eigen::Matrix4d> lu(A);
    if (lu.rank() < 4) continue;
    const Eigen::Vector4d p = lu.solve(b);
    if (!p.allFinite() || p.head<3>().norm() > 100.0 || std::abs(p(3)) > params.max_yaw_rate_rps || !admissible(p)) continue;
    Score s = score(rows, subset, column_points, p, params.inlier_threshold_mps);
    if (!s.better_than(best)) continue;
    best = s;
    best_p = p;
    // Local optimisation: a minimal set amplifies noise, so refit on the hypothesis' inliers
    // within the subset and keep the refit while it scores better.
    for (int lo = 0; lo < 3; ++lo) {
      Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
      Eigen::Vector4d g = Eigen::Vector4d::Zero();
      for (const std::uint32_t q : subset) {
        if (std::abs(rows.v[q] + rows.a[q].dot(best_p)) >= params.inlier_threshold_mps) continue;
        N.noalias() += rows.a[q] * rows.a[q].transpose();
        g.noalias() -= rows.v[q] * rows.a[q];
      }
      if (!with_yaw) {
        N.col(3).setZero();
        N.row(3).setZero();
        N(3, 3) = 1.0;
        g(3) = 0.0;
      }
      const Eigen::Vector4d refit = N.ldlt().solve(g);
      if (!refit.allFinite() || std::abs(refit(3)) > params.max_yaw_rate_rps || !admissible(refit)) break;
      s = score(rows, subset, column_points, refit, params.inlier_threshold_mps);
      if (!s.better_than(best)) break;
      best = s;
      best_p = refit;
    }
  }
  if (prior != nullptr && best.inliers < params.min_inliers) return estimate_ego_twist(scan, params, seed, nullptr);
  // Zero-velocity test: a standing rig sees the static world at zero Doppler.
  const Score zero = score(rows, subset, column_points, Eigen::Vector4d::Zero(), params.inlier_threshold_mps);
  out.standing = admissible(Eigen::Vector4d::Zero()) && zero.columns >= best.columns && zero.coverage >= params.standing_coverage_fraction * best.coverage &&
                 zero.inliers >= params.standing_coverage_fraction * best.inliers;
  Eigen::Vector4d p = out.standing ? Eigen::Vector4d::Zero() : best_p;

  // Refinement on all points: inliers of the current twist, Huber-weighted least squares.
  const double k = params.huber_k_sigma * params.noise_sigma_mps;
  Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
  Eigen::Vector4d g = Eigen::Vector4d::Zero();
  double rss = 0.0, weight_sum = 0.0;
  int inliers = 0;
  Coverage covered;
  // With a prior, a weak pull towards the previous twist in the rows' units (noise^2 /
  // window^2): it decides only what the points leave open, such as the yaw rate when one head
  // alone sees the static world, and it counts in the conditioning below.
  Eigen::Vector4d prior_info = Eigen::Vector4d::Zero();
  Eigen::Vector4d prior_twist = Eigen::Vector4d::Zero();
  if (prior != nullptr) {
    const double s2 = params.noise_sigma_mps * params.noise_sigma_mps;
    prior_info << Eigen::Vector3d::Constant(s2 / (prior->max_velocity_change_mps * prior->max_velocity_change_mps)),
        with_yaw ? s2 / (prior->max_yaw_rate_change_rps * prior->max_yaw_rate_change_rps) : 0.0;
    prior_twist << prior->velocity_mps, with_yaw ? prior->yaw_rate_rps : 0.0;
  }
  // A car's rear axle does not slide sideways: with the yaw rate estimated, a soft pull of the
  // lateral velocity towards zero (same units) settles the direction in which lateral velocity
  // and yaw rate trade off when the static world shows only ahead.
  double lateral_info = 0.0;
  if (with_yaw && params.lateral_velocity_sigma_mps > 0.0) {
    const double s2 = params.noise_sigma_mps * params.noise_sigma_mps;
    lateral_info = s2 / (params.lateral_velocity_sigma_mps * params.lateral_velocity_sigma_mps);
  }
  for (int iter = 0; iter < params.refine_iterations; ++iter) {
    N.setZero();
    g.setZero();
    rss = weight_sum = 0.0;
    inliers = 0;
    covered.reset();
    for (std::uint32_t i = 0; i < n; ++i) {
      const double res = rows.v[i] + rows.a[i].dot(p);
      const double ares = std::abs(res);
      if (ares >= params.inlier_threshold_mps) continue;
      const double w = ares <= k ? 1.0 : k / ares;
      N.noalias() += w * rows.a[i] * rows.a[i].transpose();
      g.noalias() -= w * rows.v[i] * rows.a[i];
      rss += w * res * res;
      weight_sum += w;
      ++inliers;
      covered.set(rows.cell[i]);
    }
    N.diagonal() += prior_info;
    g += prior_info.cwiseProduct(prior_twist);
    N(1, 1) += lateral_info;  // towards v_y = 0
    if (out.standing || inliers < dof) break;
    if (!with_yaw) {
      N.col(3).setZero();
      N.row(3).setZero();
      N(3, 3) = 1.0;
      g(3) = 0.0;
    }
    const Eigen::Vector4d next = N.ldlt().solve(g);
    if (!next.allFinite() || std::abs(next(3)) > params.max_yaw_rate_rps || !admissible(next)) break;
    p = next;
  }
  out.inliers = inliers;
  out.inlier_fraction = static_cast<double>(inliers) / n;
  out.coverage_cells = static_cast<int>(covered.count());
  out.velocity.velocity_mps = p.head<3>();
  out.velocity.num_points = inliers;
  out.angular_velocity_rps = Eigen::Vector3d(0.0, 0.0, with_yaw ? p(3) : 0.0);
  out.yaw_rate_estimated = with_yaw;
  // Conditioning and covariance of the estimated parameters: sigma^2 N^-1 on the inliers.
  const Eigen::MatrixXd Nd = with_yaw ? Eigen::MatrixXd(N) : Eigen::MatrixXd(N.topLeftCorner<3, 3>());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Nd);
  const double lmin = eig.eigenvalues()(0);
  out.velocity.information_eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(N.topLeftCorner<3, 3>()).eigenvalues();
  out.velocity.condition_number = lmin > 0.0 ? eig.eigenvalues()(dof - 1) / lmin : std::numeric_limits<double>::infinity();
  out.velocity.residual_rms_mps = weight_sum > 0.0 ? std::sqrt(rss / weight_sum) : VelocityEstimate::kNaN;
  if (inliers > dof && lmin > 0.0) {
    const double sigma2 = rss / std::max(1.0, weight_sum - dof);
    const Eigen::MatrixXd cov = sigma2 * Nd.inverse();
    out.velocity.covariance = cov.topLeftCorner<3, 3>();
    out.yaw_rate_std_rps = with_yaw ? std::sqrt(cov(3, 3)) : 0.0;
  }
  out.valid = inliers >= std::max(dof, params.min_inliers) && std::isfinite(out.velocity.condition_number) && p.allFinite();
  out.velocity.valid = out.valid;
  return out;
}

}  // namespace fmcw::core
