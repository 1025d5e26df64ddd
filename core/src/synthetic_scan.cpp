#include "fmcw/core/synthetic_scan.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "fmcw/core/check.hpp"
#include "fmcw/core/random.hpp"

namespace fmcw::core {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// Ray/oriented-box intersection by the slab method in the box frame; returns the hit distance
// and the outward normal (rig frame), or kInf.
double intersect_box(const SyntheticBox& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                     Eigen::Vector3d& normal) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(box.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d o = R.transpose() * (origin - box.center_m);
  const Eigen::Vector3d d = R.transpose() * dir;
  double t_near = -kInf;
  double t_far = kInf;
  int axis_near = -1;
  double sign_near = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d(a)) < 1e-15) {
      if (std::abs(o(a)) > box.half_extent_m(a)) return kInf;
      continue;
    }
    double t0 = (-box.half_extent_m(a) - o(a)) / d(a);
    double t1 = (box.half_extent_m(a) - o(a)) / d(a);
    double s = -1.0;
    if (t0 > t1) {
      std::swap(t0, t1);
      s = 1.0;
    }
    if (t0 > t_near) {
      t_near = t0;
      axis_near = a;
      sign_near = s;
    }
    t_far = std::min(t_far, t1);
  }
  if (t_near > t_far || t_near <= 0.0 || axis_near < 0) return kInf;  // origin inside: ignore
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n(axis_near) = sign_near;
  normal = R * n;
  return t_near;
}
}  // namespace

void SyntheticSceneParams::validate() const {
  rig.validate();
  FMCW_CHECK_ARG(range_noise_m >= 0.0 && velocity_noise_mps >= 0.0,
                 "synthetic scene: noise sigmas must be >= 0");
  for (const auto* list : {&static_boxes, &actors}) {
    for (const auto& box : *list) {
      FMCW_CHECK_ARG((box.half_extent_m.array() > 0.0).all(), "synthetic scene: box half extents must be > 0");
    }
  }
}

Frame render_synthetic_scan(const SyntheticSceneParams& params) {
  params.validate();
  const int rows = params.rig.rows();
  const int cols = params.rig.cols();
  Frame frame;
  Scan& scan = frame.scan;
  scan = Scan::make_empty(rows, cols);
  scan.heads = params.rig.head_infos();
  frame.truth = PixelGroundTruth::make_empty(scan.size());
  PixelGroundTruth& gt = *frame.truth;
  const std::vector<Eigen::Vector3f> dirs = params.rig.directions_rig();

  for (std::size_t h = 0; h < params.rig.heads.size(); ++h) {
    const HeadModel& head = params.rig.heads[h];
    const HeadInfo& info = scan.heads[h];
    const Eigen::Vector3d origin = head.T_rig_head.translation();
    // Velocity of the head's origin: rigid body motion of the rig.
    const Eigen::Vector3d v_origin = params.ego_velocity_mps + params.ego_angular_velocity_rps.cross(origin);
    for (int r = 0; r < rows; ++r) {
      Rng rng(mix_seed(params.seed, static_cast<std::uint64_t>(r) * 4096u + h));
      for (int c = info.col_begin; c < info.col_end; ++c) {
        const std::size_t i = scan.index(r, c);
        const Eigen::Vector3d e = dirs[i].cast<double>();
        double t_best = kInf;
        Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
        Eigen::Vector3d v_point = Eigen::Vector3d::Zero();
        std::uint32_t instance = 0;
        float reflectivity = 0.2f;
        if (params.ground && e.z() < 0.0) {
          const double t = (params.ground_z_m - origin.z()) / e.z();
          if (t > 0.0) t_best = t;
        }
        for (const auto& box : params.static_boxes) {
          Eigen::Vector3d n;
          const double t = intersect_box(box, origin, e, n);
          if (t < t_best) {
            t_best = t;
            normal = n;
            reflectivity = box.reflectivity;
          }
        }
        for (std::size_t a = 0; a < params.actors.size(); ++a) {
          const SyntheticBox& box = params.actors[a];
          Eigen::Vector3d n;
          const double t = intersect_box(box, origin, e, n);
          if (t < t_best) {
            t_best = t;
            normal = n;
            reflectivity = box.reflectivity;
            instance = static_cast<std::uint32_t>(a + 1);
            const Eigen::Vector3d p = origin + t * e;
            v_point = box.velocity_mps + Eigen::Vector3d(0, 0, box.yaw_rate_rps).cross(p - box.center_m);
          }
        }
        if (!(t_best <= head.max_range_m)) continue;
        // Eq. 6: v = e . (V_point - V_lidar).
        const double doppler = e.dot(v_point - v_origin);
        const double range = t_best + params.range_noise_m * rng.normal();
        const double v_meas = doppler + params.velocity_noise_mps * rng.normal();
        const Eigen::Vector3d p = origin + range * e;
        scan.x_m[i] = static_cast<float>(p.x());
        scan.y_m[i] = static_cast<float>(p.y());
        scan.z_m[i] = static_cast<float>(p.z());
        scan.range_m[i] = static_cast<float>(range);
        scan.radial_velocity_mps[i] = static_cast<float>(v_meas);
        scan.intensity[i] = static_cast<float>(reflectivity * std::abs(normal.dot(e)));
        scan.valid[i] = 1;
        gt.range_m[i] = static_cast<float>(t_best);
        gt.radial_velocity_mps[i] = static_cast<float>(doppler);
        gt.vx_mps[i] = static_cast<float>(v_point.x());
        gt.vy_mps[i] = static_cast<float>(v_point.y());
        gt.vz_mps[i] = static_cast<float>(v_point.z());
        gt.instance[i] = instance;
        gt.moving[i] = v_point.norm() > params.moving_threshold_mps ? 1 : 0;
      }
    }
  }
  return frame;
}

SyntheticSceneParams benchmark_scene(int num_actors, std::uint64_t seed) {
  SyntheticSceneParams p;
  p.ego_velocity_mps = Eigen::Vector3d(10.0, 0.0, 0.0);
  p.range_noise_m = 0.025;
  p.velocity_noise_mps = 0.031;
  p.seed = seed;
  // Building rows on both sides of a 20 m wide street, and a block closing the view ahead.
  for (int k = 0; k < 8; ++k) {
    SyntheticBox left;
    left.center_m = {8.0 + 16.0 * k, 16.0, 10.0};
    left.half_extent_m = {7.0, 5.0, 10.0};
    SyntheticBox right = left;
    right.center_m.y() = -16.0;
    p.static_boxes.push_back(left);
    p.static_boxes.push_back(right);
  }
  SyntheticBox end;
  end.center_m = {140.0, 0.0, 20.0};
  end.half_extent_m = {5.0, 60.0, 20.0};
  p.static_boxes.push_back(end);
  Rng rng(seed);
  for (int a = 0; a < num_actors; ++a) {
    SyntheticBox car;
    const double x = 12.0 + 100.0 * rng.uniform();
    const double y = -8.0 + 16.0 * rng.uniform();
    car.center_m = {x, y, 0.75};
    car.half_extent_m = {2.25, 0.9, 0.75};
    car.yaw_rad = (rng.uniform() - 0.5) * M_PI;
    const double speed = 3.0 + 12.0 * rng.uniform();
    car.velocity_mps = speed * Eigen::Vector3d(std::cos(car.yaw_rad), std::sin(car.yaw_rad), 0.0);
    p.actors.push_back(car);
  }
  return p;
}

}  // namespace fmcw::core
