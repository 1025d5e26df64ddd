#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/core/head_model.hpp"

namespace fmcw::core {
namespace {

TEST(HeadModel, TableIHeadIs200By150) {
  const HeadModel head;
  EXPECT_EQ(head.cols(), 200);
  EXPECT_EQ(head.rows(), 150);
  // Column k looks 0.2 deg further right than column k - 1, starting half a pixel in.
  EXPECT_NEAR(head.azimuth_rad(0) * 180.0 / M_PI, 19.9, 1e-9);
  EXPECT_NEAR(head.azimuth_rad(199) * 180.0 / M_PI, -19.9, 1e-9);
  EXPECT_NEAR(head.elevation_rad(0) * 180.0 / M_PI, 14.9, 1e-9);
  EXPECT_NEAR(head.direction_head(75, 100).norm(), 1.0, 1e-12);
}

TEST(RigModel, PaperRigIs600By150WithStitchedSeamsAndSeparateOrigins) {
  const RigModel rig = RigModel::paper_rig();
  EXPECT_EQ(rig.cols(), 600);
  EXPECT_EQ(rig.rows(), 150);
  const auto infos = rig.head_infos();
  ASSERT_EQ(infos.size(), 3u);
  EXPECT_EQ(infos[1].col_begin, 200);
  EXPECT_TRUE(infos[0].stitched_to_next);
  EXPECT_TRUE(infos[1].stitched_to_next);
  EXPECT_FALSE(infos[2].stitched_to_next);
  EXPECT_GT((infos[0].origin_m() - infos[1].origin_m()).norm(), 0.1);
  // Across the seam, neighbouring columns of the middle row (elevation -0.1 deg) point 0.2 deg
  // apart in the rig frame, as columns inside one head do.
  const auto dirs = rig.directions_rig();
  const auto angle = [&](int a, int b) {
    return std::acos(dirs[static_cast<std::size_t>(a)].cast<double>().normalized().dot(
        dirs[static_cast<std::size_t>(b)].cast<double>().normalized()));
  };
  const int row = 75 * 600;
  EXPECT_NEAR(angle(row + 100, row + 101) * 180.0 / M_PI, 0.2, 1e-4);
  const double step = angle(row + 199, row + 200);
  EXPECT_NEAR(step * 180.0 / M_PI, 0.2, 1e-4);
}

TEST(RigModel, HeadsThatDoNotMeetAreNotStitched) {
  RigModel rig = RigModel::paper_rig();
  rig.heads[0].T_rig_head.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_FALSE(rig.head_infos()[0].stitched_to_next);
}

TEST(HeadModel, BadParametersAreRejectedByName) {
  HeadModel head;
  head.name = "roof";
  head.rate_hz = -10.0;
  try {
    head.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("head 'roof': rate must be > 0 Hz, got -10"), std::string::npos) << e.what();
  }
  head = HeadModel();
  head.resolution_horizontal_rad = 0.0;
  EXPECT_THROW(head.validate(), std::invalid_argument);
  head = HeadModel();
  head.fov_horizontal_rad = 0.01 * M_PI / 180.0;  // rounds to zero columns
  EXPECT_THROW(head.validate(), std::invalid_argument);
  head = HeadModel();
  head.max_range_m = 0.0;
  EXPECT_THROW(head.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace fmcw::core
