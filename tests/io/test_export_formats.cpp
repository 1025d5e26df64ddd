// PLY and SemanticKITTI writers, labels and colours on clouds whose every byte is known.
// (tests/python/test_export_tools.py loads the same files with Open3D, numpy and PCL.)

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <tuple>

#include "fmcw/core/semantic_classes.hpp"
#include "fmcw/io/ply.hpp"
#include "fmcw/io/point_colors.hpp"
#include "fmcw/io/point_labels.hpp"
#include "fmcw/io/semantic_kitti.hpp"
#include "support/ply_reader.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::io {
namespace {

class ExportTest : public fmcw::test::TempDirTest {
 protected:
  std::string bytes(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
};

// 2 x 2 cloud: point 1 has no return. Truth fields, and the estimate's label.
PcdCloud cloud() {
  const double nan = std::nan("");
  PcdCloud c;
  c.width = 2;
  c.height = 2;
  c.fields = {{"x", 'F', 4, {1, nan, 3, 4}},       {"y", 'F', 4, {0.5, nan, -0.5, 0}},
              {"z", 'F', 4, {0, nan, 1, 2}},        {"v", 'F', 4, {-20, nan, 0, 2.5}},
              {"intensity", 'F', 4, {0.1, 0, 0.2, 0.3}}, {"instance", 'U', 4, {0, 0, 7, 70000}},
              {"moving", 'U', 1, {0, 0, 1, 0}},     {"label", 'I', 4, {0, -1, 2, -2}}};
  c.comments = {"fmcw_stamp 0"};
  return c;
}

std::uint32_t u32_at(const std::string& s, std::size_t offset) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | static_cast<unsigned char>(s[offset + static_cast<std::size_t>(b)]);
  return v;
}
float f32_at(const std::string& s, std::size_t offset) {
  const std::uint32_t bits = u32_at(s, offset);
  float f = 0;
  std::memcpy(&f, &bits, 4);
  return f;
}

TEST_F(ExportTest, PlyHasEveryFieldOfTheCloudAndOnlyPointsWithAReturn) {
  const PcdCloud c = cloud();
  const std::vector<Rgb> colors = doppler_colors(c, 10.0, "test");
  EXPECT_EQ(write_ply(path("c.ply"), c, colors), 3u);
  const std::string s = bytes("c.ply");
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by fmcw export\ncomment fmcw_stamp 0\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float v\n"
      "property float intensity\nproperty uint instance\nproperty uchar moving\nproperty int label\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  ASSERT_EQ(s.substr(0, header.size()), header);
  const std::size_t stride = 4 * 5 + 4 + 1 + 4 + 3;
  ASSERT_EQ(s.size(), header.size() + 3 * stride);
  const std::size_t second = header.size() + stride;  // cloud point 2: point 1 had no return
  EXPECT_EQ(f32_at(s, second), 3.0f);
  EXPECT_EQ(u32_at(s, second + 20), 7u);  // uint instance
  EXPECT_EQ(s[second + 24], 1);
  EXPECT_EQ(u32_at(s, second + 25), 2u);
  // v = -20 m/s: full blue; v = 0: white.
  EXPECT_EQ(s.substr(header.size() + 29, 3), std::string("\x00\x00\xff", 3));
  EXPECT_EQ(s.substr(second + 29, 3), std::string("\xff\xff\xff", 3));
}

TEST_F(ExportTest, PlyRefusesWhatItCannotWrite) {
  PcdCloud c = cloud();
  c.fields.push_back({"big", 'U', 8, {0, 0, 0, 0}});
  EXPECT_THROW(write_ply(path("a.ply"), c), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path("a.ply")));
  // A field named red is a field like any other when no colour is asked for.
  c = cloud();
  c.fields.push_back({"red", 'U', 1, {0, 5, 9, 255}});
  EXPECT_EQ(write_ply(path("b.ply"), c), 3u);
  const test::PlyVertices b = test::read_ply(path("b.ply"));
  EXPECT_EQ(b.comments, (std::vector<std::string>{"written by fmcw export", "fmcw_stamp 0"}));
  EXPECT_EQ(b.names, (std::vector<std::string>{"x", "y", "z", "v", "intensity", "instance", "moving", "label", "red"}));
  EXPECT_EQ(b.types.at("red"), "uchar");
  EXPECT_EQ(b.types.at("label"), "int");
  ASSERT_EQ(b.count, 3u);
  // Cloud points 0, 2 and 3: point 1 has no return.
  EXPECT_EQ(b.values.at("x"), (std::vector<double>{1, 3, 4}));
  EXPECT_EQ(b.values.at("y"), (std::vector<double>{0.5, -0.5, 0}));
  EXPECT_EQ(b.values.at("v"), (std::vector<double>{-20, 0, 2.5}));
  EXPECT_EQ(b.values.at("instance"), (std::vector<double>{0, 7, 70000}));
  EXPECT_EQ(b.values.at("label"), (std::vector<double>{0, 2, -2}));
  EXPECT_EQ(b.values.at("red"), (std::vector<double>{0, 9, 255}));
  // Colours on top of it are refused, and the file written before is left whole.
  const std::string before = bytes("b.ply");
  EXPECT_THROW(write_ply(path("b.ply"), c, doppler_colors(c, 1.0, "t")), std::invalid_argument);
  EXPECT_EQ(bytes("b.ply"), before);
}

TEST_F(ExportTest, SemanticKittiPacksClassLowAndInstanceHigh) {
  PcdCloud c = cloud();
  c.fields[5].values[3] = 9;
  const std::map<std::uint32_t, std::string> classes = {{7, "car"}, {9, "pedestrian"}};
  const PointLabels truth = point_labels(c, LabelSource::kTruth, classes, "test");
  EXPECT_EQ(write_semantic_kitti(path("s.bin"), path("s.label"), c, truth, "test"), 3u);
  const std::string bin = bytes("s.bin");
  const std::string label = bytes("s.label");
  ASSERT_EQ(bin.size(), 3u * 16u);
  ASSERT_EQ(label.size(), 3u * 4u);
  EXPECT_EQ(f32_at(bin, 16), 3.0f);       // x of cloud point 2
  EXPECT_EQ(f32_at(bin, 16 + 12), 0.2f);  // its remission = intensity
  EXPECT_EQ(u32_at(label, 0), 9u);                 // static world: class 9, instance 0
  EXPECT_EQ(u32_at(label, 4), 252u | (7u << 16));  // moving car 7
  EXPECT_EQ(u32_at(label, 8), 30u | (9u << 16));   // pedestrian 9, standing still
}

TEST_F(ExportTest, LabelsFromTheEstimateAndTheirLimits) {
  const PcdCloud c = cloud();
  const PointLabels est = point_labels(c, LabelSource::kAuto, {}, "test");  // has 'label': the estimate
  EXPECT_EQ(est.source, LabelSource::kEstimate);
  EXPECT_EQ(est.semantic, (std::vector<std::uint16_t>{9, 0, 251, 0}));
  EXPECT_EQ(est.instance, (std::vector<std::uint16_t>{0, 0, 2, 0}));
  try {
    point_labels(c, LabelSource::kTruth, {}, "f.pcd");  // instance 70000 does not fit 16 bits
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("f.pcd: point 3: id 70000 does not fit"), std::string::npos) << e.what();
  }
  PcdCloud bare = c;
  bare.fields.resize(5);
  try {
    point_labels(bare, LabelSource::kAuto, {}, "bare.pcd");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bare.pcd: no labels"), std::string::npos) << e.what();
  }
  EXPECT_EQ(semantic_class("bus", true), 257);
  EXPECT_EQ(semantic_class("van", false), 10);
  EXPECT_EQ(semantic_class("tram", true), 251);
  EXPECT_EQ(semantic_class("tram", false), 99);
}

// With the field `class`, truth labels carry the class: SemanticKITTI's own ids as they are, van
// as other-vehicle, a scenario's own classes as other-object, moving codes where the surface
// moves (251 for a class SemanticKITTI has no moving code for).
TEST_F(ExportTest, SemanticKittiLabelsFromTheFieldClass) {
  PcdCloud c = cloud();
  c.fields.resize(7);  // no estimate: auto takes the truth
  c.fields[5].values = {0, 0, 7, 9};
  c.fields[6].values = {0, 0, 1, 1};
  c.fields.push_back({"class", 'U', 2, {40, 0, 100, 30}});
  PointLabels truth = point_labels(c, LabelSource::kAuto, {{7, "car"}}, "test");  // the field wins over the name
  EXPECT_EQ(truth.source, LabelSource::kTruth);
  EXPECT_EQ(truth.semantic, (std::vector<std::uint16_t>{40, 0, 259, 254}));  // road, no return, moving van, person
  EXPECT_EQ(truth.instance, (std::vector<std::uint16_t>{0, 0, 7, 9}));
  c.fields[6].values = {0, 0, 0, 0};
  truth = point_labels(c, LabelSource::kTruth, {}, "test");
  EXPECT_EQ(truth.semantic, (std::vector<std::uint16_t>{40, 0, 20, 30}));
  c.fields[7].values[0] = 0.5;
  try {
    point_labels(c, LabelSource::kTruth, {}, "f.pcd");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("f.pcd: point 0: class 0.5 is not a class id"), std::string::npos) << e.what();
  }
  EXPECT_EQ(semantic_kitti_class(10, false), 10);
  EXPECT_EQ(semantic_kitti_class(10, true), 252);
  EXPECT_EQ(semantic_kitti_class(18, true), 258);
  EXPECT_EQ(semantic_kitti_class(13, true), 257);
  EXPECT_EQ(semantic_kitti_class(31, true), 253);
  EXPECT_EQ(semantic_kitti_class(32, true), 255);
  EXPECT_EQ(semantic_kitti_class(20, true), 259);
  EXPECT_EQ(semantic_kitti_class(50, false), 50);
  EXPECT_EQ(semantic_kitti_class(100, false), 20);
  EXPECT_EQ(semantic_kitti_class(120, false), 99);  // a scenario's own (configs/classes.yaml: forklift)
  EXPECT_EQ(semantic_kitti_class(120, true), 251);
  EXPECT_EQ(semantic_kitti_class(11, true), 251);  // bicycle: no moving code in SemanticKITTI
  EXPECT_EQ(semantic_kitti_class(0, false), 0);
  EXPECT_EQ(semantic_kitti_class(0, true), 0);
}

TEST(PointColors, ClassPaletteIsFixedAndTellsTheBuiltInClassesApart) {
  const core::ClassTable table = core::ClassTable::builtin();
  std::set<std::tuple<int, int, int>> seen;
  for (const core::SemanticClass& c : table.classes()) {
    const Rgb rgb = class_color(c.id);
    EXPECT_TRUE(seen.insert({rgb.r, rgb.g, rgb.b}).second) << c.name << " shares its colour";
    EXPECT_FALSE(rgb.r == kUnknownClassColor.r && rgb.g == kUnknownClassColor.g && rgb.b == kUnknownClassColor.b) << c.name;
  }
  EXPECT_EQ(class_color(40).r, 255);  // road: SemanticKITTI's magenta
  EXPECT_EQ(class_color(40).g, 0);
  EXPECT_EQ(class_color(0).r + class_color(0).g + class_color(0).b, 0);
  EXPECT_EQ(class_color(120).r, kUnknownClassColor.r);
  EXPECT_EQ(class_color(120).g, kUnknownClassColor.g);

  PcdCloud c;
  c.width = 3;
  c.height = 1;
  c.fields = {{"x", 'F', 4, {1, std::nan(""), 2}}, {"class", 'U', 2, {70, 0, 70}}};
  const std::vector<Rgb> colors = class_colors(c, "c.pcd");
  ASSERT_EQ(colors.size(), 3u);
  EXPECT_EQ(colors[0].g, 175);  // vegetation
  EXPECT_EQ(colors[2].g, 175);
  c.fields.pop_back();
  try {
    class_colors(c, "c.pcd");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("c.pcd: no field 'class'"), std::string::npos) << e.what();
  }
}

TEST(PointColors, DopplerScaleAndLabelHues) {
  EXPECT_EQ(doppler_color(5.0, 10.0).r, 255);
  EXPECT_EQ(doppler_color(5.0, 10.0).g, 128);
  EXPECT_EQ(doppler_color(-50.0, 10.0).b, 255);
  EXPECT_EQ(doppler_color(-50.0, 10.0).r, 0);
  const Rgb grey = label_color(kSemanticStatic, 0);
  EXPECT_EQ(grey.r, 150);
  const Rgb moving = label_color(252, 3);
  const Rgb parked = label_color(10, 3);
  EXPECT_EQ(std::max({moving.r, moving.g, moving.b}), 255);
  EXPECT_EQ(std::max({parked.r, parked.g, parked.b}), 128);
  EXPECT_NE(label_color(252, 3).g, label_color(252, 4).g);
  EXPECT_THROW(doppler_color(1.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace fmcw::io
