#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/core/errors.hpp"
#include "fmcw/core/grid_projection.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "scenes.hpp"

namespace fmcw::core {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A point at a given azimuth, elevation [deg] and range [m], with Doppler v.
void add_point(PointList& points, double az_deg, double el_deg, double range_m, float v) {
  points.x_m.push_back(static_cast<float>(range_m * std::cos(el_deg * kDeg) * std::cos(az_deg * kDeg)));
  points.y_m.push_back(static_cast<float>(range_m * std::cos(el_deg * kDeg) * std::sin(az_deg * kDeg)));
  points.z_m.push_back(static_cast<float>(range_m * std::sin(el_deg * kDeg)));
  points.radial_velocity_mps.push_back(v);
}

GridProjectionParams small_grid() {
  GridProjectionParams g;
  g.fov_horizontal_deg = 10.0;
  g.resolution_horizontal_deg = 1.0;
  g.fov_vertical_deg = 4.0;
  g.resolution_vertical_deg = 1.0;
  return g;
}

// The message of the Error f throws, or "no error".
template <typename Error = std::invalid_argument, typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(GridProjection, ColumnKHoldsThePointAtAzimuthStepK) {
  // Ten points at 1 deg steps from the left edge inwards, on the row just above the horizon.
  PointList points;
  for (int k = 0; k < 10; ++k) add_point(points, 4.5 - k, 0.5, 10.0 + k, static_cast<float>(k));
  const GridProjection g = project_to_grid(points, small_grid());
  ASSERT_EQ(g.scan.rows, 4);
  ASSERT_EQ(g.scan.cols, 10);
  EXPECT_EQ(g.stats.placed, 10u);
  EXPECT_EQ(g.stats.collisions + g.stats.outside_fov, 0u);
  EXPECT_FALSE(g.stats.rows_by_line);
  for (int k = 0; k < 10; ++k) {
    const std::size_t i = g.scan.index(1, k);
    ASSERT_TRUE(g.scan.valid[i]) << "column " << k;
    EXPECT_EQ(g.scan.radial_velocity_mps[i], static_cast<float>(k));
    EXPECT_NEAR(g.scan.range_m[i], 10.0 + k, 1e-5);
    EXPECT_EQ(g.point_of_pixel[i], k);
    EXPECT_EQ(g.pixel_of_point[static_cast<std::size_t>(k)], static_cast<std::int64_t>(i));
  }
  EXPECT_EQ(g.scan.num_valid(), 10u);
  ASSERT_EQ(g.scan.heads.size(), 1u);
  EXPECT_TRUE(g.scan.heads[0].origin_m().isZero());
  EXPECT_NO_THROW(g.scan.validate());
}

TEST(GridProjection, NearestReturnWinsACollisionWhateverTheOrder) {
  for (const bool near_first : {true, false}) {
    PointList points;
    add_point(points, 0.5, 0.5, near_first ? 5.0 : 9.0, near_first ? 1.0f : 2.0f);
    add_point(points, 0.6, 0.6, near_first ? 9.0 : 5.0, near_first ? 2.0f : 1.0f);
    const GridProjection g = project_to_grid(points, small_grid());
    const std::size_t i = g.scan.index(1, 4);
    EXPECT_EQ(g.scan.radial_velocity_mps[i], 1.0f);
    EXPECT_EQ(g.point_of_pixel[i], near_first ? 0 : 1);
    EXPECT_EQ(g.pixel_of_point[near_first ? 1u : 0u], -1);
    EXPECT_EQ(g.stats.placed, 1u);
    EXPECT_EQ(g.stats.collisions, 1u);
  }
  // Equal range: the earlier point stays.
  PointList tie;
  add_point(tie, 0.5, 0.5, 7.0, 1.0f);
  add_point(tie, 0.7, 0.5, 7.0, 2.0f);
  EXPECT_EQ(project_to_grid(tie, small_grid()).point_of_pixel[small_grid().cols() + 4], 0);
}

TEST(GridProjection, PointsOutsideTheFieldOfViewAreCountedNotPlaced) {
  PointList points;
  add_point(points, 6.0, 0.5, 10.0, 0.0f);   // left of +5 deg
  add_point(points, -5.5, 0.5, 10.0, 0.0f);  // right of -5 deg
  add_point(points, 0.5, 2.5, 10.0, 0.0f);   // above +2 deg
  add_point(points, 0.5, 0.5, 10.0, 0.0f);
  const GridProjection g = project_to_grid(points, small_grid());
  EXPECT_EQ(g.stats.outside_fov, 3u);
  EXPECT_EQ(g.stats.placed, 1u);
  EXPECT_EQ(g.pixel_of_point[0], -1);
}

TEST(GridProjection, RowsByScanLine) {
  PointList points;
  add_point(points, 0.5, 10.0, 10.0, 0.0f);  // elevation is ignored when lines are given
  add_point(points, 0.5, -10.0, 10.0, 0.0f);
  points.line_index = {3, 0};
  GridProjection g = project_to_grid(points, small_grid());
  EXPECT_TRUE(g.stats.rows_by_line);
  EXPECT_EQ(g.scan.rows, 4);  // largest line + 1
  EXPECT_TRUE(g.scan.valid[g.scan.index(3, 4)]);
  EXPECT_TRUE(g.scan.valid[g.scan.index(0, 4)]);
  GridProjectionParams fixed = small_grid();
  fixed.lines = 8;
  EXPECT_EQ(project_to_grid(points, fixed).scan.rows, 8);
  fixed.lines = 3;
  EXPECT_EQ(error_of([&] { project_to_grid(points, fixed); }),
            "points: point 0: line index 3 is out of range [0, 3) (failed: params.lines == 0 || line < params.lines)");
}

TEST(GridProjection, FullCircleWrapsAzimuth) {
  GridProjectionParams g = small_grid();
  g.fov_horizontal_deg = 360.0;
  PointList points;
  points.x_m = {-10.0f, -10.0f};
  points.y_m = {0.0f, -0.0f};  // azimuth +180 and -180 deg: one direction
  points.z_m = {0.05f, 0.05f};
  points.radial_velocity_mps = {1.0f, 2.0f};
  const GridProjection p = project_to_grid(points, g);
  EXPECT_EQ(p.stats.outside_fov, 0u);
  EXPECT_EQ(p.stats.collisions, 1u);
}

TEST(GridProjection, BadInputNamesThePointAndField) {
  PointList points;
  add_point(points, 0.5, 0.5, 10.0, 0.0f);
  add_point(points, 0.5, 0.5, 10.0, std::nanf(""));
  EXPECT_NE(error_of([&] { project_to_grid(points, small_grid()); }).find("point 1: field 'v' is nan"), std::string::npos);
  points.radial_velocity_mps[1] = 0.0f;
  points.intensity = {1.0f};
  EXPECT_NE(error_of([&] { project_to_grid(points, small_grid()); }).find("field 'intensity' has 1 values, expected 0 or 2"),
            std::string::npos);
  points.intensity.clear();
  points.x_m[0] = points.y_m[0] = points.z_m[0] = 0.0f;
  EXPECT_NE(error_of([&] { project_to_grid(points, small_grid()); }).find("point 0 is at the sensor origin"),
            std::string::npos);
  GridProjectionParams g = small_grid();
  g.resolution_horizontal_deg = 0.3;
  EXPECT_NE(error_of([&] { g.validate(); }).find("fov_horizontal_deg (10) must be a whole multiple of resolution_horizontal_deg (0.3)"),
            std::string::npos);
  g = small_grid();
  g.resolution_vertical_deg = 0.0;
  EXPECT_NE(error_of([&] { g.validate(); }).find("resolution_vertical_deg must be in (0, fov_vertical_deg]"),
            std::string::npos);
}

// A bin typed in the wrong unit gives a grid of billions of pixels: refused naming the
// parameter and the size it would give, computed without integer overflow.
// A resource limit (LimitError), not a bad parameter: the resolution may be meant.
TEST(GridProjection, HugeGridIsRefusedNamingTheParameterAndTheSize) {
  PointList points;
  add_point(points, 0.5, 0.5, 10.0, 0.0f);
  GridProjectionParams g;
  g.resolution_horizontal_deg = 1e-9;
  for (const std::string& message :
       {error_of<LimitError>([&] { g.validate(); }), error_of<LimitError>([&] { project_to_grid(points, g); })}) {
    EXPECT_NE(message.find("grid projection: resolution_horizontal_deg 1e-09 over fov_horizontal_deg 120 gives "
                           "1.2e+11 columns"),
              std::string::npos)
        << message;
    EXPECT_EQ(message.find("-2147483648"), std::string::npos) << message;
  }
  g = GridProjectionParams{};
  g.resolution_vertical_deg = 1e-9;
  const std::string rows = error_of<LimitError>([&] { project_to_grid(points, g); });
  EXPECT_NE(rows.find("resolution_vertical_deg 1e-09 over fov_vertical_deg 30 gives 3e+10 rows"), std::string::npos)
      << rows;
  // Each span fits an int, their product does not fit the pixel limit.
  g = GridProjectionParams{};
  g.fov_horizontal_deg = 360.0;
  g.resolution_horizontal_deg = 0.001;
  g.resolution_vertical_deg = 0.001;
  const std::string both = error_of<LimitError>([&] { project_to_grid(points, g); });
  EXPECT_NE(both.find("grid projection: 30000 x 360000 pixels (1.08e+10) is more than the 67108864 a grid may have"),
            std::string::npos)
      << both;
}

// The documented path for unorganized input: a single-head scan flattened to a point list and
// projected onto a grid of the head's own resolution gives back the same image, and the motion
// pipeline finds the same ego velocity on it.
TEST(GridProjection, FlattenedScanProjectsBackOntoItsImage) {
  SyntheticSceneParams p = test::static_courtyard();
  HeadModel head;
  head.fov_horizontal_rad = 60.0 * kDeg;
  head.fov_vertical_rad = 20.0 * kDeg;
  head.resolution_horizontal_rad = 0.5 * kDeg;
  head.resolution_vertical_rad = 0.5 * kDeg;
  p.rig.heads = {head};
  p.ground_z_m = -1.6;  // the head sits 1.6 m above the ground
  p.ego_velocity_mps = {8.0, 0.5, 0.0};
  p.range_noise_m = 0.025;
  p.velocity_noise_mps = 0.031;
  p.seed = 3;
  const Scan scan = render_synthetic_scan(p).scan;

  PointList points;
  for (std::size_t i = scan.size(); i-- > 0;) {  // reversed order: the grid, not the order, decides
    if (!scan.valid[i]) continue;
    points.x_m.push_back(scan.x_m[i]);
    points.y_m.push_back(scan.y_m[i]);
    points.z_m.push_back(scan.z_m[i]);
    points.radial_velocity_mps.push_back(scan.radial_velocity_mps[i]);
  }
  GridProjectionParams g;
  g.fov_horizontal_deg = 60.0;
  g.fov_vertical_deg = 20.0;
  g.resolution_horizontal_deg = 0.5;
  g.resolution_vertical_deg = 0.5;
  const GridProjection projected = project_to_grid(points, g);
  ASSERT_EQ(projected.scan.rows, scan.rows);
  ASSERT_EQ(projected.scan.cols, scan.cols);
  EXPECT_EQ(projected.stats.placed, scan.num_valid());
  EXPECT_EQ(projected.scan.valid, scan.valid);
  EXPECT_EQ(projected.scan.radial_velocity_mps.size(), scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.valid[i]) continue;
    ASSERT_EQ(projected.scan.x_m[i], scan.x_m[i]) << "pixel " << i;
    ASSERT_EQ(projected.scan.radial_velocity_mps[i], scan.radial_velocity_mps[i]) << "pixel " << i;
  }
  MotionPipeline pipeline(MotionPipelineParams::preset("fast"));
  const MotionEstimate est = pipeline.process(projected.scan);
  ASSERT_TRUE(est.ok()) << est.message;
  EXPECT_NEAR(est.ego.velocity_mps.x(), 8.0, 0.02);
  EXPECT_NEAR(est.ego.velocity_mps.y(), 0.5, 0.02);
}

}  // namespace
}  // namespace fmcw::core
