// The CLI on other people's formats: Aeva Aeries II scans and unorganized point clouds in,
// PLY / SemanticKITTI / PCD out, with one clear error for bad input.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>

#include "fmcw/core/ego_motion.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "fmcw/io/aeva.hpp"
#include "fmcw/io/pcd.hpp"
#include "support/cli.hpp"
#include "support/ply_reader.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using fmcw::test::CliResult;
using fmcw::test::run_cli;

class CliFormats : public fmcw::test::TempDirTest {};

constexpr double kDeg = M_PI / 180.0;
const Eigen::Vector3d kEgo(7.0, -0.6, 0.0);

// One 120 x 30 deg head at 0.2 deg, 1.8 m above the ground, driving through a walled street
// with one car crossing: what an Aeva sensor would see, with the scan lines as rows. Another
// field of view gives a frame of another rig.
fmcw::core::Frame street(double fov_horizontal_deg = 120.0, double fov_vertical_deg = 30.0) {
  fmcw::core::SyntheticSceneParams p;
  fmcw::core::HeadModel head;
  head.fov_horizontal_rad = fov_horizontal_deg * kDeg;
  head.fov_vertical_rad = fov_vertical_deg * kDeg;
  p.rig.heads = {head};
  p.ground_z_m = -1.8;
  fmcw::core::SyntheticBox wall;
  wall.center_m = {0.0, 14.0, 5.0};
  wall.half_extent_m = {200.0, 1.0, 10.0};
  fmcw::core::SyntheticBox other = wall;
  other.center_m.y() = -14.0;
  fmcw::core::SyntheticBox car;
  car.center_m = {18.0, 2.0, -1.0};
  car.half_extent_m = {2.2, 0.9, 0.8};
  car.velocity_mps = {-6.0, 0.0, 0.0};
  p.static_boxes = {wall, other};
  p.actors = {car};
  p.ego_velocity_mps = kEgo;
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  p.seed = 5;
  return fmcw::core::render_synthetic_scan(p);
}

// The scan's returns as Aeva records in a shuffled order (a sensor's order is not the image's).
fmcw::io::AevaRecords to_aeva(const fmcw::core::Scan& scan) {
  std::vector<std::size_t> order(scan.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(11));
  fmcw::io::AevaRecords r;
  for (const std::size_t i : order) {
    if (!scan.valid[i]) continue;
    r.x_m.push_back(scan.x_m[i]);
    r.y_m.push_back(scan.y_m[i]);
    r.z_m.push_back(scan.z_m[i]);
    r.reflectivity.push_back(scan.intensity[i]);
    r.velocity_mps.push_back(scan.radial_velocity_mps[i]);
    r.time_offset_ns.push_back(static_cast<std::int32_t>(i % 100000));
    r.line_index.push_back(static_cast<std::uint8_t>(i / static_cast<std::size_t>(scan.cols)));
  }
  return r;
}

// vx, vy of frame 0 in ego.csv (frame,source,method,status,static_pixels,clusters,vx,vy,...).
std::pair<double, double> ego_velocity(const fs::path& ego_csv) {
  const std::vector<std::string> cells = fmcw::test::csv_row(ego_csv);
  EXPECT_GE(cells.size(), 9u) << fmcw::test::slurp(ego_csv);
  if (cells.size() < 9) return {NAN, NAN};
  EXPECT_EQ(cells[3], "ok");
  return {std::stod(cells[6]), std::stod(cells[7])};
}

TEST_F(CliFormats, ProcessRunsTheCoreOnAnAevaScan) {
  const fmcw::core::Frame frame = street();
  const fmcw::io::AevaRecords records = to_aeva(frame.scan);
  fmcw::io::write_aeva(path("1690000000000000000.bin"), records);
  // These records hold the raw Doppler: the Aeva default (ego-compensated) is overridden.
  const CliResult r = run_cli("process --format aeva --aeva-lines 150 --velocity-frame raw " +
                              path("1690000000000000000.bin") + " -o " + path("out") + " --method robust");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("placed " + std::to_string(records.size()) + " of " + std::to_string(records.size()) +
                          " points (0 collisions, 0 outside the field of view) on 150 x 600 by line and azimuth"),
            std::string::npos)
      << r.output;
  const auto [vx, vy] = ego_velocity(dir_ / "out" / "ego.csv");
  EXPECT_NEAR(vx, kEgo.x(), 0.03);
  EXPECT_NEAR(vy, kEgo.y(), 0.03);
  EXPECT_TRUE(fs::exists(dir_ / "out" / "labels" / "1690000000000000000.pcd"));
  // The labelled cloud is the organized image: 600 x 150.
  const fmcw::io::PcdCloud labelled = fmcw::io::read_pcd((dir_ / "out" / "labels" / "1690000000000000000.pcd").string());
  EXPECT_EQ(labelled.width, 600);
  EXPECT_EQ(labelled.height, 150);
}

TEST_F(CliFormats, CompensatedAevaScanTakesItsEgoVelocityFromThePoses) {
  fmcw::core::Frame frame = street();
  fmcw::core::compensate_ego_velocity(frame.scan, {kEgo, Eigen::Vector3d::Zero()});
  fmcw::io::write_aeva(path("1690000000000000000.bin"), to_aeva(frame.scan));
  const std::string scan = path("1690000000000000000.bin");
  // Without poses: the frame assumed is said once, and the ego velocity is not measurable.
  CliResult r = run_cli("process --format aeva --aeva-lines 150 " + scan + " -o " + path("a") + " --method robust");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("velocity frame: ego-compensated assumed, from the Aeva datasets' convention"), std::string::npos)
      << r.output;
  const std::vector<std::string> cells = fmcw::test::csv_row(dir_ / "a" / "ego.csv");
  ASSERT_GE(cells.size(), 9u);
  EXPECT_EQ(cells[6], "nan");
  // With the poses (TUM, the rig driving at kEgo, stamps on the scan's clock).
  std::string tum = "# t x y z qx qy qz qw\n";
  for (int k = -2; k <= 2; ++k) {
    const Eigen::Vector3d p = kEgo * (0.1 * k);
    tum += std::to_string(1690000000 + 0.1 * k) + " " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " 0 0 0 0 1\n";
  }
  r = run_cli("process --format aeva --aeva-lines 150 " + scan + " -o " + path("b") + " --method robust --poses " +
              write("poses.tum", tum));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto [vx, vy] = ego_velocity(dir_ / "b" / "ego.csv");
  EXPECT_NEAR(vx, kEgo.x(), 0.03);
  EXPECT_NEAR(vy, kEgo.y(), 0.03);
  // Bad poses: one error line naming the file, nothing written.
  const auto refused = [&](const std::string& text, int code, const std::string& names) {
    const CliResult bad = run_cli("process --format aeva --aeva-lines 150 " + scan + " -o " + path("c") + " --poses " +
                                  write("bad.tum", text));
    EXPECT_EQ(bad.code, code) << bad.output;
    const std::vector<std::string> errors = fmcw::test::error_lines(bad.output);
    ASSERT_EQ(errors.size(), 1u) << bad.output;
    EXPECT_NE(errors[0].find(names), std::string::npos) << errors[0];
    EXPECT_FALSE(fs::exists(dir_ / "c" / "ego.csv"));
  };
  refused("1690000000.1 0 0 0 0 0 0 1\n1689999999.9 0 0 0 0 0 0 1\n", fmcw::test::kExitFile, "stamps must increase");
  refused("1689999999.9 0 0 0 0 0 0 1\n1690000000.1 nan 0 0 0 0 0 1\n", fmcw::test::kExitFile, "bad.tum:2");
  refused("1689999999.9 0 0 0 0 0 0 1\n1690000000.1 0 0 0 0.5 0 0 1\n", fmcw::test::kExitFile, "unit quaternion");
  refused("1689999999.8 0 0 0 0 0 0 1\n1689999999.9 0 0 0 0 0 0 1\n", fmcw::test::kExitUsage, "do not cover");
  refused("1689999999.9 0 0 0 0 0 1\n", fmcw::test::kExitFile, "7 values, expected 8");
}

TEST_F(CliFormats, ProcessProjectsAnUnorganizedCloud) {
  const fmcw::core::Frame frame = street();
  // x y z v as one row of points, no return dropped: HEIGHT 1, the layout most tools write.
  fmcw::io::PcdCloud cloud;
  cloud.height = 1;
  for (const char* name : {"x", "y", "z", "v"}) cloud.fields.push_back({name, 'F', 4, {}});
  for (std::size_t i = 0; i < frame.scan.size(); ++i) {
    if (!frame.scan.valid[i]) continue;
    cloud.fields[0].values.push_back(frame.scan.x_m[i]);
    cloud.fields[1].values.push_back(frame.scan.y_m[i]);
    cloud.fields[2].values.push_back(frame.scan.z_m[i]);
    cloud.fields[3].values.push_back(frame.scan.radial_velocity_mps[i]);
  }
  cloud.width = static_cast<int>(cloud.fields[0].values.size());
  fmcw::io::write_pcd(path("points.pcd"), cloud);
  // As an organized frame it is refused, with the reason.
  const CliResult organized = run_cli("process " + path("points.pcd") + " -o " + path("no"));
  EXPECT_EQ(organized.code, fmcw::test::kExitFile);
  EXPECT_NE(organized.output.find("HEIGHT 1"), std::string::npos) << organized.output;
  const CliResult r = run_cli("process --format points " + path("points.pcd") + " -o " + path("out") + " --method fast");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("on 150 x 600 by elevation and azimuth"), std::string::npos) << r.output;
  const auto [vx, vy] = ego_velocity(dir_ / "out" / "ego.csv");
  EXPECT_NEAR(vx, kEgo.x(), 0.03);
  EXPECT_NEAR(vy, kEgo.y(), 0.03);
}

TEST_F(CliFormats, ExportWritesEachFormatForEveryFrame) {
  fs::create_directories(dir_ / "in");
  ASSERT_EQ(run_cli("synth -o " + path("in/a.pcd") + " --objects 3").code, 0);
  ASSERT_EQ(run_cli("synth -o " + path("in/b.pcd") + " --objects 3 --seed 2").code, 0);
  for (const std::string to : {"ply", "kitti", "pcd"}) {
    const CliResult r = run_cli("export " + path("in") + " -o " + path(to) + " --to " + to);
    ASSERT_EQ(r.code, 0) << r.output;
  }
  for (const char* f : {"ply/a.ply", "ply/b.ply", "kitti/velodyne/a.bin", "kitti/labels/b.label", "pcd/a.pcd"}) {
    EXPECT_TRUE(fs::exists(dir_ / f)) << f;
  }
  // The PCD export reads back as the same frame.
  const fmcw::core::Frame a = fmcw::io::read_frame(path("in/a.pcd"));
  const fmcw::core::Frame back = fmcw::io::read_frame(path("pcd/a.pcd"));
  EXPECT_EQ(fs::file_size(dir_ / "kitti/velodyne/a.bin"), a.scan.num_valid() * 16);
  // The PLY holds every point with a return, in pixel order, at its position and Doppler, and
  // a colour per point.
  const fmcw::test::PlyVertices ply = fmcw::test::read_ply(path("ply/a.ply"));
  ASSERT_EQ(ply.count, a.scan.num_valid());
  for (const char* name : {"x", "y", "z", "v", "red", "green", "blue"}) ASSERT_EQ(ply.values.count(name), 1u) << name;
  std::size_t vertex = 0;
  for (std::size_t i = 0; i < a.scan.size(); ++i) {
    if (!a.scan.valid[i]) continue;
    ASSERT_EQ(ply.values.at("x")[vertex], a.scan.x_m[i]) << "pixel " << i;
    ASSERT_EQ(ply.values.at("y")[vertex], a.scan.y_m[i]) << "pixel " << i;
    ASSERT_EQ(ply.values.at("z")[vertex], a.scan.z_m[i]) << "pixel " << i;
    ASSERT_EQ(ply.values.at("v")[vertex], a.scan.radial_velocity_mps[i]) << "pixel " << i;
    ++vertex;
  }
  EXPECT_EQ(back.scan.radial_velocity_mps.size(), a.scan.radial_velocity_mps.size());
  EXPECT_TRUE(std::equal(a.scan.x_m.begin(), a.scan.x_m.end(), back.scan.x_m.begin(),
                         [](float p, float q) { return (std::isnan(p) && std::isnan(q)) || p == q; }));
}

// process compares every frame with the first: a frame of another rig (shape or heads) stops
// the run with one error naming both, and nothing of the run is left behind.
TEST_F(CliFormats, ProcessRefusesAFrameOfAnotherRig) {
  const fmcw::core::Frame first = street();
  fmcw::core::Frame moved = first;
  moved.scan.heads[0].T_rig_head.translation().x() = 1.5;
  struct Case {
    fmcw::core::Frame second;
    std::string message;
  };
  const std::vector<Case> cases = {
      {street(8.0, 4.0),
       "b.pcd: 20 x 40 pixels (rows x cols) with head 'head' [0, 40) differs from " + path("in/a.pcd") +
           ", the first frame: 150 x 600 pixels (rows x cols) with head 'head' [0, 600); every frame must come from "
           "one rig"},
      {moved, "b.pcd: head 'head' [0, 600) is mounted at (1.5, 0, 0), rotation quaternion (1, 0, 0, 0) where the first "
              "frame's is at (0, 0, 0), rotation quaternion (1, 0, 0, 0)"},
  };
  for (const Case& c : cases) {
    fs::remove_all(dir_ / "in");
    fs::create_directories(dir_ / "in");
    fmcw::io::write_frame(path("in/a.pcd"), first);
    fmcw::io::write_frame(path("in/b.pcd"), c.second);
    const CliResult r = run_cli("process " + path("in") + " -o " + path("out"));
    EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
    EXPECT_NE(r.output.find("fmcw: error: " + path("in/") + c.message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << "the run leaves nothing behind";
  }
}

// A 2 GiB file is refused from its size or its first line without being read: the CLI's peak
// memory stays far below the file's size.
TEST_F(CliFormats, HugeInputIsRefusedWithoutBeingRead) {
  const off_t two_gib = off_t{1} << 31;
  write("big.bin", "");
  ASSERT_EQ(::truncate(path("big.bin").c_str(), two_gib), 0);
  write("big.pcd", "VERSION");
  ASSERT_EQ(::truncate(path("big.pcd").c_str(), two_gib), 0);
  CliResult r = run_cli("process --format aeva " + path("big.bin") + " -o " + path("o1"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
  EXPECT_NE(r.output.find("big.bin: size 2147483648 bytes is not a whole number of Aeva records"), std::string::npos)
      << r.output;
  r = run_cli("process " + path("big.pcd") + " -o " + path("o2"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
  EXPECT_NE(r.output.find("big.pcd:1: header line too long"), std::string::npos) << r.output;
  fs::remove(path("big.bin"));
  fs::remove(path("big.pcd"));
  EXPECT_FALSE(fs::exists(dir_ / "o1"));
  EXPECT_FALSE(fs::exists(dir_ / "o2"));
  rusage children{};
  ::getrusage(RUSAGE_CHILDREN, &children);
  EXPECT_LT(children.ru_maxrss, 200 * 1024) << "peak resident memory of the CLI [KiB]";
}

TEST_F(CliFormats, BadInputGetsOneErrorLine) {
  fmcw::io::write_aeva(path("scan.bin"), to_aeva(street().scan));
  {
    std::ofstream bad(path("bad.bin"), std::ios::binary);
    bad << std::string(26, '\0');
  }
  struct Case {
    std::string args;
    std::string message;
    int code;  // the file's fault unless an option's
  };
  using fmcw::test::kExitFile;
  const std::vector<Case> cases = {
      {"process --format aeva " + path("bad.bin") + " -o " + path("o1"),
       "bad.bin: size 26 bytes is not a whole number of Aeva records", kExitFile},
      {"process --format aeva --aeva-lines 100 " + path("scan.bin") + " -o " + path("o2"),
       "is out of range [0, 100) (the sensor has 100 lines)", kExitFile},
      {"process --format aeva --res-h 0.7 " + path("scan.bin") + " -o " + path("o3"),
       "fov_horizontal_deg (120) must be a whole multiple of resolution_horizontal_deg (0.7)", fmcw::test::kExitUsage},
      {"export --format aeva " + path("scan.bin") + " -o " + path("o4") + " --to kitti",
       "no labels: the cloud has neither 'label'", kExitFile},
      {"export " + path("nothing") + " -o " + path("o5") + " --to ply", "does not exist", kExitFile},
      // (the output outside the input folder: inside it would be refused before bad.bin is read)
      {"process --format aeva " + dir_.string() + " -o " + dir_.string() + "_o6", "bad.bin", kExitFile},
      {"process --format aeva --res-h 1e-9 " + path("scan.bin") + " -o " + path("o7"),
       "grid projection: resolution_horizontal_deg 1e-09 over fov_horizontal_deg 120 gives 1.2e+11 columns",
       fmcw::test::kExitLimit},
  };
  for (const Case& c : cases) {
    const CliResult r = run_cli(c.args);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("fmcw: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "o4" / "velodyne" / "scan.bin"));
  EXPECT_FALSE(fs::exists(dir_ / "o7"));
}

}  // namespace
