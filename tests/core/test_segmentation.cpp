#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "fmcw/core/doppler_segmentation.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "scenes.hpp"

namespace fmcw::core {
namespace {

TEST(DopplerThreshold, DerivedAsInEq14) {
  // 0.2 deg pixels, 25 m/s object and 25 m/s ego: the paper's 0.17 m/s.
  EXPECT_NEAR(doppler_threshold_mps(0.2 * M_PI / 180.0, 25.0, 25.0), 0.1745, 1e-4);
  EXPECT_THROW(doppler_threshold_mps(0.0, 25.0, 25.0), std::invalid_argument);
}

// A 1 x n strip with hand-set velocities: neighbours join below v_th, chains propagate.
Scan strip(const std::vector<float>& v) {
  Scan scan = Scan::make_empty(1, static_cast<int>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) {
    scan.x_m[i] = 10.0f;
    scan.y_m[i] = static_cast<float>(i) * 0.1f;
    scan.z_m[i] = 0.0f;
    scan.range_m[i] = 10.0f;
    scan.radial_velocity_mps[i] = v[i];
    scan.valid[i] = 1;
  }
  return scan;
}

TEST(DopplerSegmenter, LargestRegionIsStaticOthersAreClustersInScanOrder) {
  // Regions: {0,1,2,3} (v ~ 0), {4,5} (v = 3), {6} (v = -2), then {7,8,9} static again but cut
  // off by pixel 6: it is its own region.
  Scan scan = strip({0.0f, 0.1f, 0.2f, 0.3f, 3.0f, 3.1f, -2.0f, 0.0f, 0.0f, 0.0f});
  DopplerSegmenter seg;
  const Segmentation s = seg.segment(scan);
  EXPECT_EQ(s.num_regions, 4u);
  EXPECT_EQ(s.static_pixels, 4u);
  const std::vector<std::int32_t> expected = {0, 0, 0, 0, 1, 1, 2, 3, 3, 3};
  EXPECT_EQ(s.labels, expected);
  ASSERT_EQ(s.num_clusters(), 3);
  EXPECT_EQ(s.cluster_sizes[0], 2u);
  EXPECT_EQ(s.cluster_sizes[1], 1u);
  EXPECT_EQ(s.cluster_sizes[2], 3u);
}

TEST(DopplerSegmenter, ThresholdIsStrictAndInvalidPixelsNeverJoin) {
  Scan scan = strip({0.0f, 0.5f, 0.5f, 0.5f});
  scan.valid[2] = 0;
  SegmentationParams params;
  params.velocity_threshold_mps = 0.5;  // |0.5 - 0.0| == v_th: does not join (strict <)
  DopplerSegmenter seg(params);
  const Segmentation s = seg.segment(scan);
  EXPECT_EQ(s.labels[2], Segmentation::kInvalid);
  // pixel 0 alone, pixel 1 alone (cut off from 3 by the invalid pixel), pixel 3 alone
  EXPECT_EQ(s.num_regions, 3u);
}

TEST(DopplerSegmenter, EightNeighbourhoodJoinsDiagonals) {
  // 2 x 2 checkerboard of two velocities: only diagonal neighbours match.
  Scan scan = Scan::make_empty(2, 2);
  const float v[4] = {1.0f, 5.0f, 5.0f, 1.0f};
  for (int i = 0; i < 4; ++i) {
    scan.x_m[i] = 5.0f;
    scan.y_m[i] = scan.z_m[i] = 0.0f;
    scan.range_m[i] = 5.0f;
    scan.radial_velocity_mps[i] = v[i];
    scan.valid[i] = 1;
  }
  const Segmentation s = DopplerSegmenter().segment(scan);
  EXPECT_EQ(s.num_regions, 2u);
  EXPECT_EQ(s.labels[0], s.labels[3]);
  EXPECT_EQ(s.labels[1], s.labels[2]);
}

TEST(DopplerSegmenter, MinClusterPixelsDropsSmallRegions) {
  Scan scan = strip({0.0f, 0.0f, 0.0f, 3.0f, 0.0f, 0.0f, 0.0f, 0.0f});
  SegmentationParams params;
  params.min_cluster_pixels = 2;
  const Segmentation s = DopplerSegmenter(params).segment(scan);
  // Regions {0,1,2}, {3}, {4..7}: the last is static, the first a cluster, the lone pixel dropped.
  EXPECT_EQ(s.labels[3], Segmentation::kUnassigned);
  ASSERT_EQ(s.num_clusters(), 1);
  EXPECT_EQ(s.cluster_sizes[0], 3u);
  EXPECT_EQ(s.labels[0], 1);
}

TEST(DopplerSegmenter, EmptyAndAllInvalidScansGiveNoRegions) {
  DopplerSegmenter seg;
  Scan empty = Scan::make_empty(0, 0);
  empty.heads.clear();
  EXPECT_EQ(seg.segment(empty).num_regions, 0u);
  Scan invalid = Scan::make_empty(4, 5);
  const Segmentation s = seg.segment(invalid);
  EXPECT_EQ(s.num_regions, 0u);
  for (const auto l : s.labels) EXPECT_EQ(l, Segmentation::kInvalid);
}

// Labels of the actor's pixels: which clusters they fell in, and how many pixels.
std::map<std::int32_t, int> labels_of_instance(const Frame& frame, const Segmentation& s, std::uint32_t instance) {
  std::map<std::int32_t, int> counts;
  for (std::size_t i = 0; i < s.labels.size(); ++i) {
    if (frame.truth->instance[i] == instance && frame.scan.valid[i]) ++counts[s.labels[i]];
  }
  return counts;
}

TEST(DopplerSegmenter, BoxMovingTowardsSensorIsOneClusterApartFromStaticWorld) {
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  SyntheticBox car;
  car.center_m = {20.0, 2.0, 0.75};
  car.half_extent_m = {2.25, 0.9, 0.75};
  car.velocity_mps = {-8.0, 0.0, 0.0};
  p.actors = {car};
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  p.seed = 7;
  const Frame frame = render_synthetic_scan(p);
  const Segmentation s = DopplerSegmenter().segment(frame.scan);
  const auto car_labels = labels_of_instance(frame, s, 1);
  ASSERT_EQ(car_labels.size(), 1u) << "the car split into several regions";
  EXPECT_GT(car_labels.begin()->first, 0) << "the car was taken as static";
  EXPECT_GT(car_labels.begin()->second, 200);
  // Static world: one region, every pixel of it.
  const auto world = labels_of_instance(frame, s, 0);
  ASSERT_EQ(world.size(), 1u);
  EXPECT_EQ(world.begin()->first, Segmentation::kStatic);
}

TEST(DopplerSegmenter, BoxMovingAcrossTheBeamsIsNotSeparatedAsEq15Predicts) {
  // Straight ahead at 30 m, moving sideways at 2 m/s: |v cos(phi)| <= 2 * sin(2 deg) = 0.07 m/s
  // < v_th at every pixel, so Doppler cannot tell the box from the wall behind it.
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  SyntheticBox box;
  box.center_m = {30.0, 0.0, 1.5};
  box.half_extent_m = {0.5, 1.0, 0.5};
  box.velocity_mps = {0.0, 2.0, 0.0};
  p.actors = {box};
  const Frame frame = render_synthetic_scan(p);
  const Segmentation s = DopplerSegmenter().segment(frame.scan);
  const auto box_labels = labels_of_instance(frame, s, 1);
  ASSERT_EQ(box_labels.size(), 1u);
  EXPECT_EQ(box_labels.begin()->first, Segmentation::kStatic);
  EXPECT_GT(box_labels.begin()->second, 50);
  // The same box moving along the beams at the same speed is separated.
  p.actors[0].velocity_mps = {2.0, 0.0, 0.0};
  const Frame radial = render_synthetic_scan(p);
  const auto radial_labels = labels_of_instance(radial, DopplerSegmenter().segment(radial.scan), 1);
  ASSERT_EQ(radial_labels.size(), 1u);
  EXPECT_GT(radial_labels.begin()->first, 0);
}

TEST(DopplerSegmenter, ObjectAcrossAStitchedSeamIsOneCluster) {
  // The paper rig's left head (yaw +40 deg) meets the front head at azimuth +20 deg. A car
  // centred on that azimuth shows in both heads' columns.
  SyntheticSceneParams p = fmcw::test::static_courtyard();
  SyntheticBox car;
  const double az = 20.0 * M_PI / 180.0;
  car.center_m = {18.0 * std::cos(az), 18.0 * std::sin(az), 0.75};
  car.half_extent_m = {2.25, 0.9, 0.75};
  car.yaw_rad = az + M_PI / 2;
  car.velocity_mps = 6.0 * Eigen::Vector3d(std::cos(az), std::sin(az), 0.0);
  p.actors = {car};
  const Frame frame = render_synthetic_scan(p);
  ASSERT_TRUE(frame.scan.heads[0].stitched_to_next);
  const int seam = frame.scan.heads[0].col_end;
  std::set<int> heads_seen;
  for (std::size_t i = 0; i < frame.scan.size(); ++i) {
    if (frame.truth->instance[i] == 1) heads_seen.insert(static_cast<int>(i % frame.scan.cols) < seam ? 0 : 1);
  }
  ASSERT_EQ(heads_seen.size(), 2u) << "the car must straddle the seam for this test";
  const auto stitched = labels_of_instance(frame, DopplerSegmenter().segment(frame.scan), 1);
  ASSERT_EQ(stitched.size(), 1u);
  EXPECT_GT(stitched.begin()->first, 0);

  // Without the seam stitched, the same car is cut in two clusters.
  Scan unstitched = frame.scan;
  unstitched.heads[0].stitched_to_next = false;
  const auto cut = labels_of_instance(frame, DopplerSegmenter().segment(unstitched), 1);
  EXPECT_EQ(cut.size(), 2u);
}

TEST(DopplerSegmenter, UnionFindAndRegionGrowingGiveIdenticalLabels) {
  // Random velocity fields with holes, coarse enough to make many regions that touch, merge
  // through diagonals, and wrap around invalid pixels; then the benchmark street scene.
  SegmentationParams grow;
  grow.algorithm = RegionAlgorithm::kRegionGrowing;
  SegmentationParams uf;
  uf.algorithm = RegionAlgorithm::kUnionFind;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Rng rng(seed);
    const int rows = 5 + static_cast<int>(rng.uniform_below(40));
    const int cols = 5 + static_cast<int>(rng.uniform_below(60));
    Scan scan = Scan::make_empty(rows, cols);
    scan.heads[0].col_end = cols / 2;
    scan.heads[0].stitched_to_next = seed % 2 == 0;
    HeadInfo second;
    second.name = "b";
    second.col_begin = cols / 2;
    second.col_end = cols;
    scan.heads.push_back(second);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      scan.x_m[i] = scan.y_m[i] = scan.z_m[i] = 1.0f;
      scan.range_m[i] = 1.0f;
      scan.radial_velocity_mps[i] = static_cast<float>(0.1 * static_cast<double>(rng.uniform_below(5)));
      scan.valid[i] = rng.uniform() > 0.15 ? 1 : 0;
    }
    const Segmentation a = DopplerSegmenter(grow).segment(scan);
    const Segmentation b = DopplerSegmenter(uf).segment(scan);
    ASSERT_EQ(a.labels, b.labels) << "seed " << seed;
    ASSERT_EQ(a.cluster_sizes, b.cluster_sizes);
    ASSERT_EQ(a.num_regions, b.num_regions);
    EXPECT_GT(a.num_regions, 3u);
  }
  const Frame street = render_synthetic_scan(benchmark_scene(20, 3));
  EXPECT_EQ(DopplerSegmenter(grow).segment(street.scan).labels, DopplerSegmenter(uf).segment(street.scan).labels);
}

}  // namespace
}  // namespace fmcw::core
