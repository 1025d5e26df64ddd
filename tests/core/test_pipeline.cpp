#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fmcw/core/check.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "scenes.hpp"

namespace fmcw::core {
namespace {

TEST(MotionPipeline, StaticWorldEgoVelocityExactWithoutNoise) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.ego_velocity_mps = {12.0, -0.8, 0.2};
  const Frame frame = render_synthetic_scan(p);
  for (const std::string method : {"fast", "paper"}) {
    MotionPipeline pipeline(MotionPipelineParams::preset(method));
    const MotionEstimate est = pipeline.process(frame.scan);
    ASSERT_TRUE(est.ok()) << est.message;
    ASSERT_TRUE(est.ego.valid);
    // Positions and Doppler are stored as float32, so "exact" means to float rounding.
    EXPECT_LT((est.ego.velocity_mps - p.ego_velocity_mps).cwiseAbs().maxCoeff(), 1e-6) << method;
    EXPECT_EQ(est.clusters.size(), 0u) << method;
  }
}

TEST(MotionPipeline, EgoVelocityWithinOneCmPerSecondAtTableINoise) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.ego_velocity_mps = {15.0, 1.0, 0.0};
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    p.seed = seed;
    const Frame frame = render_synthetic_scan(p);
    for (const std::string method : {"fast", "paper"}) {
      const MotionEstimate est = MotionPipeline(MotionPipelineParams::preset(method)).process(frame.scan);
      ASSERT_TRUE(est.ego.valid);
      const Eigen::Vector3d err = est.ego.velocity_mps - p.ego_velocity_mps;
      EXPECT_LT(std::abs(err.x()), 0.01) << method << " seed " << seed;
      EXPECT_LT(std::abs(err.y()), 0.01) << method << " seed " << seed;
      EXPECT_LT(std::abs(err.z()), 0.03) << method << " seed " << seed;
    }
  }
}

TEST(MotionPipeline, EgoUsesEachHeadsOwnOrigin) {
  // A yawing rig: each head's origin moves at V + omega x r_mount. The paper's model (one
  // velocity for all heads) cannot fit it exactly, but with omega = 0 and heads at different
  // mounts the estimate must be exact, which it would not be if e_i were taken from the rig
  // origin instead of the beam origin.
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.ego_velocity_mps = {8.0, 0.0, 0.0};
  const Frame frame = render_synthetic_scan(p);
  Scan wrong = frame.scan;
  for (auto& head : wrong.heads) head.T_rig_head.translation().setZero();
  const MotionEstimate good = MotionPipeline(MotionPipelineParams::preset("fast")).process(frame.scan);
  const MotionEstimate bad = MotionPipeline(MotionPipelineParams::preset("fast")).process(wrong);
  EXPECT_LT((good.ego.velocity_mps - p.ego_velocity_mps).norm(), 1e-6);
  EXPECT_GT((bad.ego.velocity_mps - p.ego_velocity_mps).norm(), 1e-3);
}

SyntheticSceneParams moving_box_scene() {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.ego_velocity_mps = {5.0, 0.0, 0.0};
  SyntheticBox car;
  car.center_m = {18.0, -3.0, 0.75};
  car.half_extent_m = {2.25, 0.9, 0.75};
  car.yaw_rad = 0.4;
  car.velocity_mps = {-6.0, 2.5, 0.0};
  p.actors = {car};
  return p;
}

TEST(MotionPipeline, MovingBoxIsOneClusterWithItsVelocityExactWithoutNoise) {
  const SyntheticSceneParams p = moving_box_scene();
  const Frame frame = render_synthetic_scan(p);
  for (const std::string method : {"fast", "paper"}) {
    const MotionEstimate est = MotionPipeline(MotionPipelineParams::preset(method)).process(frame.scan);
    ASSERT_TRUE(est.ok());
    ASSERT_EQ(est.clusters.size(), 1u) << method;
    const ClusterEstimate& c = est.clusters[0];
    ASSERT_TRUE(c.velocity.valid);
    EXPECT_LT((c.velocity.velocity_mps - p.actors[0].velocity_mps).cwiseAbs().maxCoeff(), 1e-6) << method;
    // Every car pixel carries the cluster's label.
    int car_pixels = 0;
    for (std::size_t i = 0; i < frame.scan.size(); ++i) {
      if (frame.truth->instance[i] == 1) {
        ++car_pixels;
        EXPECT_EQ(est.labels[i], c.id);
      }
    }
    EXPECT_EQ(c.num_pixels, car_pixels);
    if (method == "paper") {
      EXPECT_EQ(c.velocity.num_points, 200);
    }
    EXPECT_NEAR(c.centroid_m.x(), 18.0, 2.5);
  }
}

TEST(MotionPipeline, PaperAndFastAgreeOnTheSamePoints) {
  SyntheticSceneParams p = moving_box_scene();
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  p.seed = 3;
  const Frame frame = render_synthetic_scan(p);
  MotionPipelineParams ceres = MotionPipelineParams::preset("paper");
  MotionPipelineParams fast = MotionPipelineParams::preset("fast");
  fast.velocity.ego_max_points = ceres.velocity.ego_max_points;
  fast.velocity.object_max_points = ceres.velocity.object_max_points;
  const MotionEstimate a = MotionPipeline(ceres).process(frame.scan, 4);
  const MotionEstimate b = MotionPipeline(fast).process(frame.scan, 4);
  EXPECT_LT((a.ego.velocity_mps - b.ego.velocity_mps).cwiseAbs().maxCoeff(), 1e-6);
  ASSERT_EQ(a.clusters.size(), b.clusters.size());
  for (std::size_t k = 0; k < a.clusters.size(); ++k) {
    EXPECT_LT((a.clusters[k].velocity.velocity_mps - b.clusters[k].velocity.velocity_mps).cwiseAbs().maxCoeff(), 1e-6);
  }
}

class ThreadCount : public ::testing::TestWithParam<std::string> {};

TEST_P(ThreadCount, SerialAndParallelGiveIdenticalResults) {
  // Enough clusters that every method solves them on two threads: `fast` goes parallel from
  // 256 clusters on, `paper` from 2.
  const Frame frame = render_synthetic_scan(fmcw::test::crowded_courtyard());
  MotionPipelineParams serial = MotionPipelineParams::preset(GetParam());
  serial.num_threads = 1;
  serial.seed = 99;
  MotionPipelineParams parallel = serial;
  parallel.num_threads = 2;
  const MotionEstimate a = MotionPipeline(serial).process(frame.scan, 7);
  const MotionEstimate b = MotionPipeline(parallel).process(frame.scan, 7);
  ASSERT_TRUE(a.ok()) << a.message;
  EXPECT_EQ(a.labels, b.labels);
  ASSERT_EQ(a.clusters.size(), b.clusters.size());
  ASSERT_GE(a.clusters.size(), 256u);
  EXPECT_EQ(a.ego.velocity_mps, b.ego.velocity_mps);
  for (std::size_t k = 0; k < a.clusters.size(); ++k) {
    // Bitwise equal, NaN (too few points) included.
    EXPECT_EQ(0, std::memcmp(a.clusters[k].velocity.velocity_mps.data(), b.clusters[k].velocity.velocity_mps.data(),
                             3 * sizeof(double)));
  }
  // Another frame index draws another subsample for the paper's capped solves.
  const MotionEstimate c = MotionPipeline(serial).process(frame.scan, 8);
  if (GetParam() == "paper") {
    EXPECT_NE(a.ego.velocity_mps, c.ego.velocity_mps);
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, ThreadCount, ::testing::Values("fast", "paper"));

TEST(MotionPipeline, ManyClustersGiveIdenticalResultsWithOneOrTwoThreads) {
  // A wall of 4 x 4 pixel tiles, every other tile moving at its own velocity: hundreds of
  // clusters, enough for the closed form to solve them in parallel.
  Scan scan = Scan::make_empty(120, 160);
  for (int r = 0; r < scan.rows; ++r) {
    for (int c = 0; c < scan.cols; ++c) {
      const std::size_t i = scan.index(r, c);
      const double az = (80 - c) * 0.004, el = (60 - r) * 0.004;
      const Eigen::Vector3d e(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const double range = 20.0 / e.x();
      const int tile = (r / 4) * 40 + c / 4;
      const bool moving = ((r / 4) + (c / 4)) % 2 == 1;
      const Eigen::Vector3d v = moving ? Eigen::Vector3d(1.0 + 0.37 * (tile % 11), 0.5 * (tile % 5), 0.0) : Eigen::Vector3d::Zero();
      scan.x_m[i] = static_cast<float>(range * e.x());
      scan.y_m[i] = static_cast<float>(range * e.y());
      scan.z_m[i] = static_cast<float>(range * e.z());
      scan.range_m[i] = static_cast<float>(range);
      scan.radial_velocity_mps[i] = static_cast<float>(e.dot(v) + 3.0 * e.x());  // ego at -3 m/s along x
      scan.intensity[i] = 1.0f;
      scan.valid[i] = 1;
    }
  }
  MotionPipelineParams one = MotionPipelineParams::preset("fast");
  one.num_threads = 1;
  MotionPipelineParams two = one;
  two.num_threads = 2;
  const MotionEstimate a = MotionPipeline(one).process(scan);
  const MotionEstimate b = MotionPipeline(two).process(scan);
  ASSERT_GE(a.clusters.size(), 256u);
  ASSERT_EQ(a.clusters.size(), b.clusters.size());
  for (std::size_t k = 0; k < a.clusters.size(); ++k) {
    EXPECT_EQ(0, std::memcmp(a.clusters[k].velocity.velocity_mps.data(), b.clusters[k].velocity.velocity_mps.data(),
                             3 * sizeof(double)));
  }
}

TEST(MotionPipeline, EmptyAndAllInvalidScansGiveDocumentedStatus) {
  MotionPipeline pipeline;
  Scan invalid = Scan::make_empty(10, 12);
  const MotionEstimate est = pipeline.process(invalid);
  EXPECT_EQ(est.status, MotionStatus::kNoValidPoints);
  EXPECT_FALSE(est.ego.valid);
  EXPECT_TRUE(est.clusters.empty());
  EXPECT_EQ(est.labels.size(), 120u);

  Scan empty = Scan::make_empty(0, 0);
  empty.heads.clear();
  EXPECT_EQ(pipeline.process(empty).status, MotionStatus::kNoValidPoints);
}

TEST(MotionPipeline, FewerThanThreeStaticPointsIsAStatusNotACrash) {
  Scan scan = Scan::make_empty(1, 2);
  for (int i = 0; i < 2; ++i) {
    scan.x_m[i] = 10.0f;
    scan.y_m[i] = static_cast<float>(i);
    scan.z_m[i] = 0.0f;
    scan.range_m[i] = 10.0f;
    scan.radial_velocity_mps[i] = -1.0f;
    scan.valid[i] = 1;
  }
  const MotionEstimate est = MotionPipeline(MotionPipelineParams::preset("fast")).process(scan);
  EXPECT_EQ(est.status, MotionStatus::kTooFewStaticPoints);
  EXPECT_NE(est.message.find("2 static points"), std::string::npos) << est.message;
  EXPECT_FALSE(est.ego.valid);
}

// Every return moving, each at its own velocity (a swarm, or a sensor fault): no set of points
// agrees on one ego motion, so no method may report one.
TEST(MotionPipeline, ScanWithEveryPointMovingGivesTheStatusNotAnEgoVelocity) {
  Frame frame = render_synthetic_scan(fmcw::test::static_courtyard());
  std::uint64_t state = 12345;
  for (std::size_t i = 0; i < frame.scan.size(); ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;  // LCG: reproducible
    frame.scan.radial_velocity_mps[i] = static_cast<float>(static_cast<double>(state >> 11) / 9007199254740992.0 * 40.0 - 20.0);
  }
  for (const std::string& method : MotionPipelineParams::preset_names()) {
    const MotionEstimate est = MotionPipeline(MotionPipelineParams::preset(method)).process(frame.scan);
    EXPECT_EQ(est.status, MotionStatus::kTooFewStaticPoints) << method << ": " << est.message << " ego "
                                                             << est.ego.velocity_mps.transpose();
    EXPECT_NE(est.message.find("ego velocity not estimable"), std::string::npos) << method << ": " << est.message;
    EXPECT_FALSE(est.ego.valid) << method;
  }
}

TEST(MotionPipeline, NaNVelocityInAValidPixelIsRejectedWithItsPixel) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  Frame frame = render_synthetic_scan(p);
  const std::size_t i = frame.scan.index(100, 37);
  ASSERT_TRUE(frame.scan.valid[i]);
  frame.scan.radial_velocity_mps[i] = std::nanf("");
  try {
    MotionPipeline(MotionPipelineParams::preset("fast")).process(frame.scan);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("row 100, col 37"), std::string::npos) << e.what();
  }
}

// A stamp that is not a finite time would make every frame interval NaN, and the tracker
// start over quietly at each frame: every method refuses the scan, naming the stamp.
TEST(MotionPipeline, StampThatIsNotFiniteIsRejected) {
  Frame frame = render_synthetic_scan(fmcw::test::static_courtyard());
  for (const double stamp : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    frame.scan.stamp_s = stamp;
    for (const std::string& method : MotionPipelineParams::preset_names()) {
      try {
        MotionPipeline(MotionPipelineParams::preset(method)).process(frame.scan);
        ADD_FAILURE() << method << ": expected std::invalid_argument for stamp " << stamp;
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(concat("scan: stamp_s is ", stamp, ", expected a finite time [s]")),
                  std::string::npos)
            << method << ": " << e.what();
      }
    }
  }
}

TEST(MotionPipeline, MismatchedArraysAreRejected) {
  Scan scan = Scan::make_empty(3, 3);
  scan.radial_velocity_mps.pop_back();
  try {
    MotionPipeline(MotionPipelineParams::preset("fast")).process(scan);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'v' has 8 values, expected rows*cols = 9"), std::string::npos) << e.what();
  }
}

TEST(MotionPipelineParams, UnknownMethodNamesTheKnownOnes) {
  try {
    MotionPipelineParams::preset("magic");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown method 'magic' (known: paper, fast, robust, tracked)"), std::string::npos);
  }
  MotionPipelineParams bad;
  bad.segmentation.velocity_threshold_mps = -1.0;
  EXPECT_THROW(MotionPipeline{bad}, std::invalid_argument);
}

TEST(MotionPipelineParams, TheEgoPriorsBoundsAreChecked) {
  const std::vector<std::pair<std::function<void(TwistPriorParams&)>, std::string>> cases = {
      {[](TwistPriorParams& p) { p.accel_mps2 = 0.0; }, "ego prior: accel_mps2 must be > 0, got 0"},
      {[](TwistPriorParams& p) { p.velocity_margin_mps = -0.1; },
       "ego prior: velocity_margin_mps must be >= 0, got -0.1"},
      {[](TwistPriorParams& p) { p.yaw_accel_rps2 = -2.0; },
       "ego prior: yaw_accel_rps2 must be > 0, got -2"},
      {[](TwistPriorParams& p) { p.yaw_rate_margin_rps = -1.0; },
       "ego prior: yaw_rate_margin_rps must be >= 0, got -1"},
      {[](TwistPriorParams& p) { p.fallback_max_windows = -1.0; },
       "ego prior: fallback_max_windows must be finite and >= 0 (0 = no bound), got -1"},
      {[](TwistPriorParams& p) {
         p.fallback_max_windows = std::numeric_limits<double>::quiet_NaN();
       },
       "ego prior: fallback_max_windows must be finite and >= 0 (0 = no bound), got nan"},
  };
  for (const auto& [set, expected] : cases) {
    MotionPipelineParams params = MotionPipelineParams::preset("tracked");
    set(params.ego_prior);
    try {
      MotionPipeline{params};
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace fmcw::core

namespace fmcw::core {
namespace {

// paper and fast keep the published fit, but a velocity its covariance calls meaningless is
// not valid: a cluster of 3 pixels or fewer has no covariance (RSS / (n - 3)).
TEST(MotionPipeline, PaperAndFastFlagTinyClustersNotValid) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  p.ego_velocity_mps = {5.0, 0.0, 0.0};
  // Thin poles moving across the view far away: a few pixels each.
  for (int k = 0; k < 6; ++k) {
    SyntheticBox pole;
    pole.center_m = Eigen::Vector3d(18.0 + 1.5 * k, -6.0 + 2.5 * k, 1.0);
    pole.half_extent_m = Eigen::Vector3d(0.02, 0.02, 0.05 + 0.03 * k);
    pole.velocity_mps = Eigen::Vector3d(0.0, 3.0, 0.0);
    p.actors.push_back(pole);
  }
  SyntheticBox car;  // and one object large enough to measure
  car.center_m = Eigen::Vector3d(12.0, 4.0, 0.9);
  car.half_extent_m = Eigen::Vector3d(2.2, 0.9, 0.75);
  car.velocity_mps = Eigen::Vector3d(-6.0, 0.0, 0.0);
  p.actors.push_back(car);
  const Frame frame = render_synthetic_scan(p);
  for (const std::string method : {"paper", "fast"}) {
    SCOPED_TRACE(method);
    MotionPipeline pipeline(MotionPipelineParams::preset(method));
    const MotionEstimate est = pipeline.process(frame.scan);
    ASSERT_TRUE(est.ok()) << est.message;
    int tiny = 0, large_valid = 0;
    for (const ClusterEstimate& c : est.clusters) {
      if (c.num_pixels <= 3) {
        ++tiny;
        EXPECT_FALSE(c.velocity.valid) << c.num_pixels << " pixels, " << c.velocity.velocity_mps.transpose();
      }
      if (c.num_pixels >= 200 && c.velocity.valid) {
        ++large_valid;
        EXPECT_LT((c.velocity.velocity_mps - car.velocity_mps).norm(), 1e-3);
      }
      if (c.velocity.valid) {
        EXPECT_LE(c.velocity.velocity_mps.norm(), kMaxPlausibleSpeedMps);
      }
    }
    EXPECT_GT(tiny, 0) << "the scene must hold clusters of 3 pixels or fewer";
    EXPECT_EQ(large_valid, 1);
  }
}

TEST(FlagMeaningless, NoCovarianceAWideOneOrAnAbsurdSpeedIsNotValid) {
  VelocityEstimate e;
  e.valid = true;
  e.velocity_mps = {1.0, 2.0, 0.0};
  e.covariance = Eigen::Matrix3d::Identity() * 0.01;
  VelocityEstimate ok = e;
  flag_meaningless(ok, 10.0);
  EXPECT_TRUE(ok.valid);
  VelocityEstimate wide = e;
  wide.covariance(2, 2) = 200.0;  // sigma 14 m/s on z
  flag_meaningless(wide, 10.0);
  EXPECT_FALSE(wide.valid);
  VelocityEstimate none = e;
  none.covariance.setConstant(std::nan(""));
  flag_meaningless(none, 10.0);
  EXPECT_FALSE(none.valid);
  VelocityEstimate fast = e;
  fast.velocity_mps = {2e6, 0.0, 0.0};
  flag_meaningless(fast, 1e9);
  EXPECT_FALSE(fast.valid);
}

}  // namespace
}  // namespace fmcw::core
