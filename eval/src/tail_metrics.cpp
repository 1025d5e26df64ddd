#include "fmcw/eval/tail_metrics.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "fmcw/eval/statistics.hpp"

namespace fmcw::eval {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double share(std::size_t part, std::size_t all) {
  return all == 0 ? kNaN : static_cast<double>(part) / static_cast<double>(all);
}
}  // namespace

ErrorStats error_stats(const std::vector<double>& errors) {
  ErrorStats e;
  std::vector<double> v;
  v.reserve(errors.size());
  for (const double x : errors) {
    if (std::isfinite(x)) v.push_back(x);
  }
  e.count = static_cast<int>(v.size());
  e.median = quantile(v, 0.5);
  e.p90 = quantile(v, 0.9);
  e.p95 = quantile(v, 0.95);
  e.max = quantile(v, 1.0);
  const auto over = [&v](double limit) {
    return static_cast<std::size_t>(std::count_if(v.begin(), v.end(), [limit](double x) { return x > limit; }));
  };
  e.share_over_0p5mps = share(over(0.5), v.size());
  e.share_over_1mps = share(over(1.0), v.size());
  return e;
}

double chi2_95(int dof) {
  // Quantiles of the chi-square distribution at 0.95 (e.g. Abramowitz & Stegun, Table 26.8).
  return dof == 1 ? 3.841458820694124 : 5.991464547107979;
}

NeesScore score_nees(const Eigen::Vector2d& e, const Eigen::Matrix2d& cov, double unobservable_sigma) {
  NeesScore s;
  if (!e.allFinite()) return s;
  // An infinite variance says "not observed"; NaN or a negative variance is no covariance.
  Eigen::Matrix2d c = cov.unaryExpr([](double x) { return std::isinf(x) ? 1e300 : x; });
  if (!c.allFinite()) return s;
  c = 0.5 * (c + c.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(c);
  if (eig.info() != Eigen::Success || eig.eigenvalues()(0) < 0.0) return s;
  s.has_covariance = true;
  const double limit = unobservable_sigma * unobservable_sigma;
  for (int k = 0; k < 2; ++k) {
    const double var = eig.eigenvalues()(k);
    if (!(var <= limit)) continue;  // unobservable direction
    const double along = eig.eigenvectors().col(k).dot(e);
    // A zero variance with a non-zero error is infinitely far outside: NEES = inf.
    s.nees += var > 0.0 ? along * along / var : (along == 0.0 ? 0.0 : std::numeric_limits<double>::infinity());
    ++s.dof;
  }
  s.inside_95 = s.dof > 0 && s.nees <= chi2_95(s.dof);
  return s;
}

std::string distance_band(double d) {
  if (d < 20.0) return "0-20";
  if (d < 40.0) return "20-40";
  if (d < 80.0) return "40-80";
  return "80+";
}

namespace {
// Sums of the scored estimates of one group, turned into CalibrationStats by finish().
struct CalibrationSums {
  CalibrationStats c;
  int inside = 0;
  double nees = 0.0, dof = 0.0;

  void add(const NeesScore& n) {
    ++c.estimates;
    if (!n.has_covariance) {
      ++c.without_covariance;
    } else if (n.dof == 0) {
      ++c.fully_unobservable;
    } else {
      ++c.scored;
      c.partly_unobservable += n.dof < 2 ? 1 : 0;
      inside += n.inside_95 ? 1 : 0;
      nees += n.nees;
      dof += n.dof;
    }
  }
  CalibrationStats finish() const {
    CalibrationStats out = c;
    out.coverage_95 = share(static_cast<std::size_t>(inside), static_cast<std::size_t>(c.scored));
    out.mean_nees = c.scored == 0 ? kNaN : nees / c.scored;
    out.mean_dof = c.scored == 0 ? kNaN : dof / c.scored;
    return out;
  }
};
}  // namespace

ObjectTails object_tails(const std::vector<FrameEvaluation>& frames, const TailParams& params) {
  ObjectTails t;
  std::vector<double> large;
  std::map<std::string, std::vector<double>> by_class, by_distance, by_age;
  std::map<std::uint32_t, int> age;  // frames in which the actor has been evaluated so far
  CalibrationSums all;
  std::map<std::string, CalibrationSums> cal_class, cal_age;
  const std::string young = "first_" + std::to_string(params.young_updates), later = "later";
  for (const FrameEvaluation& f : frames) {
    for (const ObjectMatch& o : f.objects) {
      if (!o.evaluated) continue;
      const int a = ++age[o.actor_id];
      if (!o.estimate_valid) continue;
      const Eigen::Vector3d e = o.reference_error_mps();
      const std::string& age_key = a <= params.young_updates ? young : later;
      const NeesScore n = score_nees(e.head<2>(), o.estimate_covariance.topLeftCorner<2, 2>(), params.unobservable_sigma_mps);
      all.add(n);
      cal_class[o.class_name].add(n);
      cal_age[age_key].add(n);
      if (o.pixels < params.large_object_pixels) continue;
      const double err = e.norm();
      large.push_back(err);
      by_class[o.class_name].push_back(err);
      by_distance[distance_band(o.distance_m)].push_back(err);
      by_age[age_key].push_back(err);
    }
  }
  t.calibration = all.finish();
  for (const auto& [k, v] : cal_class) t.calibration_by_class[k] = v.finish();
  for (const auto& [k, v] : cal_age) t.calibration_by_age[k] = v.finish();
  t.ge200 = error_stats(large);
  for (const auto& [k, v] : by_class) t.by_class[k] = error_stats(v);
  for (const auto& [k, v] : by_distance) t.by_distance[k] = error_stats(v);
  for (const auto& [k, v] : by_age) t.by_age[k] = error_stats(v);
  return t;
}

}  // namespace fmcw::eval
