#pragma once
// JSON pieces shared by the metrics.json of an evaluation and of an aggregate evaluation
// (private to fmcw::eval: nlohmann_json is not part of its interface).

#include <Eigen/Core>
#include <cmath>
#include <map>
#include <string>
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

/// Order statistics of a list of errors [m/s].
inline json error_json(const ErrorStats& e) {
  return {{"count", e.count},
          {"median", number(e.median)},
          {"p90", number(e.p90)},
          {"p95", number(e.p95)},
          {"max", number(e.max)},
          {"share_over_0p5mps", number(e.share_over_0p5mps)},
          {"share_over_1mps", number(e.share_over_1mps)}};
}

/// One object per group: {group: to_json(stats)}.
template <class Stats>
json group_map_json(const std::map<std::string, Stats>& m, json (*to_json)(const Stats&)) {
  json out = json::object();
  for (const auto& [k, x] : m) out[k] = to_json(x);
  return out;
}

inline json error_map_json(const std::map<std::string, ErrorStats>& m) { return group_map_json(m, &error_json); }

/// The calibration of a group of estimates (CalibrationStats).
inline json calibration_json(const CalibrationStats& c) {
  return {{"covariance_coverage_95", number(c.coverage_95)},
          {"mean_nees", number(c.mean_nees)},
          {"mean_dof", number(c.mean_dof)},
          {"estimates", c.estimates},
          {"scored", c.scored},
          {"without_covariance", c.without_covariance},
          {"partly_unobservable", c.partly_unobservable},
          {"fully_unobservable", c.fully_unobservable}};
}

inline json calibration_map_json(const std::map<std::string, CalibrationStats>& m) {
  return group_map_json(m, &calibration_json);
}

inline json mot_json(const MotMetrics& m) {
  return {{"mota", number(m.mota)},
          {"motp_m", number(m.motp_m)},
          {"motp_iou", number(m.motp_iou)},
          {"idf1", number(m.idf1)},
          {"idp", number(m.idp)},
          {"idr", number(m.idr)},
          {"hota", number(m.hota)},
          {"deta", number(m.deta)},
          {"assa", number(m.assa)},
          {"loca", number(m.loca)},
          {"id_switches", m.id_switches},
          {"fragmentations", m.fragmentations},
          {"objects", m.objects},
          {"hypotheses", m.hypotheses},
          {"matches", m.matches},
          {"misses", m.misses},
          {"false_positives", m.false_positives},
          {"idtp", m.idtp}};
}

/// The targets held and the thresholds of the metrics they are held on.
inline json held_targets(const EvaluationParams& p) {
  const Targets& t = p.targets;
  return {{"min_accuracy", t.min_accuracy},
          {"max_ego_rmse_mps", vec(t.max_ego_rmse_mps)},
          {"max_median_error_ge200_mps", t.max_median_error_large_mps},
          {"max_yaw_rate_rmse_dps", t.max_yaw_rate_rmse_dps},
          {"min_blind_recall", t.min_blind_recall},
          {"max_p95_error_ge200_mps", t.max_p95_error_large_mps},
          {"max_share_over_1mps_ge200", t.max_share_over_1mps_large},
          {"coverage_95_range", json::array({t.min_coverage_95, t.max_coverage_95})},
          {"min_mota", t.min_mota},
          {"min_idf1", t.min_idf1},
          {"min_mota_vehicles", t.min_mota_vehicles},
          {"min_idf1_vehicles", t.min_idf1_vehicles},
          {"mot_iou_threshold", p.summary.mot_iou_threshold},
          {"blind_band_mps", p.blind_band_mps},
          {"large_object_pixels", p.summary.large_object_pixels},
          {"min_moving_pixels", p.objects.min_moving_pixels}};
}

}  // namespace fmcw::eval::report_json
