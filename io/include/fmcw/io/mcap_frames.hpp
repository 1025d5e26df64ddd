#pragma once
// Frames from the sensor_msgs/msg/PointCloud2 messages of one topic of an MCAP file (a ROS 2
// bag, or an `fmcw export --to mcap`): each message as PCD columns, the Doppler field renamed
// to `v`, fields a frame does not know dropped (said once on stderr), the stamp and, from the
// file's "fmcw" metadata, the heads as the PCD's comments; frame_input.hpp turns them into
// scans (organized clouds keep their shape, HEIGHT 1 clouds are projected onto the grid).

#include <memory>
#include <string>
#include <vector>

#include "fmcw/io/mcap_reader.hpp"
#include "fmcw/io/pcd.hpp"

namespace fmcw::io {

/// The Doppler field names tried in order when none is given.
const std::vector<std::string>& doppler_field_names();

struct McapInputOptions {
  std::string topic = "/points";
  std::string doppler_field = "auto";  ///< one of doppler_field_names(), or "auto": the first present
};

class McapFrames {
 public:
  /// Opens and checks the file; core::FileError when the topic is missing (naming the topics
  /// there are) or is not sensor_msgs/msg/PointCloud2 in ros2msg schema and cdr encoding.
  McapFrames(const std::string& path, const McapInputOptions& options);
  ~McapFrames();
  std::size_t size() const;
  /// "FILE.mcap#K" (K from 0), the name a frame's errors and results carry.
  std::string source(std::size_t k) const;
  /// The k-th message as PCD columns with fmcw_stamp and fmcw_head comments.
  PcdCloud cloud(std::size_t k);

 private:
  std::unique_ptr<McapReader> reader_;
  McapInputOptions options_;
  std::vector<std::string> head_comments_;
  bool told_fields_ = false;
  bool told_doppler_ = false;
};

}  // namespace fmcw::io
