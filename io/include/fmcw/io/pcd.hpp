#pragma once
// Organized PCD (v0.7), the format PCL, Open3D, CloudCompare and ROS tools read directly.
//
// Frames are written as binary PCD with WIDTH = cols, HEIGHT = rows, NaN x/y/z where a beam had
// no return, and fields x y z range v intensity, t (each beam's time after the stamp) when the
// scan has it, plus gt_range gt_v gt_vx gt_vy gt_vz instance moving when the frame carries
// ground truth. Head layout and stamp travel in comment lines
// ("# fmcw_head ...", "# fmcw_stamp ..."), which other PCD readers skip.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fmcw/core/ground_truth.hpp"

namespace fmcw::io {

/// One PCD field with COUNT 1, its values widened to double (exact for every PCD type we use).
struct PcdField {
  std::string name;
  char type = 'F';  ///< 'F' float, 'U' unsigned, 'I' signed
  int size = 4;     ///< bytes: F 4|8, I/U 1|2|4|8
  std::vector<double> values;
};

/// A PCD file in memory: header, fields as columns, and its comment lines (without "# ").
struct PcdCloud {
  int width = 0;
  int height = 0;
  std::vector<PcdField> fields;
  std::vector<std::string> comments;
  /// Fields with COUNT > 1 (name, COUNT): not read, so not in `fields`; a reader that needs one
  /// names it (check_single_count) rather than calling it missing.
  std::vector<std::pair<std::string, int>> multi_count_fields;

  std::size_t points() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  const PcdField* find(const std::string& name) const;
};

/// Reads DATA ascii or binary. Throws core::FileError naming the file and the header line or
/// point at fault (truncated data, sizes that disagree, unsupported types or compression);
/// core::LimitError for more than 2^31 points or more data than a file can hold.
PcdCloud read_pcd(const std::string& path);

/// A binary PCD's data as it lies in the file (points packed, fields interleaved), for writers
/// that pass it on without decoding it (the MCAP export).
struct PcdPackedData {
  struct Field {
    std::string name;
    char type = 'F';
    int size = 4;
    int count = 1;
    std::size_t offset = 0;  ///< in a point [bytes]
  };
  std::vector<Field> layout;  ///< every field of the file in order, "_" padding and COUNT > 1 included
  std::size_t stride = 0;     ///< bytes per point
  std::vector<std::uint8_t> data;  ///< points() * stride bytes
};

/// read_pcd with the same checks, but the data of a binary file is copied into `packed` and the
/// cloud's fields carry no values: returns true. An ASCII file is read as read_pcd reads it
/// (the fields hold the values): returns false.
bool read_pcd_packed(const std::string& path, PcdCloud& cloud, PcdPackedData& packed);

/// Writes binary PCD atomically; std::runtime_error when the file cannot be written.
void write_pcd(const std::string& path, const PcdCloud& cloud);

/// Field names a frame may carry; anything else is rejected by frame_from_pcd.
const std::vector<std::string>& known_frame_fields();

/// Throws std::invalid_argument "<source>: field 'v' has COUNT 3; <reader> COUNT 1" when one of
/// `names` has COUNT > 1 in the file (reader: who needs it, e.g. "a frame's fields must have").
void check_single_count(const PcdCloud& cloud, const std::vector<std::string>& names, const std::string& source,
                        const std::string& reader);

/// The stamp of a "# fmcw_stamp SECONDS" comment [s], 0 without one. std::invalid_argument naming
/// the source and the comment when it is not one finite number.
double stamp_from_comments(const PcdCloud& cloud, const std::string& source);
/// The velocity frame of a "# fmcw_velocity_frame sensor|ego_compensated" comment, kSensor
/// without one. core::FileError naming the source for any other value.
core::VelocityFrame velocity_frame_from_comments(const PcdCloud& cloud, const std::string& source);

/// The heads of "# fmcw_head NAME COL_BEGIN COL_END STITCHED TX TY TZ QW QX QY QZ" comments, in
/// order; none without such comments. std::invalid_argument naming the source and the comment
/// when one is malformed. Spans are not checked against the cloud here (frame_from_pcd does).
std::vector<core::HeadInfo> heads_from_comments(const PcdCloud& cloud, const std::string& source);

/// Builds a Frame. Requires x y z v; range defaults to the distance from the beam origin,
/// intensity to 0. A point with finite x, y, z is valid and must have finite values in every
/// field; NaN x, y, z marks no return. All or none of the ground-truth fields. HEIGHT 1 clouds
/// are rejected: segmentation needs an organized range image. Errors name source and pixel.
core::Frame frame_from_pcd(const PcdCloud& cloud, const std::string& source);

/// Frame -> PCD columns; with_truth adds the ground-truth fields (the frame must carry them).
PcdCloud pcd_from_frame(const core::Frame& frame, bool with_truth = true);

/// read_pcd + frame_from_pcd.
core::Frame read_frame(const std::string& path);
/// pcd_from_frame + write_pcd.
void write_frame(const std::string& path, const core::Frame& frame, bool with_truth = true);

}  // namespace fmcw::io
