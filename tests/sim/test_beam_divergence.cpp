#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/sim/beam_divergence.hpp"
#include "fmcw/sim/lidar_simulator.hpp"

namespace fmcw::sim {
namespace {

TEST(SubRayPattern, NineteenRaysInTwoHexagonalRingsWithGaussianWeights) {
  const SubRayPattern p = make_sub_ray_pattern(19);
  ASSERT_EQ(p.offsets.size(), 19u);
  EXPECT_EQ(p.offsets[0], Eigen::Vector2d::Zero());
  double sum = 0.0;
  for (std::size_t k = 0; k < 19; ++k) {
    sum += p.weights[k];
    EXPECT_LE(p.offsets[k].norm(), 1.0 + 1e-12);
    EXPECT_LE(p.weights[k], p.weights[0]);
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_THROW(make_sub_ray_pattern(12), std::invalid_argument);
  // Directions stay inside the cone around the axis.
  std::vector<Eigen::Vector3f> dirs(19);
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 0.2, -0.1).normalized();
  sub_ray_directions(axis, p, 0.002, dirs.data());
  double widest = 0.0;
  for (const auto& d : dirs) {
    const Eigen::Vector3d v = d.cast<double>();
    widest = std::max(widest, std::atan2(v.cross(axis).norm(), v.dot(axis)));
  }
  EXPECT_NEAR(widest, 0.001, 1e-6);
}

TEST(MergeSubReturns, CloseReturnsFormOnePeakAndTheStrongestPeakWins) {
  BeamDivergenceParams params;
  std::vector<SubReturn> r = {
      {15.0, 5.0, {5, 0, 0}, 0.35, 2},    // a far surface, moving: its own peak
      {10.0, 0.00, {0, 0, 0}, 0.30, 1},   // near surface ...
      {10.01, 0.02, {0, 0, 0}, 0.20, 1},  // ... within 2.5 cm and 0.031 m/s: same peak
      {10.02, 0.03, {0, 0, 0}, 0.10, 3},  // chained by single linkage
  };
  MergedReturn m;
  ASSERT_TRUE(merge_sub_returns(r, params, m));
  EXPECT_EQ(m.peaks, 2);
  EXPECT_NEAR(m.energy, 0.60, 1e-12);
  EXPECT_NEAR(m.range_m, (10.0 * 0.3 + 10.01 * 0.2 + 10.02 * 0.1) / 0.6, 1e-12);
  EXPECT_NEAR(m.doppler_mps, (0.02 * 0.2 + 0.03 * 0.1) / 0.6, 1e-12);
  EXPECT_EQ(m.instance, 1u);
  // Same ranges but Doppler apart by more than the resolution: separate peaks.
  std::vector<SubReturn> split = {{10.0, 0.0, {0, 0, 0}, 0.3, 1}, {10.0, 1.0, {1, 0, 0}, 0.4, 2}};
  ASSERT_TRUE(merge_sub_returns(split, params, m));
  EXPECT_EQ(m.peaks, 2);
  EXPECT_EQ(m.instance, 2u);
  EXPECT_DOUBLE_EQ(m.doppler_mps, 1.0);
  std::vector<SubReturn> none;
  EXPECT_FALSE(merge_sub_returns(none, params, m));
}

std::shared_ptr<const MeshAsset> slab(const Eigen::Vector3f& h, float reflectivity) {
  return std::make_shared<const MeshAsset>(box_mesh(h, reflectivity));
}

TEST(BeamDivergence, DepthStepsStaySeparatePeaksAndOnlyTheSilhouetteChanges) {
  // A bright (retroreflective) box approaching at 5 m/s, 3 m in front of a dark static wall.
  // With a beam wider than a pixel the edge pixels see both surfaces; FMCW separates them by
  // range, so every pixel reports one of the two velocities, never a blend. Where a small part
  // of a beam on the bright box outweighs the rest on the dark wall, the box wins: the
  // silhouette grows, and only there.
  const auto run = [](int sub_rays) {
    auto scene = std::make_shared<Scene>();
    SceneObject wall;
    wall.asset = slab({0.5f, 50.0f, 20.0f}, 0.05f);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(23.5, 0, 0);
    wall.trajectory = make_static_trajectory(T);
    scene->add(std::move(wall));
    SceneObject box;
    box.actor_id = 1;
    box.asset = slab({0.5f, 1.0f, 0.8f}, 0.9f);
    T.translation() = Eigen::Vector3d(20.5, 0.3, 1.2);
    box.trajectory = make_constant_velocity_trajectory(T, {-5.0, 0.0, 0.0});
    scene->add(std::move(box));
    scene->build();
    LidarSimulatorParams p;
    p.measurement.range_sigma_m = p.measurement.velocity_sigma_mps = 0.0;
    p.divergence.sub_rays = sub_rays;
    p.divergence.divergence_rad = 0.3 * M_PI / 180.0;  // wider than a pixel: edges see both
    LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), p);
    return sim.simulate(0, 0.0);
  };
  const core::Frame narrow = run(1);
  const core::Frame wide = run(19);
  int changed = 0, box_pixels = 0;
  for (std::size_t i = 0; i < wide.scan.size(); ++i) {
    if (!wide.scan.valid[i]) continue;
    const double speed = Eigen::Vector3d(wide.truth->vx_mps[i], wide.truth->vy_mps[i], wide.truth->vz_mps[i]).norm();
    ASSERT_TRUE(speed < 1e-6 || std::abs(speed - 5.0) < 1e-6) << "blended velocity " << speed << " at pixel " << i;
    ASSERT_EQ(speed > 1.0, wide.truth->instance[i] == 1u);
    box_pixels += wide.truth->instance[i] == 1u;
    if (wide.truth->instance[i] != narrow.truth->instance[i]) {
      ++changed;
      EXPECT_EQ(wide.truth->instance[i], 1u) << "only the bright box can take over edge pixels";
      EXPECT_LT(wide.scan.intensity[i], 0.5f * 0.9f) << "an edge pixel returns part of the beam";
      // Only next to the box's outline in the narrow-beam image.
      const int r = static_cast<int>(i) / wide.scan.cols, c = static_cast<int>(i) % wide.scan.cols;
      bool near_edge = false;
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const std::size_t j = wide.scan.index(r + dr, c + dc);
          near_edge |= narrow.truth->instance[j] != narrow.truth->instance[i];
        }
      }
      EXPECT_TRUE(near_edge) << "pixel " << i;
    }
  }
  EXPECT_GT(box_pixels, 500);
  EXPECT_GT(changed, 0) << "a beam wider than a pixel must move the silhouette";
}

TEST(BeamDivergenceParams, RejectsPatternsThatAreNotHexagonal) {
  BeamDivergenceParams p;
  p.sub_rays = 10;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p.sub_rays = 19;
  p.divergence_rad = -1.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace fmcw::sim
