// The Aeva Aeries II reader on small files written in the documented layout.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "fmcw/io/aeva.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::io {
namespace {

class AevaTest : public fmcw::test::TempDirTest {
 protected:
  // Expects f() to throw std::invalid_argument whose message holds every fragment.
  template <typename F>
  void expect_error(F&& f, const std::vector<std::string>& fragments) const {
    try {
      f();
      FAIL() << "expected an error";
    } catch (const std::invalid_argument& e) {
      for (const auto& s : fragments) EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << e.what();
    }
  }
};

AevaRecords sample(std::size_t n, bool with_intensity) {
  AevaRecords r;
  for (std::size_t i = 0; i < n; ++i) {
    const double az = (49.9 - static_cast<double>(i)) * M_PI / 180.0;  // bin centres at 0.2 deg
    r.x_m.push_back(static_cast<float>(20.0 * std::cos(az)));
    r.y_m.push_back(static_cast<float>(20.0 * std::sin(az)));
    r.z_m.push_back(0.25f * static_cast<float>(i % 3));
    r.reflectivity.push_back(0.1f * static_cast<float>(i));
    r.velocity_mps.push_back(-3.5f + 0.01f * static_cast<float>(i));
    r.time_offset_ns.push_back(i % 2 ? -123456789 : 2000000000);
    r.line_index.push_back(static_cast<std::uint8_t>(i % 4));
    if (with_intensity) r.intensity.push_back(0.5f + 0.001f * static_cast<float>(i));
  }
  return r;
}

// Bytes of one record assembled by hand, independent of the writer.
std::string record_bytes(float x, float y, float z, float refl, float vel, std::int32_t t, std::uint8_t line) {
  std::string out;
  for (const float f : {x, y, z, refl, vel}) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, 4);
    for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xFF));
  }
  const auto tb = static_cast<std::uint32_t>(t);
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((tb >> (8 * b)) & 0xFF));
  out.push_back(static_cast<char>(line));
  return out;
}

TEST_F(AevaTest, RecordsRoundTripInBothLayouts) {
  for (const bool with_intensity : {false, true}) {
    const AevaRecords r = sample(37, with_intensity);
    const std::string file = path(with_intensity ? "29.bin" : "25.bin");
    write_aeva(file, r);
    EXPECT_EQ(std::filesystem::file_size(file), 37u * (with_intensity ? 29u : 25u));
    const AevaRecords back = read_aeva(file);
    EXPECT_EQ(back.x_m, r.x_m);
    EXPECT_EQ(back.y_m, r.y_m);
    EXPECT_EQ(back.z_m, r.z_m);
    EXPECT_EQ(back.reflectivity, r.reflectivity);
    EXPECT_EQ(back.velocity_mps, r.velocity_mps);
    EXPECT_EQ(back.time_offset_ns, r.time_offset_ns);
    EXPECT_EQ(back.line_index, r.line_index);
    EXPECT_EQ(back.intensity, r.intensity);
  }
}

TEST_F(AevaTest, LittleEndianLayoutByteForByte) {
  const std::string bytes = record_bytes(1.5f, -2.0f, 0.25f, 7.0f, -0.5f, -42, 9);
  ASSERT_EQ(bytes.size(), kAevaRecordBytes);
  const std::string file = write("one.bin", bytes);
  const AevaRecords r = read_aeva(file, AevaLayout::k25);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r.x_m[0], 1.5f);
  EXPECT_EQ(r.y_m[0], -2.0f);
  EXPECT_EQ(r.reflectivity[0], 7.0f);
  EXPECT_EQ(r.velocity_mps[0], -0.5f);
  EXPECT_EQ(r.time_offset_ns[0], -42);
  EXPECT_EQ(r.line_index[0], 9);
  EXPECT_FALSE(r.has_intensity());
  // The writer produces the same bytes.
  write_aeva(path("again.bin"), r);
  std::ifstream in(path("again.bin"), std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), bytes);
}

TEST_F(AevaTest, ScanRowsAreLinesAndColumnsAzimuthBins) {
  AevaRecords r = sample(12, true);
  write_aeva(path("1700000000123456789.bin"), r);
  AevaScanParams p;
  p.grid.lines = 4;
  const core::GridProjection g = read_aeva_scan(path("1700000000123456789.bin"), p);
  EXPECT_EQ(g.scan.rows, 4);
  EXPECT_EQ(g.scan.cols, 600);
  EXPECT_NEAR(g.scan.stamp_s, 1700000000.123456789, 1e-6);
  EXPECT_EQ(g.stats.placed, 12u);
  ASSERT_EQ(g.scan.time_offset_s.size(), g.scan.size());
  for (std::size_t i = 0; i < r.size(); ++i) {
    // Point i at azimuth 49.9 - i deg: column (60 - az) / 0.2, line i % 4.
    const int col = static_cast<int>((60.0 - (49.9 - static_cast<double>(i))) / 0.2);
    const std::size_t pixel = g.scan.index(static_cast<int>(i % 4), col);
    ASSERT_EQ(g.pixel_of_point[i], static_cast<std::int64_t>(pixel)) << i;
    EXPECT_EQ(g.scan.radial_velocity_mps[pixel], r.velocity_mps[i]);
    EXPECT_EQ(g.scan.intensity[pixel], r.intensity[i]);  // intensity, not reflectivity, when present
    EXPECT_FLOAT_EQ(g.scan.time_offset_s[pixel], static_cast<float>(r.time_offset_ns[i] * 1e-9));
  }
}

TEST_F(AevaTest, BadFilesGetOneClearError) {
  const AevaRecords r = sample(10, false);
  write_aeva(path("ok.bin"), r);
  std::string bytes;
  {
    std::ifstream in(path("ok.bin"), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string cut = write("cut.bin", bytes.substr(0, bytes.size() - 1));
  expect_error([&] { read_aeva(cut, AevaLayout::k25); },
               {"cut.bin", "size 249 bytes is not a multiple of the 25-byte Aeva record", "9 whole records and 24 bytes"});
  expect_error([&] { read_aeva(cut); }, {"cut.bin", "neither 25-byte", "nor 29-byte", "truncated"});
  expect_error([&] { read_aeva(write("empty.bin", "")); }, {"empty.bin", "empty Aeva file"});
  expect_error([&] { read_aeva(path("missing.bin")); }, {"missing.bin", "cannot open"});
  expect_error([&] { read_aeva(dir_.string()); }, {"is a directory"});

  AevaRecords nan = r;
  nan.z_m[3] = std::nanf("");
  write_aeva(path("nan.bin"), nan);
  expect_error([&] { read_aeva(path("nan.bin")); }, {"nan.bin", "record 3 (byte 83): field 'z' is nan"});
  AevaRecords inf = sample(10, true);
  inf.intensity[2] = INFINITY;
  write_aeva(path("inf.bin"), inf);
  expect_error([&] { read_aeva(path("inf.bin"), AevaLayout::k29); }, {"record 2 (byte 83): field 'intensity' is inf"});

  AevaScanParams p;
  p.grid.lines = 3;  // sample() uses lines 0..3
  expect_error([&] { read_aeva_scan(path("ok.bin"), p); },
               {"ok.bin", "record 3: line_index 3 is out of range [0, 3)"});
  p.grid.lines = 0;
  p.grid.resolution_horizontal_deg = 0.7;
  expect_error([&] { read_aeva_scan(path("ok.bin"), p); }, {"must be a whole multiple"});
  expect_error([] { parse_aeva_layout("27"); }, {"auto, 25 or 29", "'27'"});
}

TEST_F(AevaTest, LayoutFromSizeAndFromTimeStampNames) {
  EXPECT_EQ(detect_aeva_layout("a.bin", 250), AevaLayout::k25);
  EXPECT_EQ(detect_aeva_layout("a.bin", 290), AevaLayout::k29);
  // 725 bytes fit both: a time-stamp name decides as the datasets' tools do.
  EXPECT_EQ(detect_aeva_layout("/d/1691936557946849179.bin", 725), AevaLayout::k25);
  EXPECT_EQ(detect_aeva_layout("/d/1691936557946849180.bin", 725), AevaLayout::k29);
  expect_error([] { detect_aeva_layout("/d/000001.bin", 1450); }, {"fits both 25- and 29-byte", "--aeva-record"});
}

}  // namespace
}  // namespace fmcw::io
