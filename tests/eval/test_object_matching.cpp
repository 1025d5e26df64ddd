// Actor-to-cluster matching on a hand-made 2 x 6 image: which cluster, detection by the
// more-than-half rule, the truth it is compared with, and the "evaluated" threshold.

#include <gtest/gtest.h>

#include "fmcw/eval/frame_evaluation.hpp"
#include "fmcw/eval/object_matching.hpp"
#include "fmcw/core/synthetic_scan.hpp"

namespace fmcw::eval {
namespace {

struct Case {
  core::PixelGroundTruth gt = core::PixelGroundTruth::make_empty(12);
  std::vector<std::uint8_t> valid = std::vector<std::uint8_t>(12, 1);
  core::FrameTruth truth;
  core::MotionEstimate estimate;

  Case() {
    // Pixels 0-5: actor 7 (4 in cluster 1, 2 static); 6-9: actor 9 (2 in cluster 2, 2 in
    // cluster 3); 10-11: static world.
    const std::uint32_t instance[12] = {7, 7, 7, 7, 7, 7, 9, 9, 9, 9, 0, 0};
    const std::int32_t labels[12] = {1, 1, 1, 1, 0, 0, 2, 2, 3, 3, 0, 0};
    for (std::size_t i = 0; i < 12; ++i) {
      gt.instance[i] = instance[i];
      gt.moving[i] = instance[i] != 0;
      gt.range_m[i] = gt.radial_velocity_mps[i] = 1.0f;
      gt.vx_mps[i] = instance[i] == 7 ? 4.0f + 0.5f * static_cast<float>(i) : 0.0f;  // 4, 4.5, 5, 5.5 in cluster 1
      gt.vy_mps[i] = instance[i] == 9 ? 2.0f : 0.0f;
      gt.vz_mps[i] = 0.0f;
      estimate.labels.push_back(labels[i]);
    }
    core::ActorTruth a7;
    a7.id = 7;
    a7.class_name = "car";
    a7.position_rig_m = Eigen::Vector3d(3.0, 4.0, 0.0);
    a7.velocity_rig_mps = Eigen::Vector3d(5.0, 0.0, 0.0);
    core::ActorTruth a9 = a7;
    a9.id = 9;
    a9.class_name = "pedestrian";
    truth.actors = {a9, a7};
    for (int k = 1; k <= 3; ++k) {
      core::ClusterEstimate c;
      c.id = k;
      c.num_pixels = k == 1 ? 4 : 2;
      c.velocity.valid = true;
      c.velocity.velocity_mps = Eigen::Vector3d(4.9, 0.2, -0.1) * k;
      estimate.clusters.push_back(c);
    }
  }
};

TEST(ObjectMatching, MostPixelsClusterMoreThanHalfDetectsAndComparesWithItsPointsMeanVelocity) {
  const Case c;
  const std::vector<ObjectMatch> m = match_objects(c.gt, c.valid, c.truth, c.estimate);
  ASSERT_EQ(m.size(), 2u);
  const ObjectMatch& a = m[0];  // actor 7 (sorted by id)
  EXPECT_EQ(a.actor_id, 7u);
  EXPECT_EQ(a.class_name, "car");
  EXPECT_EQ(a.pixels, 6);
  EXPECT_EQ(a.cluster, 1);
  EXPECT_EQ(a.pixels_in_cluster, 4);
  EXPECT_EQ(a.cluster_pixels, 4);
  EXPECT_TRUE(a.evaluated);
  EXPECT_TRUE(a.detected);  // 4 of 6 > half
  EXPECT_DOUBLE_EQ(a.distance_m, 5.0);
  // Truth at the cluster's own points: mean of 4, 4.5, 5, 5.5 (the two static-labelled pixels
  // of the actor are not part of it).
  EXPECT_TRUE(a.truth_mean_mps.isApprox(Eigen::Vector3d(4.75, 0.0, 0.0)));
  EXPECT_TRUE(a.error_mps().isApprox(Eigen::Vector3d(0.15, 0.2, -0.1)));
  EXPECT_TRUE(a.reference_error_mps().isApprox(Eigen::Vector3d(-0.1, 0.2, -0.1)));

  const ObjectMatch& b = m[1];  // actor 9: 2 + 2 pixels in two clusters
  EXPECT_EQ(b.actor_id, 9u);
  EXPECT_EQ(b.cluster, 2);  // a tie goes to the lower label
  EXPECT_FALSE(b.detected);  // exactly half is not more than half
  EXPECT_FALSE(b.estimate_valid);
  EXPECT_TRUE(b.error_mps().array().isNaN().all());
}

TEST(ObjectMatching, InvalidPixelsDoNotCountAndFewMovingPixelsAreNotEvaluated) {
  Case c;
  c.valid[8] = c.valid[9] = 0;  // actor 9 keeps its 2 pixels in cluster 2: all of them
  c.gt.moving[6] = 0;           // ... of which 1 truly moving
  const std::vector<ObjectMatch> m = match_objects(c.gt, c.valid, c.truth, c.estimate);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[1].pixels, 2);
  EXPECT_TRUE(m[1].detected);
  EXPECT_FALSE(m[1].evaluated);  // 1 moving pixel < 3
  ObjectMatchParams one;
  one.min_moving_pixels = 1;
  EXPECT_TRUE(match_objects(c.gt, c.valid, c.truth, c.estimate, one)[1].evaluated);
}

TEST(ObjectMatching, InvalidClusterVelocityIsDetectedButNotEstimated) {
  Case c;
  c.estimate.clusters[0].velocity.valid = false;
  const ObjectMatch a = match_objects(c.gt, c.valid, c.truth, c.estimate)[0];
  EXPECT_TRUE(a.detected);
  EXPECT_FALSE(a.estimate_valid);
}

TEST(ObjectMatching, InconsistentTruthOrEstimateThrows) {
  Case c;
  c.truth.actors.pop_back();  // actor 7 gone
  EXPECT_THROW(match_objects(c.gt, c.valid, c.truth, c.estimate), std::invalid_argument);
  Case d;
  d.estimate.clusters.clear();  // label 1 (actor 7's cluster) has no estimate
  EXPECT_THROW(match_objects(d.gt, d.valid, d.truth, d.estimate), std::invalid_argument);
  Case e;
  e.estimate.labels.pop_back();
  EXPECT_THROW(match_objects(e.gt, e.valid, e.truth, e.estimate), std::invalid_argument);
}


// The blind band on a rendered scene: a box crossing the x axis 40 m ahead (its body's motion
// along every beam below 0.06 m/s, from any head: in the band) and one driving off to the side,
// whose lowest pixels are given the vertical velocity of the front and back of a rolling wheel
// (across the near-horizontal beams: their own motion is in the band, the body's is not).
TEST(BlindBand, JudgedByTheBodysMotionWithRollingPartsCountedApart) {
  core::SyntheticSceneParams p;
  core::SyntheticBox crossing;
  crossing.center_m = Eigen::Vector3d(40.0, 0.0, 0.8);
  crossing.half_extent_m = Eigen::Vector3d(0.3, 0.3, 0.8);
  crossing.velocity_mps = Eigen::Vector3d(0.0, 1.5, 0.0);
  core::SyntheticBox driving = crossing;
  driving.center_m = Eigen::Vector3d(20.0, 8.0, 0.8);
  driving.half_extent_m = Eigen::Vector3d(0.9, 0.9, 0.8);
  driving.velocity_mps = Eigen::Vector3d(5.0, 0.0, 0.0);
  p.actors = {crossing, driving};
  core::Frame f = core::render_synthetic_scan(p);
  core::PixelGroundTruth& gt = *f.truth;
  core::FrameTruth truth;
  for (std::uint32_t id = 1; id <= 2; ++id) {
    core::ActorTruth a;
    a.id = id;
    a.class_name = "car";
    a.position_rig_m = p.actors[id - 1].center_m;
    a.velocity_rig_mps = p.actors[id - 1].velocity_mps;
    truth.actors.push_back(a);
  }
  core::MotionEstimate estimate;
  estimate.labels.assign(f.scan.size(), 0);
  int crossing_pixels = 0, driving_pixels = 0, wheel_pixels = 0, crossing_labelled = 0, wheels_labelled = 0;
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (!f.scan.valid[i] || gt.instance[i] == 0) continue;
    ASSERT_TRUE(gt.moving[i]);
    if (gt.instance[i] == 1) {
      ++crossing_pixels;
      if (crossing_pixels % 4 != 0) {  // three in four labelled moving
        estimate.labels[i] = 1;
        ++crossing_labelled;
      }
      continue;
    }
    ++driving_pixels;
    if (f.scan.position(i).z() < 0.3) {  // a wheel's front or back: moving up or down
      gt.vx_mps[i] = gt.vy_mps[i] = 0.0f;
      gt.vz_mps[i] = 1.0f;
      ++wheel_pixels;
      if (wheel_pixels % 2 == 0) {
        estimate.labels[i] = 2;
        ++wheels_labelled;
      }
    }
  }
  ASSERT_GT(crossing_pixels, 30);
  ASSERT_GT(wheel_pixels, 10);
  const std::vector<BlindBandActor> band = blind_band_actors(f.scan, gt, truth, estimate, 0.15);
  ASSERT_EQ(band.size(), 2u);
  EXPECT_EQ(band[0].actor_id, 1u);
  EXPECT_EQ(band[0].band_pixels, crossing_pixels);
  EXPECT_EQ(band[0].band_detected, crossing_labelled);
  EXPECT_EQ(band[0].visible_pixels, 0);
  EXPECT_EQ(band[1].band_pixels, 0);  // the body drives away from the beams
  EXPECT_EQ(band[1].visible_pixels, driving_pixels);
  EXPECT_EQ(band[1].part_band_pixels, wheel_pixels);
  EXPECT_EQ(band[1].part_band_detected, wheels_labelled);

  truth.actors.pop_back();  // pixels of an actor the truth does not list
  EXPECT_THROW(blind_band_actors(f.scan, gt, truth, estimate, 0.15), std::invalid_argument);
  EXPECT_THROW(blind_band_actors(f.scan, gt, core::FrameTruth{}, estimate, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace fmcw::eval
