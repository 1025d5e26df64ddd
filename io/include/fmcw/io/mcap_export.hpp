#pragma once
// A sequence of frames as one MCAP file for Foxglove and ROS 2 (docs/FORMATS.md, "MCAP"):
//   /points      sensor_msgs/msg/PointCloud2 in frame `rig`: every field of the frame's PCD at its
//                own type, organized (width x height = the range image)
//   /tf          tf2_msgs/msg/TFMessage world -> rig, per frame (when the ego pose is known)
//   /tf_static   tf2_msgs/msg/TFMessage rig -> each head, once
//   /markers/truth      visualization_msgs/msg/MarkerArray: actor boxes and velocity arrows
//   /markers/estimated  the method's moving clusters (centroid, velocity arrow)
// The heads' layout (the PCD's fmcw_head lines) also goes into a Metadata record "fmcw", so that
// an import rebuilds the scan's heads.

#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/io/mcap_writer.hpp"
#include "fmcw/io/pcd.hpp"
#include "fmcw/io/ros2_messages.hpp"

namespace fmcw::io {

/// A moving cluster as `fmcw process` reports it (results.json).
struct EstimatedObject {
  int cluster = 0;
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();  ///< rig frame
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  ///< rig axes
  bool valid = false;
};

/// Per frame of a results.json, its clusters. core::FileError naming the file on a malformed one.
std::vector<std::vector<EstimatedObject>> read_estimated_objects(const std::string& results_json);

struct McapExportOptions {
  McapWriterOptions writer;
  std::string points_topic = "/points";
  std::string rig_frame = "rig";
  std::string world_frame = "world";
  bool truth_markers = false;      ///< add /markers/truth
  bool estimated_markers = false;  ///< add /markers/estimated
  bool ego_poses = false;          ///< add /tf
};

class McapSequenceWriter {
 public:
  McapSequenceWriter(std::ostream& out, const McapExportOptions& options);
  ~McapSequenceWriter();
  /// One frame: its cloud (stamp and heads from its fmcw comments), its truth and its estimates
  /// when the options ask for them. Errors name `source`.
  void add_frame(const PcdCloud& cloud, const std::string& source, const core::FrameTruth* truth,
                 const std::vector<EstimatedObject>* estimated);
  /// The same for a binary PCD read by read_pcd_packed: its data goes into the message as it is.
  void add_packed_frame(const PcdCloud& cloud, PcdPackedData&& packed, const std::string& source,
                        const core::FrameTruth* truth, const std::vector<EstimatedObject>* estimated);
  void finish();
  std::uint64_t bytes_written() const;

 private:
  struct State;
  ros2::Time begin_frame(const PcdCloud& cloud, const std::string& source);
  void end_frame(ros2::Time stamp, const std::string& source, const core::FrameTruth* truth,
                 const std::vector<EstimatedObject>* estimated);
  std::unique_ptr<State> s_;
};

}  // namespace fmcw::io
