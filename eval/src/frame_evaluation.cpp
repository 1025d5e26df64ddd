#include "fmcw/eval/frame_evaluation.hpp"

#include "fmcw/core/check.hpp"

namespace fmcw::eval {

FrameEvaluation evaluate_frame(std::size_t frame_index, const core::Frame& frame, const core::FrameTruth& truth,
                               const core::MotionEstimate& estimate, const ObjectMatchParams& objects,
                               double blind_band_mps) {
  FMCW_CHECK_ARG(frame.truth.has_value(), "frame ", frame_index, ": no per-pixel ground truth (gt_* fields)");
  const core::Scan& scan = frame.scan;
  FMCW_CHECK_ARG(estimate.labels.size() == scan.size(), "frame ", frame_index, ": estimate has ",
                 estimate.labels.size(), " labels for ", scan.size(), " pixels");
  FrameEvaluation e;
  e.frame = frame_index;
  e.stamp_s = truth.stamp_s;
  e.method = estimate.method;
  e.status = estimate.status;
  e.motion = count_motion(estimate.labels, frame.truth->moving, scan.valid);
  e.num_clusters = static_cast<int>(estimate.clusters.size());
  e.static_pixels = estimate.num_static_pixels;
  e.ego_valid = estimate.ego.valid;
  if (e.ego_valid) e.ego_estimate_mps = estimate.ego.velocity_mps;
  e.ego_truth_mps = truth.ego.velocity_mps;
  Eigen::Vector3d mean_mount = Eigen::Vector3d::Zero();
  for (const core::HeadInfo& h : scan.heads) mean_mount += h.origin_m();
  if (!scan.heads.empty()) mean_mount /= static_cast<double>(scan.heads.size());
  e.ego_truth_at_heads_mps = truth.ego.velocity_mps + truth.ego.angular_velocity_rps.cross(mean_mount);
  e.objects = match_objects(*frame.truth, scan.valid, truth, estimate, objects);
  e.instances = count_instances(*frame.truth, scan.valid, estimate, objects);
  e.tracking = tracking_frame(frame_index, *frame.truth, scan.valid, truth, estimate, objects.min_moving_pixels);
  e.blind_band = blind_band_actors(scan, *frame.truth, truth, estimate, blind_band_mps);
  e.yaw_rate_valid = estimate.ego.valid && estimate.ego_yaw_rate_estimated;
  if (e.yaw_rate_valid) e.yaw_rate_estimate_rps = estimate.ego_angular_velocity_rps.z();
  e.yaw_rate_truth_rps = truth.ego.angular_velocity_rps.z();
  e.timing = estimate.timing;
  return e;
}

}  // namespace fmcw::eval
