#include "fmcw/sim/actor_boxes.hpp"

#include <cmath>
#include <limits>

#include "fmcw/sim/actor_culling.hpp"

namespace fmcw::sim {

namespace {

// Where the ray o + t d (t in [near, far]) meets the box |x| <= half of its own frame.
bool ray_meets_box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half, double near, double far) {
  double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-15) {
      if (std::abs(o[a]) > half[a]) return false;
      continue;
    }
    double ta = (-half[a] - o[a]) / d[a], tb = (half[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 && t1 >= near && t0 <= far;
}

bool in_field_of_view(const core::HeadModel& head, const Eigen::Vector3d& p_rig) {
  const Eigen::Vector3d p = head.T_rig_head.inverse() * p_rig;
  const double azimuth = std::atan2(p.y(), p.x());
  const double elevation = std::atan2(p.z(), std::hypot(p.x(), p.y()));
  return std::abs(azimuth) <= 0.5 * head.fov_horizontal_rad && std::abs(elevation) <= 0.5 * head.fov_vertical_rad;
}

// Actor k's box, and how many beams meet it.
void actor_box(const Scene& scene, const core::RigModel& rig, const std::vector<Eigen::Vector3f>& directions_rig,
               const Eigen::Isometry3d& T_rig_world, double min_range_m, std::size_t k, core::ActorTruth& actor) {
  core::BoxTruth& box = actor.box;
  box = core::BoxTruth{};
  const MotionState& st = scene.actor_state(k);
  // The heading frame: the body's origin, turned about the world's z to the body's heading.
  const Eigen::Matrix3d& R = st.T_world_body.linear();
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  Eigen::Isometry3d T_world_heading = Eigen::Isometry3d::Identity();
  T_world_heading.translation() = st.T_world_body.translation();
  T_world_heading.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::AlignedBox3d extent = scene.actor_extent(k, T_world_heading.inverse());
  if (extent.isEmpty()) return;
  box.center_world_m = T_world_heading * extent.center();
  box.yaw_world_rad = yaw;
  box.size_m = extent.sizes();
  box.center_m = T_rig_world * box.center_world_m;
  const Eigen::Matrix3d R_rig_box = T_rig_world.linear() * T_world_heading.linear();
  const Eigen::Vector3d heading_rig = R_rig_box.col(0);
  box.yaw_rad = std::atan2(heading_rig.y(), heading_rig.x());
  // The body's rigid motion at the centre: v + omega x r.
  const Eigen::Vector3d v = st.twist.linear_mps + st.twist.angular_rps.cross(box.center_world_m - st.T_world_body.translation());
  box.velocity_mps = T_rig_world.linear() * v;
  for (int corner = 0; corner < 8 && !box.truncated; ++corner) {
    const Eigen::Vector3d c = box.center_m + R_rig_box * (0.5 * box.size_m).cwiseProduct(Eigen::Vector3d(
                                                         corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1));
    bool seen = false;
    for (const auto& head : rig.heads) seen = seen || in_field_of_view(head, c);
    box.truncated = !seen;
  }
  // An actor no beam hit has nothing visible, however many beams meet its box.
  if (actor.pixels == 0) return;
  // Beams that meet the box: only those in the footprint of its sphere (rig frame throughout).
  const BoundingSphere sphere{box.center_m, 0.5 * box.size_m.norm() + 1e-3};
  const Eigen::Vector3d half = 0.5 * box.size_m;
  const int cols = rig.cols();
  std::vector<ActorFootprint> footprint;
  int meeting = 0, col_begin = 0;
  for (const core::HeadModel& head : rig.heads) {
    actor_footprints({sphere}, head, col_begin, head.T_rig_head, 1e-5, footprint);
    col_begin += head.cols();
    if (footprint.empty()) continue;
    const ActorFootprint& f = footprint.front();
    const Eigen::Vector3d o = R_rig_box.transpose() * (head.T_rig_head.translation() - box.center_m);
    for (int r = f.row_begin; r < f.row_end; ++r) {
      for (int c = f.col_begin; c < f.col_end; ++c) {
        // Unit already (RigModel::directions_rig).
        const Eigen::Vector3d e =
            directions_rig[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c)].cast<double>();
        meeting += ray_meets_box(o, R_rig_box.transpose() * e, half, min_range_m, head.max_range_m) ? 1 : 0;
      }
    }
  }
  box.visible_fraction = meeting > 0 ? std::min(1.0, static_cast<double>(actor.pixels) / meeting) : 0.0;
}

}  // namespace

void actor_boxes(const Scene& scene, const core::RigModel& rig, const std::vector<Eigen::Vector3f>& directions_rig,
                 const Eigen::Isometry3d& T_world_rig, double min_range_m, int num_threads,
                 std::vector<core::ActorTruth>& actors) {
  const Eigen::Isometry3d T_rig_world = T_world_rig.inverse();
  // Actors are independent: each thread writes only its own actors' boxes.
#pragma omp parallel for schedule(dynamic, 1) num_threads(num_threads)
  for (std::size_t k = 0; k < actors.size(); ++k) {
    actor_box(scene, rig, directions_rig, T_rig_world, min_range_m, k, actors[k]);
  }
}

}  // namespace fmcw::sim
