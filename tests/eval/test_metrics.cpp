// Metrics on hand-made cases with known answers: Eq. 23-25 counts, RMSE, medians, the >= 200
// points filter, target checks.

#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/eval/motion_confusion.hpp"
#include "fmcw/eval/run_summary.hpp"
#include "fmcw/eval/statistics.hpp"

namespace fmcw::eval {
namespace {

TEST(MotionConfusion, CountsValidPixelsWithMovingAsPositive) {
  // label:  static, cluster 1, unassigned, static, (no return), cluster 2
  const std::vector<std::int32_t> labels = {0, 1, -2, 0, -1, 2};
  const std::vector<std::uint8_t> moving = {0, 1, 1, 1, 1, 0};
  const std::vector<std::uint8_t> valid = {1, 1, 1, 1, 0, 1};
  const MotionConfusion c = count_motion(labels, moving, valid);
  EXPECT_EQ(c.tp, 2u);  // cluster 1 and the unassigned region on moving pixels
  EXPECT_EQ(c.fp, 1u);  // cluster 2 on a static pixel
  EXPECT_EQ(c.tn, 1u);
  EXPECT_EQ(c.fn, 1u);
  EXPECT_EQ(c.total(), 5u);  // the pixel without a return is not counted
  EXPECT_DOUBLE_EQ(c.precision(), 2.0 / 3.0);  // Eq. 23
  EXPECT_DOUBLE_EQ(c.recall(), 2.0 / 3.0);     // Eq. 24
  EXPECT_DOUBLE_EQ(c.accuracy(), 3.0 / 5.0);   // Eq. 25
}

TEST(MotionConfusion, UndefinedRatiosAreNaNAndSumsPool) {
  MotionConfusion c;
  c.tn = 10;
  EXPECT_TRUE(std::isnan(c.precision()));
  EXPECT_TRUE(std::isnan(c.recall()));
  EXPECT_DOUBLE_EQ(c.accuracy(), 1.0);
  EXPECT_TRUE(std::isnan(MotionConfusion{}.accuracy()));
  MotionConfusion d;
  d.tp = 3;
  d.fn = 1;
  c += d;
  EXPECT_DOUBLE_EQ(c.recall(), 0.75);
  EXPECT_DOUBLE_EQ(c.accuracy(), 13.0 / 14.0);
}

TEST(MotionConfusion, SizeMismatchIsNamed) {
  try {
    count_motion({0, 1}, {0}, {1, 1});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("truth moving (1)"), std::string::npos) << e.what();
  }
}

TEST(Statistics, MedianAndQuantileSkipNonFinite) {
  EXPECT_DOUBLE_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_DOUBLE_EQ(median({NAN, 5.0, INFINITY, 1.0}), 3.0);
  EXPECT_TRUE(std::isnan(median({})));
  EXPECT_TRUE(std::isnan(median({NAN})));
  EXPECT_DOUBLE_EQ(quantile({0.0, 10.0}, 0.9), 9.0);
  EXPECT_THROW(quantile({1.0}, 1.5), std::invalid_argument);
}

TEST(Statistics, AxisErrorRmseAndMax) {
  AxisErrorStats s;
  EXPECT_TRUE(s.rmse().array().isNaN().all());
  s.add({0.01, 0.0, -0.02});
  s.add({-0.01, 0.03, 0.02});
  EXPECT_NEAR(s.rmse().x(), 0.01, 1e-15);
  EXPECT_NEAR(s.rmse().y(), std::sqrt(0.0009 / 2.0), 1e-15);
  EXPECT_NEAR(s.rmse().z(), 0.02, 1e-15);
  EXPECT_NEAR(s.max_abs_or_nan().y(), 0.03, 1e-15);
  EXPECT_THROW(s.add({NAN, 0, 0}), std::invalid_argument);
}

// An estimated object: pixels on the actor and the error of its velocity along x.
ObjectMatch object(int pixels, double error_x, bool evaluated = true, bool detected = true) {
  ObjectMatch m;
  m.pixels = pixels;
  m.moving_pixels = evaluated ? pixels : 0;
  m.evaluated = evaluated;
  m.detected = detected;
  m.estimate_valid = detected;
  m.truth_mean_mps = Eigen::Vector3d(5.0, 0.0, 0.0);
  m.reference_mps = Eigen::Vector3d(5.0, 0.1, 0.0);
  if (detected) m.estimate_mps = m.truth_mean_mps + Eigen::Vector3d(error_x, 0.0, 0.0);
  return m;
}

TEST(Summary, MediansUseOnlyEvaluatedDetectedObjectsAndTheLargeFilter) {
  FrameEvaluation f;
  f.method = "fast";
  f.ego_valid = true;
  f.ego_estimate_mps = Eigen::Vector3d(10.01, 0.0, -0.03);
  f.ego_truth_mps = Eigen::Vector3d(10.0, 0.0, 0.0);
  f.ego_truth_at_heads_mps = f.ego_truth_mps;
  f.objects = {object(150, 1.0), object(250, 0.05), object(300, -0.2), object(500, 0.1),
               object(1000, 9.0, /*evaluated=*/false), object(400, 0.0, true, /*detected=*/false)};
  f.timing.total_ms = 2.0;
  FrameEvaluation g = f;
  g.ego_estimate_mps = Eigen::Vector3d(9.99, 0.0, 0.03);
  g.objects.clear();
  g.timing.total_ms = 4.0;
  const MethodSummary s = summarize({f, g});
  EXPECT_EQ(s.objects_evaluated, 5);
  EXPECT_EQ(s.objects_detected, 4);
  EXPECT_DOUBLE_EQ(s.detected_fraction, 0.8);
  EXPECT_EQ(s.objects_large, 3);
  EXPECT_NEAR(s.median_error_mps, 0.15, 1e-12);       // {0.05, 0.1, 0.2, 1.0}
  EXPECT_NEAR(s.median_error_mps_ge200, 0.1, 1e-12);  // {0.05, 0.2, 0.1}
  EXPECT_NEAR(s.median_reference_error_mps_ge200, std::hypot(0.1, 0.1), 1e-12);
  EXPECT_NEAR(s.ego_rmse_mps.x(), 0.01, 1e-12);
  EXPECT_NEAR(s.ego_rmse_mps.z(), 0.03, 1e-12);
  EXPECT_NEAR(s.ego_max_abs_mps.x(), 0.01, 1e-12);
  EXPECT_EQ(s.ego_frames, 2);
  EXPECT_DOUBLE_EQ(s.mean_timing_ms.total_ms, 3.0);
  EXPECT_DOUBLE_EQ(s.max_timing_ms.total_ms, 4.0);
}

TEST(Summary, InvalidEgoFramesAreLeftOutAndMethodsMayNotMix) {
  FrameEvaluation f;
  f.method = "paper";
  f.ego_valid = false;
  const MethodSummary s = summarize({f});
  EXPECT_EQ(s.ego_frames, 0);
  EXPECT_TRUE(std::isnan(s.ego_rmse_mps.x()));
  FrameEvaluation g;
  g.method = "fast";
  EXPECT_THROW(summarize({f, g}), std::invalid_argument);
}

TEST(Targets, MetMissedAndUnmeasurable) {
  MethodSummary s;
  s.motion.tn = 996;
  s.motion.fn = 4;  // accuracy 0.996
  s.ego_rmse_mps = Eigen::Vector3d(0.005, 0.02, 0.03);
  s.median_error_mps_ge200 = NAN;
  s.yaw_rate_rmse_dps = 0.4;
  s.median_reference_error_mps_ge200 = 0.2;
  s.tails.ge200.p95 = 0.4;
  s.tails.ge200.share_over_1mps = 0.03;
  s.tails.calibration.coverage_95 = 0.99;  // too wide an ellipse: the upper bound is missed
  s.tracking.all.mota = 0.9;
  s.tracking.all.idf1 = NAN;
  std::vector<TargetCheck> c = check_targets(s);
  ASSERT_EQ(c.size(), 13u);  // no blind-band check: the run had no blind-band pixels
  EXPECT_TRUE(c[0].met);   // accuracy 0.996 >= 0.995
  EXPECT_TRUE(c[1].met);   // x 0.005 <= 0.01
  EXPECT_FALSE(c[2].met);  // y 0.02 > 0.01
  EXPECT_TRUE(c[3].met);   // z 0.03 <= 0.03
  EXPECT_EQ(c[4].key, "yaw_rate_rmse");
  EXPECT_TRUE(c[4].met);   // 0.4 <= 0.5 deg/s
  EXPECT_EQ(c[5].key, "object_median_ge200");
  EXPECT_FALSE(c[5].met);  // nothing to measure is not a pass
  EXPECT_EQ(c[6].key, "object_centre_median_ge200");
  EXPECT_FALSE(c[6].met);  // 0.2 > 0.1
  EXPECT_EQ(c[7].key, "object_centre_p95_ge200");
  EXPECT_TRUE(c[7].met);  // 0.4 <= 0.5
  EXPECT_EQ(c[8].key, "object_centre_share_over_1mps_ge200");
  EXPECT_FALSE(c[8].met);  // 3 % > 2 %
  EXPECT_EQ(c[9].key, "covariance_coverage_95_min");
  EXPECT_TRUE(c[9].met);
  EXPECT_EQ(c[10].key, "covariance_coverage_95_max");
  EXPECT_FALSE(c[10].met);  // 0.99 > 0.98
  EXPECT_EQ(c[11].key, "tracking_mota");
  EXPECT_TRUE(c[11].met);
  EXPECT_EQ(c[12].key, "tracking_idf1");
  EXPECT_FALSE(c[12].met);  // nothing to measure

  s.blind_band_pixels = 100;
  s.blind_band_detected = 95;
  s.blind_recall_tracked = 0.95;
  s.yaw_rate_rmse_dps = NAN;  // a method that does not estimate the yaw rate
  c = check_targets(s);
  ASSERT_EQ(c.size(), 14u);
  EXPECT_FALSE(c[4].met);
  EXPECT_EQ(c[13].key, "blind_zone_recall_tracked");
  EXPECT_TRUE(c[13].met);  // 0.95 >= 0.9

  // Where vehicles are evaluated, their MOTA and IDF1 are held too (0.9 each).
  s.tracking.vehicles.objects = 40;
  s.tracking.vehicles.mota = 0.875;
  s.tracking.vehicles.idf1 = 0.95;
  c = check_targets(s);
  ASSERT_EQ(c.size(), 16u);
  EXPECT_EQ(c[14].key, "tracking_mota_vehicles");
  EXPECT_FALSE(c[14].met);  // 0.875 < 0.9
  EXPECT_EQ(c[15].key, "tracking_idf1_vehicles");
  EXPECT_TRUE(c[15].met);
}

}  // namespace
}  // namespace fmcw::eval
