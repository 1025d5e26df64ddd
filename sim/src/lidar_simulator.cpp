#include "fmcw/sim/lidar_simulator.hpp"

#include <omp.h>

#include <cmath>
#include <limits>
#include <map>

#include "fmcw/core/check.hpp"
#include "fmcw/core/random.hpp"

namespace fmcw::sim {

void LidarSimulatorParams::validate() const {
  rig.validate();
  measurement.validate();
  FMCW_CHECK_ARG(min_range_m >= 0.0, "simulator: min_range_m must be >= 0, got ", min_range_m);
  FMCW_CHECK_ARG(moving_threshold_mps >= 0.0, "simulator: moving_threshold_mps must be >= 0, got ", moving_threshold_mps);
  FMCW_CHECK_ARG(num_threads >= 0, "simulator: num_threads must be >= 0, got ", num_threads);
}

LidarSimulator::LidarSimulator(std::shared_ptr<Scene> scene, std::shared_ptr<const Trajectory> ego,
                               const LidarSimulatorParams& params)
    : scene_(std::move(scene)), ego_(std::move(ego)), params_(params), measurement_((params.validate(), params.measurement)) {
  FMCW_CHECK_ARG(scene_ != nullptr && ego_ != nullptr, "simulator: scene and ego trajectory are required");
  head_infos_ = params_.rig.head_infos();
  directions_rig_ = params_.rig.directions_rig();
  directions_world_.resize(directions_rig_.size());
  col_head_.resize(static_cast<std::size_t>(params_.rig.cols()));
  for (std::size_t h = 0; h < head_infos_.size(); ++h) {
    for (int c = head_infos_[h].col_begin; c < head_infos_[h].col_end; ++c) col_head_[static_cast<std::size_t>(c)] = h;
  }
}

core::Frame LidarSimulator::simulate(std::uint64_t frame_index, double t_s) {
  core::Frame frame;
  simulate(frame_index, t_s, frame);
  return frame;
}

void LidarSimulator::simulate(std::uint64_t frame_index, double t_s, core::Frame& frame) {
  scene_->set_time(t_s);
  const MotionState ego = ego_->state(t_s);
  const Eigen::Matrix3d R_wr = ego.T_world_body.linear();
  const Eigen::Vector3d p_wr = ego.T_world_body.translation();
  const Eigen::Isometry3d T_rw = ego.T_world_body.inverse();
  const int rows = params_.rig.rows();
  const int cols = params_.rig.cols();
  const std::size_t n = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);

  if (frame.scan.rows != rows || frame.scan.cols != cols || frame.scan.size() != frame.scan.x_m.size()) {
    frame.scan = core::Scan::make_empty(rows, cols);
  }
  if (!frame.truth || frame.truth->range_m.size() != n) frame.truth = core::PixelGroundTruth::make_empty(n);
  frame.scan.heads = head_infos_;
  frame.scan.stamp_s = t_s;
  core::Scan& scan = frame.scan;
  core::PixelGroundTruth& gt = *frame.truth;
  const float nan = std::numeric_limits<float>::quiet_NaN();

  const Eigen::Matrix3f R_wr_f = R_wr.cast<float>();
  // Rotations keep the rig's unit directions unit.
  for (std::size_t i = 0; i < n; ++i) directions_world_[i] = R_wr_f * directions_rig_[i];

  struct HeadFrame {
    Eigen::Vector3d origin_world;
    Eigen::Vector3d origin_velocity_world;  // V_ego + omega x r_mount
    double max_range_m;
  };
  std::vector<HeadFrame> heads;
  for (std::size_t h = 0; h < params_.rig.heads.size(); ++h) {
    const core::HeadModel& head = params_.rig.heads[h];
    const Eigen::Vector3d o = ego.T_world_body * head.T_rig_head.translation();
    heads.push_back({o, ego.twist.linear_mps + ego.twist.angular_rps.cross(o - p_wr), head.max_range_m});
  }

  const int threads = params_.num_threads > 0 ? params_.num_threads : omp_get_max_threads();
  const std::uint64_t frame_seed = core::mix_seed(params_.seed, frame_index);
#pragma omp parallel num_threads(threads)
  {
    std::vector<RayHit> hits(static_cast<std::size_t>(cols));
    // Dynamic rows: sky rows cost little, ground rows a lot. Each row draws from its own seed,
    // so the result does not depend on which thread takes it.
#pragma omp for schedule(dynamic, 2)
    for (int r = 0; r < rows; ++r) {
      core::Rng rng(core::mix_seed(frame_seed, static_cast<std::uint64_t>(r)));
      const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols);
      for (std::size_t h = 0; h < heads.size(); ++h) {
        const core::HeadInfo& info = head_infos_[h];
        const auto c0 = static_cast<std::size_t>(info.col_begin);
        scene_->intersect(heads[h].origin_world.cast<float>(), &directions_world_[row + c0],
                          static_cast<std::size_t>(info.cols()), static_cast<float>(params_.min_range_m),
                          static_cast<float>(heads[h].max_range_m), &hits[c0]);
      }
      for (int c = 0; c < cols; ++c) {
        const RayHit& hit = hits[static_cast<std::size_t>(c)];
        const std::size_t i = row + static_cast<std::size_t>(c);
        if (!std::isfinite(hit.distance_m)) {
          scan.x_m[i] = scan.y_m[i] = scan.z_m[i] = scan.range_m[i] = scan.radial_velocity_mps[i] = nan;
          scan.intensity[i] = 0.0f;
          scan.valid[i] = 0;
          gt.range_m[i] = gt.radial_velocity_mps[i] = gt.vx_mps[i] = gt.vy_mps[i] = gt.vz_mps[i] = nan;
          gt.instance[i] = 0;
          gt.moving[i] = 0;
          continue;
        }
        const HeadFrame& head = heads[col_head_[static_cast<std::size_t>(c)]];
        const Eigen::Vector3d e = directions_world_[i].cast<double>();
        const double range = hit.distance_m;
        const Eigen::Vector3d p_world = head.origin_world + range * e;
        const SurfaceSample s = scene_->resolve(hit, p_world);
        // Eq. 6: v = e . (V_point - V_lidar), both in the world frame (the dot product does not
        // depend on the frame it is evaluated in).
        const double doppler = e.dot(s.velocity_world_mps - head.origin_velocity_world);
        const MeasurementModel::Reading m = measurement_.measure(range, doppler, rng);
        const Eigen::Vector3d p_rig = T_rw * (head.origin_world + m.range_m * e);
        scan.x_m[i] = static_cast<float>(p_rig.x());
        scan.y_m[i] = static_cast<float>(p_rig.y());
        scan.z_m[i] = static_cast<float>(p_rig.z());
        scan.range_m[i] = static_cast<float>(m.range_m);
        scan.radial_velocity_mps[i] = static_cast<float>(m.radial_velocity_mps);
        scan.intensity[i] = return_intensity(s.reflectivity, e.dot(s.normal_world), range);
        scan.valid[i] = 1;
        const Eigen::Vector3d v_rig = R_wr.transpose() * s.velocity_world_mps;
        gt.range_m[i] = static_cast<float>(range);
        gt.radial_velocity_mps[i] = static_cast<float>(doppler);
        gt.vx_mps[i] = static_cast<float>(v_rig.x());
        gt.vy_mps[i] = static_cast<float>(v_rig.y());
        gt.vz_mps[i] = static_cast<float>(v_rig.z());
        gt.instance[i] = s.actor_id;
        gt.moving[i] = s.velocity_world_mps.norm() > params_.moving_threshold_mps ? 1 : 0;
      }
    }
  }

  core::FrameTruth truth;
  truth.stamp_s = t_s;
  truth.ego.T_world_rig = ego.T_world_body;
  truth.ego.velocity_mps = R_wr.transpose() * ego.twist.linear_mps;
  truth.ego.angular_velocity_rps = R_wr.transpose() * ego.twist.angular_rps;
  std::map<std::uint32_t, int> pixels;
  for (std::size_t i = 0; i < n; ++i) {
    if (scan.valid[i] && gt.instance[i] != 0) ++pixels[gt.instance[i]];
  }
  for (std::size_t a = 0; a < scene_->actors().size(); ++a) {
    const SceneObject& actor = scene_->actors()[a];
    const MotionState& st = scene_->actor_state(a);
    core::ActorTruth at;
    at.id = actor.actor_id;
    at.class_name = actor.class_name;
    at.T_world_actor = st.T_world_body;
    at.position_rig_m = T_rw * st.T_world_body.translation();
    at.velocity_rig_mps = R_wr.transpose() * st.twist.linear_mps;
    at.angular_velocity_rig_rps = R_wr.transpose() * st.twist.angular_rps;
    const auto it = pixels.find(actor.actor_id);
    at.pixels = it == pixels.end() ? 0 : it->second;
    truth.actors.push_back(at);
  }
  frame.frame_truth = std::move(truth);
}

}  // namespace fmcw::sim
