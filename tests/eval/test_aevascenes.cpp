// The AevaScenes layout: a sequence written by the project's own .npz writer reads back into
// the scans and the truth it was made from.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "fmcw/core/errors.hpp"
#include "fmcw/eval/aevascenes_source.hpp"
#include "fmcw/io/aevascenes.hpp"
#include "fmcw/io/npz.hpp"
#include "support/aevascenes_writer.hpp"
#include "support/temp_dir.hpp"

namespace fmcw {
namespace {

class AevaScenesLayout : public test::TempDirTest {
 protected:
  io::AevaScenesOptions grid() const { return {}; }  // the defaults: the test rig's heads
};

TEST_F(AevaScenesLayout, NpyBytesRoundTripEveryDtypeTheLayoutUses) {
  if (!io::npz_supported()) GTEST_SKIP() << "built without libzip";
  const std::string file = path("a.npz");
  io::write_npz(file, {{"f", io::npy_f32({1.5f, -2.0f, 3.25f}, {3, 1})},
                       {"u", io::npy_u32({0u, 7u, 4000000000u}, {3})},
                       {"i", io::npy_i64({-5, 0, 1LL << 40}, {3, 1})},
                       {"s", io::npy_strings({"car", "road", ""}, {3, 1})}});
  const auto a = io::read_npz(file);
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a.at("f").to_doubles("f"), (std::vector<double>{1.5, -2.0, 3.25}));
  EXPECT_EQ(a.at("u").to_doubles("u"), (std::vector<double>{0, 7, 4000000000.0}));
  EXPECT_EQ(a.at("i").to_doubles("i"), (std::vector<double>{-5, 0, 1099511627776.0}));
  EXPECT_EQ(a.at("s").to_strings("s"), (std::vector<std::string>{"car", "road", ""}));
  EXPECT_THROW(a.at("s").to_doubles("s"), core::FileError);
  // Not a zip, a truncated .npy member: one clear error each.
  EXPECT_THROW(io::read_npz(write("bad.npz", "not a zip")), core::FileError);
  EXPECT_THROW(io::parse_npy(io::npy_bytes(io::npy_f32({1, 2, 3}, {3})).substr(0, 130), "t.npy"), core::FileError);
  // A pickled object array is named as such when read.
  const std::string pickled = std::string("\x93NUMPY\x01\x00", 8) + std::string("\x46\x00", 2) +
                              "{'descr': '|O', 'fortran_order': False, 'shape': (2, 1), }" + std::string(11, ' ') + "\n";
  const io::NpyArray o = io::parse_npy(pickled, "p.npy");
  try {
    o.to_strings("p.npy");
    FAIL();
  } catch (const core::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("pickled"), std::string::npos) << e.what();
  }
}

TEST_F(AevaScenesLayout, ReadsBackTheScansTruthAndEgoMotionItWasWrittenFrom) {
  if (!io::npz_supported()) GTEST_SKIP() << "built without libzip";
  const test::AevaScenesFixture fx = test::write_aevascenes_sequence(dir_, 3);
  const io::AevaScenesSequence seq = io::read_aevascenes_sequence(dir_.string());
  ASSERT_EQ(seq.frames.size(), 3u);
  ASSERT_EQ(seq.lidars, fx.lidars);
  ASSERT_EQ(seq.track_ids, std::vector<std::string>{"car-1"});
  const core::ClassTable classes = core::ClassTable::builtin();
  for (std::size_t k = 0; k < 3; ++k) {
    io::AevaScenesOptions o = grid();
    const core::Frame comp = io::read_aevascenes_frame(seq, k, o, classes);
    EXPECT_EQ(comp.scan.velocity_frame, core::VelocityFrame::kEgoCompensated);
    o.to_sensor_frame = true;
    const core::Frame f = io::read_aevascenes_frame(seq, k, o, classes);
    const core::Frame& want = fx.frames[k];
    ASSERT_EQ(f.scan.rows, want.scan.rows);
    ASSERT_EQ(f.scan.cols, want.scan.cols);
    ASSERT_EQ(f.scan.num_valid(), want.scan.num_valid());
    std::size_t car = 0, agree = 0;
    for (std::size_t i = 0; i < f.scan.size(); ++i) {
      ASSERT_EQ(f.scan.valid[i], want.scan.valid[i]) << "pixel " << i;
      if (!f.scan.valid[i]) continue;
      // Pixel for pixel: the same point, the raw Doppler back from the compensated file.
      ASSERT_LT((f.scan.position(i) - want.scan.position(i)).norm(), 1e-4) << "pixel " << i;
      ASSERT_NEAR(f.scan.radial_velocity_mps[i], want.scan.radial_velocity_mps[i], 1e-4) << "pixel " << i;
      ASSERT_NEAR(f.truth->radial_velocity_mps[i], want.truth->radial_velocity_mps[i], 1e-4) << "pixel " << i;
      car += want.truth->instance[i] == 1 ? 1 : 0;
      agree += f.truth->instance[i] == want.truth->instance[i] ? 1 : 0;
      EXPECT_EQ(f.truth->moving[i], want.truth->moving[i]) << "pixel " << i;
      EXPECT_EQ(f.truth->semantic_class[i], *classes.find(want.truth->instance[i] ? "car" : "road"));
    }
    EXPECT_GT(car, 100u);
    EXPECT_EQ(agree, f.scan.num_valid());
    // Ego motion from the poses; the box as annotated.
    EXPECT_LT((f.frame_truth->ego.velocity_mps - fx.ego_velocity_mps).norm(), 1e-6);
    ASSERT_EQ(f.frame_truth->actors.size(), 1u);
    EXPECT_EQ(f.frame_truth->actors[0].id, 1u);
    EXPECT_EQ(f.frame_truth->actors[0].class_name, "car");
    EXPECT_EQ(static_cast<std::size_t>(f.frame_truth->actors[0].pixels), car);
    EXPECT_LT((f.frame_truth->actors[0].velocity_rig_mps - fx.car_velocity_mps).norm(), 1e-12);
    EXPECT_EQ(f.scan.heads[1].name, "left_lidar");
  }
}

TEST_F(AevaScenesLayout, BadSequencesAreOneClearFileError) {
  if (!io::npz_supported()) GTEST_SKIP() << "built without libzip";
  test::write_aevascenes_sequence(dir_, 2);
  const auto expect_error = [&](const std::string& from, const std::string& to, const std::string& names) {
    const std::string file = path("sequence.json");
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string saved = text;
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    write("sequence.json", text);
    try {
      eval::AevaScenesSource source(dir_.string());
      FAIL() << "accepted: " << to;
    } catch (const core::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
    }
    write("sequence.json", saved);
  };
  expect_error("\"ego_pose\": {\"translation\"", "\"ego_posed\": {\"translation\"", "missing key 'ego_pose'");
  expect_error("\"w\": 1", "\"w\": 2", "unit quaternion");
  expect_error("\"timestamp_ns\": 1700000000100000000", "\"timestamp_ns\": 1600000000000000000", "stamp");
  expect_error("{\"metadata\"", "[{\"metadata\"", "sequence.json");
  // A point cloud that is not there.
  std::filesystem::remove_all(dir_ / "pointcloud_compensated");
  EXPECT_THROW(eval::AevaScenesSource source(dir_.string()), core::FileError);
}

}  // namespace
}  // namespace fmcw
