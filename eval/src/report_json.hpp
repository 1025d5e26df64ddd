#pragma once
// JSON pieces shared by the metrics.json of an evaluation and of an aggregate evaluation
// (private to fmcw::eval: nlohmann_json is not part of its interface).

#include <Eigen/Core>
#include <cmath>
#include <nlohmann/json.hpp>

#include "fmcw/eval/evaluator.hpp"

namespace fmcw::eval::report_json {

using json = nlohmann::ordered_json;

/// A number, or null when it is NaN or infinite (nothing was measured).
inline json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

inline json vec(const Eigen::Vector3d& v) { return json::array({number(v.x()), number(v.y()), number(v.z())}); }

/// Pooled moving/static counts and their ratios (Eq. 23-25).
inline json motion(const MotionConfusion& m) {
  return {{"precision", number(m.precision())},
          {"recall", number(m.recall())},
          {"accuracy", number(m.accuracy())},
          {"tp", m.tp},
          {"fp", m.fp},
          {"tn", m.tn},
          {"fn", m.fn}};
}

/// The targets held and the thresholds of the metrics they are held on.
inline json held_targets(const EvaluationParams& p) {
  const Targets& t = p.targets;
  return {{"min_accuracy", t.min_accuracy},
          {"max_ego_rmse_mps", vec(t.max_ego_rmse_mps)},
          {"max_median_error_ge200_mps", t.max_median_error_large_mps},
          {"max_yaw_rate_rmse_dps", t.max_yaw_rate_rmse_dps},
          {"min_blind_recall", t.min_blind_recall},
          {"blind_band_mps", p.blind_band_mps},
          {"large_object_pixels", p.summary.large_object_pixels},
          {"min_moving_pixels", p.objects.min_moving_pixels}};
}

}  // namespace fmcw::eval::report_json
