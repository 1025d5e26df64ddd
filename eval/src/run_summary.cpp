#include "fmcw/eval/run_summary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "fmcw/core/check.hpp"
#include "fmcw/eval/statistics.hpp"

namespace fmcw::eval {

void SummaryParams::validate() const {
  FMCW_CHECK_ARG(large_object_pixels >= 1, "summary: large_object_pixels must be >= 1, got ", large_object_pixels);
  FMCW_CHECK_ARG(blind_visible_pixels >= 1, "summary: blind_visible_pixels must be >= 1, got ", blind_visible_pixels);
  FMCW_CHECK_ARG(turning_yaw_rate_rps >= 0.0, "summary: turning_yaw_rate_rps must be >= 0, got ", turning_yaw_rate_rps);
  MotParams{mot_iou_threshold}.validate();
  FMCW_CHECK_ARG(unobservable_sigma_mps > 0.0, "summary: unobservable_sigma_mps must be > 0, got ", unobservable_sigma_mps);
  FMCW_CHECK_ARG(young_updates >= 1, "summary: young_updates must be >= 1, got ", young_updates);
}

namespace {
void add_timing(core::StageTiming& sum, core::StageTiming& max, const core::StageTiming& t) {
  sum.clustering_ms += t.clustering_ms;
  sum.ego_ms += t.ego_ms;
  sum.objects_ms += t.objects_ms;
  sum.total_ms += t.total_ms;
  max.clustering_ms = std::max(max.clustering_ms, t.clustering_ms);
  max.ego_ms = std::max(max.ego_ms, t.ego_ms);
  max.objects_ms = std::max(max.objects_ms, t.objects_ms);
  max.total_ms = std::max(max.total_ms, t.total_ms);
}
}  // namespace

MethodSummary summarize(const std::vector<FrameEvaluation>& frames, const SummaryParams& params) {
  params.validate();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  MethodSummary s;
  if (!frames.empty()) s.method = frames.front().method;
  s.frames = static_cast<int>(frames.size());
  AxisErrorStats ego, ego_heads;
  std::vector<double> errors, errors_large, ref_errors, ref_errors_large, ref_errors_turning;
  double yaw_sq = 0.0;
  std::set<std::uint32_t> seen_moving;  // actors visibly moving in an earlier frame
  core::StageTiming sum;
  for (const FrameEvaluation& f : frames) {
    FMCW_CHECK_ARG(f.method == s.method, "summarize: frame ", f.frame, " is method '", f.method, "', expected '",
                   s.method, "'");
    if (f.status != core::MotionStatus::kOk) ++s.frames_not_ok;
    s.motion += f.motion;
    if (f.ego_valid) {
      ego.add(f.ego_error_mps());
      ego_heads.add(f.ego_error_at_heads_mps());
    }
    for (const ObjectMatch& m : f.objects) {
      if (!m.evaluated) continue;
      ++s.objects_evaluated;
      if (m.detected) ++s.objects_detected;
      if (!m.estimate_valid) continue;
      ++s.objects_estimated;
      const bool large = m.pixels >= params.large_object_pixels;
      errors.push_back(m.error_mps().norm());
      ref_errors.push_back(m.reference_error_mps().norm());
      if (large) {
        ++s.objects_large;
        errors_large.push_back(errors.back());
        ref_errors_large.push_back(ref_errors.back());
        if (std::abs(m.yaw_rate_rps) > params.turning_yaw_rate_rps) ref_errors_turning.push_back(ref_errors.back());
      }
    }
    if (f.yaw_rate_valid) {
      ++s.yaw_frames;
      const double d = (f.yaw_rate_estimate_rps - f.yaw_rate_truth_rps) * 180.0 / M_PI;
      yaw_sq += d * d;
    }
    s.instances += f.instances;
    for (const BlindBandActor& a : f.blind_band) {
      if (seen_moving.count(a.actor_id) == 0) continue;
      if (a.band_pixels > 0) ++s.blind_actor_frames;
      s.blind_band_pixels += static_cast<std::uint64_t>(a.band_pixels);
      s.blind_band_detected += static_cast<std::uint64_t>(a.band_detected);
      s.blind_part_pixels += static_cast<std::uint64_t>(a.part_band_pixels);
      s.blind_part_detected += static_cast<std::uint64_t>(a.part_band_detected);
    }
    for (const BlindBandActor& a : f.blind_band) {
      if (a.visible_pixels >= params.blind_visible_pixels) seen_moving.insert(a.actor_id);
    }
    add_timing(sum, s.max_timing_ms, f.timing);
  }
  s.ego_frames = ego.count;
  s.ego_rmse_mps = ego.rmse();
  s.ego_max_abs_mps = ego.max_abs_or_nan();
  s.ego_rmse_at_heads_mps = ego_heads.rmse();
  s.detected_fraction = s.objects_evaluated == 0
                            ? kNaN
                            : static_cast<double>(s.objects_detected) / static_cast<double>(s.objects_evaluated);
  s.median_error_mps = median(errors);
  s.median_error_mps_ge200 = median(errors_large);
  s.p90_error_mps_ge200 = quantile(errors_large, 0.9);
  s.median_reference_error_mps = median(ref_errors);
  s.median_reference_error_mps_ge200 = median(ref_errors_large);
  s.objects_large_turning = static_cast<int>(ref_errors_turning.size());
  s.median_reference_error_mps_ge200_turning = median(ref_errors_turning);
  s.yaw_rate_rmse_dps = s.yaw_frames == 0 ? kNaN : std::sqrt(yaw_sq / s.yaw_frames);
  const auto ratio = [&](double a, double b) { return b > 0.0 ? a / b : kNaN; };
  s.instance_precision = ratio(s.instances.clusters_matched, s.instances.clusters);
  s.instance_recall = ratio(s.instances.actors_matched, s.instances.actors);
  s.blind_recall_tracked = ratio(static_cast<double>(s.blind_band_detected), static_cast<double>(s.blind_band_pixels));
  s.blind_part_recall = ratio(static_cast<double>(s.blind_part_detected), static_cast<double>(s.blind_part_pixels));
  s.tails = object_tails(frames, {params.large_object_pixels, params.unobservable_sigma_mps, params.young_updates});
  std::vector<TrackingFrame> tracking;
  tracking.reserve(frames.size());
  for (const FrameEvaluation& f : frames) tracking.push_back(f.tracking);
  s.tracking = clear_mot(tracking, {params.mot_iou_threshold});
  const double n = frames.empty() ? kNaN : static_cast<double>(frames.size());
  s.mean_timing_ms = {sum.clustering_ms / n, sum.ego_ms / n, sum.objects_ms / n, sum.total_ms / n};
  return s;
}

std::vector<TargetCheck> check_targets(const MethodSummary& s, const Targets& t) {
  std::vector<TargetCheck> out;
  const auto at_least = [&](const char* key, double value, double limit) {
    out.push_back({key, ">=", value, limit, std::isfinite(value) && value >= limit});
  };
  const auto at_most = [&](const char* key, double value, double limit) {
    out.push_back({key, "<=", value, limit, std::isfinite(value) && value <= limit});
  };
  at_least("accuracy", s.motion.accuracy(), t.min_accuracy);
  at_most("ego_rmse_x", s.ego_rmse_mps.x(), t.max_ego_rmse_mps.x());
  at_most("ego_rmse_y", s.ego_rmse_mps.y(), t.max_ego_rmse_mps.y());
  at_most("ego_rmse_z", s.ego_rmse_mps.z(), t.max_ego_rmse_mps.z());
  at_most("yaw_rate_rmse", s.yaw_rate_rmse_dps, t.max_yaw_rate_rmse_dps);
  at_most("object_median_ge200", s.median_error_mps_ge200, t.max_median_error_large_mps);
  at_most("object_centre_median_ge200", s.median_reference_error_mps_ge200, t.max_median_error_large_mps);
  at_most("object_centre_p95_ge200", s.tails.ge200.p95, t.max_p95_error_large_mps);
  at_most("object_centre_share_over_1mps_ge200", s.tails.ge200.share_over_1mps, t.max_share_over_1mps_large);
  at_least("covariance_coverage_95_min", s.tails.calibration.coverage_95, t.min_coverage_95);
  at_most("covariance_coverage_95_max", s.tails.calibration.coverage_95, t.max_coverage_95);
  at_least("tracking_mota", s.tracking.all.mota, t.min_mota);
  at_least("tracking_idf1", s.tracking.all.idf1, t.min_idf1);
  if (s.blind_band_pixels > 0) at_least("blind_zone_recall_tracked", s.blind_recall_tracked, t.min_blind_recall);
  if (s.tracking.vehicles.objects > 0) {
    at_least("tracking_mota_vehicles", s.tracking.vehicles.mota, t.min_mota_vehicles);
    at_least("tracking_idf1_vehicles", s.tracking.vehicles.idf1, t.min_idf1_vehicles);
  }
  return out;
}

}  // namespace fmcw::eval
