#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "fmcw/core/errors.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "fmcw/io/frame_input.hpp"
#include "fmcw/io/pcd.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::io {
namespace {

namespace fs = std::filesystem;

class PcdTest : public fmcw::test::TempDirTest {
 protected:
  void write_text(const std::string& name, const std::string& text) const { write(name, text); }
  // Expects read_frame(path) to throw an Error (the file's fault, unless said otherwise) whose
  // message holds every fragment.
  template <typename Error = core::FileError>
  void expect_error(const std::string& name, const std::vector<std::string>& fragments) const {
    try {
      read_frame(path(name));
      FAIL() << "expected an error for " << name;
    } catch (const Error& e) {
      for (const auto& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
};

core::Frame small_frame() {
  core::SyntheticSceneParams p;
  p.rig = core::RigModel::paper_rig();
  for (auto& head : p.rig.heads) {
    head.fov_horizontal_rad = 4.0 * M_PI / 180.0;
    head.fov_vertical_rad = 3.0 * M_PI / 180.0;
  }
  p.rig.heads[0].T_rig_head.linear() = Eigen::AngleAxisd(4.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.rig.heads[2].T_rig_head.linear() = Eigen::AngleAxisd(-4.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  core::SyntheticBox wall;
  wall.center_m = {20.0, 0.0, 1.6};
  wall.half_extent_m = {0.5, 1.0, 1.0};  // covers the middle only: other beams see nothing
  core::SyntheticBox car = wall;
  car.center_m = {10.0, 0.3, 1.6};
  car.half_extent_m = {0.5, 0.3, 0.3};
  car.velocity_mps = {3.0, 1.0, 0.0};
  p.static_boxes = {wall};
  p.actors = {car};
  p.ground = false;
  p.ego_velocity_mps = {2.0, 0.0, 0.0};
  p.velocity_noise_mps = 0.031;
  p.seed = 4;
  return core::render_synthetic_scan(p);
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST_F(PcdTest, RoundTripKeepsEveryFieldHeadsAndTruthBitForBit) {
  const core::Frame frame = small_frame();
  ASSERT_GT(frame.scan.num_valid(), 10u);
  ASSERT_LT(frame.scan.num_valid(), frame.scan.size());
  write_frame(path("f.pcd"), frame);
  const core::Frame back = read_frame(path("f.pcd"));
  EXPECT_EQ(back.scan.rows, frame.scan.rows);
  EXPECT_EQ(back.scan.cols, frame.scan.cols);
  EXPECT_EQ(back.scan.valid, frame.scan.valid);
  for (std::size_t i = 0; i < frame.scan.size(); ++i) {
    if (!frame.scan.valid[i]) continue;
    ASSERT_EQ(back.scan.x_m[i], frame.scan.x_m[i]);
    ASSERT_EQ(back.scan.range_m[i], frame.scan.range_m[i]);
    ASSERT_EQ(back.scan.radial_velocity_mps[i], frame.scan.radial_velocity_mps[i]);
    ASSERT_EQ(back.scan.intensity[i], frame.scan.intensity[i]);
  }
  ASSERT_TRUE(back.truth.has_value());
  EXPECT_TRUE(same_bits(back.truth->range_m, frame.truth->range_m));
  EXPECT_TRUE(same_bits(back.truth->vx_mps, frame.truth->vx_mps));
  EXPECT_EQ(back.truth->instance, frame.truth->instance);
  EXPECT_EQ(back.truth->moving, frame.truth->moving);
  ASSERT_EQ(back.scan.heads.size(), 3u);
  for (std::size_t h = 0; h < 3; ++h) {
    EXPECT_EQ(back.scan.heads[h].name, frame.scan.heads[h].name);
    EXPECT_EQ(back.scan.heads[h].col_begin, frame.scan.heads[h].col_begin);
    EXPECT_EQ(back.scan.heads[h].stitched_to_next, frame.scan.heads[h].stitched_to_next);
    EXPECT_TRUE(back.scan.heads[h].T_rig_head.isApprox(frame.scan.heads[h].T_rig_head, 1e-12));
  }
  // Writing the read frame again gives the same bytes.
  write_frame(path("g.pcd"), back);
  std::ifstream a(path("f.pcd"), std::ios::binary), b(path("g.pcd"), std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}), std::string(std::istreambuf_iterator<char>(b), {}));
}

TEST_F(PcdTest, HeaderIsPlainPcdV07Organized) {
  const core::Frame frame = small_frame();
  write_frame(path("f.pcd"), frame, false);
  std::ifstream in(path("f.pcd"));
  std::string header, line;
  while (std::getline(in, line) && line.rfind("DATA", 0) != 0) header += line + "\n";
  EXPECT_NE(header.find("FIELDS x y z range v intensity\n"), std::string::npos) << header;
  EXPECT_NE(header.find("WIDTH " + std::to_string(frame.scan.cols) + "\n"), std::string::npos);
  EXPECT_NE(header.find("HEIGHT " + std::to_string(frame.scan.rows) + "\n"), std::string::npos);
  EXPECT_EQ(line, "DATA binary");
}

TEST_F(PcdTest, AsciiPcdWithoutRangeOrHeadsIsRead) {
  write_text("a.pcd",
             "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
             "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
             "3 4 0 -1.5\nnan nan nan nan\n1 0 0 0.25\n0 0 2 0\n");
  const core::Frame f = read_frame(path("a.pcd"));
  EXPECT_EQ(f.scan.rows, 2);
  EXPECT_EQ(f.scan.valid, (std::vector<std::uint8_t>{1, 0, 1, 1}));
  EXPECT_FLOAT_EQ(f.scan.range_m[0], 5.0f);  // from the origin of the single default head
  EXPECT_FLOAT_EQ(f.scan.radial_velocity_mps[2], 0.25f);
  EXPECT_FALSE(f.truth.has_value());
}

std::string header(const std::string& fields, const std::string& sizes, const std::string& types, int w, int h,
                   int points, const std::string& data = "binary") {
  return "VERSION 0.7\nFIELDS " + fields + "\nSIZE " + sizes + "\nTYPE " + types + "\nWIDTH " + std::to_string(w) +
         "\nHEIGHT " + std::to_string(h) + "\nPOINTS " + std::to_string(points) + "\nDATA " + data + "\n";
}

TEST_F(PcdTest, AMissingFileIsAFileErrorAndABadWriteArgumentAnInputError) {
  expect_error("missing.pcd", {"missing.pcd"});
  fs::create_directories(path("folder.pcd"));
  expect_error("folder.pcd", {"folder.pcd: is a directory"});
  PcdCloud cloud;
  cloud.width = 2;
  cloud.height = 1;
  cloud.fields = {{"x", 'F', 4, {1.0}}};  // one value for two points
  EXPECT_THROW(write_pcd(path("w.pcd"), cloud), core::InputError);
  EXPECT_FALSE(fs::exists(path("w.pcd")));
}

TEST_F(PcdTest, TruncatedDataIsReportedWithSizes) {
  write_text("t.pcd", header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4) + std::string(40, '\0'));
  expect_error("t.pcd", {"t.pcd", "truncated PCD", "64 bytes", "40 bytes"});
}

TEST_F(PcdTest, HeaderThatLiesAboutItsSizeIsRejected) {
  write_text("p.pcd", header("x y z v", "4 4 4 4", "F F F F", 2, 2, 5) + std::string(80, '\0'));
  expect_error("p.pcd", {"p.pcd:", "POINTS is 5 but WIDTH x HEIGHT is 2 x 2 = 4"});
  write_text("q.pcd", header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4) + std::string(64, '\0') + std::string(16, '\1'));
  expect_error("q.pcd", {"80 bytes but the header describes 64"});
  write_text("r.pcd", header("x y z v", "4 4 4", "F F F F", 2, 2, 4));
  expect_error("r.pcd", {"r.pcd:3: SIZE has 3 entries but FIELDS has 4"});
  write_text("s.pcd", header("x y z v", "4 4 4 3", "F F F F", 2, 2, 4));
  expect_error("s.pcd", {"field 'v' has TYPE F with SIZE 3"});
  write_text("u.pcd", "VERSION 0.7\nFIELDS x y z v\n");
  expect_error("u.pcd", {"u.pcd: PCD header has no SIZE line"});
  write_text("c.pcd", header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4, "binary_compressed"));
  expect_error("c.pcd", {"DATA 'binary_compressed' is not supported"});
  // A header promising 1.6 billion points over 64 bytes is refused before anything is allocated.
  write_text("big.pcd", header("x y z v", "4 4 4 4", "F F F F", 40000, 40000, 1600000000) + std::string(64, '\0'));
  expect_error("big.pcd", {"big.pcd: truncated PCD: header promises 1600000000 points of 16 bytes", "64 bytes of data"});
  write_text("bigascii.pcd", header("x y z v", "4 4 4 4", "F F F F", 40000, 40000, 1600000000, "ascii") + "1 2 3 4\n");
  expect_error("bigascii.pcd", {"truncated PCD: header promises 1600000000 points of 4 values but only 8 bytes follow"});
  write_text("cnt.pcd", "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 8\nTYPE F F F F\nCOUNT 1 1 1 2147483647\nWIDTH 40000\n"
                        "HEIGHT 40000\nPOINTS 1600000000\nDATA binary\n");
  expect_error<core::LimitError>("cnt.pcd", {"POINTS: 1600000000 points of", "is more data than a file can hold"});
  write_text("asc.pcd", header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4, "ascii") + "1 2 3 4\n1 2 3 4\n1 2 3 4\n");
  expect_error("asc.pcd", {"asc.pcd: truncated PCD: header promises 4 points"});
}

// PCL's writer stretches binary files to a memory page past the data, with zeros.
TEST_F(PcdTest, ZeroPaddingAfterBinaryDataAsPclWritesIsAccepted) {
  std::string data;
  for (const float f : {1.0f, 0.0f, 0.0f, 0.5f, 1.0f, 1.0f, 0.0f, 0.5f, 1.0f, 0.0f, 1.0f, 0.5f, 1.0f, 1.0f, 1.0f, 0.5f}) {
    data.append(reinterpret_cast<const char*>(&f), 4);
  }
  const std::string h = header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4);
  write_text("pcl.pcd", h + data + std::string(4096 - h.size(), '\0'));
  const core::Frame frame = read_frame(path("pcl.pcd"));
  EXPECT_EQ(frame.scan.num_valid(), 4u);
  EXPECT_EQ(frame.scan.radial_velocity_mps[3], 0.5f);
  write_text("big.pcd", h + data + std::string(70000, '\0'));
  expect_error("big.pcd", {"the header does not match the data"});
}

TEST_F(PcdTest, UnknownAndMissingFieldsAreNamed) {
  write_text("u.pcd", header("x y z v rgb", "4 4 4 4 4", "F F F F F", 2, 2, 4) + std::string(80, '\0'));
  expect_error("u.pcd", {"unknown field 'rgb'", "known: x y z range v"});
  write_text("m.pcd", header("x y z", "4 4 4", "F F F", 2, 2, 4) + std::string(48, '\0'));
  expect_error("m.pcd", {"missing field 'v'"});
  write_text("g.pcd", header("x y z v gt_v", "4 4 4 4 4", "F F F F F", 2, 2, 4) + std::string(80, '\0'));
  expect_error("g.pcd", {"ground truth is incomplete", "gt_range", "moving"});
}

TEST_F(PcdTest, NaNAndInfValuesAreRejectedWithThePixel) {
  const std::string h = "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA ascii\n";
  write_text("n.pcd", h + "1 0 0 0\n1 1 0 nan\n1 0 1 0\n1 1 1 0\n");
  expect_error("n.pcd", {"n.pcd", "(row 0, col 1)", "NaN or Inf 'v'"});
  write_text("i.pcd", h + "1 0 0 0\n1 1 0 0\ninf 0 1 0\n1 1 1 0\n");
  expect_error("i.pcd", {"(row 1, col 0) has an infinite coordinate"});
}

TEST_F(PcdTest, EmptyAndUnorganizedCloudsAreRejected) {
  write_text("e.pcd", header("x y z v", "4 4 4 4", "F F F F", 0, 0, 0));
  expect_error("e.pcd", {"the cloud has no points"});
  write_text("l.pcd", header("x y z v", "4 4 4 4", "F F F F", 4, 1, 4) + std::string(64, '\0'));
  expect_error("l.pcd", {"not organized (HEIGHT 1, WIDTH 4)", "project it onto a grid"});
  expect_error("missing.pcd", {"missing.pcd: cannot open PCD file"});
}

TEST_F(PcdTest, BadHeadCommentIsRejected) {
  write_text("h.pcd", "# fmcw_head a 0 1 0 0 0 0 1 0 0\n" + header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4) +
                          std::string(64, '\0'));
  expect_error("h.pcd", {"expected fmcw_head NAME COL_BEGIN COL_END"});
  write_text("k.pcd", "# fmcw_head a 0 1 0 0 0 0 1 0 0 0\n" + header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4) +
                          std::string(64, '\0'));
  expect_error("k.pcd", {"heads cover 1 columns but the scan has 2"});
}

// A stamp that is not a finite number would reset tracking quietly (dt is NaN); both readers
// of a PCD refuse it, naming the file and the comment.
TEST_F(PcdTest, StampThatIsNotAFiniteNumberIsRejected) {
  InputOptions points;
  points.format = InputFormat::kPoints;
  for (const std::string stamp : {"nan", "yesterday", "inf", "1e999", "12.5s"}) {
    write_text("s.pcd", "# fmcw_stamp " + stamp + "\n" + header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4, "ascii") +
                            "1 0 0 0\n1 1 0 0\n1 0 1 0\n1 1 1 0\n");
    const std::vector<std::string> message = {"s.pcd: comment '# fmcw_stamp " + stamp + "'",
                                              "the stamp must be a finite number of seconds"};
    expect_error("s.pcd", message);
    try {
      read_input_frame(path("s.pcd"), points);
      ADD_FAILURE() << "points: expected an error for stamp " << stamp;
    } catch (const std::invalid_argument& e) {
      for (const auto& f : message) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
  // A good stamp is read; the points reader takes the file too.
  write_text("g.pcd", "# fmcw_stamp 12.5\n" + header("x y z v", "4 4 4 4", "F F F F", 2, 2, 4, "ascii") +
                          "1 0 0 0\n1 1 0 0\n1 0 1 0\n1 1 1 0\n");
  EXPECT_EQ(read_frame(path("g.pcd")).scan.stamp_s, 12.5);
  EXPECT_NO_THROW(read_input_frame(path("g.pcd"), points));
}

// A field the frame needs with COUNT other than 1 is named as such, not as missing.
TEST_F(PcdTest, CountOtherThanOneOnAFrameFieldIsNamed) {
  write_text("c.pcd", "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1000000\nWIDTH 2\nHEIGHT 2\n"
                      "POINTS 4\nDATA binary\n" + std::string(4 * (12 + 4000000), '\0'));
  expect_error("c.pcd", {"c.pcd: field 'v' has COUNT 1000000; a frame's fields must have COUNT 1"});
  InputOptions points;
  points.format = InputFormat::kPoints;
  try {
    read_input_frame(path("c.pcd"), points);
    ADD_FAILURE() << "points: expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("c.pcd: field 'v' has COUNT 1000000; points need COUNT 1"), std::string::npos)
        << e.what();
  }
  // An optional field the frame would read (intensity) is not dropped quietly either.
  write_text("i.pcd", "VERSION 0.7\nFIELDS x y z v intensity\nSIZE 4 4 4 4 4\nTYPE F F F F F\nCOUNT 1 1 1 1 3\n"
                      "WIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA binary\n" + std::string(4 * 28, '\0'));
  expect_error("i.pcd", {"i.pcd: field 'intensity' has COUNT 3; a frame's fields must have COUNT 1"});
}

}  // namespace
}  // namespace fmcw::io
