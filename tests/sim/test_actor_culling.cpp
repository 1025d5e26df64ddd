// The simulator traces only some beams against the actors (those inside an actor's footprint in
// the image and not hidden behind the static world). Here every beam is also traced against the
// whole scene directly, and the two must agree on every pixel: culling may only save work.

#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/core/random.hpp"
#include "fmcw/sim/actor_culling.hpp"
#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/scene.hpp"

namespace fmcw::sim {
namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw, double pitch = 0.0, double roll = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

// Heads that look every way: pitched and rolled, wide, backwards (azimuths near +-180 deg).
core::RigModel odd_rig() {
  core::RigModel rig;
  const double deg = M_PI / 180.0;
  const struct {
    double yaw, pitch, roll, fov_h;
  } heads[] = {{0.0, 20.0, 10.0, 100.0}, {180.0, -5.0, 0.0, 60.0}, {90.0, -30.0, 0.0, 170.0}};
  for (const auto& h : heads) {
    core::HeadModel head;
    head.name = "h" + std::to_string(rig.heads.size());
    head.T_rig_head = pose(0.5, 0.2 * static_cast<double>(rig.heads.size()), 1.5, h.yaw * deg, h.pitch * deg, h.roll * deg);
    head.fov_horizontal_rad = h.fov_h * deg;
    head.fov_vertical_rad = 40.0 * deg;
    head.resolution_horizontal_rad = head.resolution_vertical_rad = 0.5 * deg;
    head.max_range_m = 80.0;
    rig.heads.push_back(head);
  }
  return rig;
}

std::shared_ptr<Scene> crowded_scene(const Eigen::Isometry3d& T_world_rig, const core::RigModel& rig) {
  auto scene = std::make_shared<Scene>();
  scene->add_ground_plane(0.0, 200.0, 0.1f);
  SceneObject wall;
  wall.name = "wall";
  wall.asset = std::make_shared<const MeshAsset>(box_mesh({0.5f, 30.0f, 6.0f}, 0.6f));
  wall.trajectory = make_static_trajectory(pose(25.0, 0.0, 3.0, 0.0));
  scene->add(std::move(wall));
  // Boxes all around, near (one encloses a head's origin) and far, some beyond range, moving.
  core::Rng rng(42);
  for (std::uint32_t id = 1; id <= 40; ++id) {
    SceneObject box;
    box.name = "box" + std::to_string(id);
    box.class_name = "car";
    box.actor_id = id;
    const auto half = static_cast<float>(0.2 + 1.5 * rng.uniform());
    box.asset = std::make_shared<const MeshAsset>(box_mesh({half, 0.6f * half, 0.8f * half}, 0.4f));
    const double bearing = 2.0 * M_PI * rng.uniform();
    const double distance = 2.0 + 100.0 * rng.uniform();
    const Eigen::Vector3d velocity(rng.normal() * 5.0, rng.normal() * 5.0, 0.0);
    Eigen::Isometry3d start = pose(distance * std::cos(bearing), distance * std::sin(bearing), 0.5 + 4.0 * rng.uniform(), bearing);
    if (id == 1) start.translation() = T_world_rig * rig.heads[0].T_rig_head.translation();  // around a head
    box.trajectory = make_constant_velocity_trajectory(start, id == 1 ? Eigen::Vector3d::Zero() : velocity);
    scene->add(std::move(box));
  }
  scene->build();
  return scene;
}

void expect_same_hits_as_brute_force(bool motion_distortion) {
  LidarSimulatorParams params;
  params.rig = odd_rig();
  const Eigen::Isometry3d T_world_rig = pose(1.0, -2.0, 0.1, 0.3, 0.05, -0.02);
  const std::shared_ptr<Scene> scene = crowded_scene(T_world_rig, params.rig);
  params.measurement.range_sigma_m = 0.0;
  params.measurement.velocity_sigma_mps = 0.0;
  params.motion_distortion = motion_distortion;
  params.time_slices = 4;
  LidarSimulator sim(scene, make_static_trajectory(T_world_rig), params);
  const double t = 0.35;
  const core::Frame f = sim.simulate(0, t);

  // The same beams, every one traced against both layers, with directions and origins formed as
  // the simulator forms them. With motion distortion the actors move between time slices: the
  // brute force moves the scene to each slice's instant too.
  const auto dirs_rig = params.rig.directions_rig();
  const Eigen::Matrix3f R = T_world_rig.linear().cast<float>();
  const float* m = R.data();
  std::size_t actor_pixels = 0, compared = 0;
  const int slices = motion_distortion ? params.time_slices : 1;
  for (int k = 0; k < slices; ++k) {
    const double slice_t =
        motion_distortion ? t + sim.beam_time_offset_s(0, (k * f.scan.heads[0].cols() + f.scan.heads[0].cols() / 2) / slices)
                          : t;
    scene->set_time(slice_t);
    for (std::size_t h = 0; h < params.rig.heads.size(); ++h) {
      const core::HeadInfo& info = f.scan.heads[h];
      const int w = info.cols();
      const int c0 = info.col_begin + k * w / slices, c1 = info.col_begin + (k + 1) * w / slices;
      const Eigen::Vector3f origin = (T_world_rig * params.rig.heads[h].T_rig_head.translation()).cast<float>();
      for (int r = 0; r < f.scan.rows; ++r) {
        for (int c = c0; c < c1; ++c) {
          const std::size_t i = f.scan.index(r, c);
          const float x = dirs_rig[i].x(), y = dirs_rig[i].y(), z = dirs_rig[i].z();
          const Eigen::Vector3f d(m[0] * x + m[3] * y + m[6] * z, m[1] * x + m[4] * y + m[7] * z,
                                  m[2] * x + m[5] * y + m[8] * z);
          RayHit hit;
          const auto far = static_cast<float>(params.rig.heads[h].max_range_m);
          const auto near = static_cast<float>(params.min_range_m);
          scene->intersect(SceneLayer::kStatic, origin, &d, nullptr, 1, near, far, &hit);
          scene->intersect(SceneLayer::kActors, origin, &d, nullptr, 1, near, far, &hit);
          const bool valid = std::isfinite(hit.distance_m);
          ASSERT_EQ(f.scan.valid[i] != 0, valid) << "head " << h << " row " << r << " col " << c;
          if (!valid) continue;
          ASSERT_EQ(f.truth->range_m[i], hit.distance_m) << "head " << h << " row " << r << " col " << c;
          const std::uint32_t id = hit.slot == 0 ? 0 : scene->slot(hit.slot).actor_id;
          ASSERT_EQ(f.truth->instance[i], id) << "head " << h << " row " << r << " col " << c;
          actor_pixels += id != 0;
          ++compared;
        }
      }
    }
  }
  EXPECT_EQ(compared, f.scan.num_valid());
  EXPECT_GT(actor_pixels, 2000u);  // the actors fill a good part of the image
}

// Whether a ray from the origin along unit d passes through the sphere within range.
bool ray_meets_sphere(const Eigen::Vector3d& d, const BoundingSphere& s, double max_range_m) {
  const double along = d.dot(s.center);
  const double miss_sq = s.center.squaredNorm() - along * along;
  if (miss_sq > s.radius_m * s.radius_m) return false;
  const double half_chord = std::sqrt(s.radius_m * s.radius_m - miss_sq);
  return along + half_chord >= 0.0 && along - half_chord <= max_range_m;
}

TEST(ActorCulling, FootprintHoldsEveryBeamThatMeetsTheSphere) {
  const core::RigModel rig = odd_rig();
  const auto infos = rig.head_infos();
  core::Rng rng(7);
  std::size_t inside = 0;
  for (std::size_t h = 0; h < rig.heads.size(); ++h) {
    const core::HeadModel& head = rig.heads[h];
    // Spheres all around the head, in the head's frame (T_world_head = identity); a few wrap
    // the origin.
    std::vector<BoundingSphere> spheres;
    for (int k = 0; k < 300; ++k) {
      const Eigen::Vector3d dir = Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal()).normalized();
      const double distance = k < 3 ? 0.1 : 1.0 + 100.0 * rng.uniform();
      spheres.push_back({distance * dir, 0.05 + 3.0 * rng.uniform()});
    }
    for (const BoundingSphere& sphere : spheres) {
      // This sphere alone, to know which footprint is its (or that it has none).
      std::vector<ActorFootprint> own;
      actor_footprints({sphere}, head, infos[h].col_begin, Eigen::Isometry3d::Identity(), 0.0, own);
      for (int r = 0; r < head.rows(); ++r) {
        for (int c = 0; c < head.cols(); ++c) {
          if (!ray_meets_sphere(head.direction_head(r, c), sphere, head.max_range_m)) continue;
          ++inside;
          ASSERT_EQ(own.size(), 1u) << "head " << h << " sphere at " << sphere.center.transpose();
          const ActorFootprint& fp = own[0];
          const int col = infos[h].col_begin + c;
          ASSERT_TRUE(fp.row_begin <= r && r < fp.row_end && fp.col_begin <= col && col < fp.col_end)
              << "head " << h << " beam (" << r << ", " << c << ") sphere at " << sphere.center.transpose() << " radius "
              << sphere.radius_m;
          ASSERT_LE(fp.nearest_m, sphere.center.norm());
        }
      }
    }
  }
  EXPECT_GT(inside, 20000u);
}

TEST(ActorCulling, EveryBeamHitsWhatTheWholeSceneGives) { expect_same_hits_as_brute_force(false); }

TEST(ActorCulling, EveryBeamHitsWhatTheWholeSceneGivesWithMotionDistortion) { expect_same_hits_as_brute_force(true); }

}  // namespace
}  // namespace fmcw::sim
