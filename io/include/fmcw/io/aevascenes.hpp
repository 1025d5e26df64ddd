#pragma once
// The AevaScenes layout: a sequence folder SEQ/ with SEQ/sequence.json (sensors, extrinsics,
// frames with ego poses and boxes) and one .npz per lidar and frame (xyz in the lidar's frame,
// ego-compensated radial velocity, reflectivity, line_index, time_offset_ns, semantic labels).
// Read into Scans (each lidar a head, projected by line and azimuth) with ground truth from the
// boxes. Field by field: docs/FORMATS.md, "AevaScenes".

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "fmcw/core/ego_motion.hpp"
#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/semantic_classes.hpp"

namespace fmcw::io {

/// One annotated box of a frame (sequence.json "boxes"), in the vehicle frame.
struct AevaScenesBox {
  std::string track;       ///< "id": the track's UUID
  std::string class_name;  ///< "class"
  Eigen::Isometry3d T_vehicle_box = Eigen::Isometry3d::Identity();  ///< "pose"
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();                 ///< "dimensions" (full x, y, z)
  Eigen::Vector3d linear_velocity_mps = Eigen::Vector3d::Zero();    ///< "linear_velocity", vehicle axes
  Eigen::Vector3d angular_velocity_rps = Eigen::Vector3d::Zero();   ///< "angular_velocity", vehicle axes
};

struct AevaScenesFrame {
  double stamp_s = 0.0;  ///< [s] after the sequence's first frame ("timestamp_ns" - the first's, * 1e-9)
  Eigen::Isometry3d T_world_vehicle = Eigen::Isometry3d::Identity();  ///< "ego_pose"
  std::vector<std::string> files;  ///< per lidar (sequence order): its .npz, full path
  std::vector<AevaScenesBox> boxes;
};

struct AevaScenesSequence {
  std::string dir;
  std::string uuid;                                  ///< metadata.sequence_uuid
  std::vector<std::string> lidars;                   ///< metadata.sensors.lidars
  std::vector<Eigen::Isometry3d> T_vehicle_lidar;    ///< metadata.vehicle_to_lidar_extrinsics (applied to
                                                     ///< a lidar's points gives vehicle coordinates)
  std::vector<AevaScenesFrame> frames;
  std::vector<std::string> track_ids;  ///< every box "id" in order of first appearance: instance k + 1
  core::PoseSeries poses;              ///< the frames' ego poses at their stamps
};

/// Reads DIR/sequence.json. core::FileError naming the file and the JSON path at fault (a
/// missing key, a wrong type, a NaN, a non-unit quaternion, stamps that do not increase).
AevaScenesSequence read_aevascenes_sequence(const std::string& dir);

/// How each lidar's points become a head of the image: rows by line_index, columns by azimuth
/// in the lidar's own frame (core::project_to_grid).
struct AevaScenesOptions {
  double wide_fov_deg = 130.0;   ///< [deg] azimuth span of a lidar whose id does not hold "narrow"
  double narrow_fov_deg = 42.0;  ///< [deg] of a lidar whose id holds "narrow"
  double resolution_deg = 0.2;   ///< [deg] azimuth bin
  /// Scan lines (rows) of every head; 0: the largest line_index of the frame + 1.
  int lines = 0;
  double moving_threshold_mps = 0.1;  ///< ground truth "moving" above this box speed [m/s]
  /// Undo the ego compensation with the sequence's ego poses (scan and truth alike), so that
  /// the methods measure the ego velocity; otherwise the scans stay compensated, as the files
  /// hold them. Needs at least two frames.
  bool to_sensor_frame = false;
};

/// Frame k: the lidars side by side (sequence order), the scan ego-compensated as the files hold
/// it (or in the sensor frame: AevaScenesOptions::to_sensor_frame), with per-pixel truth from the boxes (a pixel inside a box is that track's instance, its
/// velocity the box's rigid motion at that point) and frame truth (ego from the poses, actors
/// from the boxes). classes names semantic labels (unknown names: class 0); what is not read is
/// added to notes, the same text for the same cause (for the caller to say once).
/// core::FileError naming the .npz and the array for a missing or malformed field.
core::Frame read_aevascenes_frame(const AevaScenesSequence& sequence, std::size_t k, const AevaScenesOptions& grid,
                                  const core::ClassTable& classes, std::vector<std::string>* notes = nullptr);

}  // namespace fmcw::io
