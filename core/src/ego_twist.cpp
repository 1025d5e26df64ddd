#include "fmcw/core/ego_twist.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>

#include "fmcw/core/check.hpp"
#include "fmcw/core/random.hpp"
#include "ego_twist_beams.hpp"
#include "vector_clones.hpp"

namespace fmcw::core {

namespace {

// The rows of the seeded subset MSAC scores hypotheses on, copied together.
void subset_rows(const TwistRows& rows, const std::vector<std::uint32_t>& subset, TwistRows& out) {
  out.clear();
  for (const std::uint32_t k : subset) out.push_back(rows.ex[k], rows.ey[k], rows.ez[k], rows.ew[k], rows.v[k], rows.cell[k]);
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

// Per lane: the truncated cost and the inlier count (counted in doubles: one vector type for
// the loop).
struct TruncatedTerms {
  double cost[kLanes] = {};
  double inliers[kLanes] = {};
};

// Row k's squared residual of the twist (p0, p1, p2, p3) into out, and its terms to lane j. The
// components come as plain pointers and the twist by value: a store to out could otherwise
// change what a vector or an array holds, and they would be loaded again per row (scalar code).
inline void truncated_row(const double* ex, const double* ey, const double* ez, const double* ew, const double* v,
                          std::size_t k, std::size_t j, double p0, double p1, double p2, double p3, double t2, double* out,
                          TruncatedTerms& terms) {
  const double res = v[k] + ex[k] * p0 + ey[k] * p1 + ez[k] * p2 + ew[k] * p3;
  const double q = res * res;
  out[k] = q;
  const double inlier = q < t2 ? 1.0 : 0.0;
  terms.cost[j] += q < t2 ? q : t2;
  terms.inliers[j] += inlier;
}

// The squared residuals of twist p into out, their truncated sum and the inlier count, point k in
// lane k % kLanes (vector_clones.hpp). The last partial block adds to a copy of the lanes: with
// the lanes of the whole blocks indexed by a variable there, GCC left the loop scalar.
FMCW_VECTOR_CLONES void truncated_sums(const TwistRows& sub, const double (&p)[4], double t2, double* out, double& cost,
                                       double& inliers) {
  const std::size_t n = sub.size();
  const double *ex = sub.ex.data(), *ey = sub.ey.data(), *ez = sub.ez.data(), *ew = sub.ew.data(), *v = sub.v.data();
  const double p0 = p[0], p1 = p[1], p2 = p[2], p3 = p[3];
  TruncatedTerms whole;
  std::size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    for (std::size_t j = 0; j < kLanes; ++j) truncated_row(ex, ey, ez, ew, v, i + j, j, p0, p1, p2, p3, t2, out, whole);
  }
  TruncatedTerms all = whole;
  for (std::size_t j = 0; i < n; ++i, ++j) truncated_row(ex, ey, ez, ew, v, i, j, p0, p1, p2, p3, t2, out, all);
  cost = 0.0;
  inliers = 0.0;
  for (int j = 0; j < kLanes; ++j) {
    cost += all.cost[j];
    inliers += all.inliers[j];
  }
}

// Squared residuals of twist p, then the truncated cost and the inliers per cell.
Score score(const TwistRows& sub, const std::vector<int>& column_points, const Eigen::Vector4d& p, double threshold,
            std::vector<double>& r2) {
  Score s;
  const double t2 = threshold * threshold;
  const std::size_t n = sub.size();
  r2.resize(n);
  double* out = r2.data();
  const double pv[4] = {p(0), p(1), p(2), p(3)};
  double cost = 0.0;
  double inliers = 0.0;
  truncated_sums(sub, pv, t2, out, cost, inliers);
  s.inliers = static_cast<int>(inliers);
  s.cost = cost;
  std::array<int, kCellCols * kCellRows> per_cell{};
  for (std::size_t k = 0; k < n; ++k) per_cell[sub.cell[k]] += out[k] < t2 ? 1 : 0;
  // A cell counts once it holds a few inliers: single stray points do not make coverage.
  s.coverage = 0;
  for (const int count : per_cell) s.coverage += count >= 3 ? 1 : 0;
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
  FMCW_CHECK_ARG(min_ransac_iterations >= 1 && min_ransac_iterations <= ransac_iterations,
                 "ego twist: min_ransac_iterations must be in [1, ransac_iterations], got ", min_ransac_iterations);
  FMCW_CHECK_ARG(ransac_confidence > 0.0 && ransac_confidence < 1.0, "ego twist: ransac_confidence must be in (0, 1), got ",
                 ransac_confidence);
  FMCW_CHECK_ARG(huber_k_sigma > 0.0 && refine_iterations >= 1, "ego twist: huber_k_sigma > 0 and refine_iterations >= 1 required");
  FMCW_CHECK_ARG(max_yaw_rate_rps > 0.0, "ego twist: max_yaw_rate_rps must be > 0");
  FMCW_CHECK_ARG(lateral_velocity_sigma_mps >= 0.0, "ego twist: lateral_velocity_sigma_mps must be >= 0, got ",
                 lateral_velocity_sigma_mps);
  FMCW_CHECK_ARG(min_inliers >= 4, "ego twist: min_inliers must be >= 4, got ", min_inliers);
  FMCW_CHECK_ARG(standing_coverage_fraction > 0.0 && standing_coverage_fraction <= 1.0,
                 "ego twist: standing_coverage_fraction must be in (0, 1]");
}

void TwistPriorParams::validate() const {
  FMCW_CHECK_ARG(accel_mps2 > 0.0, "ego prior: accel_mps2 must be > 0, got ", accel_mps2);
  FMCW_CHECK_ARG(velocity_margin_mps >= 0.0, "ego prior: velocity_margin_mps must be >= 0, got ", velocity_margin_mps);
  FMCW_CHECK_ARG(yaw_accel_rps2 > 0.0, "ego prior: yaw_accel_rps2 must be > 0, got ", yaw_accel_rps2);
  FMCW_CHECK_ARG(yaw_rate_margin_rps >= 0.0, "ego prior: yaw_rate_margin_rps must be >= 0, got ", yaw_rate_margin_rps);
  FMCW_CHECK_ARG(std::isfinite(fallback_max_windows) && fallback_max_windows >= 0.0,
                 "ego prior: fallback_max_windows must be finite and >= 0 (0 = no bound), got ",
                 fallback_max_windows);
}

EgoTwistEstimate estimate_ego_twist(const Scan& scan, const EgoTwistParams& params, std::uint64_t seed,
                                    const TwistPrior* prior) {
  EgoTwistWorkspace ws;
  return estimate_ego_twist(scan, ScanBeams(scan), params, seed, prior, ws);
}

namespace {

// One pass of Huber-weighted least squares over the inliers of twist p:
// the normal equations N = sum w a a^T, g = -sum w v a, with k = infinity plain least squares on
// the inliers. The sums run in kLanes lanes (their order is fixed, so results are reproducible).
struct HuberSums {
  Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
  Eigen::Vector4d g = Eigen::Vector4d::Zero();
  double rss = 0.0;
  double weight_sum = 0.0;
  int inliers = 0;
};

// Adds row q's terms to lane j of the sums (acc[term][lane]).
inline void huber_row(const TwistRows& rows, std::size_t q, int j, const double (&p)[4], double threshold, double k,
                      double (&acc)[17][kLanes]) {
  const double a0 = rows.ex[q], a1 = rows.ey[q], a2 = rows.ez[q], a3 = rows.ew[q];
  const double res = rows.v[q] + a0 * p[0] + a1 * p[1] + a2 * p[2] + a3 * p[3];
  const double ares = std::abs(res);
  const double huber = std::min(1.0, k / ares);  // 1 within k (also for k = infinity)
  const double w = ares < threshold ? huber : 0.0;
  const double t0 = w * a0, t1 = w * a1, t2 = w * a2, t3 = w * a3;
  acc[0][j] += t0 * a0;
  acc[1][j] += t0 * a1;
  acc[2][j] += t0 * a2;
  acc[3][j] += t0 * a3;
  acc[4][j] += t1 * a1;
  acc[5][j] += t1 * a2;
  acc[6][j] += t1 * a3;
  acc[7][j] += t2 * a2;
  acc[8][j] += t2 * a3;
  acc[9][j] += t3 * a3;
  const double wv = w * rows.v[q];
  acc[10][j] -= wv * a0;
  acc[11][j] -= wv * a1;
  acc[12][j] -= wv * a2;
  acc[13][j] -= wv * a3;
  acc[14][j] += w * res * res;
  acc[15][j] += w;
  acc[16][j] += ares < threshold ? 1.0 : 0.0;  // counted in doubles: one vector type for the loop
}

// The seventeen sums of a Huber pass, point k in lane k % kLanes (vector_clones.hpp).
FMCW_VECTOR_CLONES void huber_sums(const TwistRows& rows, const double (&p)[4], double threshold, double k,
                                   double (&out)[17]) {
  double acc[17][kLanes] = {};
  const std::size_t count = rows.size();
  std::size_t i = 0;
  for (; i + kLanes <= count; i += kLanes) {
    for (int j = 0; j < kLanes; ++j) huber_row(rows, i + static_cast<std::size_t>(j), j, p, threshold, k, acc);
  }
  for (int j = 0; i < count; ++i, ++j) huber_row(rows, i, j, p, threshold, k, acc);
  for (int t = 0; t < 17; ++t) {
    double sum = 0.0;
    for (int j = 0; j < kLanes; ++j) sum += acc[t][j];
    out[t] = sum;
  }
}

HuberSums huber_pass(const TwistRows& rows, const Eigen::Vector4d& p, double threshold, double k) {
  const double pv[4] = {p(0), p(1), p(2), p(3)};
  double s[17];
  huber_sums(rows, pv, threshold, k, s);
  HuberSums out;
  out.N << s[0], s[1], s[2], s[3], s[1], s[4], s[5], s[6], s[2], s[5], s[7], s[8], s[3], s[6], s[8], s[9];
  out.g << s[10], s[11], s[12], s[13];
  out.rss = s[14];
  out.weight_sum = s[15];
  out.inliers = static_cast<int>(s[16]);
  return out;
}

// What the estimate needs besides the rows: the twist's unknowns and the prior's window.
struct TwistProblem {
  const EgoTwistParams& params;
  const TwistPrior* prior;
  bool with_yaw = false;
  int dof = 3;

  bool admissible(const Eigen::Vector4d& q) const {
    if (prior == nullptr) return true;
    return (q.head<3>() - prior->velocity_mps).norm() <= prior->max_velocity_change_mps &&
           std::abs(q(3) - prior->yaw_rate_rps) <= prior->max_yaw_rate_change_rps;
  }
  // Without the yaw rate its row and column are the identity's.
  void fix_yaw(Eigen::Matrix4d& N, Eigen::Vector4d& g) const {
    if (with_yaw) return;
    N.col(3).setZero();
    N.row(3).setZero();
    N(3, 3) = 1.0;
    g(3) = 0.0;
  }
};

struct MsacResult {
  Eigen::Vector4d p = Eigen::Vector4d::Zero();
  Score score;
};

// Local optimisation: a minimal set amplifies noise, so refit on the hypothesis' inliers within
// the subset and keep the refit while it scores better.
void local_refit(const TwistRows& sub, const std::vector<int>& column_points, const TwistProblem& pb, MsacResult& best,
                 std::vector<double>& r2) {
  const double thr = pb.params.inlier_threshold_mps;
  for (int lo = 0; lo < 3; ++lo) {
    HuberSums sums = huber_pass(sub, best.p, thr, std::numeric_limits<double>::infinity());
    pb.fix_yaw(sums.N, sums.g);
    const Eigen::Vector4d refit = sums.N.ldlt().solve(sums.g);
    if (!refit.allFinite() || std::abs(refit(3)) > pb.params.max_yaw_rate_rps || !pb.admissible(refit)) break;
    const Score s = score(sub, column_points, refit, thr, r2);
    if (!s.better_than(best.score)) break;
    best.score = s;
    best.p = refit;
  }
}

// Early termination: once the best hypothesis holds inliers in every azimuth column of the grid
// (the static world: no other hypothesis can beat it on columns), as many minimal sets as give
// ransac_confidence of having drawn one of its inliers only, at least min_ransac_iterations.
// Otherwise (a world that shows in part of the view) all ransac_iterations.
int iterations_needed(const Score& best, std::size_t points, const TwistProblem& pb) {
  const EgoTwistParams& params = pb.params;
  if (best.columns < kCellCols || points == 0) return params.ransac_iterations;
  const double clean = std::pow(static_cast<double>(best.inliers) / static_cast<double>(points), pb.dof);
  if (clean >= 1.0) return params.min_ransac_iterations;
  const double needed = std::ceil(std::log(1.0 - params.ransac_confidence) / std::log1p(-clean));
  return static_cast<int>(std::clamp(needed, static_cast<double>(params.min_ransac_iterations),
                                     static_cast<double>(params.ransac_iterations)));
}

// MSAC over minimal sets drawn from the subset; the prior's twist, if any, is the first hypothesis.
MsacResult msac(const TwistRows& sub, const std::vector<int>& column_points, const TwistProblem& pb, std::uint64_t seed,
                std::vector<double>& r2) {
  const EgoTwistParams& params = pb.params;
  Rng rng(mix_seed(seed, 1));
  MsacResult best;
  if (pb.prior != nullptr) {
    best.p << pb.prior->velocity_mps, pb.with_yaw ? pb.prior->yaw_rate_rps : 0.0;
    best.score = score(sub, column_points, best.p, params.inlier_threshold_mps, r2);
  }
  int limit = pb.prior != nullptr ? iterations_needed(best.score, sub.v.size(), pb) : params.ransac_iterations;
  for (int it = 0; it < limit; ++it) {
    Eigen::Matrix4d A = Eigen::Matrix4d::Identity();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    std::array<std::uint32_t, 4> pick{};
    for (int j = 0; j < pb.dof; ++j) {
      bool fresh = false;
      while (!fresh) {
        pick[static_cast<std::size_t>(j)] = static_cast<std::uint32_t>(rng.uniform_below(sub.size()));
        fresh = true;
        for (int q = 0; q < j; ++q) fresh &= pick[static_cast<std::size_t>(q)] != pick[static_cast<std::size_t>(j)];
      }
      A.row(j) = sub.a(pick[static_cast<std::size_t>(j)]).transpose();
      b(j) = -sub.v[pick[static_cast<std::size_t>(j)]];
    }
    if (!pb.with_yaw) {
      A.col(3).setZero();
      A(3, 3) = 1.0;
    }
    const Eigen::FullPivLU<Eigen::Matrix4d> lu(A);
    if (lu.rank() < 4) continue;
    const Eigen::Vector4d p = lu.solve(b);
    if (!p.allFinite() || p.head<3>().norm() > 100.0 || std::abs(p(3)) > params.max_yaw_rate_rps || !pb.admissible(p)) continue;
    const Score s = score(sub, column_points, p, params.inlier_threshold_mps, r2);
    if (!s.better_than(best.score)) continue;
    best.score = s;
    best.p = p;
    local_refit(sub, column_points, pb, best, r2);
    limit = iterations_needed(best.score, sub.v.size(), pb);
  }
  return best;
}

// Refinement on all points: inliers of the current twist, Huber-weighted least squares.
// With a prior, a weak pull towards the previous twist in the rows' units (noise^2 / window^2):
// it decides only what the points leave open, such as the yaw rate when one head alone sees the
// static world, and it counts in the conditioning. A car's rear axle does not slide sideways:
// with the yaw rate estimated, a soft pull of the lateral velocity towards zero (same units)
// settles the direction in which lateral velocity and yaw rate trade off when the static world
// shows only ahead.
HuberSums refine(const TwistRows& rows, const TwistProblem& pb, bool standing, Eigen::Vector4d& p) {
  const EgoTwistParams& params = pb.params;
  const double k = params.huber_k_sigma * params.noise_sigma_mps;
  const double s2 = params.noise_sigma_mps * params.noise_sigma_mps;
  Eigen::Vector4d prior_info = Eigen::Vector4d::Zero();
  Eigen::Vector4d prior_twist = Eigen::Vector4d::Zero();
  if (pb.prior != nullptr) {
    const TwistPrior& prior = *pb.prior;
    prior_info << Eigen::Vector3d::Constant(s2 / (prior.max_velocity_change_mps * prior.max_velocity_change_mps)),
        pb.with_yaw ? s2 / (prior.max_yaw_rate_change_rps * prior.max_yaw_rate_change_rps) : 0.0;
    prior_twist << prior.velocity_mps, pb.with_yaw ? prior.yaw_rate_rps : 0.0;
  }
  double lateral_info = 0.0;
  if (pb.with_yaw && params.lateral_velocity_sigma_mps > 0.0) {
    lateral_info = s2 / (params.lateral_velocity_sigma_mps * params.lateral_velocity_sigma_mps);
  }
  HuberSums sums;
  for (int iter = 0; iter < params.refine_iterations; ++iter) {
    sums = huber_pass(rows, p, params.inlier_threshold_mps, k);
    sums.N.diagonal() += prior_info;
    sums.g += prior_info.cwiseProduct(prior_twist);
    sums.N(1, 1) += lateral_info;  // towards v_y = 0
    if (standing || sums.inliers < pb.dof) break;
    Eigen::Matrix4d N = sums.N;
    Eigen::Vector4d g = sums.g;
    pb.fix_yaw(N, g);
    const Eigen::Vector4d next = N.ldlt().solve(g);
    if (!next.allFinite() || std::abs(next(3)) > params.max_yaw_rate_rps || !pb.admissible(next)) break;
    p = next;
  }
  return sums;
}

// The estimate from the refined twist p and the sums of its last pass: conditioning and
// covariance of the estimated parameters, sigma^2 N^-1 on the inliers.
void fill_estimate(const TwistRows& rows, const HuberSums& sums, const Eigen::Vector4d& p, const TwistProblem& pb,
                   EgoTwistEstimate& out) {
  const std::size_t n = rows.size();
  const Eigen::Matrix4d& N = sums.N;
  const int dof = pb.dof;
  out.inliers = sums.inliers;
  out.inlier_fraction = static_cast<double>(sums.inliers) / n;
  out.velocity.velocity_mps = p.head<3>();
  out.velocity.num_points = sums.inliers;
  out.angular_velocity_rps = Eigen::Vector3d(0.0, 0.0, pb.with_yaw ? p(3) : 0.0);
  out.yaw_rate_estimated = pb.with_yaw;
  const Eigen::MatrixXd Nd = pb.with_yaw ? Eigen::MatrixXd(N) : Eigen::MatrixXd(N.topLeftCorner<3, 3>());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Nd);
  const double lmin = eig.eigenvalues()(0);
  out.velocity.information_eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(N.topLeftCorner<3, 3>()).eigenvalues();
  out.velocity.condition_number = lmin > 0.0 ? eig.eigenvalues()(dof - 1) / lmin : std::numeric_limits<double>::infinity();
  out.velocity.residual_rms_mps = sums.weight_sum > 0.0 ? std::sqrt(sums.rss / sums.weight_sum) : VelocityEstimate::kNaN;
  if (sums.inliers > dof && lmin > 0.0) {
    const double sigma2 = sums.rss / std::max(1.0, sums.weight_sum - dof);
    const Eigen::MatrixXd cov = sigma2 * Nd.inverse();
    out.velocity.covariance = cov.topLeftCorner<3, 3>();
    out.yaw_rate_std_rps = pb.with_yaw ? std::sqrt(cov(3, 3)) : 0.0;
  }
  out.valid = sums.inliers >= std::max(dof, pb.params.min_inliers) && std::isfinite(out.velocity.condition_number) &&
              p.allFinite();
  out.velocity.valid = out.valid;
}

}  // namespace

namespace {

// The estimate on the rows already in ws.rows. With a prior that finds too few inliers, it
// starts afresh without the prior on the same rows, and keeps that only near the prior.
EgoTwistEstimate estimate_on_rows(const Scan& scan, const EgoTwistParams& params, std::uint64_t seed, const TwistPrior* prior,
                                  EgoTwistWorkspace& ws) {
  EgoTwistEstimate out;
  const TwistRows& rows = ws.rows;
  const auto n = static_cast<std::uint32_t>(rows.v.size());
  if (n < 4) return out;

  // The yaw rate is observable only when heads sit at different points.
  bool distinct_mounts = false;
  for (const auto& h : scan.heads) distinct_mounts |= (h.origin_m() - scan.heads.front().origin_m()).norm() > 0.01;
  TwistProblem pb{params, prior};
  pb.with_yaw = params.estimate_yaw_rate && distinct_mounts;
  pb.dof = pb.with_yaw ? 4 : 3;

  // MSAC on a seeded subset of the points.
  const std::vector<std::uint32_t> subset = subsample_indices(n, static_cast<std::uint32_t>(params.sample_points), seed);
  std::vector<int> column_points(kCellCols, 0);
  for (const std::uint32_t k : subset) ++column_points[rows.cell[k] % kCellCols];
  const TwistRows& sub = ws.sub;
  subset_rows(rows, subset, ws.sub);
  const MsacResult best = msac(sub, column_points, pb, seed, ws.r2);
  if (prior != nullptr && best.score.inliers < params.min_inliers) {
    EgoTwistEstimate fresh = estimate_on_rows(scan, params, seed, nullptr, ws);
    if (!fresh.valid || prior->max_fallback_change_mps <= 0.0 ||
        (fresh.velocity.velocity_mps - prior->velocity_mps).norm() <=
            prior->max_fallback_change_mps)
      return fresh;
    out.fallback_rejected = true;
    out.rejected_velocity_mps = fresh.velocity.velocity_mps;
    out.rejected_inliers = fresh.inliers;
    out.inliers = best.score.inliers;
    return out;
  }
  // Zero-velocity test: a standing rig sees the static world at zero Doppler.
  const Score zero = score(sub, column_points, Eigen::Vector4d::Zero(), params.inlier_threshold_mps, ws.r2);
  out.standing = pb.admissible(Eigen::Vector4d::Zero()) && zero.columns >= best.score.columns &&
                 zero.coverage >= params.standing_coverage_fraction * best.score.coverage &&
                 zero.inliers >= params.standing_coverage_fraction * best.score.inliers;
  Eigen::Vector4d p = out.standing ? Eigen::Vector4d::Zero() : best.p;
  const HuberSums sums = refine(rows, pb, out.standing, p);
  fill_estimate(rows, sums, p, pb, out);
  return out;
}

}  // namespace

EgoTwistEstimate estimate_ego_twist(const Scan& scan, const ScanBeams& beams, const EgoTwistParams& params,
                                    std::uint64_t seed, const TwistPrior* prior, EgoTwistWorkspace& ws) {
  gather_rows(scan, beams, ws.rows);
  return estimate_on_rows(scan, params, seed, prior, ws);
}

}  // namespace fmcw::core
