// The robust method on analytic scans: ego twist with yaw rate, standing test, a vehicle that
// fills most of the view, instances, and object velocities robust to limbs.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include "fmcw/core/head_model.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "fmcw/core/velocity_lsq.hpp"
#include "scenes.hpp"

namespace fmcw::core {
namespace {

MotionEstimate robust(const Scan& scan) { return MotionPipeline(MotionPipelineParams::preset("robust")).process(scan); }

// A street: ground, 10 m buildings on both sides (their faces wall_y_m - 1 from the middle) and
// 60 m ahead, sky above.
SyntheticSceneParams street_scene(double wall_y_m) {
  SyntheticSceneParams p;
  for (const auto& [center, half] :
       {std::pair<Eigen::Vector3d, Eigen::Vector3d>{{61, 0, 5}, {1, 80, 5}},
        {{0, wall_y_m, 5}, {80, 1, 5}},
        {{0, -wall_y_m, 5}, {80, 1, 5}}}) {
    SyntheticBox wall;
    wall.center_m = center;
    wall.half_extent_m = half;
    p.static_boxes.push_back(wall);
  }
  return p;
}

TEST(EgoTwist, RecoversVelocityAndYawRateFromHeadsAtDifferentMounts) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.ego_velocity_mps = {9.0, 0.3, 0.0};
  p.ego_angular_velocity_rps = {0.0, 0.0, 0.4};  // turning at 23 deg/s
  const Frame exact = render_synthetic_scan(p);
  const EgoTwistEstimate t = estimate_ego_twist(exact.scan, EgoTwistParams{}, 1);
  ASSERT_TRUE(t.valid);
  ASSERT_TRUE(t.yaw_rate_estimated);
  EXPECT_LT((t.velocity.velocity_mps - p.ego_velocity_mps).norm(), 1e-4);
  EXPECT_NEAR(t.angular_velocity_rps.z(), 0.4, 1e-4);
  EXPECT_FALSE(t.standing);
  // At Table I noise the yaw rate stays within 0.5 deg/s, and its reported sigma is honest.
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    p.seed = seed;
    const EgoTwistEstimate n = estimate_ego_twist(render_synthetic_scan(p).scan, EgoTwistParams{}, seed);
    EXPECT_LT(std::abs(n.angular_velocity_rps.z() - 0.4) * 180.0 / M_PI, 0.5) << "seed " << seed;
    EXPECT_LT(std::abs(n.angular_velocity_rps.z() - 0.4), 5.0 * n.yaw_rate_std_rps + 1e-4);
    EXPECT_LT(std::abs(n.velocity.velocity_mps.y() - 0.3), 0.01);
  }
  // The paper's model (one velocity for every head) cannot fit the turning rig.
  const MotionEstimate paper = MotionPipeline(MotionPipelineParams::preset("fast")).process(exact.scan);
  EXPECT_GT((paper.ego.velocity_mps - p.ego_velocity_mps).norm(), 0.05);
}

TEST(EgoTwist, ALateralPullSettlesWhatTheWorldAheadLeavesOpen) {
  // The rig drives straight at 10 m/s; the static world is a wall 40 m ahead, seen by the front
  // head only. Its rows fix V_x and V_y + 1.4 m * omega (the front head's mount), not the two
  // apart. The previous frame's twist (the prior of tracking) carries a yaw-rate error of
  // 0.02 rad/s; the pull towards it keeps that error, the lateral pull removes it.
  SyntheticSceneParams p;
  p.ground = false;
  SyntheticBox wall;
  wall.center_m = {40.0, 0.0, 2.0};
  wall.half_extent_m = {0.5, 6.0, 3.0};
  p.static_boxes = {wall};
  p.ego_velocity_mps = {10.0, 0.0, 0.0};
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  TwistPrior prior;
  prior.velocity_mps = {10.0, -0.028, 0.0};  // consistent with the wall: V_y + 1.4 omega = 0
  prior.yaw_rate_rps = 0.02;
  prior.max_velocity_change_mps = 1.1;
  prior.max_yaw_rate_change_rps = 0.3;
  EgoTwistParams pull;
  pull.lateral_velocity_sigma_mps = 0.1;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    p.seed = seed;
    const Scan scan = render_synthetic_scan(p).scan;
    const EgoTwistEstimate free = estimate_ego_twist(scan, EgoTwistParams{}, seed, &prior);
    const EgoTwistEstimate pulled = estimate_ego_twist(scan, pull, seed, &prior);
    ASSERT_TRUE(free.valid && pulled.valid) << "seed " << seed;
    EXPECT_GT(std::abs(free.angular_velocity_rps.z()), 0.01) << "seed " << seed;
    EXPECT_LT(std::abs(pulled.angular_velocity_rps.z()), 0.005) << "seed " << seed;
    EXPECT_LT(std::abs(pulled.velocity.velocity_mps.y()), 0.007) << "seed " << seed;
    EXPECT_NEAR(pulled.velocity.velocity_mps.x(), 10.0, 0.01) << "seed " << seed;
  }
}

TEST(EgoTwist, StandingRigIsDetectedAndReportsExactlyZero) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  SyntheticBox car;
  car.center_m = {15.0, 3.0, 0.75};
  car.half_extent_m = {2.25, 0.9, 0.75};
  car.velocity_mps = {-7.0, 0.0, 0.0};
  p.actors = {car};
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  p.seed = 4;
  const MotionEstimate est = robust(render_synthetic_scan(p).scan);
  ASSERT_TRUE(est.ok());
  EXPECT_TRUE(est.ego_standing);
  EXPECT_EQ(est.ego.velocity_mps, Eigen::Vector3d::Zero());
  ASSERT_EQ(est.clusters.size(), 1u);
  EXPECT_NEAR(est.clusters[0].velocity.velocity_mps.x(), -7.0, 0.05);
}

TEST(RobustMethod, VehicleFillingMostOfTheViewDoesNotFoolTheEgoEstimate) {
  // A bus overtakes close beside the rig and fills more of the image than the static world: the
  // paper's "largest region is static" takes the bus for the world; MSAC scored by the azimuths
  // its inliers cover does not (the world still shows across the rest of the view).
  SyntheticSceneParams p = street_scene(26.0);
  p.ego_velocity_mps = {5.0, 0.0, 0.0};
  SyntheticBox bus;  // a truck and trailer, 28 m long, 4 m tall, 1.1 m to the left of the rig
  bus.center_m = {11.0, 2.3, 2.0};
  bus.half_extent_m = {14.0, 1.2, 2.0};
  bus.velocity_mps = {10.0, 0.0, 0.0};
  p.actors = {bus};
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  p.seed = 2;
  const Frame frame = render_synthetic_scan(p);
  std::size_t bus_pixels = 0, valid = 0;
  for (std::size_t i = 0; i < frame.scan.size(); ++i) {
    valid += frame.scan.valid[i];
    bus_pixels += frame.truth->instance[i] == 1;
  }
  ASSERT_GT(bus_pixels, valid / 2) << "the bus must fill most of the view for this test";
  const MotionEstimate paper = MotionPipeline(MotionPipelineParams::preset("fast")).process(frame.scan);
  EXPECT_GT((paper.ego.velocity_mps - p.ego_velocity_mps).norm(), 1.0) << "the paper's method is fooled";
  const MotionEstimate est = robust(frame.scan);
  EXPECT_LT((est.ego.velocity_mps - p.ego_velocity_mps).norm(), 0.02);
  int bus_labelled_moving = 0;
  for (std::size_t i = 0; i < frame.scan.size(); ++i) bus_labelled_moving += frame.truth->instance[i] == 1 && est.labels[i] > 0;
  EXPECT_GT(bus_labelled_moving, static_cast<int>(0.95 * static_cast<double>(bus_pixels)));
}

TEST(TrackedMethod, TrafficThatFillsTheViewAfterTheWorldIsNotTakenForTheWorld) {
  // The rig drives at 10 m/s down a street (frames 0-2, 10 Hz); then oncoming traffic at 12 m/s
  // fills every beam that returns (frames 3-5: a wall of vehicles ahead, no ground, nothing
  // static in view); then the street again (frame 6). The traffic is static to a rig driving at
  // 22 m/s: a scan alone says that, the last twist says it cannot be.
  SyntheticSceneParams street = street_scene(12.0);
  street.ego_velocity_mps = {10.0, 0.0, 0.0};
  street.velocity_noise_mps = 0.031;
  street.range_noise_m = 0.025;
  SyntheticSceneParams traffic = street;
  traffic.ground = false;
  traffic.static_boxes.clear();
  SyntheticBox lorries;
  lorries.center_m = {19.0, 0.0, 4.0};
  lorries.half_extent_m = {11.0, 20.0, 5.0};
  lorries.velocity_mps = {-12.0, 0.0, 0.0};
  traffic.actors = {lorries};
  // Per frame: W the street's ego (10 m/s), T the traffic taken for the world (22 m/s), R no
  // ego velocity: the fit without the window's bound was rejected.
  struct Case {
    double windows;
    bool hold;
    const char* expected;
  };
  // Without the bound, the traffic is the world. Without the hold, the bound guards one frame;
  // the next, with no last twist, takes the traffic, and bounds the street's return against it.
  for (const Case c :
       {Case{3.0, true, "WWWRRRW"}, Case{0.0, true, "WWWTTTW"}, Case{3.0, false, "WWWRTTR"}}) {
    MotionPipelineParams params = MotionPipelineParams::preset("tracked");
    params.ego_prior.fallback_max_windows = c.windows;
    params.ego_prior.hold_across_failures = c.hold;
    MotionPipeline tracked(params);
    for (int k = 0; k <= 6; ++k) {
      const bool in_traffic = k >= 3 && k <= 5;
      SyntheticSceneParams p = in_traffic ? traffic : street;
      p.seed = static_cast<std::uint64_t>(k + 1);
      Scan scan = render_synthetic_scan(p).scan;
      scan.stamp_s = 0.1 * k;
      const MotionEstimate est = tracked.process(scan, static_cast<std::uint64_t>(k));
      const std::string what = "fallback_max_windows " + std::to_string(c.windows) + ", hold " +
                               std::to_string(c.hold) + ", frame " + std::to_string(k) + ": " +
                               est.message;
      const Eigen::Vector3d seen =
          in_traffic ? Eigen::Vector3d(22.0, 0.0, 0.0) : street.ego_velocity_mps;
      if (c.expected[k] != 'R') {
        ASSERT_TRUE(est.ok()) << what;
        EXPECT_LT((est.ego.velocity_mps - seen).norm(), 0.05)
            << what << " ego " << est.ego.velocity_mps.transpose();
        EXPECT_EQ(c.expected[k] == 'T', in_traffic) << what;
        continue;
      }
      EXPECT_EQ(est.status, MotionStatus::kTooFewStaticPoints) << what;
      EXPECT_FALSE(est.ego.valid) << what;
      EXPECT_NE(est.message.find(std::string("the fit without that bound (") +
                                 (in_traffic ? "22.0" : "10.0")),
                std::string::npos)
          << what;
      EXPECT_NE(est.message.find("taken for traffic filling the view"), std::string::npos) << what;
    }
  }
}

TEST(RobustMethod, CarsSideBySideAtOneSpeedAreTwoInstancesAndATouchingPartStaysWithItsBody) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  // Van-height boxes: their roofs are above the sensors (a roof seen edge-on from just above
  // breaks into strips metres apart in range, a separate matter).
  SyntheticBox a;
  a.center_m = {18.0, -1.6, 0.95};
  a.half_extent_m = {2.25, 0.9, 0.95};
  a.velocity_mps = {-8.0, 0.0, 0.0};
  SyntheticBox b = a;
  b.center_m = {21.0, 2.0, 0.95};  // same speed, beside and behind: a range step between them
  // A "wheel" on car a: touching its side, moving differently (Doppler differs from the body's).
  SyntheticBox wheel;
  wheel.center_m = {17.0, -0.72, 0.35};  // 3 cm proud of the body's side
  wheel.half_extent_m = {0.35, 0.05, 0.35};
  wheel.velocity_mps = {-3.0, 0.0, 0.0};
  p.actors = {a, b, wheel};
  const Frame frame = render_synthetic_scan(p);
  const MotionEstimate est = robust(frame.scan);
  std::map<std::uint32_t, std::set<std::int32_t>> labels;
  for (std::size_t i = 0; i < frame.scan.size(); ++i) {
    if (frame.truth->instance[i] != 0 && frame.scan.valid[i]) labels[frame.truth->instance[i]].insert(est.labels[i]);
  }
  ASSERT_EQ(labels[1].size(), 1u);
  ASSERT_EQ(labels[2].size(), 1u);
  EXPECT_NE(*labels[1].begin(), *labels[2].begin()) << "two cars at one speed are two objects";
  EXPECT_GT(*labels[1].begin(), 0);
  ASSERT_FALSE(labels[3].empty()) << "the wheel must be visible for this test";
  EXPECT_EQ(labels[3], labels[1]) << "the wheel belongs to its car";
}

TEST(RobustMethod, AWalkerBehindAnotherIsASecondInstanceAndAGrazingSideStaysOne) {
  // Two walkers at one speed, the second 0.8 m further out along nearly the same beams, so the
  // first hides part of it: one range step between two flat runs, within the range gap that
  // keeps grazing surfaces whole. A bus 12 m long whose side the beams meet at about 85 degrees
  // (its range steps about 0.3 m from pixel to pixel along the row) must stay one object.
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  SyntheticBox near;
  near.center_m = {16.0, 0.0, 0.9};  // straight ahead: the boxes' flat sides are seen edge-on
  near.half_extent_m = {0.25, 0.3, 0.9};
  near.velocity_mps = {1.4, 0.0, 0.0};  // walking away, side by side in file
  SyntheticBox far = near;
  far.center_m = {16.8, 0.35, 0.8};  // shorter: box tops at one height would touch in range
  far.half_extent_m.z() = 0.8;
  SyntheticBox bus;
  bus.center_m = {20.0, -3.0, 1.5};
  bus.half_extent_m = {6.0, 1.25, 1.5};
  bus.velocity_mps = {6.0, 0.0, 0.0};
  p.actors = {near, far, bus};
  const Frame frame = render_synthetic_scan(p);
  const auto labels_of = [&](const MotionEstimate& est) {
    std::map<std::uint32_t, std::map<std::int32_t, int>> labels;
    for (std::size_t i = 0; i < frame.scan.size(); ++i) {
      if (frame.truth->instance[i] != 0 && frame.scan.valid[i]) ++labels[frame.truth->instance[i]][est.labels[i]];
    }
    return labels;
  };
  const auto main_label = [](const std::map<std::int32_t, int>& counts) {
    return std::max_element(counts.begin(), counts.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
  };
  auto labels = labels_of(robust(frame.scan));
  ASSERT_GT(labels[2].size(), 0u) << "the far walker must be visible for this test";
  EXPECT_GT(main_label(labels[1]), 0);
  EXPECT_GT(main_label(labels[2]), 0);
  EXPECT_NE(main_label(labels[1]), main_label(labels[2])) << "a walker behind another is a second object";
  EXPECT_EQ(labels[3].size(), 1u) << "the bus's grazing side stays one object";
  EXPECT_GT(main_label(labels[3]), 0);

  MotionPipelineParams without = MotionPipelineParams::preset("robust");
  without.instances.edge_flatness = 0.0;  // the range gap alone joins the two walkers
  labels = labels_of(MotionPipeline(without).process(frame.scan));
  EXPECT_EQ(main_label(labels[1]), main_label(labels[2]));
}

TEST(PlanarRobustVelocity, TorsoOutvotesSwingingLimbs) {
  // 300 points of a body moving at (1.2, -0.8); 30 % of them (limbs) move 2.5 m/s faster or
  // slower along x. Plain least squares is pulled off; the biweight fit is not.
  Rng rng(3);
  VelocityRows rows;
  const Eigen::Vector2d body(1.2, -0.8);
  for (int k = 0; k < 300; ++k) {
    const double az = -0.4 + 0.8 * rng.uniform();
    const double el = -0.05 + 0.1 * rng.uniform();
    const Eigen::Vector3d e(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    Eigen::Vector2d v = body;
    if (k % 10 < 3) v.x() += (k % 2 ? 2.5 : -1.5);
    rows.directions.push_back(e);
    rows.targets_mps.push_back(e.head<2>().dot(v) + 0.031 * rng.normal());
  }
  const VelocityEstimate plain = solve_velocity_planar(rows);
  const VelocityEstimate fit = solve_velocity_planar_robust(rows, 0.031);
  EXPECT_GT((plain.velocity_mps.head<2>() - body).norm(), 0.1);
  EXPECT_LT((fit.velocity_mps.head<2>() - body).norm(), 0.03);
  EXPECT_EQ(fit.velocity_mps.z(), 0.0);
  // Its covariance is the torso's: noise over the kept rows, not the limbs' spread.
  EXPECT_LT(std::sqrt(fit.covariance.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff()), 0.02);
  EXPECT_GT(std::sqrt(plain.covariance.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff()), 0.1);
}

// Rows of a body moving at v seen by n beams fanning over `spread` radians of azimuth around
// +x, with Doppler noise; every tenth row (a limb) 1.5 m/s faster along the beam.
VelocityRows fan_rows(const Eigen::Vector2d& v, int n, double spread, std::uint64_t seed) {
  Rng rng(seed);
  VelocityRows rows;
  for (int k = 0; k < n; ++k) {
    const double az = spread * (static_cast<double>(k) / std::max(n - 1, 1) - 0.5);
    const Eigen::Vector3d e(std::cos(az), std::sin(az), 0.0);
    rows.directions.push_back(e);
    rows.targets_mps.push_back(e.head<2>().dot(v) + 0.031 * rng.normal() + (k % 10 == 9 ? 1.5 : 0.0));
  }
  return rows;
}

TEST(PlanarRobustVelocity, AnUnobservedDirectionIsReportedAsZeroAndUnknown) {
  // Four beams within 0.3 deg: the lateral velocity is fitted to whatever the noise says.
  const Eigen::Vector2d v(-6.0, 1.5);
  VelocityEstimate narrow = solve_velocity_planar_robust(fan_rows(v, 4, 0.005, 7), 0.031);
  ASSERT_TRUE(narrow.valid);
  zero_unobserved_direction(narrow, 0.031, 0.5);
  EXPECT_NEAR(narrow.velocity_mps.x(), v.x(), 0.1);  // the radial part stays
  EXPECT_NEAR(narrow.velocity_mps.y(), 0.0, 0.01);   // the lateral part is not guessed
  EXPECT_GE(narrow.covariance(1, 1), 100.0);         // and says it is unknown
  // Forty beams over 30 deg observe both directions: nothing changes.
  VelocityEstimate wide = solve_velocity_planar_robust(fan_rows(v, 40, 0.5, 7), 0.031);
  const VelocityEstimate before = wide;
  zero_unobserved_direction(wide, 0.031, 0.5);
  EXPECT_EQ(wide.velocity_mps, before.velocity_mps);
  EXPECT_EQ(wide.covariance, before.covariance);
  EXPECT_LT((wide.velocity_mps.head<2>() - v).norm(), 0.1);
}

// The courtyard from an ego at 10 m/s, with a car 30 m ahead closing at 5 m/s, its Doppler noise
// as a coherent lidar's, which falls with the signal: sigma_of(range, height) [m/s].
template <class Sigma>
Frame scan_with_noise(std::uint64_t seed, Sigma sigma_of) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.ego_velocity_mps = {10.0, 0.0, 0.0};
  SyntheticBox car;
  car.center_m = {30.0, -3.0, 0.75};
  car.half_extent_m = {2.25, 0.9, 0.75};
  car.velocity_mps = {-5.0, 0.0, 0.0};
  p.actors = {car};
  Frame f = render_synthetic_scan(p);
  Rng rng(seed);
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (!f.scan.valid[i]) continue;
    const double sigma =
        sigma_of(static_cast<double>(f.scan.range_m[i]), static_cast<double>(f.scan.z_m[i]));
    f.scan.radial_velocity_mps[i] += static_cast<float>(sigma * rng.normal());
  }
  return f;
}

// Table I's 0.031 m/s to 15 m, in proportion to range beyond (0.08 m/s at 40 m); or that on the
// walls and three times as much on the ground beyond 15 m (a dark surface at a grazing angle),
// where a band's spread, mostly the walls', is less than the ground's.
double growing_with_range(double range_m, double) { return 0.031 * std::max(1.0, range_m / 15.0); }
double dark_ground(double range_m, double z_m) {
  return growing_with_range(range_m, z_m) * (z_m < 0.2 && range_m > 15.0 ? 3.0 : 1.0);
}

TEST(RobustMethod, NoiseThatGrowsWithRangeFindsNoMovingStaticWorld) {
  // The static world's residual spread per image row and range band stands for the sensor's
  // sigma where it exceeds the nominal (MotionPipelineParams::range_noise_band_m); with the
  // nominal sigma everywhere (the control), the far walls and ground show moving pixels in
  // clusters.
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const Frame f =
        seed <= 3 ? scan_with_noise(seed, growing_with_range) : scan_with_noise(seed, dark_ground);
    MotionPipelineParams off = MotionPipelineParams::preset("robust");
    off.range_noise_band_m = 0.0;
    const MotionEstimate adaptive = robust(f.scan);
    const MotionEstimate nominal = MotionPipeline(off).process(f.scan);
    ASSERT_TRUE(adaptive.ok() && nominal.ok()) << adaptive.message << nominal.message;
    const auto count = [&](const MotionEstimate& e, std::size_t& static_moving,
                           std::size_t& car_moving, std::size_t& car_pixels,
                           std::set<int>& clutter) {
      for (std::size_t i = 0; i < f.scan.size(); ++i) {
        if (!f.scan.valid[i]) continue;
        const bool moving = e.labels[i] > 0;
        if (f.truth->instance[i] == 0) {
          static_moving += moving ? 1 : 0;
          if (moving) clutter.insert(e.labels[i]);
        } else {
          ++car_pixels;
          car_moving += moving ? 1 : 0;
        }
      }
      for (std::size_t i = 0; i < f.scan.size(); ++i) {
        if (f.scan.valid[i] && f.truth->instance[i] != 0)
          clutter.erase(e.labels[i]);  // the car's own
      }
    };
    std::size_t a_static = 0, a_car = 0, n_static = 0, n_car = 0, car_pixels = 0, unused = 0;
    std::set<int> a_clutter, n_clutter;
    count(adaptive, a_static, a_car, car_pixels, a_clutter);
    count(nominal, n_static, n_car, unused, n_clutter);
    std::printf(
        "seed %d: static pixels found moving %zu (nominal sigma: %zu), clusters of them %zu (%zu); "
        "car %zu (%zu) of %zu\n",
        static_cast<int>(seed), a_static, n_static, a_clutter.size(), n_clutter.size(), a_car,
        n_car, car_pixels);
    ASSERT_GT(car_pixels, 100u);
    EXPECT_GE(n_clutter.size(), 300u) << "seed " << seed << ": the control finds little clutter";
    // Noise that follows range alone leaves none; a dark ground's leaves a few (under 1 % of
    // the control's).
    if (seed <= 3) {
      EXPECT_EQ(a_clutter.size(), 0u) << "seed " << seed;
    }
    EXPECT_LE(a_clutter.size() * 100, n_clutter.size()) << "seed " << seed;
    EXPECT_LE(a_static * 100, n_static) << "seed " << seed;
    EXPECT_EQ(a_car, car_pixels) << "seed " << seed;
    EXPECT_EQ(n_car, car_pixels) << "seed " << seed;
  }
}

// A wide head (60 deg) and a narrow one (20 deg) inside its view, 0.6 m apart on the roof, as
// the AevaScenes rig's front heads are; a car 15 m ahead and one 12 m to the left, 20 m ahead,
// both closing at 5 m/s, the ego at 10 m/s.
SyntheticSceneParams overlapping_heads_scene() {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.rig.heads.clear();
  for (const auto& [name, fov_deg, y] :
       {std::tuple{"wide", 60.0, 0.3}, std::tuple{"narrow", 20.0, -0.3}}) {
    HeadModel head;
    head.name = name;
    head.fov_horizontal_rad = fov_deg * M_PI / 180.0;
    head.T_rig_head.translation() = Eigen::Vector3d(1.4, y, 1.6);
    p.rig.heads.push_back(head);
  }
  p.ego_velocity_mps = {10.0, 0.0, 0.0};
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  SyntheticBox car;
  car.half_extent_m = {2.25, 0.9, 0.75};
  car.velocity_mps = {-5.0, 0.0, 0.0};
  car.center_m = {15.0, 0.5, 0.75};
  SyntheticBox other = car;
  other.center_m = {20.0, 12.0, 0.75};
  p.actors = {car, other};
  return p;
}

TEST(RobustMethod, ABodySeenByTwoHeadsWhoseViewsOverlapIsOneInstance) {
  // The car ahead is in both heads' views: two groups of pixels in two column spans, never
  // neighbours in the image. Joined by the space they share (InstanceParams::cross_head_share);
  // the car to the left, in the wide head's view alone, stays apart. Control: the rule off.
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SyntheticSceneParams p = overlapping_heads_scene();
    p.seed = seed;
    const Frame f = render_synthetic_scan(p);
    MotionPipelineParams off = MotionPipelineParams::preset("robust");
    off.instances.cross_head_share = 0.0;
    const MotionEstimate joined = robust(f.scan);
    const MotionEstimate apart = MotionPipeline(off).process(f.scan);
    ASSERT_TRUE(joined.ok() && apart.ok()) << joined.message << apart.message;
    // The instances holding each car's pixels, and the pixels of each car found moving.
    const auto instances_of = [&](const MotionEstimate& e, std::uint32_t actor,
                                  std::size_t& found) {
      std::set<int> labels;
      found = 0;
      for (std::size_t i = 0; i < f.scan.size(); ++i) {
        if (!f.scan.valid[i] || f.truth->instance[i] != actor || e.labels[i] < 1) continue;
        labels.insert(e.labels[i]);
        ++found;
      }
      return labels;
    };
    std::size_t found_joined = 0, found_apart = 0, found_other = 0, unused = 0;
    const std::set<int> ahead = instances_of(joined, 1, found_joined);
    const std::set<int> ahead_apart = instances_of(apart, 1, found_apart);
    const std::set<int> left = instances_of(joined, 2, found_other);
    EXPECT_EQ(instances_of(apart, 2, unused).size(), 1u) << "seed " << seed;
    std::printf(
        "seed %d: the car ahead in %zu instance(s), %zu without the rule; the car to the left in "
        "%zu\n",
        static_cast<int>(seed), ahead.size(), ahead_apart.size(), left.size());
    EXPECT_EQ(ahead_apart.size(), 2u)
        << "seed " << seed << ": the control does not see the car twice";
    EXPECT_EQ(ahead.size(), 1u) << "seed " << seed;
    EXPECT_EQ(found_joined, found_apart) << "seed " << seed;
    ASSERT_EQ(left.size(), 1u) << "seed " << seed;
    EXPECT_NE(*left.begin(), *ahead.begin()) << "seed " << seed;
    EXPECT_EQ(joined.clusters.size() + 1, apart.clusters.size()) << "seed " << seed;
    // The joined instance's velocity: the car's, from both heads' rows.
    const ClusterEstimate& car = joined.clusters[static_cast<std::size_t>(*ahead.begin() - 1)];
    EXPECT_NEAR(car.velocity.velocity_mps.x(), -5.0, 0.05) << "seed " << seed;
  }
}

}  // namespace
}  // namespace fmcw::core
