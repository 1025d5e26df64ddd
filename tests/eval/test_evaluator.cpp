// The whole evaluation on analytic frames with known answers: a rigidly translating box seen
// by the paper's rig from a moving ego, without noise, so every method must be exact.

#include <gtest/gtest.h>

#include "fmcw/eval/evaluator.hpp"
#include "support/synthetic_source.hpp"

namespace fmcw::eval {
namespace {

using test::SyntheticSource;

TEST(Evaluator, ExactOnANoiseFreeRigidScene) {
  SyntheticSource source(3);
  EvaluationParams params;
  params.methods = {"fast", "tracked"};
  std::size_t calls = 0;
  const EvaluationResult r = evaluate(source, params, [&](std::size_t done, std::size_t total) {
    EXPECT_EQ(done, ++calls);
    EXPECT_EQ(total, 3u);
  });
  ASSERT_EQ(r.methods, (std::vector<std::string>{"paper", "fast", "tracked"}));  // the baseline is always there, first
  ASSERT_EQ(r.frames.size(), 3u);
  EXPECT_EQ(r.dataset.frames, 3);
  EXPECT_TRUE(r.dataset.ego_moving);
  EXPECT_EQ(r.dataset.actors_seen, 1);
  EXPECT_GT(r.dataset.motion_points, 1000u);
  for (std::size_t m = 0; m < r.methods.size(); ++m) {
    const MethodSummary& s = r.summaries[m];
    SCOPED_TRACE(r.methods[m]);
    const bool tracks = r.methods[m] == "tracked";
    EXPECT_EQ(s.frames, 3);
    EXPECT_DOUBLE_EQ(s.motion.accuracy(), 1.0);
    EXPECT_DOUBLE_EQ(s.motion.precision(), 1.0);
    EXPECT_DOUBLE_EQ(s.motion.recall(), 1.0);
    EXPECT_LT(s.ego_max_abs_mps.maxCoeff(), 1e-4);
    EXPECT_EQ(s.objects_evaluated, 3);
    EXPECT_DOUBLE_EQ(s.detected_fraction, 1.0);
    // A single scan is exact; a track also follows its box's path, whose centre moves a little
    // as the view of the box changes: a few mm/s.
    const double exact = tracks ? 0.02 : 1e-3;
    EXPECT_LT(s.median_error_mps, exact);
    EXPECT_LT(s.median_error_mps_ge200, exact);  // the box has thousands of pixels
    for (const TargetCheck& c : r.checks[m]) {
      // Without noise the covariances are from residuals at rounding level: their coverage
      // means nothing here (tests/eval/test_tracking_metrics.cpp checks NEES on known draws).
      if (c.key.rfind("covariance_coverage", 0) == 0) continue;
      // paper and fast assume a rig that does not turn: they have no yaw rate to check; nor
      // do they track, so the tracking targets are theirs to miss.
      const bool has_yaw = r.methods[m] == "robust" || tracks;
      const bool needs_tracks = c.key.rfind("tracking_", 0) == 0;
      EXPECT_EQ(c.met, (c.key != "yaw_rate_rmse" || has_yaw) && (!needs_tracks || tracks)) << c.key;
    }
    // The box is matched every frame; a method without tracks gets a new id every frame.
    EXPECT_EQ(s.tracking.all.matches, 3);
    EXPECT_EQ(s.tracking.all.id_switches, tracks ? 0 : 2);
    EXPECT_DOUBLE_EQ(s.tracking.all.mota, tracks ? 1.0 : 1.0 / 3.0);
    EXPECT_DOUBLE_EQ(s.tracking.all.idf1, tracks ? 1.0 : 1.0 / 3.0);
    EXPECT_EQ(s.tails.ge200.count, 3);
    EXPECT_LT(s.tails.ge200.max, exact);
    EXPECT_EQ(s.yaw_frames, r.methods[m] == "paper" || r.methods[m] == "fast" ? 0 : 3);
    // One box, one cluster, every frame.
    EXPECT_EQ(s.instances.actors, 3);
    EXPECT_EQ(s.instances.actors_matched, 3);
    EXPECT_DOUBLE_EQ(s.instance_precision, 1.0);
    EXPECT_DOUBLE_EQ(s.instance_recall, 1.0);
  }
  // The snapshot is a whole frame with one estimate per method.
  EXPECT_EQ(r.snapshot.estimates.size(), 3u);
  EXPECT_EQ(r.snapshot.frame.scan.size(), r.snapshot.estimates[0].labels.size());
}

TEST(Evaluator, UnknownMethodIsRejectedBeforeAnyFrame) {
  SyntheticSource source(1);
  EvaluationParams params;
  params.methods = {"fastest"};
  try {
    evaluate(source, params);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fastest"), std::string::npos) << e.what();
  }
}

TEST(Evaluator, FrameWithoutTruthNamesTheFrame) {
  class NoTruth : public SyntheticSource {
   public:
    NoTruth() : SyntheticSource(2) {}
    core::Frame frame(std::size_t k) override {
      core::Frame f = SyntheticSource::frame(k);
      if (k == 1) f.truth.reset();
      return f;
    }
  } source;
  try {
    evaluate(source, EvaluationParams{});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic frame 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fmcw::eval
