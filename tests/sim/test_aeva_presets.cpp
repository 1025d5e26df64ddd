// The Aeva presets: the committed scenario with the Aeries II-like head carries scan lines and
// time offsets, and its scans read back through the Aeva file format pixel for pixel.

#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/io/aeva.hpp"
#include "fmcw/io/pcd.hpp"
#include "fmcw/sim/scenario.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::sim {
namespace {

const std::string kSource = FMCW_SOURCE_DIR;

class AevaPresets : public test::TempDirTest {};

TEST_F(AevaPresets, AeriesTwoScanReadsBackThroughTheAevaFormat) {
  const LoadedScenario loaded = load_scenario(kSource + "/scenarios/aeva_highway.yaml");
  ASSERT_TRUE(loaded.scenario.rig.scan_lines);
  SimulationSetup setup = build_simulation(loaded, 2);
  LidarSimulator sim(setup.scene, setup.ego, setup.params);
  const core::Frame f = sim.simulate(1, loaded.scenario.frame_time_s(1));
  const core::Scan& scan = f.scan;
  ASSERT_EQ(scan.cols, 600);  // 120 deg at 0.2 deg
  ASSERT_EQ(scan.rows, 96);   // 19.2 deg at 0.2 deg
  EXPECT_EQ(scan.velocity_frame, core::VelocityFrame::kEgoCompensated);
  ASSERT_EQ(scan.line_index.size(), scan.size());
  ASSERT_EQ(scan.time_offset_s.size(), scan.size());
  // Lines are rows; the time offsets sweep the frame (0 .. 0.1 s, left to right).
  EXPECT_EQ(scan.line_index[scan.index(37, 5)], 37);
  EXPECT_LT(scan.time_offset_s[scan.index(10, 0)], 0.01f);
  EXPECT_GT(scan.time_offset_s[scan.index(10, 599)], 0.09f);
  ASSERT_GT(scan.num_valid(), 10000u);

  // Through a PCD: line_index and time_offset_ns are fields, the velocity frame a comment.
  const std::string pcd = path("f.pcd");
  io::write_frame(pcd, f);
  const io::PcdCloud cloud = io::read_pcd(pcd);
  ASSERT_NE(cloud.find("line_index"), nullptr);
  ASSERT_NE(cloud.find("time_offset_ns"), nullptr);
  const core::Frame back = io::read_frame(pcd);
  EXPECT_EQ(back.scan.velocity_frame, core::VelocityFrame::kEgoCompensated);
  EXPECT_EQ(back.scan.line_index, scan.line_index);

  // Through an Aeva file: every return lands on its own pixel again.
  const std::string bin = path(io::aeva_file_name(scan.stamp_s));
  io::write_aeva(bin, io::aeva_records_from_scan(back.scan));
  io::AevaScanParams params;
  params.grid.lines = 96;  // the defaults are the Aeries II's 120 deg at 0.2 deg
  const core::GridProjection p = io::read_aeva_scan(bin, params);
  EXPECT_EQ(p.stats.collisions, 0u);
  EXPECT_EQ(p.stats.outside_fov, 0u);
  ASSERT_EQ(p.scan.rows, scan.rows);
  ASSERT_EQ(p.scan.cols, scan.cols);
  EXPECT_NEAR(p.scan.stamp_s, scan.stamp_s, 1e-9);
  const Eigen::Isometry3d T_head_rig = scan.heads[0].T_rig_head.inverse();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    ASSERT_EQ(p.scan.valid[i], scan.valid[i]) << "pixel " << i;
    if (!scan.valid[i]) continue;
    ASSERT_EQ(p.scan.radial_velocity_mps[i], scan.radial_velocity_mps[i]) << "pixel " << i;
    ASSERT_LT((p.scan.position(i) - T_head_rig * scan.position(i)).norm(), 1e-4) << "pixel " << i;
    ASSERT_NEAR(p.scan.time_offset_s[i], scan.time_offset_s[i], 1e-8) << "pixel " << i;
  }
}

TEST_F(AevaPresets, AevaScenesRigHasSixHeadsOnOneImage) {
  const core::RigModel rig = load_rig(kSource + "/configs/aevascenes_rig.yaml");
  ASSERT_EQ(rig.heads.size(), 6u);
  int wide = 0, narrow = 0;
  for (const core::HeadModel& h : rig.heads) {
    const double fov = h.fov_horizontal_rad * 180.0 / M_PI;
    wide += std::abs(fov - 110.0) < 1e-9 ? 1 : 0;
    narrow += std::abs(fov - 35.0) < 1e-9 ? 1 : 0;
    EXPECT_EQ(h.rows(), 48) << h.name;
    EXPECT_GT(h.T_rig_head.translation().z(), 1.9) << h.name;  // on the roof, above the rear axle's frame
  }
  EXPECT_EQ(wide, 4);
  EXPECT_EQ(narrow, 2);
  EXPECT_EQ(rig.cols(), 1450);
  EXPECT_TRUE(rig.scan_lines);
}

}  // namespace
}  // namespace fmcw::sim
