#pragma once
// The ROS 2 messages an MCAP export carries, CDR-encoded (cdr.hpp), with their definitions as
// the `ros2msg` schema encoding wants them (the MCAP specification's "Well-known schema
// encodings", ros2msg): the message's own .msg text, then each type it depends on after a line
// of 80 '=' and "MSG: package/Type", as rosbag2 writes them.
//
//   sensor_msgs/msg/PointCloud2   the frames (point_cloud2_from_pcd, pcd_from_point_cloud2)
//   tf2_msgs/msg/TFMessage        /tf (world -> rig per frame) and /tf_static (rig -> heads)
//   visualization_msgs/msg/MarkerArray   boxes and velocity arrows

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "fmcw/io/pcd.hpp"

namespace fmcw::io::ros2 {

/// builtin_interfaces/Time.
struct Time {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  /// Rounded to the nanosecond; core::InputError for a negative, NaN or too large stamp.
  static Time from_seconds(double stamp_s);
  std::uint64_t nanoseconds() const { return static_cast<std::uint64_t>(sec) * 1000000000ull + nanosec; }
  /// Nanoseconds / 1e9, one rounding: the stamp of a "0.1 s" frame reads back as 0.1.
  double seconds() const { return static_cast<double>(nanoseconds()) / 1e9; }
};

/// sensor_msgs/PointField datatypes.
enum PointFieldType : std::uint8_t { kInt8 = 1, kUint8 = 2, kInt16 = 3, kUint16 = 4, kInt32 = 5, kUint32 = 6,
                                     kFloat32 = 7, kFloat64 = 8 };

struct PointField {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = kFloat32;
  std::uint32_t count = 1;
};

/// sensor_msgs/PointCloud2.
struct PointCloud2 {
  Time stamp;
  std::string frame_id;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::vector<PointField> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  std::vector<std::uint8_t> data;
  bool is_dense = false;
};

std::vector<std::uint8_t> encode(const PointCloud2& cloud);
/// The same appended to `out` (a chunk's records: no copy of the message on its way there).
void encode(const PointCloud2& cloud, std::vector<std::uint8_t>& out);
/// Errors (core::FileError) name `where` and the byte at fault.
PointCloud2 decode_point_cloud2(const std::uint8_t* data, std::size_t size, const std::string& where);

/// A PCD cloud as a PointCloud2: same fields, same types, points packed in PCD order (row-major,
/// HEIGHT rows of WIDTH), NaN where a beam had no return (is_dense false).
PointCloud2 point_cloud2_from_pcd(const PcdCloud& cloud, Time stamp, const std::string& frame_id);
/// The same from a binary PCD's packed data (read_pcd_packed), without decoding a value: the
/// data moves into the message; COUNT > 1 fields keep their count, "_" padding stays unnamed.
PointCloud2 point_cloud2_from_packed(const PcdCloud& cloud, PcdPackedData&& packed, Time stamp,
                                     const std::string& frame_id);
/// Back to PCD columns. Fields with count > 1 go to multi_count_fields; a big-endian cloud, a
/// field outside point_step, or data of the wrong size is a core::FileError naming `where`.
PcdCloud pcd_from_point_cloud2(const PointCloud2& cloud, const std::string& where);

/// geometry_msgs/TransformStamped.
struct TransformStamped {
  Time stamp;
  std::string parent_frame;
  std::string child_frame;
  Eigen::Isometry3d T_parent_child = Eigen::Isometry3d::Identity();
};
/// tf2_msgs/TFMessage.
std::vector<std::uint8_t> encode_tf(const std::vector<TransformStamped>& transforms);

/// visualization_msgs/Marker, the kinds an export writes.
struct Marker {
  enum Type : std::int32_t { kArrow = 0, kCube = 1, kSphere = 2, kText = 9 };
  enum Action : std::int32_t { kAdd = 0, kDeleteAll = 3 };
  std::string ns;
  std::int32_t id = 0;
  std::int32_t type = kCube;
  std::int32_t action = kAdd;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  float rgba[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  std::vector<Eigen::Vector3d> points;  ///< an arrow's tail and head
  std::string text;
};
/// visualization_msgs/MarkerArray, every marker with this stamp and frame.
std::vector<std::uint8_t> encode_markers(const std::vector<Marker>& markers, Time stamp, const std::string& frame_id);

/// The ros2msg schema text of each type (with its dependencies).
const std::string& point_cloud2_definition();
const std::string& tf_message_definition();
const std::string& marker_array_definition();

}  // namespace fmcw::io::ros2
