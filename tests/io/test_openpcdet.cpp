// OpenPCDet's custom-dataset files and the .npy writer under them, byte by byte.
// (tests/python/test_export_labels.py loads the same files with numpy from a simulated dataset.)

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "fmcw/io/npy.hpp"
#include "fmcw/io/openpcdet.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::io {
namespace {

class OpenPcdetTest : public fmcw::test::TempDirTest {
 protected:
  std::string bytes(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
};

float f32_at(const std::string& s, std::size_t offset) {
  std::uint32_t bits = 0;
  for (int b = 3; b >= 0; --b) bits = (bits << 8) | static_cast<unsigned char>(s[offset + static_cast<std::size_t>(b)]);
  float f = 0;
  std::memcpy(&f, &bits, 4);
  return f;
}

TEST(Npy, HeaderIsVersion1AlignedTo64Bytes) {
  for (const std::size_t rows : {0ul, 3ul, 123456789ul}) {
    const std::string h = npy_f32_header(rows, 5);
    ASSERT_EQ(h.size() % 64, 0u) << rows;
    EXPECT_EQ(h.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const std::size_t length =
        static_cast<unsigned char>(h[8]) | (static_cast<std::size_t>(static_cast<unsigned char>(h[9])) << 8);
    EXPECT_EQ(length + 10, h.size());
    const std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", 5), }";
    EXPECT_EQ(h.substr(10, dict.size()), dict);
    EXPECT_EQ(h.back(), '\n');
    EXPECT_EQ(h.find_first_not_of(' ', 10 + dict.size()), h.size() - 1);  // spaces up to the newline
  }
}

TEST_F(OpenPcdetTest, NpyHoldsTheValuesLittleEndianAfterTheHeader) {
  write_npy_f32(path("a.npy"), {1.5f, -2.0f, 3.25f, 4.0f}, 2, 2);
  const std::string s = bytes("a.npy");
  const std::string header = npy_f32_header(2, 2);
  ASSERT_EQ(header.size(), 128u);  // 10 bytes, a dict of 60 and its newline: padded to 128
  ASSERT_EQ(s.size(), header.size() + 16u);
  EXPECT_EQ(s.substr(0, header.size()), header);
  EXPECT_EQ(f32_at(s, 128), 1.5f);
  EXPECT_EQ(f32_at(s, 128 + 12), 4.0f);
  EXPECT_THROW(write_npy_f32(path("b.npy"), {1.0f}, 2, 2), std::invalid_argument);
}

// A 2 x 2 cloud (point 1 without a return) and a frame with three actors, one of them unseen.
PcdCloud cloud() {
  const double nan = std::nan("");
  PcdCloud c;
  c.width = 2;
  c.height = 2;
  c.fields = {{"x", 'F', 4, {1, nan, 3, 4}},
              {"y", 'F', 4, {0.5, nan, -0.5, 0}},
              {"z", 'F', 4, {0, nan, 1, 2}},
              {"v", 'F', 4, {-20, nan, 0, 2.5}},
              {"intensity", 'F', 4, {0.1, nan, 0.2, 0.3}}};
  return c;
}

core::FrameTruth truth() {
  core::FrameTruth t;
  t.stamp_s = 0.5;
  for (const auto& [id, name, pixels] :
       {std::tuple<int, const char*, int>{3, "car", 120}, {5, "bus", 0}, {8, "pedestrian", 7}}) {
    core::ActorTruth a;
    a.id = static_cast<std::uint32_t>(id);
    a.class_name = name;
    a.pixels = pixels;
    a.box.center_m = {10.0 + id, -2.0, 0.75};
    a.box.size_m = {4.5, 1.8, 1.5};
    a.box.yaw_rad = 0.25 * id;
    a.box.velocity_mps = {1.0 * id, -0.5, 0.0};
    a.box.visible_fraction = 0.1 * id;
    a.box.truncated = id == 8;
    t.actors.push_back(a);
  }
  return t;
}

TEST_F(OpenPcdetTest, FrameHasPointsWithAReturnAndABoxPerActorWithPixels) {
  EXPECT_EQ(write_openpcdet_frame(path("p.npy"), path("l.txt"), cloud(), truth(), "f.pcd"), 3u);
  const std::string npy = bytes("p.npy");
  const std::string header = npy_f32_header(3, 5);
  ASSERT_EQ(npy.size(), header.size() + 3u * 5u * 4u);
  EXPECT_EQ(npy.substr(0, header.size()), header);
  const float second[] = {3.0f, -0.5f, 1.0f, 0.2f, 0.0f};  // cloud point 2: x y z intensity v
  for (std::size_t c = 0; c < 5; ++c) EXPECT_EQ(f32_at(npy, header.size() + 20 + 4 * c), second[c]) << c;
  EXPECT_EQ(f32_at(npy, header.size() + 16), -20.0f);  // v of the first point
  EXPECT_EQ(bytes("l.txt"), "13 -2 0.75 4.5 1.8 1.5 0.75 car\n18 -2 0.75 4.5 1.8 1.5 2 pedestrian\n");
}

TEST_F(OpenPcdetTest, MetaHasTheClassesAndPerBoxWhatTheLabelsCannotCarry) {
  std::vector<core::FrameTruth> frames = {truth(), truth()};
  frames[1].actors[0].pixels = 0;
  frames[1].actors.push_back(frames[1].actors[1]);
  frames[1].actors.back().class_name = "van";
  write_openpcdet_meta(path("meta.json"), {"000000", "000001"}, frames, "ds");
  const nlohmann::json meta = nlohmann::json::parse(bytes("meta.json"));
  EXPECT_EQ(meta["classes"], nlohmann::json({"car", "bus", "pedestrian", "van"}));
  EXPECT_EQ(meta["point_features"], nlohmann::json({"x", "y", "z", "intensity", "v"}));
  const nlohmann::json& boxes = meta["frames"]["000000"]["boxes"];
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_EQ(boxes[1]["actor_id"], 8);
  EXPECT_EQ(boxes[1]["class"], "pedestrian");
  EXPECT_EQ(boxes[1]["velocity_mps"], nlohmann::json({8.0, -0.5, 0.0}));
  EXPECT_DOUBLE_EQ(boxes[1]["visible_fraction"].get<double>(), 0.8);
  EXPECT_EQ(boxes[1]["truncated"], true);
  EXPECT_EQ(boxes[0]["truncated"], false);
  EXPECT_EQ(meta["frames"]["000001"]["frame"], 1);
  EXPECT_EQ(meta["frames"]["000001"]["boxes"].size(), 1u);  // car 3 unseen there, bus 5 and the "van" too

  write_openpcdet_split(path("train.txt"), {"000000", "000001"});
  EXPECT_EQ(bytes("train.txt"), "000000\n000001\n");
}

TEST_F(OpenPcdetTest, RefusesWhatItCannotWriteBeforeWritingAnything) {
  PcdCloud no_v = cloud();
  no_v.fields.erase(no_v.fields.begin() + 3);
  try {
    write_openpcdet_frame(path("p.npy"), path("l.txt"), no_v, truth(), "f.pcd");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("f.pcd: no field 'v'"), std::string::npos) << e.what();
  }
  core::FrameTruth spaced = truth();
  spaced.actors[0].class_name = "fork lift";
  EXPECT_THROW(write_openpcdet_frame(path("p.npy"), path("l.txt"), cloud(), spaced, "f.pcd"), std::invalid_argument);
  PcdCloud bad = cloud();
  bad.fields[4].values[2] = std::nan("");
  EXPECT_THROW(write_openpcdet_frame(path("p.npy"), path("l.txt"), bad, truth(), "f.pcd"), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path("p.npy")));
  EXPECT_FALSE(std::filesystem::exists(path("l.txt")));
}

}  // namespace
}  // namespace fmcw::io
