// CLEAR MOT, IDF1 and HOTA on hand-made track sequences with known answers, the assignment they use,
// and the calibration score (NEES) on estimates drawn from their own covariance.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fmcw/eval/tail_metrics.hpp"
#include "fmcw/eval/tracking_metrics.hpp"

namespace {

using namespace fmcw::eval;

// A frame in which each listed (actor, track, iou) pair overlaps: the actor and the track both
// have 100 pixels, their overlap is chosen so that the IoU is the one given.
struct Pair {
  std::uint32_t actor;
  std::int64_t track;
  double iou;
};
TrackingFrame frame(const std::vector<std::uint32_t>& actors, const std::vector<std::int64_t>& tracks,
                    const std::vector<Pair>& pairs, const std::string& cls = "car") {
  TrackingFrame f;
  for (const std::uint32_t a : actors) f.truths.push_back({a, cls, 100, Eigen::Vector3d(a, 0, 0)});
  for (const std::int64_t t : tracks) {
    TrackObservation o;
    o.track = t;
    o.pixels = 100;
    o.class_name = cls;
    f.tracks.push_back(o);
  }
  for (const Pair& p : pairs) {
    int ai = -1, ti = -1;
    for (std::size_t i = 0; i < actors.size(); ++i) ai = actors[i] == p.actor ? static_cast<int>(i) : ai;
    for (std::size_t j = 0; j < tracks.size(); ++j) ti = tracks[j] == p.track ? static_cast<int>(j) : ti;
    // iou = x / (200 - x)  =>  x = 200 iou / (1 + iou)
    f.overlaps.push_back({ai, ti, static_cast<int>(std::lround(200.0 * p.iou / (1.0 + p.iou)))});
  }
  return f;
}

TEST(MaxWeightAssignment, FindsTheBestOneToOnePairing) {
  // Greedy would take (0,0) = 0.9 and leave row 1 with 0.1; the best is 0.8 + 0.7.
  const std::vector<int> a = max_weight_assignment({{0.9, 0.8}, {0.7, 0.0}});
  EXPECT_EQ(a, (std::vector<int>{1, 0}));
  // More rows than columns; zero weight is no pair.
  const std::vector<int> b = max_weight_assignment({{0.0}, {0.5}, {0.0}});
  EXPECT_EQ(b, (std::vector<int>{-1, 0, -1}));
  EXPECT_EQ(max_weight_assignment({{0.0, 0.0}}), (std::vector<int>{-1}));
}

TEST(ClearMot, PerfectTrackingScoresOne) {
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 10; ++k) frames.push_back(frame({1, 2}, {7, 8}, {{1, 7, 0.9}, {2, 8, 0.8}}));
  const MotMetrics m = clear_mot(frames).all;
  EXPECT_EQ(m.objects, 20);
  EXPECT_EQ(m.matches, 20);
  EXPECT_DOUBLE_EQ(m.mota, 1.0);
  EXPECT_DOUBLE_EQ(m.idf1, 1.0);
  EXPECT_EQ(m.id_switches, 0);
  EXPECT_EQ(m.fragmentations, 0);
  EXPECT_NEAR(m.motp_m, 1.5, 1e-12);  // truth centres at x = 1 and 2, tracks at the origin
}

TEST(ClearMot, ASwitchCostsMotaOnceAndIdf1Half) {
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 10; ++k) frames.push_back(frame({1}, {k < 5 ? 7 : 8}, {{1, k < 5 ? 7 : 8, 0.9}}));
  const MotMetrics m = clear_mot(frames).all;
  EXPECT_EQ(m.id_switches, 1);
  EXPECT_EQ(m.false_positives, 0);
  EXPECT_DOUBLE_EQ(m.mota, 1.0 - 1.0 / 10.0);
  EXPECT_EQ(m.idtp, 5);  // object 1 is paired with one of the two tracks, five frames each
  EXPECT_DOUBLE_EQ(m.idf1, 2.0 * 5 / (10 + 10));
}

TEST(ClearMot, AFragmentIsCountedAndTheGapIsMissed) {
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 10; ++k) {
    const bool gap = k == 4 || k == 5;
    frames.push_back(gap ? frame({1}, {}, {}) : frame({1}, {7}, {{1, 7, 0.9}}));
  }
  const MotMetrics m = clear_mot(frames).all;
  EXPECT_EQ(m.misses, 2);
  EXPECT_EQ(m.fragmentations, 1);
  EXPECT_EQ(m.id_switches, 0);  // the same track resumes
  EXPECT_DOUBLE_EQ(m.mota, 1.0 - 2.0 / 10.0);
  EXPECT_DOUBLE_EQ(m.idf1, 2.0 * 8 / (10 + 8));
}

TEST(ClearMot, AFalseTrackCostsItsFrames) {
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 10; ++k) {
    frames.push_back(k < 3 ? frame({1}, {7, 9}, {{1, 7, 0.9}}) : frame({1}, {7}, {{1, 7, 0.9}}));
  }
  const MotMetrics m = clear_mot(frames).all;
  EXPECT_EQ(m.false_positives, 3);
  EXPECT_DOUBLE_EQ(m.mota, 1.0 - 3.0 / 10.0);
  EXPECT_DOUBLE_EQ(m.idf1, 2.0 * 10 / (10 + 13));
}

TEST(ClearMot, TheThresholdDecidesAMatchAndAnUntrackedMethodPaysForNewIds) {
  // IoU 0.45: a miss and a false positive at 0.5, a match at 0.4.
  const std::vector<TrackingFrame> frames = {frame({1}, {7}, {{1, 7, 0.45}})};
  EXPECT_EQ(clear_mot(frames, {0.5}).all.matches, 0);
  EXPECT_DOUBLE_EQ(clear_mot(frames, {0.5}).all.mota, -1.0);
  EXPECT_EQ(clear_mot(frames, {0.4}).all.matches, 1);
  // A new track id every frame (one per cluster per frame) switches every frame.
  std::vector<TrackingFrame> untracked;
  for (int k = 0; k < 4; ++k) untracked.push_back(frame({1}, {-(k + 1)}, {{1, -(k + 1), 0.9}}));
  const MotMetrics u = clear_mot(untracked).all;
  EXPECT_EQ(u.id_switches, 3);
  EXPECT_DOUBLE_EQ(u.idf1, 2.0 * 1 / (4 + 4));
}

TEST(ClearMot, KeepsALastingCorrespondenceOverABetterNewOne) {
  std::vector<TrackingFrame> frames = {frame({1}, {7}, {{1, 7, 0.9}}),
                                       frame({1}, {7, 8}, {{1, 7, 0.6}, {1, 8, 0.9}})};
  const MotMetrics m = clear_mot(frames).all;
  EXPECT_EQ(m.id_switches, 0);
  EXPECT_EQ(m.false_positives, 1);  // track 8
}

// ---- HOTA ----------------------------------------------------------------------------------

// DetA and AssA at one localisation threshold alpha = (k + 1) / 20.
double deta_at(const MotMetrics& m, int k) {
  const auto i = static_cast<std::size_t>(k);
  return static_cast<double>(m.hota_tp[i]) / (m.hota_tp[i] + m.hota_fn[i] + m.hota_fp[i]);
}
double assa_at(const MotMetrics& m, int k) {
  const auto i = static_cast<std::size_t>(k);
  return m.hota_tp[i] > 0 ? m.hota_assoc[i] / m.hota_tp[i] : 0.0;
}

TEST(Hota, PerfectTrackingScoresOne) {
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 10; ++k) frames.push_back(frame({1, 2}, {7, 8}, {{1, 7, 1.0}, {2, 8, 1.0}}));
  const MotMetrics m = clear_mot(frames).all;
  EXPECT_DOUBLE_EQ(m.hota, 1.0);
  EXPECT_DOUBLE_EQ(m.deta, 1.0);
  EXPECT_DOUBLE_EQ(m.assa, 1.0);
  EXPECT_DOUBLE_EQ(m.loca, 1.0);
}

TEST(Hota, ASwitchHalvesTheAssociationNotTheDetection) {
  // Object 1 over 10 frames, track 7 for five and track 8 for five: each match's pair is
  // together 5 of the 10 + 5 - 5 frames either is present, A = 0.5.
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 10; ++k) frames.push_back(frame({1}, {k < 5 ? 7 : 8}, {{1, k < 5 ? 7 : 8, 1.0}}));
  const MotMetrics m = clear_mot(frames).all;
  EXPECT_DOUBLE_EQ(m.deta, 1.0);
  EXPECT_DOUBLE_EQ(m.assa, 0.5);
  EXPECT_NEAR(m.hota, std::sqrt(0.5), 1e-12);
  // A new track id every frame: A = 1 / 4 for each of the four matches.
  std::vector<TrackingFrame> untracked;
  for (int k = 0; k < 4; ++k) untracked.push_back(frame({1}, {-(k + 1)}, {{1, -(k + 1), 1.0}}));
  const MotMetrics u = clear_mot(untracked).all;
  EXPECT_DOUBLE_EQ(u.deta, 1.0);
  EXPECT_DOUBLE_EQ(u.assa, 0.25);
  EXPECT_DOUBLE_EQ(u.hota, 0.5);
}

TEST(Hota, AMatchCountsAtTheThresholdsItsIouReaches) {
  // IoU 67 / 133 = 0.504 in every frame: a match at alpha = 0.05 ... 0.50 (10 of the 19), a miss
  // and a false positive above. A false track in three frames costs DetA there.
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 10; ++k) frames.push_back(frame({1}, {7}, {{1, 7, 0.504}}));
  const MotMetrics m = clear_mot(frames).all;
  const double iou = 67.0 / 133.0;
  EXPECT_EQ(m.hota_tp[9], 10);   // alpha 0.50
  EXPECT_EQ(m.hota_tp[10], 0);   // alpha 0.55
  EXPECT_EQ(m.hota_fn[10], 10);
  EXPECT_EQ(m.hota_fp[10], 10);
  EXPECT_NEAR(m.hota, 10.0 / 19.0, 1e-12);
  EXPECT_NEAR(m.deta, 10.0 / 19.0, 1e-12);
  EXPECT_NEAR(m.assa, 10.0 / 19.0, 1e-12);
  EXPECT_NEAR(m.loca, iou, 1e-12);
  std::vector<TrackingFrame> with_false;
  for (int k = 0; k < 10; ++k) {
    const std::vector<std::int64_t> tracks = k < 3 ? std::vector<std::int64_t>{7, 9} : std::vector<std::int64_t>{7};
    with_false.push_back(frame({1}, tracks, {{1, 7, 1.0}}));
  }
  const MotMetrics f = clear_mot(with_false).all;
  EXPECT_DOUBLE_EQ(f.deta, 10.0 / 13.0);
  EXPECT_DOUBLE_EQ(f.assa, 1.0);
  EXPECT_NEAR(f.hota, std::sqrt(10.0 / 13.0), 1e-12);
}

TEST(Hota, AFramesMatchFollowsThePairAlignedOverTheRun) {
  // Object 1 with track 7 for four frames (IoU 0.8); in the fifth, track 7 at IoU 0.6 and a
  // new track 8 at 0.8. Matched by IoU alone it would take track 8; HOTA weighs each pair by
  // its alignment over the run and keeps track 7: every match's pair is (1, 7), A = 5 / 5.
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 4; ++k) frames.push_back(frame({1}, {7}, {{1, 7, 0.8}}));
  frames.push_back(frame({1}, {7, 8}, {{1, 7, 0.6}, {1, 8, 0.8}}));
  const MotMetrics m = clear_mot(frames).all;
  for (int k = 0; k <= 11; ++k) {  // alpha up to 0.60: all five frames matched, to track 7
    EXPECT_EQ(m.hota_tp[static_cast<std::size_t>(k)], 5) << k;
    EXPECT_EQ(m.hota_fp[static_cast<std::size_t>(k)], 1) << k;  // track 8
    EXPECT_DOUBLE_EQ(assa_at(m, k), 1.0) << k;
    EXPECT_DOUBLE_EQ(deta_at(m, k), 5.0 / 6.0) << k;
  }
  // Above 0.60 the fifth frame's match (IoU 0.6) no longer counts: track 7's A is 4 / (5 + 5 -
  // 4).
  EXPECT_EQ(m.hota_tp[12], 4);
  EXPECT_DOUBLE_EQ(assa_at(m, 12), 4.0 / 6.0);
}

TEST(Hota, RunsPoolByAddingTheirCountsAsAnAggregateDoes) {
  // Two runs with no object or track in common: pooled as an aggregate pools them
  // (add_mot_counts), they give the HOTA, MOTA and IDF1 of both sequences as one.
  std::vector<TrackingFrame> a, b;
  for (int k = 0; k < 10; ++k) a.push_back(frame({1}, {k < 5 ? 7 : 8}, {{1, k < 5 ? 7 : 8, 0.8}}));
  for (int k = 0; k < 6; ++k) {
    const std::vector<std::int64_t> tracks = k < 3 ? std::vector<std::int64_t>{9, 10} : std::vector<std::int64_t>{9};
    b.push_back(frame({2}, tracks, {{2, 9, 0.6}}));
  }
  MotMetrics pooled;
  add_mot_counts(pooled, clear_mot(a).all);
  add_mot_counts(pooled, clear_mot(b).all);
  complete_mot(pooled);
  std::vector<TrackingFrame> both = a;
  both.insert(both.end(), b.begin(), b.end());
  const MotMetrics whole = clear_mot(both).all;
  EXPECT_NEAR(pooled.hota, whole.hota, 1e-12);
  EXPECT_NEAR(pooled.deta, whole.deta, 1e-12);
  EXPECT_NEAR(pooled.assa, whole.assa, 1e-12);
  EXPECT_NEAR(pooled.loca, whole.loca, 1e-12);
  EXPECT_NEAR(pooled.mota, whole.mota, 1e-12);
  EXPECT_NEAR(pooled.idf1, whole.idf1, 1e-12);
  EXPECT_NEAR(pooled.motp_iou, whole.motp_iou, 1e-12);
  EXPECT_LT(whole.hota, clear_mot(a).all.hota);  // b's false track and lower IoU cost it
  // Nothing to score: NaN, not a number that looks like a score.
  EXPECT_TRUE(std::isnan(clear_mot({}).all.hota));
}

TEST(ClearMot, ByClassKeepsEachClassApart) {
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 4; ++k) {
    TrackingFrame f = frame({1}, {7}, {{1, 7, 0.9}}, "car");
    TrackingFrame p = frame({2}, {}, {}, "pedestrian");  // a pedestrian never tracked
    f.truths.push_back(p.truths[0]);
    frames.push_back(f);
  }
  const MotReport r = clear_mot(frames);
  EXPECT_DOUBLE_EQ(r.by_class.at("car").mota, 1.0);
  EXPECT_DOUBLE_EQ(r.by_class.at("pedestrian").mota, 0.0);
  EXPECT_DOUBLE_EQ(r.all.mota, 0.5);
  EXPECT_DOUBLE_EQ(r.vehicles.mota, 1.0);  // the car alone
  EXPECT_EQ(r.vehicles.objects, 4);
}

// A van and a truck tracked without fault, and a car whose track is replaced halfway: the
// vehicles are scored together (one switch over 12 object-frames), and a walker is not one.
TEST(ClearMot, VehiclesAreScoredTogether) {
  std::vector<TrackingFrame> frames;
  for (int k = 0; k < 4; ++k) {
    TrackingFrame f = frame({1}, {k < 2 ? 7 : 8}, {{1, k < 2 ? 7 : 8, 0.9}}, "car");
    const TrackingFrame v = frame({2}, {9}, {{2, 9, 0.9}}, "van");
    const TrackingFrame t = frame({3}, {10}, {{3, 10, 0.9}}, "truck");
    const TrackingFrame w = frame({4}, {}, {}, "pedestrian");  // never tracked
    for (const TrackingFrame* g : {&v, &t, &w}) {
      const int base_truth = static_cast<int>(f.truths.size()), base_track = static_cast<int>(f.tracks.size());
      f.truths.insert(f.truths.end(), g->truths.begin(), g->truths.end());
      f.tracks.insert(f.tracks.end(), g->tracks.begin(), g->tracks.end());
      for (PointOverlap o : g->overlaps) {
        o.truth += base_truth;
        o.track += base_track;
        f.overlaps.push_back(o);
      }
    }
    frames.push_back(f);
  }
  const MotReport r = clear_mot(frames);
  EXPECT_EQ(r.vehicles.objects, 12);
  EXPECT_EQ(r.vehicles.id_switches, 1);
  EXPECT_NEAR(r.vehicles.mota, 1.0 - 1.0 / 12.0, 1e-12);
  EXPECT_NEAR(r.all.mota, 1.0 - 5.0 / 16.0, 1e-12);  // the walker's four misses count here
  MotParams only_cars;
  only_cars.vehicle_classes = {"car"};
  EXPECT_EQ(clear_mot(frames, only_cars).vehicles.objects, 4);
}

TEST(Nees, EstimatesDrawnFromTheirOwnCovarianceCoverNinetyFivePercent) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u(0.01, 2.0), angle(0.0, M_PI);
  int inside = 0, inside_over = 0;
  double sum = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double a = angle(rng);
    Eigen::Matrix2d R;
    R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    const Eigen::Vector2d sd(u(rng), u(rng));
    const Eigen::Matrix2d cov = R * sd.cwiseProduct(sd).asDiagonal() * R.transpose();
    const Eigen::Vector2d e = R * Eigen::Vector2d(sd.x() * n01(rng), sd.y() * n01(rng));
    const NeesScore s = score_nees(e, cov, 1e3);
    ASSERT_TRUE(s.has_covariance);
    ASSERT_EQ(s.dof, 2);
    inside += s.inside_95 ? 1 : 0;
    sum += s.nees;
    inside_over += score_nees(e, 0.25 * cov, 1e3).inside_95 ? 1 : 0;  // claims half the sigma
  }
  EXPECT_NEAR(static_cast<double>(inside) / n, 0.95, 0.006);
  EXPECT_NEAR(sum / n, 2.0, 0.06);
  EXPECT_LT(static_cast<double>(inside_over) / n, 0.6);  // overconfident: 1 - exp(-5.99 / 8) = 0.53
}

TEST(Nees, AnUnobservableDirectionIsLeftOut) {
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  cov(0, 0) = 0.01;
  cov(1, 1) = std::numeric_limits<double>::infinity();
  const NeesScore s = score_nees(Eigen::Vector2d(0.05, 40.0), cov, 1e3);
  EXPECT_EQ(s.dof, 1);
  EXPECT_NEAR(s.nees, 0.25, 1e-12);
  EXPECT_TRUE(s.inside_95);
  const NeesScore none = score_nees(Eigen::Vector2d(0.05, 0.0), Eigen::Matrix2d::Constant(std::nan("")), 1e3);
  EXPECT_FALSE(none.has_covariance);
}

TEST(ObjectTails, BreaksErrorsDownByDistanceAndAge) {
  std::vector<FrameEvaluation> frames;
  for (int k = 0; k < 8; ++k) {
    FrameEvaluation f;
    f.method = "m";
    ObjectMatch o;
    o.actor_id = 3;
    o.class_name = "truck";
    o.pixels = 300;
    o.evaluated = o.detected = o.estimate_valid = true;
    o.distance_m = 50.0;
    o.reference_mps = Eigen::Vector3d(8, 0, 0);
    o.estimate_mps = Eigen::Vector3d(k < 5 ? 10 : 8.1, 0, 0);  // young: 2 m/s off; later 0.1
    f.objects.push_back(o);
    frames.push_back(f);
  }
  const ObjectTails t = object_tails(frames);
  EXPECT_EQ(t.ge200.count, 8);
  EXPECT_DOUBLE_EQ(t.ge200.share_over_1mps, 5.0 / 8.0);
  EXPECT_NEAR(t.by_age.at("first_5").median, 2.0, 1e-12);
  EXPECT_NEAR(t.by_age.at("later").max, 0.1, 1e-12);
  EXPECT_EQ(t.by_distance.at("40-80").count, 8);
  EXPECT_EQ(t.by_class.at("truck").count, 8);
  EXPECT_EQ(t.calibration.without_covariance, 8);
}

// Two classes, one overconfident (it claims a quarter of its error's variance) and one honest,
// over a young and a later age: the breakdowns keep them apart, and all of it pools.
TEST(ObjectTails, BreaksCalibrationDownByClassAndAge) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  std::vector<FrameEvaluation> frames;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    FrameEvaluation f;
    f.method = "m";
    for (const std::uint32_t actor : {1u, 2u}) {
      ObjectMatch o;
      o.actor_id = actor;
      o.class_name = actor == 1 ? "car" : "pedestrian";
      o.pixels = 50;
      o.evaluated = o.detected = o.estimate_valid = true;
      const double sd = 0.3;  // the error's true sigma per axis
      o.estimate_mps = Eigen::Vector3d(sd * n01(rng), sd * n01(rng), 0.0);
      o.reference_mps = Eigen::Vector3d::Zero();
      o.estimate_covariance = Eigen::Matrix3d::Zero();
      const double claimed = actor == 1 ? sd : 0.5 * sd;
      o.estimate_covariance.topLeftCorner<2, 2>() = claimed * claimed * Eigen::Matrix2d::Identity();
      f.objects.push_back(o);
    }
    frames.push_back(f);
  }
  const ObjectTails t = object_tails(frames);
  const CalibrationStats& car = t.calibration_by_class.at("car");
  const CalibrationStats& walker = t.calibration_by_class.at("pedestrian");
  EXPECT_EQ(car.scored, n);
  EXPECT_NEAR(car.coverage_95, 0.95, 0.012);
  EXPECT_NEAR(car.mean_nees, 2.0, 0.12);
  EXPECT_NEAR(walker.coverage_95, 1.0 - std::exp(-5.991464547107979 / 8.0), 0.02);  // 0.53
  EXPECT_NEAR(walker.mean_nees, 8.0, 0.5);
  // Each actor's first five frames are young: 2 x 5 estimates.
  EXPECT_EQ(t.calibration_by_age.at("first_5").scored, 10);
  EXPECT_EQ(t.calibration_by_age.at("later").scored, 2 * n - 10);
  // The pooled figure is the scored-weighted mean of the classes'.
  EXPECT_EQ(t.calibration.scored, 2 * n);
  EXPECT_NEAR(t.calibration.coverage_95, 0.5 * (car.coverage_95 + walker.coverage_95), 1e-12);
  EXPECT_NEAR(t.calibration.mean_nees, 0.5 * (car.mean_nees + walker.mean_nees), 1e-9);
}

}  // namespace
