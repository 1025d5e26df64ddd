// MCAP: the writer's layout against the specification, the reader's errors (truncated file, bad
// CRC, unknown schema, missing field, each naming the file and the record's offset), PointCloud2
// in CDR, and the round trip PCD frame -> MCAP -> scan, bit for bit.

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "fmcw/core/errors.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "fmcw/io/frame_input.hpp"
#include "fmcw/io/input_sequence.hpp"
#include "fmcw/io/mcap_export.hpp"
#include "fmcw/io/mcap_frames.hpp"
#include "fmcw/io/mcap_reader.hpp"
#include "fmcw/io/ros2_messages.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace io = fmcw::io;
namespace core = fmcw::core;
using Bytes = std::string;

class Mcap : public fmcw::test::TempDirTest {
 protected:
  std::string save(const std::string& name, const Bytes& bytes) const {
    std::ofstream(path(name), std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path(name);
  }
  // The FileError message of opening `file` on `topic` and reading every frame; "" when none.
  static std::string read_error(const std::string& file, const std::string& doppler = "auto") {
    try {
      io::McapInputOptions o;
      o.doppler_field = doppler;
      io::McapFrames frames(file, o);
      for (std::size_t k = 0; k < frames.size(); ++k) io::frame_from_pcd(frames.cloud(k), frames.source(k));
    } catch (const core::FileError& e) {
      return e.what();
    }
    return "";
  }
};

// The paper rig (three heads, seams) on a street with a moving car, with per-beam times.
core::Frame frame_at(int k) {
  core::SyntheticSceneParams p;
  p.ground_z_m = -1.7;
  core::SyntheticBox car;
  car.center_m = {15.0 + k, 1.0, -1.0};
  car.half_extent_m = {2.0, 0.9, 0.7};
  car.velocity_mps = {4.0, 0.5, 0.0};
  p.actors = {car};
  p.ego_velocity_mps = {6.0, 0.0, 0.0};
  p.velocity_noise_mps = 0.031;
  p.range_noise_m = 0.025;
  p.seed = 3 + static_cast<std::uint64_t>(k);
  core::Frame f = core::render_synthetic_scan(p);
  f.scan.stamp_s = 0.1 * k;
  f.scan.time_offset_s.resize(f.scan.size());
  for (std::size_t i = 0; i < f.scan.size(); ++i) f.scan.time_offset_s[i] = 1e-7f * static_cast<float>(i);
  return f;
}

// An export of `frames` PCD clouds, as `fmcw export --to mcap` writes it.
Bytes export_clouds(const std::vector<io::PcdCloud>& clouds, io::McapCompression compression) {
  std::ostringstream out(std::ios::binary);
  io::McapExportOptions o;
  o.writer.compression = compression;
  io::McapSequenceWriter w(out, o);
  for (std::size_t k = 0; k < clouds.size(); ++k) w.add_frame(clouds[k], "frame" + std::to_string(k), nullptr, nullptr);
  w.finish();
  return out.str();
}

std::uint64_t u64_at(const Bytes& b, std::size_t at) {
  std::uint64_t v = 0;
  std::memcpy(&v, b.data() + at, 8);
  return v;
}
std::uint32_t u32_at(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}
std::uint32_t crc(const Bytes& b, std::size_t from, std::size_t to) {
  return static_cast<std::uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(b.data() + from), static_cast<uInt>(to - from)));
}

TEST(Cdr, PointCloud2RoundTripsAndAlignsAsRos2) {
  io::ros2::PointCloud2 c;
  c.stamp = {12, 500};
  c.frame_id = "rig";
  c.height = 2;
  c.width = 3;
  c.fields = {{"x", 0, io::ros2::kFloat32, 1}, {"label", 4, io::ros2::kInt32, 1}};
  c.point_step = 8;
  c.row_step = 24;
  c.data.resize(48);
  for (std::size_t i = 0; i < c.data.size(); ++i) c.data[i] = static_cast<std::uint8_t>(i * 7);
  const std::vector<std::uint8_t> b = io::ros2::encode(c);
  // CDR_LE header, then sec, nanosec, frame_id "rig\0" (length 4), height at byte 4 + 12.
  ASSERT_GE(b.size(), 20u);
  EXPECT_EQ(b[0], 0);
  EXPECT_EQ(b[1], 1);
  std::uint32_t height = 0, frame_id_length = 0;
  std::memcpy(&frame_id_length, b.data() + 12, 4);
  std::memcpy(&height, b.data() + 20, 4);
  EXPECT_EQ(frame_id_length, 4u);
  EXPECT_EQ(height, 2u);
  const io::ros2::PointCloud2 d = io::ros2::decode_point_cloud2(b.data(), b.size(), "msg");
  EXPECT_EQ(d.stamp.sec, 12);
  EXPECT_EQ(d.stamp.nanosec, 500u);
  EXPECT_EQ(d.frame_id, "rig");
  ASSERT_EQ(d.fields.size(), 2u);
  EXPECT_EQ(d.fields[1].name, "label");
  EXPECT_EQ(d.fields[1].offset, 4u);
  EXPECT_EQ(d.fields[1].datatype, io::ros2::kInt32);
  EXPECT_EQ(d.data, c.data);
  // Every cut of the message is refused with the byte at fault, never read past.
  for (std::size_t n = 0; n < b.size(); n += 5) {
    EXPECT_THROW(io::ros2::decode_point_cloud2(b.data(), n, "msg"), core::FileError) << n;
  }
}

TEST(Cdr, DefinitionsEmbedTheirDependencies) {
  const std::string& text = io::ros2::point_cloud2_definition();
  EXPECT_EQ(text.rfind("std_msgs/Header header\n", 0), 0u);
  EXPECT_NE(text.find("\n================================================================================\nMSG: std_msgs/Header\n"),
            std::string::npos);
  EXPECT_NE(text.find("MSG: sensor_msgs/PointField\n"), std::string::npos);
  EXPECT_NE(io::ros2::marker_array_definition().find("MSG: visualization_msgs/Marker\n"), std::string::npos);
  EXPECT_NE(io::ros2::tf_message_definition().find("MSG: geometry_msgs/TransformStamped\n"), std::string::npos);
}

// The file's layout, read by hand from the specification's record layouts.
TEST_F(Mcap, LayoutFollowsTheSpecification) {
  const Bytes b = export_clouds({io::pcd_from_frame(frame_at(0)), io::pcd_from_frame(frame_at(1))}, io::McapCompression::kNone);
  const Bytes magic("\x89MCAP0\r\n", 8);
  ASSERT_GT(b.size(), 100u);
  EXPECT_EQ(b.substr(0, 8), magic);
  EXPECT_EQ(b.substr(b.size() - 8), magic);
  EXPECT_EQ(b[8], 0x01);  // Header
  // Footer: opcode 2, length 20, summary_start, summary_offset_start, summary_crc.
  const std::size_t footer = b.size() - 8 - 29;
  EXPECT_EQ(b[footer], 0x02);
  EXPECT_EQ(u64_at(b, footer + 1), 20u);
  const std::uint64_t summary = u64_at(b, footer + 9), offsets = u64_at(b, footer + 17);
  EXPECT_EQ(u32_at(b, footer + 25), crc(b, summary, footer + 25));
  // DataEnd directly before the summary, with the CRC of every byte before it.
  const std::size_t data_end = summary - 13;
  EXPECT_EQ(b[data_end], 0x0F);
  EXPECT_EQ(u32_at(b, data_end + 9), crc(b, 0, data_end));
  // The summary offsets name each group; the chunk indexes point at chunks whose CRC holds.
  std::size_t chunk_indexes = 0;
  for (std::size_t at = offsets; at < footer; at += 9 + u64_at(b, at + 1)) {
    ASSERT_EQ(b[at], 0x0E);
    const auto group = static_cast<std::uint8_t>(b[at + 9]);
    const std::uint64_t start = u64_at(b, at + 10), length = u64_at(b, at + 18);
    EXPECT_EQ(b[start], group);
    for (std::size_t r = start; r < start + length; r += 9 + u64_at(b, r + 1)) {
      ASSERT_EQ(static_cast<std::uint8_t>(b[r]), group);
      if (group != 0x08) continue;
      ++chunk_indexes;
      const std::uint64_t chunk = u64_at(b, r + 9 + 16), chunk_length = u64_at(b, r + 9 + 24);
      ASSERT_EQ(b[chunk], 0x06);
      EXPECT_EQ(9 + u64_at(b, chunk + 1), chunk_length);
      const std::uint64_t uncompressed = u64_at(b, chunk + 9 + 16);
      const std::uint32_t records_crc = u32_at(b, chunk + 9 + 24);
      ASSERT_EQ(u32_at(b, chunk + 9 + 28), 0u);  // compression "" (uncompressed)
      const std::size_t records = chunk + 9 + 32 + 8;
      EXPECT_EQ(u64_at(b, records - 8), uncompressed);
      EXPECT_EQ(records_crc, crc(b, records, records + uncompressed));
      EXPECT_EQ(b[records], 0x05);  // the frame's first message: its /tf_static or its cloud
      EXPECT_EQ(b[chunk + chunk_length], 0x07);  // then its message indexes
    }
  }
  EXPECT_EQ(chunk_indexes, 2u);
}

TEST_F(Mcap, RoundTripEqualsThePcdScanBitForBit) {
  for (const auto compression : {io::McapCompression::kNone, io::McapCompression::kZstd}) {
    std::vector<io::PcdCloud> clouds;
    std::vector<core::Frame> pcd_frames;
    for (int k = 0; k < 3; ++k) {
      const std::string pcd = path("f" + std::to_string(k) + ".pcd");
      io::write_frame(pcd, frame_at(k));
      clouds.push_back(io::read_pcd(pcd));
      pcd_frames.push_back(io::read_frame(pcd));
    }
    const std::string file = save("seq.mcap", export_clouds(clouds, compression));
    io::InputOptions options;
    options.format = io::InputFormat::kMcap;
    io::InputSequence seq(file, options);
    ASSERT_EQ(seq.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      const io::InputFrame in = seq.read(k);
      EXPECT_FALSE(in.projected);
      const core::Scan& a = pcd_frames[k].scan;
      const core::Scan& b = in.frame.scan;
      ASSERT_EQ(b.rows, a.rows);
      ASSERT_EQ(b.cols, a.cols);
      const auto same = [](const auto& x, const auto& y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
      };
      EXPECT_TRUE(same(a.x_m, b.x_m));
      EXPECT_TRUE(same(a.y_m, b.y_m));
      EXPECT_TRUE(same(a.z_m, b.z_m));
      EXPECT_TRUE(same(a.range_m, b.range_m));
      EXPECT_TRUE(same(a.radial_velocity_mps, b.radial_velocity_mps));
      EXPECT_TRUE(same(a.intensity, b.intensity));
      EXPECT_TRUE(same(a.valid, b.valid));
      EXPECT_TRUE(same(a.time_offset_s, b.time_offset_s));
      ASSERT_EQ(b.heads.size(), 3u);
      for (std::size_t h = 0; h < 3; ++h) {
        EXPECT_EQ(b.heads[h].name, a.heads[h].name);
        EXPECT_EQ(b.heads[h].col_begin, a.heads[h].col_begin);
        EXPECT_EQ(b.heads[h].stitched_to_next, a.heads[h].stitched_to_next);
        EXPECT_TRUE(b.heads[h].T_rig_head.isApprox(a.heads[h].T_rig_head, 0.0));
      }
      // ROS time is whole nanoseconds: the stamp is equal to the nanosecond.
      EXPECT_EQ(std::llround(b.stamp_s * 1e9), std::llround(a.stamp_s * 1e9));
      ASSERT_TRUE(in.frame.truth.has_value());
      const core::PixelGroundTruth& ta = *pcd_frames[k].truth;
      const core::PixelGroundTruth& tb = *in.frame.truth;
      EXPECT_TRUE(same(ta.range_m, tb.range_m));
      EXPECT_TRUE(same(ta.radial_velocity_mps, tb.radial_velocity_mps));
      EXPECT_TRUE(same(ta.vx_mps, tb.vx_mps));
      EXPECT_TRUE(same(ta.vy_mps, tb.vy_mps));
      EXPECT_TRUE(same(ta.vz_mps, tb.vz_mps));
      EXPECT_TRUE(same(ta.instance, tb.instance));
      EXPECT_TRUE(same(ta.moving, tb.moving));
      EXPECT_TRUE(same(ta.semantic_class, tb.semantic_class));
    }
  }
}

TEST_F(Mcap, TruncatedFileNamesTheOffset) {
  const Bytes b = export_clouds({io::pcd_from_frame(frame_at(0))}, io::McapCompression::kZstd);
  for (const std::size_t keep : {std::size_t{5}, std::size_t{60}, b.size() / 2, b.size() - 9, b.size() - 1}) {
    const std::string file = save("cut.mcap", b.substr(0, keep));
    const std::string e = read_error(file);
    EXPECT_NE(e.find(file + ": "), std::string::npos) << e;
    EXPECT_NE(e.find("offset"), std::string::npos) << e;
    if (keep > 8) {
      EXPECT_NE(e.find("truncated"), std::string::npos) << keep << ": " << e;
    }
  }
  // A file cut inside its chunk, given a footer (without summary) and magic again: the chunk
  // runs past the end of the data section.
  Bytes footer(29, '\0');
  footer[0] = 0x02;
  footer[1] = 20;
  const std::size_t cut_at = b.size() / 2;
  const std::string file = save("refooted.mcap", b.substr(0, cut_at) + footer + b.substr(b.size() - 8));
  const std::string e = read_error(file);
  EXPECT_NE(e.find(file + ": record at offset "), std::string::npos) << e;
  EXPECT_NE(e.find("(Chunk): "), std::string::npos) << e;
  EXPECT_NE(e.find("run past the end of the data at offset " + std::to_string(cut_at) + ": truncated"), std::string::npos)
      << e;
  EXPECT_EQ(read_error(save("whole.mcap", b)), "");
}

TEST_F(Mcap, BadCrcIsFound) {
  const Bytes b = export_clouds({io::pcd_from_frame(frame_at(0))}, io::McapCompression::kNone);
  const std::size_t footer = b.size() - 8 - 29;
  const std::uint64_t summary = u64_at(b, footer + 9);
  // A flipped bit in a point: the chunk's CRC says so.
  Bytes in_chunk = b;
  in_chunk[summary / 2] = static_cast<char>(in_chunk[summary / 2] ^ 0x10);
  std::string e = read_error(save("a.mcap", in_chunk));
  EXPECT_NE(e.find("(Chunk): bad CRC"), std::string::npos) << e;
  EXPECT_NE(e.find("record at offset"), std::string::npos) << e;
  // A flipped bit in the summary: the footer's CRC says so.
  Bytes in_summary = b;
  in_summary[summary + 20] = static_cast<char>(in_summary[summary + 20] ^ 0x01);
  e = read_error(save("b.mcap", in_summary));
  EXPECT_NE(e.find("record at offset " + std::to_string(footer) + " (Footer): bad CRC"), std::string::npos) << e;
  // The DataEnd CRC: a flipped bit in the Header record (covered by no chunk CRC).
  Bytes in_header = b;
  in_header[9 + 8 + 4] = static_cast<char>(in_header[9 + 8 + 4] ^ 0x20);  // a letter of the profile
  e = read_error(save("c.mcap", in_header));
  EXPECT_NE(e.find("(DataEnd): bad CRC"), std::string::npos) << e;
}

TEST_F(Mcap, UnknownSchemaAndMissingTopicAreNamed) {
  std::ostringstream out(std::ios::binary);
  {
    io::McapWriter w(out);
    const auto s = w.add_schema("my_msgs/msg/Blob", "ros2msg", "uint8[] data\n");
    const auto c = w.add_channel("/points", s, "cdr");
    w.write(c, 5, {0, 1, 0, 0, 0, 0, 0, 0});
    w.finish();
  }
  const std::string file = save("blob.mcap", out.str());
  std::string e = read_error(file);
  EXPECT_NE(e.find(file + ": record at offset "), std::string::npos) << e;
  EXPECT_NE(e.find("unknown schema 'my_msgs/msg/Blob'"), std::string::npos) << e;
  try {
    io::McapInputOptions o;
    o.topic = "/lidar";
    io::McapFrames frames(file, o);
    ADD_FAILURE() << "no error for a missing topic";
  } catch (const core::FileError& err) {
    EXPECT_NE(std::string(err.what()).find("no channel on topic '/lidar'; the file has: /points (my_msgs/msg/Blob)"),
              std::string::npos)
        << err.what();
  }
}

TEST_F(Mcap, DopplerFieldByNameAndMissingField) {
  io::PcdCloud cloud = io::pcd_from_frame(frame_at(0), false);
  for (auto& f : cloud.fields) {
    if (f.name == "v") f.name = "radial_vel";
  }
  io::PcdField ring{"ring", 'U', 2, std::vector<double>(cloud.points(), 3.0)};
  cloud.fields.push_back(ring);
  const std::string file = save("radial.mcap", export_clouds({cloud}, io::McapCompression::kZstd));
  io::McapFrames frames(file, io::McapInputOptions{});
  const io::PcdCloud back = frames.cloud(0);
  ASSERT_NE(back.find("v"), nullptr);
  EXPECT_EQ(back.find("ring"), nullptr);  // not a frame's field: dropped (and said on stderr)
  const auto& got = back.find("v")->values;
  const auto& want = cloud.find("radial_vel")->values;
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(std::memcmp(got.data(), want.data(), got.size() * sizeof(double)), 0);  // NaN where no return
  EXPECT_EQ(read_error(file, "radial_vel"), "");
  const std::string e = read_error(file, "velocity");
  EXPECT_NE(e.find(file + ": message at offset "), std::string::npos) << e;
  EXPECT_NE(e.find("missing field: no Doppler field 'velocity'; the cloud has: x y z range radial_vel intensity t ring"),
            std::string::npos)
      << e;
}

TEST_F(Mcap, UnorganizedCloudIsProjected) {
  // The frame's valid returns as one row: what a sensor driver publishes.
  const core::Frame f = frame_at(0);
  io::PcdCloud cloud;
  cloud.height = 1;
  std::vector<double> x, y, z, v;
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (!f.scan.valid[i]) continue;
    x.push_back(f.scan.x_m[i]);
    y.push_back(f.scan.y_m[i]);
    z.push_back(f.scan.z_m[i]);
    v.push_back(f.scan.radial_velocity_mps[i]);
  }
  cloud.width = static_cast<int>(x.size());
  cloud.fields = {{"x", 'F', 4, x}, {"y", 'F', 4, y}, {"z", 'F', 4, z}, {"velocity", 'F', 4, v}};
  cloud.comments = {"fmcw_stamp 2.5"};
  const std::string file = save("flat.mcap", export_clouds({cloud}, io::McapCompression::kZstd));
  io::InputOptions options;
  options.format = io::InputFormat::kMcap;
  io::InputSequence seq(file, options);
  const io::InputFrame in = seq.read(0);
  EXPECT_TRUE(in.projected);
  EXPECT_EQ(in.stats.points, x.size());
  // Every point is accounted for; the heads' mount points are not the grid's origin, so some
  // returns share a pixel and the nearest wins.
  EXPECT_EQ(in.stats.placed + in.stats.collisions + in.stats.outside_fov, x.size());
  EXPECT_GT(in.stats.placed, x.size() / 3);
  std::size_t valid = 0;
  for (const std::uint8_t v : in.frame.scan.valid) valid += v;
  EXPECT_EQ(valid, in.stats.placed);
  EXPECT_EQ(in.frame.scan.rows, 150);
  EXPECT_EQ(in.frame.scan.cols, 600);
  EXPECT_DOUBLE_EQ(in.frame.scan.stamp_s, 2.5);
  EXPECT_EQ(seq.source(0), file + "#0");
  EXPECT_EQ(seq.stem(0), "flat_000000");
}

}  // namespace
