// The SNR measurement model: noise grows as 1/sqrt(SNR), returns drop out with range and with
// darkness, and the result is the same for any thread count.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "fmcw/core/errors.hpp"
#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/scene.hpp"
#include "support/sim_scenes.hpp"

namespace fmcw::sim {
namespace {

using test::at;

// One narrow head (8 x 4 deg at 0.2 deg) looking along x: every beam meets a wall across x
// within 4 deg of normal incidence.
core::RigModel narrow_rig() {
  core::RigModel rig;
  core::HeadModel head;
  head.name = "h";
  head.fov_horizontal_rad = 8.0 * M_PI / 180.0;
  head.fov_vertical_rad = 4.0 * M_PI / 180.0;
  head.resolution_horizontal_rad = head.resolution_vertical_rad = 0.2 * M_PI / 180.0;
  head.max_range_m = 400.0;
  rig.heads.push_back(head);
  return rig;
}

LidarSimulatorParams snr_params(int threads = 0) {
  LidarSimulatorParams p;
  p.rig = narrow_rig();
  p.measurement.model = MeasurementParams::Model::kSnr;
  p.seed = 23;
  p.num_threads = threads;
  return p;
}

// A wall of this reflectivity across x at range_m, seen by a rig moving at 5 m/s.
LidarSimulator wall_sim(double range_m, float reflectivity, int threads = 0) {
  auto scene = std::make_shared<Scene>();
  SceneObject wall;
  wall.name = "wall";
  wall.asset = std::make_shared<const MeshAsset>(box_mesh({0.5f, 100.0f, 100.0f}, reflectivity));
  wall.trajectory = make_static_trajectory(at(range_m + 0.5, 0, 0));
  scene->add(std::move(wall));
  scene->build();
  return LidarSimulator(scene, make_constant_velocity_trajectory(Eigen::Isometry3d::Identity(), {5, 0, 0}),
                        snr_params(threads));
}

struct WallStats {
  double detected;  // fraction of beams with a return
  double sigma_v;   // standard deviation of the velocity error [m/s]
};

WallStats measure_wall(double range_m, float reflectivity, int frames = 10) {
  LidarSimulator sim = wall_sim(range_m, reflectivity);
  double s = 0, s2 = 0;
  std::size_t n = 0, beams = 0;
  for (int k = 0; k < frames; ++k) {
    // Frames 1 ms apart: the wall stays at about range_m.
    const core::Frame f = sim.simulate(static_cast<std::uint64_t>(k), 0.001 * k);
    beams += f.scan.size();
    for (std::size_t i = 0; i < f.scan.size(); ++i) {
      if (!f.scan.valid[i]) continue;
      const double dv = f.scan.radial_velocity_mps[i] - f.truth->radial_velocity_mps[i];
      s += dv;
      s2 += dv * dv;
      ++n;
    }
  }
  const double nd = static_cast<double>(n);
  return {nd / static_cast<double>(beams), n > 1 ? std::sqrt(s2 / nd - (s / nd) * (s / nd)) : 0.0};
}

TEST(SnrModel, VelocitySigmaAtOneHundredMetresIsAtLeastThreeTimesThatAtTen) {
  const WallStats near = measure_wall(10.0, 0.1f);
  const WallStats far = measure_wall(100.0, 0.1f);
  ASSERT_GT(far.detected, 0.5);  // enough returns to measure a sigma
  std::printf("10 %% wall: sigma_v %.4f m/s at 10 m, %.4f m/s at 100 m (ratio %.2f)\n", near.sigma_v, far.sigma_v,
              far.sigma_v / near.sigma_v);
  // The law: sigma ~ 1 / sqrt(SNR) ~ R, so about 10x (incidence is the same within 4 deg).
  EXPECT_GE(far.sigma_v, 3.0 * near.sigma_v) << near.sigma_v << " at 10 m, " << far.sigma_v << " at 100 m";
  EXPECT_NEAR(far.sigma_v / near.sigma_v, 10.0, 1.5);
  // Above the floor at 10 m for a 10 % wall: Table I's 0.031 m/s scaled by sqrt(SNR_ref / SNR).
  const MeasurementModel model(snr_params().measurement);
  EXPECT_NEAR(near.sigma_v, model.sigmas(model.snr_linear(10.0, 0.1, 1.0)).velocity_mps, 0.1 * near.sigma_v);
}

TEST(SnrModel, DropoutsRiseWithRangeAndWithDarkness) {
  const double at_80 = measure_wall(80.0, 0.1f, 4).detected;
  const double at_150 = measure_wall(150.0, 0.1f, 4).detected;
  const double at_220 = measure_wall(220.0, 0.1f, 4).detected;
  EXPECT_GT(at_80, 0.95);
  EXPECT_GT(at_80, at_150 + 0.2);
  EXPECT_GT(at_150, at_220 + 0.2);
  EXPECT_NEAR(at_150, 0.5, 0.1);  // a 10 % target is seen half the time at 150 m, by construction
  const double bright = measure_wall(150.0, 0.5f, 4).detected;
  const double dark = measure_wall(150.0, 0.03f, 4).detected;
  std::printf("detected, 10 %% wall: %.3f at 80 m, %.3f at 150 m, %.3f at 220 m; at 150 m: 50 %% %.3f, 3 %% %.3f\n", at_80,
              at_150, at_220, bright, dark);
  EXPECT_GT(bright, at_150 + 0.2);
  EXPECT_GT(at_150, dark + 0.2);
}

TEST(SnrModel, SameSeedGivesIdenticalFramesWithOneOrTwoThreads) {
  LidarSimulator one = wall_sim(150.0, 0.1f, 1);
  LidarSimulator two = wall_sim(150.0, 0.1f, 2);
  for (std::uint64_t k = 0; k < 2; ++k) {
    const core::Frame a = one.simulate(k, 0.1 * static_cast<double>(k));
    const core::Frame b = two.simulate(k, 0.1 * static_cast<double>(k));
    EXPECT_EQ(a.scan.valid, b.scan.valid);
    EXPECT_EQ(0, std::memcmp(a.scan.radial_velocity_mps.data(), b.scan.radial_velocity_mps.data(),
                             a.scan.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(a.scan.range_m.data(), b.scan.range_m.data(), a.scan.size() * sizeof(float)));
  }
  // And the same seed gives the same dropouts run after run.
  LidarSimulator again = wall_sim(150.0, 0.1f, 2);
  EXPECT_EQ(again.simulate(0, 0.0).scan.valid, one.simulate(0, 0.0).scan.valid);
}

TEST(SnrModel, DetectionProbabilityAndSigmasFollowTheDocumentedCurve) {
  MeasurementParams p;
  p.model = MeasurementParams::Model::kSnr;
  const MeasurementModel m(p);
  const auto db = [](double x) { return std::pow(10.0, x / 10.0); };
  EXPECT_NEAR(m.detection_probability(db(11.2)), 0.5, 1e-12);
  EXPECT_NEAR(m.detection_probability(db(7.8)), 0.06, 0.04);   // Albersheim: 0.1
  EXPECT_NEAR(m.detection_probability(db(13.1)), 0.83, 0.08);  // Albersheim: 0.9
  EXPECT_EQ(m.detection_probability(0.0), 0.0);
  // Table I's sigmas at sigma_reference_db, floors for strong returns.
  EXPECT_NEAR(m.sigmas(db(20.0)).velocity_mps, 0.031, 1e-12);
  EXPECT_NEAR(m.sigmas(db(20.0)).range_m, 0.025, 1e-12);
  EXPECT_EQ(m.sigmas(db(80.0)).velocity_mps, p.snr.velocity_sigma_floor_mps);
  // The lidar equation: 4x the range is 1/16 the SNR; edge-on is nothing.
  EXPECT_NEAR(m.snr_linear(40.0, 0.1, 1.0) / m.snr_linear(10.0, 0.1, 1.0), 1.0 / 16.0, 1e-12);
  EXPECT_NEAR(m.snr_linear(10.0, 0.1, 0.5) / m.snr_linear(10.0, 0.1, 1.0), 0.5, 1e-12);
  EXPECT_EQ(m.snr_linear(10.0, 0.1, 0.0), 0.0);
  p.snr.detection_width_db = 0.0;
  EXPECT_THROW(p.validate(), core::InputError);
}

}  // namespace
}  // namespace fmcw::sim
