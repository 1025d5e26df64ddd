#include "fmcw/core/object_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "fmcw/core/check.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "tracking/association.hpp"
#include "tracking/band_growth.hpp"
#include "tracking/claims.hpp"
#include "tracking/ctrv.hpp"
#include "tracking/measurement.hpp"
#include "tracking/relabel.hpp"
#include "tracking/track_birth.hpp"

namespace fmcw::core {

namespace {

// One check per field, naming it: "tracking.<stage>.<field> must be <what>, got <value>".
struct FieldCheck {
  std::string stage;
  template <class T>
  void positive(const char* field, T value) const {
    FMCW_CHECK_ARG(value > T{0}, "tracking.", stage, ".", field, " must be > 0, got ", value);
  }
  template <class T>
  void non_negative(const char* field, T value) const {
    FMCW_CHECK_ARG(value >= T{0}, "tracking.", stage, ".", field, " must be >= 0, got ", value);
  }
  template <class T>
  void at_least(const char* field, T value, T least) const {
    FMCW_CHECK_ARG(value >= least, "tracking.", stage, ".", field, " must be >= ", least, ", got ", value);
  }
};

}  // namespace

int TrackerParams::Association::min_pixels_at(double range_m) const {
  if (!(range_m > full_pixels_range_m)) return min_cluster_pixels;
  const double q = full_pixels_range_m / range_m;
  return std::max(min_far_cluster_pixels, static_cast<int>(std::ceil(min_cluster_pixels * q * q)));
}

double Track::covariance_scale(const TrackerParams& p) const {
  const TrackerParams::Calibration& c = p.calibration;
  if (!c.enabled || unsteady(p)) return 1.0;
  return std::clamp((corrections + c.prior_dof) / (expected_corrections + c.prior_dof), c.min_scale, 1.0);
}

namespace {

// The measurement, small-object, motion, calibration and turning fields of
// TrackerParams::validate().
void validate_filter(const TrackerParams& p) {
  const FieldCheck m{"measurement"};
  m.positive("doppler_sigma_mps", p.measurement.doppler_sigma_mps);
  m.at_least("max_effective_rows", p.measurement.max_effective_rows, 1);
  m.positive("outlier_sigmas", p.measurement.outlier_sigmas);
  m.positive("outlier_floor_mps", p.measurement.outlier_floor_mps);
  m.positive("position_sigma_m", p.measurement.position_sigma_m);
  m.positive("claim_position_sigma_m", p.measurement.claim_position_sigma_m);
  m.non_negative("relinearise_mps", p.measurement.relinearise_mps);
  m.non_negative("relinearise_iterations (0: never)", p.measurement.relinearise_iterations);
  m.non_negative("relinearise_max_hits", p.measurement.relinearise_max_hits);
  const FieldCheck s{"small"};
  s.non_negative("small_object_m", p.small.small_object_m);
  s.positive("position_sigma_m", p.small.position_sigma_m);
  s.positive("doppler_floor_mps", p.small.doppler_floor_mps);
  s.positive("initial_tangential_sigma_mps", p.small.initial_tangential_sigma_mps);
  s.non_negative("walker_hits (0: no walkers)", p.small.walker_hits);
  s.positive("walker_max_speed_mps", p.small.walker_max_speed_mps);
  s.positive("walker_box_m", p.small.walker_box_m);
  s.non_negative("group_sigma_mps (0: never)", p.small.group_sigma_mps);
  s.at_least("vehicle_pace_updates", p.small.vehicle_pace_updates, 1);
  s.non_negative("rigid_patch_sigma_mps (0: never)", p.small.rigid_patch_sigma_mps);
  s.positive("companion_sigma_mps", p.small.companion_sigma_mps);
  s.non_negative("silhouette_stray_gap_m (0: every pixel counts)", p.small.silhouette_stray_gap_m);
  FMCW_CHECK_ARG(p.small.silhouette_stray_share >= 0.0 && p.small.silhouette_stray_share < 0.5,
                 "tracking.small.silhouette_stray_share must be in [0, 0.5), got ",
                 p.small.silhouette_stray_share);
  const FieldCheck mo{"motion"};
  mo.positive("accel_sigma_mps2", p.motion.accel_sigma_mps2);
  mo.positive("yaw_accel_sigma_rps2", p.motion.yaw_accel_sigma_rps2);
  mo.positive("initial_yaw_rate_sigma_rps", p.motion.initial_yaw_rate_sigma_rps);
  mo.positive("max_initial_velocity_sigma_mps", p.motion.max_initial_velocity_sigma_mps);
  mo.positive("max_yaw_rate_rps", p.motion.max_yaw_rate_rps);
  mo.positive("min_noise_scale", p.motion.min_noise_scale);
  FMCW_CHECK_ARG(p.motion.min_noise_scale <= 1.0,
                 "tracking.motion.min_noise_scale must be <= 1, got ", p.motion.min_noise_scale);
  const FieldCheck ca{"calibration"};
  ca.non_negative("memory", p.calibration.memory);
  FMCW_CHECK_ARG(p.calibration.memory < 1.0, "tracking.calibration.memory must be < 1, got ",
                 p.calibration.memory);
  ca.positive("prior_dof", p.calibration.prior_dof);
  FMCW_CHECK_ARG(std::isfinite(p.calibration.prior_dof),
                 "tracking.calibration.prior_dof must be finite, got ", p.calibration.prior_dof);
  ca.positive("min_scale", p.calibration.min_scale);
  FMCW_CHECK_ARG(p.calibration.min_scale <= 1.0,
                 "tracking.calibration.min_scale must be <= 1, got ", p.calibration.min_scale);
  mo.at_least("max_noise_scale", p.motion.max_noise_scale, 1.0);
  mo.non_negative("noise_gain_up", p.motion.noise_gain_up);
  mo.non_negative("noise_gain_down", p.motion.noise_gain_down);
  FMCW_CHECK_ARG(p.motion.noise_gain_down < 1.0,
                 "tracking.motion.noise_gain_down must be < 1, got ", p.motion.noise_gain_down);
  const FieldCheck tu{"turning"};
  tu.non_negative("min_turn_rate_rps", p.turning.min_turn_rate_rps);
  tu.non_negative("turn_release_significance", p.turning.turn_release_significance);
  tu.at_least("turn_significance (not below turn_release_significance)",
              p.turning.turn_significance, p.turning.turn_release_significance);
  tu.at_least("min_turn_hits", p.turning.min_turn_hits, 1);
  tu.non_negative("axis_shrink_sigmas", p.turning.axis_shrink_sigmas);
  tu.non_negative("settle_updates", p.turning.settle_updates);
  tu.non_negative("settle_growth_m", p.turning.settle_growth_m);
  tu.non_negative("release_hold_updates", p.turning.release_hold_updates);
  tu.non_negative("hold_rate_fraction (0: never)", p.turning.hold_rate_fraction);
  tu.non_negative("max_left_in_mps (0: never)", p.turning.max_left_in_mps);
  tu.non_negative("max_left_in_significance", p.turning.max_left_in_significance);
  tu.non_negative("straight_window_s (0: never)", p.turning.straight_window_s);
  tu.at_least("straight_min_axes", p.turning.straight_min_axes, 3);
  tu.positive("straight_sigmas", p.turning.straight_sigmas);
  tu.positive("straight_consistency_sigmas", p.turning.straight_consistency_sigmas);
  tu.positive("straight_max_sigma_ratio", p.turning.straight_max_sigma_ratio);
  tu.positive("line_min_length_m", p.turning.line_min_length_m);
  tu.at_least("line_min_columns", p.turning.line_min_columns, 2);
  tu.non_negative("line_max_angle_rad (0: never)", p.turning.line_max_angle_rad);
  tu.at_least("line_doppler_angle_rad (not below line_max_angle_rad)",
              p.turning.line_doppler_angle_rad, p.turning.line_max_angle_rad);
  FMCW_CHECK_ARG(p.turning.line_doppler_angle_rad <= 0.25 * M_PI,
                 "tracking.turning.line_doppler_angle_rad must be <= pi/4, got ",
                 p.turning.line_doppler_angle_rad);
}

}  // namespace

void TrackerParams::validate() const {
  validate_filter(*this);
  const FieldCheck h{"heading"};
  h.positive("min_length_m", heading.min_length_m);
  h.at_least("min_aspect", heading.min_aspect, 1.0);
  h.positive("sigma_rad", heading.sigma_rad);
  h.non_negative("end_sigma_per_m", heading.end_sigma_per_m);
  h.non_negative("near_sigma_rad", heading.near_sigma_rad);
  h.non_negative("near_range_lengths", heading.near_range_lengths);
  h.non_negative("gate_sigmas (0: never)", heading.gate_sigmas);
  h.non_negative("reopen_sigmas (0: never)", heading.reopen_sigmas);
  h.non_negative("reopen_window_s", heading.reopen_window_s);
  h.at_least("reopen_support", heading.reopen_support, 1);
  h.at_least("cut_sigma_factor", heading.cut_sigma_factor, 1.0);
  h.positive("slip_sigma_mps", heading.slip_sigma_mps);
  h.non_negative("slip_sigma_rad", heading.slip_sigma_rad);
  h.non_negative("centre_offset_fraction", heading.centre_offset_fraction);
  h.non_negative("face_min_length_m (0: never)", heading.face_min_length_m);
  h.at_least("face_min_columns", heading.face_min_columns, 2);
  FMCW_CHECK_ARG(heading.face_sight_cosine >= 0.0 && heading.face_sight_cosine <= 1.0,
                 "tracking.heading.face_sight_cosine must be in [0, 1], got ", heading.face_sight_cosine);
  FMCW_CHECK_ARG(heading.face_max_angle_rad >= 0.0 && heading.face_max_angle_rad <= 0.5 * M_PI,
                 "tracking.heading.face_max_angle_rad must be in [0, pi/2], got ", heading.face_max_angle_rad);
  h.positive("face_sigma_rad", heading.face_sigma_rad);
  h.non_negative("face_oblique_sigma_rad", heading.face_oblique_sigma_rad);
  h.non_negative("max_edge_distance_m", heading.max_edge_distance_m);
  const FieldCheck a{"association"};
  a.non_negative("gate_m", association.gate_m);
  a.at_least("min_cluster_pixels", association.min_cluster_pixels, 3);
  a.positive("full_pixels_range_m", association.full_pixels_range_m);
  a.at_least("min_far_cluster_pixels", association.min_far_cluster_pixels, 3);
  FMCW_CHECK_ARG(association.min_far_cluster_pixels <= association.min_cluster_pixels,
                 "tracking.association.min_far_cluster_pixels must be <= min_cluster_pixels (",
                 association.min_cluster_pixels, "), got ", association.min_far_cluster_pixels);
  a.positive("doppler_tolerance_mps", association.doppler_tolerance_mps);
  a.non_negative("coasting_doppler_sigmas (0: the tolerance alone)",
                 association.coasting_doppler_sigmas);
  a.positive("vehicle_length_m", association.vehicle_length_m);
  a.non_negative("absorb_max_pixels", association.absorb_max_pixels);
  a.positive("split_min_share (above 1: never split)", association.split_min_share);
  a.non_negative("doppler_split_rms_mps (0: never)", association.doppler_split_rms_mps);
  const FieldCheck f{"fragments"};
  f.non_negative("max_pixels (0: none)", fragments.max_pixels);
  f.at_least("reach_px", fragments.reach_px, 1);
  f.non_negative("range_gap_m", fragments.range_gap_m);
  f.non_negative("range_gap_fraction", fragments.range_gap_fraction);
  f.at_least("host_ratio", fragments.host_ratio, 1.0);
  f.non_negative("small_host_ratio (0: never)", fragments.small_host_ratio);
  f.non_negative("same_motion_margin_m (0: only the box)", fragments.same_motion_margin_m);
  f.non_negative("same_motion_mps", fragments.same_motion_mps);
  f.non_negative("own_motion_hits (0: never)", fragments.own_motion_hits);
  const FieldCheck l{"lifecycle"};
  l.at_least("confirm_hits", lifecycle.confirm_hits, 1);
  l.non_negative("max_misses", lifecycle.max_misses);
  l.non_negative("reid_frames (0: never)", lifecycle.reid_frames);
  l.non_negative("carry_min_speed_mps", lifecycle.carry_min_speed_mps);
  l.at_least("release_slow_frames", lifecycle.release_slow_frames, 1);
  l.positive("max_gap_s", lifecycle.max_gap_s);
  const FieldCheck c{"claims"};
  c.non_negative("claim_margin_m", claims.claim_margin_m);
  c.non_negative("ground_clearance_m", claims.ground_clearance_m);
  c.positive("doppler_tolerance_mps", claims.doppler_tolerance_mps);
  const FieldCheck b{"background"};
  b.non_negative("min_frames (0: no background)", background.min_frames);
  b.positive("margin_m", background.margin_m);
  b.non_negative("label_m", background.label_m);
  const FieldCheck g{"growth"};
  g.non_negative("reach_m (0: no growth)", growth.reach_m);
  g.positive("range_gap_m", growth.range_gap_m);
  g.non_negative("range_gap_fraction", growth.range_gap_fraction);
  const FieldCheck x{"box"};
  x.positive("max_length_m", box.max_length_m);
  x.positive("max_width_m", box.max_width_m);
  x.positive("heading_reset_rad", box.heading_reset_rad);
  x.non_negative("view_cut_end_m", box.view_cut_end_m);
  x.non_negative("occlusion_gap_m (0: no occluders)", box.occlusion_gap_m);
  x.non_negative("stray_gap_m (0: every pixel counts)", box.stray_gap_m);
  FMCW_CHECK_ARG(box.stray_share >= 0.0 && box.stray_share < 0.5, "tracking.box.stray_share must be in [0, 0.5), got ",
                 box.stray_share);
  FMCW_CHECK_ARG(box.own_stray_share >= 0.0 && box.own_stray_share < 0.5,
                 "tracking.box.own_stray_share must be in [0, 0.5), got ", box.own_stray_share);
  x.positive("own_stray_min_length_m", box.own_stray_min_length_m);
  x.non_negative("own_stray_settled_updates", box.own_stray_settled_updates);
  FMCW_CHECK_ARG(box.view_cut_cosine >= 0.0 && box.view_cut_cosine < 1.0, "tracking.box.view_cut_cosine must be in [0, 1), got ",
                 box.view_cut_cosine);
}

ObjectTracker::ObjectTracker(const TrackerParams& params) : params_(params) { params_.validate(); }

void ObjectTracker::reset() {
  tracks_.clear();
  lost_.clear();
  has_pose_ = false;
  yaw_ = 0.0;
  position_.setZero();
  last_ego_velocity_.setZero();
  last_ego_yaw_rate_ = 0.0;
  background_.reset();
}

bool ObjectTracker::advance(const Scan& scan, const MotionEstimate& est) {
  if (!est.ok() || !est.ego.valid) {  // nothing to compensate the Doppler with: start over
    reset();
    return false;
  }
  const Eigen::Vector3d V = est.ego.velocity_mps;
  const double w_ego = est.ego_yaw_rate_estimated ? est.ego_angular_velocity_rps.z() : 0.0;
  double dt = 0.0;
  if (has_pose_) {
    dt = scan.stamp_s - last_stamp_s_;
    if (!(dt > 0.0) || dt > params_.lifecycle.max_gap_s) reset();
  }
  if (has_pose_ && dt > 0.0) {
    // Midpoint rule on the mean of the two frames' twists.
    const double w_mean = 0.5 * (w_ego + last_ego_yaw_rate_);
    const Eigen::Vector2d v_mean = 0.5 * (V.head<2>() + last_ego_velocity_.head<2>());
    position_ += tracking::rotation(yaw_ + 0.5 * w_mean * dt) * v_mean * dt;
    yaw_ += w_mean * dt;
    for (Track& t : tracks_) tracking::predict(t, dt, params_.motion);
    for (Track& t : lost_) tracking::predict(t, dt, params_.motion);
  }
  has_pose_ = true;
  last_stamp_s_ = scan.stamp_s;
  last_ego_velocity_ = V;
  last_ego_yaw_rate_ = w_ego;
  return true;
}

void ObjectTracker::update(const Scan& scan, MotionEstimate& est) { update(scan, ScanBeams(scan), est); }

void ObjectTracker::update(const Scan& scan, const ScanBeams& beams, MotionEstimate& est) {
  using namespace tracking;
  const TrackerParams& p = params_;
  if (!advance(scan, est)) return;
  background_.begin_frame(scan, est.ego_standing);
  const Eigen::Vector3d omega(0.0, 0.0, est.ego_yaw_rate_estimated ? est.ego_angular_velocity_rps.z() : 0.0);
  const Frame frame{scan, beams, rotation(yaw_), position_, est.ego.velocity_mps, omega};
  const ViewEdges edges(scan, p.box.occlusion_gap_m);
  std::vector<Box> boxes(tracks_.size());
  for (std::size_t t = 0; t < tracks_.size(); ++t) boxes[t] = box_of(tracks_[t]);

  // Associate: clusters (split where two tracks share one) to the predicted tracks.
  std::vector<std::vector<std::uint32_t>> cluster_pixels = pixels_of_clusters(est);
  split_shared_clusters(frame, est, cluster_pixels, tracks_, boxes, p);
  split_by_doppler(frame, est, cluster_pixels, tracks_, boxes, p);
  const std::vector<int> companion_of =
      split_off_companions(frame, est, cluster_pixels, tracks_, boxes, p);
  std::vector<Group> groups(tracks_.size());
  Association assoc = associate(frame, cluster_pixels, est, tracks_, boxes, p, groups);
  merge_nested_tracks(frame, tracks_, boxes, p, assoc, groups);
  // Claim: the parts of carrying tracks inside the blind band.
  claim_pixels(frame, est, tracks_, boxes, background_, p, groups);
  // Measure every track that has pixels this frame.
  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    if (!groups[t].empty()) measure(tracks_[t], groups[t], false, frame, edges, p);
    update_track_state(tracks_[t], groups[t], p);
  }
  // Birth: new tracks from the clusters no track took, unless they are pieces of a tracked object.
  const std::size_t measured = tracks_.size();
  birth_tracks(frame, edges, est, cluster_pixels, companion_of, p, assoc, tracks_, groups,
               next_id_);
  // A track born where a lost one is predicted is that object again: it takes its id.
  for (std::size_t t = measured; t < tracks_.size() && !lost_.empty(); ++t) {
    const int l = lost_track_of(frame, tracks_[t], groups[t].found, lost_, p);
    if (l < 0) continue;
    const Track& lost = lost_[static_cast<std::size_t>(l)];
    tracks_[t].id = lost.id;
    // One scan does not see a vehicle's tangential velocity; the lost track's prediction does.
    if (p.lifecycle.reid_motion && lost.vehicle(p) && !lost.may_be_group(p))
      fuse_motion_prior(tracks_[t], lost);
    lost_.erase(lost_.begin() + l);
  }
  // Grow into the blind band, then relabel the estimate by the tracks.
  const std::vector<std::int32_t> group_of_label = group_of_labels(groups, est.clusters.size());
  const auto grown_untracked = grow_into_band(frame, est, cluster_pixels, tracks_, group_of_label, p, groups);
  relabel_estimate(frame, tracks_, groups, group_of_label, grown_untracked, p, est);
  if (est.ego_standing && p.background.min_frames > 0) background_.add(scan);
  // Prune the tracks missed too long; the confirmed ones are remembered for reid_frames more.
  const int max_misses = p.lifecycle.max_misses;
  for (Track& t : lost_) ++t.misses;
  const long long forget = static_cast<long long>(max_misses) + p.lifecycle.reid_frames;  // no overflow
  lost_.erase(std::remove_if(lost_.begin(), lost_.end(), [&](const Track& t) { return t.misses > forget; }), lost_.end());
  for (const Track& t : tracks_) {
    if (t.misses > max_misses && t.confirmed && !t.merged && p.lifecycle.reid_frames > 0) lost_.push_back(t);
  }
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(), [&](const Track& t) { return t.misses > max_misses; }), tracks_.end());
}

}  // namespace fmcw::core
