#include "fmcw/sim/lidar_simulator.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "fmcw/core/check.hpp"
#include "fmcw/core/random.hpp"

namespace fmcw::sim {

namespace {

// The rig at one instant: each head's origin and its velocity V_ego + omega x r_mount.
struct RigPose {
  Eigen::Isometry3d T_world_rig;
  Eigen::Isometry3d T_rig_world;
  std::vector<Eigen::Vector3d> origin_world;
  std::vector<Eigen::Vector3d> origin_velocity_world;
};

RigPose rig_pose(const MotionState& ego, const core::RigModel& rig) {
  RigPose pose;
  pose.T_world_rig = ego.T_world_body;
  pose.T_rig_world = ego.T_world_body.inverse();
  const Eigen::Vector3d p_wr = ego.T_world_body.translation();
  for (const auto& head : rig.heads) {
    const Eigen::Vector3d o = ego.T_world_body * head.T_rig_head.translation();
    pose.origin_world.push_back(o);
    pose.origin_velocity_world.push_back(ego.twist.linear_mps + ego.twist.angular_rps.cross(o - p_wr));
  }
  return pose;
}

}  // namespace

void LidarSimulatorParams::validate() const {
  rig.validate();
  measurement.validate();
  FMCW_CHECK_ARG(min_range_m >= 0.0, "simulator: min_range_m must be >= 0, got ", min_range_m);
  FMCW_CHECK_ARG(moving_threshold_mps >= 0.0, "simulator: moving_threshold_mps must be >= 0, got ", moving_threshold_mps);
  FMCW_CHECK_ARG(num_threads >= 0, "simulator: num_threads must be >= 0, got ", num_threads);
  FMCW_CHECK_ARG(time_slices >= 0, "simulator: time_slices must be >= 0, got ", time_slices);
  divergence.validate();
}

LidarSimulator::LidarSimulator(std::shared_ptr<Scene> scene, std::shared_ptr<const Trajectory> ego,
                               const LidarSimulatorParams& params)
    : scene_(std::move(scene)), ego_(std::move(ego)), params_(params), measurement_((params.validate(), params.measurement)) {
  FMCW_CHECK_ARG(scene_ != nullptr && ego_ != nullptr, "simulator: scene and ego trajectory are required");
  head_infos_ = params_.rig.head_infos();
  directions_rig_ = params_.rig.directions_rig();
  directions_world_.resize(directions_rig_.size());
  pattern_ = make_sub_ray_pattern(params_.divergence.sub_rays);
  if (pattern_.offsets.size() > 1) {
    sub_directions_rig_.resize(directions_rig_.size() * pattern_.offsets.size());
    for (std::size_t i = 0; i < directions_rig_.size(); ++i) {
      sub_ray_directions(directions_rig_[i].cast<double>().normalized(), pattern_, params_.divergence.divergence_rad,
                         &sub_directions_rig_[i * pattern_.offsets.size()]);
    }
  }
}

int LidarSimulator::slice_count() const {
  if (!params_.motion_distortion) return 1;
  if (params_.time_slices > 0) return params_.time_slices;
  int widest = 0;
  for (const auto& info : head_infos_) widest = std::max(widest, info.cols());
  return widest;  // one slice per column: every beam at its own time
}

double LidarSimulator::beam_time_offset_s(std::size_t head, int local_col) const {
  if (!params_.motion_distortion) return 0.0;
  // Each head sweeps its columns left to right over one period; rows fire together.
  const double fraction = (local_col + 0.5) / head_infos_[head].cols();
  return fraction / params_.rig.heads[head].rate_hz;
}

core::Frame LidarSimulator::simulate(std::uint64_t frame_index, double t_s) {
  core::Frame frame;
  simulate(frame_index, t_s, frame);
  return frame;
}

void LidarSimulator::simulate(std::uint64_t frame_index, double t_s, core::Frame& frame) {
  const int rows = params_.rig.rows();
  const int cols = params_.rig.cols();
  const std::size_t n = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  if (frame.scan.rows != rows || frame.scan.cols != cols || frame.scan.size() != frame.scan.x_m.size()) {
    frame.scan = core::Scan::make_empty(rows, cols);
  }
  if (!frame.truth || frame.truth->range_m.size() != n) frame.truth = core::PixelGroundTruth::make_empty(n);
  frame.scan.heads = head_infos_;
  frame.scan.stamp_s = t_s;
  if (params_.motion_distortion) {
    frame.scan.time_offset_s.resize(n);
  } else {
    frame.scan.time_offset_s.clear();
  }
  core::Scan& scan = frame.scan;
  core::PixelGroundTruth& gt = *frame.truth;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::uint64_t frame_seed = core::mix_seed(params_.seed, frame_index);
  const int threads = params_.num_threads > 0 ? params_.num_threads : omp_get_max_threads();
  const int slices = slice_count();
  const double moving_threshold_sq = params_.moving_threshold_mps * params_.moving_threshold_mps;
  std::vector<Eigen::Vector3d> mount_rig;
  for (const auto& head : params_.rig.heads) mount_rig.push_back(head.T_rig_head.translation());

  for (int k = 0; k < slices; ++k) {
    // The columns of slice k in each head, and the instant they are cast at.
    std::vector<std::pair<int, int>> span(head_infos_.size());
    for (std::size_t h = 0; h < head_infos_.size(); ++h) {
      const int w = head_infos_[h].cols();
      span[h] = {head_infos_[h].col_begin + k * w / slices, head_infos_[h].col_begin + (k + 1) * w / slices};
    }
    const double t_slice = params_.motion_distortion
                               ? t_s + beam_time_offset_s(0, (k * head_infos_[0].cols() + head_infos_[0].cols() / 2) / slices)
                               : t_s;
    scene_->set_time(t_slice);
    const RigPose pose = rig_pose(ego_->state(t_slice), params_.rig);
    const Eigen::Matrix3d R_wr = pose.T_world_rig.linear();
    const Eigen::Matrix3f R_wr_f = R_wr.cast<float>();
    // World beam directions: rotations keep unit vectors unit. A rig that did not turn since
    // the last frame keeps last frame's directions (all columns are one slice then).
    if (slices > 1 || !(R_wr_f == last_rotation_)) {
      const float* m = R_wr_f.data();  // column-major
      for (int r = 0; r < rows; ++r) {
        for (std::size_t h = 0; h < span.size(); ++h) {
          for (int c = span[h].first; c < span[h].second; ++c) {
            const std::size_t i = scan.index(r, c);
            const float x = directions_rig_[i].x(), y = directions_rig_[i].y(), z = directions_rig_[i].z();
            directions_world_[i] = Eigen::Vector3f(m[0] * x + m[3] * y + m[6] * z, m[1] * x + m[4] * y + m[7] * z,
                                                   m[2] * x + m[5] * y + m[8] * z);
          }
        }
      }
      last_rotation_ = slices > 1 ? Eigen::Matrix3f::Constant(std::numeric_limits<float>::quiet_NaN()) : R_wr_f;
    }

#pragma omp parallel num_threads(threads)
    {
      const std::size_t sub = pattern_.offsets.size();
      std::vector<RayHit> hits(static_cast<std::size_t>(cols) * sub);
      std::vector<Eigen::Vector3f> sub_dirs(sub > 1 ? static_cast<std::size_t>(cols) * sub : 0);
      std::vector<SubReturn> returns;
      // Dynamic rows: sky rows cost little, ground rows a lot. Each (row, slice) draws from its
      // own seed, so the result does not depend on which thread takes it.
#pragma omp for schedule(dynamic, 2)
      for (int r = 0; r < rows; ++r) {
        core::Rng rng(core::mix_seed(frame_seed, static_cast<std::uint64_t>(r) * static_cast<std::uint64_t>(slices) +
                                                     static_cast<std::uint64_t>(k)));
        const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols);
        for (std::size_t h = 0; h < span.size(); ++h) {
          const auto c0 = static_cast<std::size_t>(span[h].first);
          const auto count = static_cast<std::size_t>(span[h].second - span[h].first);
          const Eigen::Vector3f origin = pose.origin_world[h].cast<float>();
          const auto far = static_cast<float>(params_.rig.heads[h].max_range_m);
          const auto near = static_cast<float>(params_.min_range_m);
          if (sub == 1) {
            scene_->intersect(origin, &directions_world_[row + c0], count, near, far, &hits[c0]);
            continue;
          }
          for (std::size_t c = 0; c < count; ++c) {
            const std::size_t i = row + c0 + c;
            for (std::size_t j = 0; j < sub; ++j) sub_dirs[(c0 + c) * sub + j] = R_wr_f * sub_directions_rig_[i * sub + j];
          }
          scene_->intersect(origin, &sub_dirs[c0 * sub], count * sub, near, far, &hits[c0 * sub]);
        }
        for (std::size_t h = 0; h < span.size(); ++h) {
          const Eigen::Vector3d& origin = pose.origin_world[h];
          const Eigen::Vector3d& v_origin = pose.origin_velocity_world[h];
          for (int c = span[h].first; c < span[h].second; ++c) {
            const std::size_t i = row + static_cast<std::size_t>(c);
            if (params_.motion_distortion) {
              scan.time_offset_s[i] = static_cast<float>(beam_time_offset_s(h, c - head_infos_[h].col_begin));
            }
            const Eigen::Vector3d e = directions_world_[i].cast<double>();
            // What the receiver reports for this beam, noise-free.
            bool hit = false;
            double range = 0.0, doppler = 0.0;
            Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
            float intensity = 0.0f;
            std::uint32_t instance = 0;
            if (sub == 1) {
              const RayHit& ray = hits[static_cast<std::size_t>(c)];
              if (std::isfinite(ray.distance_m)) {
                hit = true;
                range = ray.distance_m;
                const SurfaceSample s = scene_->resolve(ray, origin + range * e);
                // Eq. 6: v = e . (V_point - V_lidar), both in the world frame (the dot product
                // does not depend on the frame it is evaluated in). The static world is at rest.
                doppler = ray.slot == 0 ? -e.dot(v_origin) : e.dot(s.velocity_world_mps - v_origin);
                velocity = s.velocity_world_mps;
                intensity = return_intensity(s.reflectivity, e.dot(s.normal_world), range);
                instance = s.actor_id;
              }
            } else {
              returns.clear();
              for (std::size_t j = 0; j < sub; ++j) {
                const RayHit& ray = hits[static_cast<std::size_t>(c) * sub + j];
                if (!std::isfinite(ray.distance_m)) continue;
                const Eigen::Vector3d d = sub_dirs[static_cast<std::size_t>(c) * sub + j].cast<double>();
                const SurfaceSample s = scene_->resolve(ray, origin + ray.distance_m * d);
                returns.push_back({ray.distance_m, d.dot(s.velocity_world_mps - v_origin), s.velocity_world_mps,
                                   pattern_.weights[j] * return_intensity(s.reflectivity, d.dot(s.normal_world), ray.distance_m),
                                   s.actor_id});
              }
              MergedReturn merged;
              if (merge_sub_returns(returns, params_.divergence, merged)) {
                hit = true;
                range = merged.range_m;
                doppler = merged.doppler_mps;
                velocity = merged.velocity_world_mps;
                intensity = static_cast<float>(merged.energy);
                instance = merged.instance;
              }
            }
            if (!hit) {
              scan.x_m[i] = scan.y_m[i] = scan.z_m[i] = scan.range_m[i] = scan.radial_velocity_mps[i] = nan;
              scan.intensity[i] = 0.0f;
              scan.valid[i] = 0;
              gt.range_m[i] = gt.radial_velocity_mps[i] = gt.vx_mps[i] = gt.vy_mps[i] = gt.vz_mps[i] = nan;
              gt.instance[i] = 0;
              gt.moving[i] = 0;
              continue;
            }
            const MeasurementModel::Reading m = measurement_.measure(range, doppler, rng);
            // Reported along the beam's axis, in the rig frame of the beam's own instant (the
            // motion skew of a real sweep): T_rig_world (o + r e) = mount + r e_rig.
            const Eigen::Vector3d p_rig = mount_rig[h] + m.range_m * directions_rig_[i].cast<double>();
            scan.x_m[i] = static_cast<float>(p_rig.x());
            scan.y_m[i] = static_cast<float>(p_rig.y());
            scan.z_m[i] = static_cast<float>(p_rig.z());
            scan.range_m[i] = static_cast<float>(m.range_m);
            scan.radial_velocity_mps[i] = static_cast<float>(m.radial_velocity_mps);
            scan.intensity[i] = intensity;
            scan.valid[i] = 1;
            const Eigen::Vector3d v_rig = instance == 0 && sub == 1 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(R_wr.transpose() * velocity);
            gt.range_m[i] = static_cast<float>(range);
            gt.radial_velocity_mps[i] = static_cast<float>(doppler);
            gt.vx_mps[i] = static_cast<float>(v_rig.x());
            gt.vy_mps[i] = static_cast<float>(v_rig.y());
            gt.vz_mps[i] = static_cast<float>(v_rig.z());
            gt.instance[i] = instance;
            gt.moving[i] = velocity.squaredNorm() > moving_threshold_sq ? 1 : 0;
          }
        }
      }
    }
  }

  // Frame truth at the frame's stamp (with distortion, pixels carry their offsets from it).
  if (slices > 1) scene_->set_time(t_s);
  const MotionState ego = ego_->state(t_s);
  const Eigen::Matrix3d R_wr = ego.T_world_body.linear();
  const Eigen::Isometry3d T_rw = ego.T_world_body.inverse();
  core::FrameTruth truth;
  truth.stamp_s = t_s;
  truth.ego.T_world_rig = ego.T_world_body;
  truth.ego.velocity_mps = R_wr.transpose() * ego.twist.linear_mps;
  truth.ego.angular_velocity_rps = R_wr.transpose() * ego.twist.angular_rps;
  std::map<std::uint32_t, int> pixels;
  for (std::size_t i = 0; i < n; ++i) {
    if (gt.instance[i] != 0) ++pixels[gt.instance[i]];  // 0 where there is no return
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
