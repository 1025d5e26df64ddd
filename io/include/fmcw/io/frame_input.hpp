#pragma once
// Where frames come from on the command line: the project's organized PCD, any PCD taken as a
// list of points and projected onto a grid, or Aeva Aeries II scans.

#include <optional>
#include <string>
#include <vector>

#include "fmcw/core/grid_projection.hpp"
#include "fmcw/io/aeva.hpp"
#include "fmcw/io/mcap_frames.hpp"
#include "fmcw/io/pcd.hpp"

namespace fmcw::io {

enum class InputFormat {
  kPcd,     ///< organized PCD as `fmcw simulate` writes it (HEIGHT = rows)
  kPoints,  ///< any PCD with x y z v (intensity and t optional), unorganized or not: projected
            ///< (stamp 0; a "# fmcw_stamp" comment must still be a finite number)
  kAeva,    ///< Aeva Aeries II .bin scans: rows by line index, columns by azimuth
  kMcap,    ///< sensor_msgs/PointCloud2 messages of one topic of an MCAP file (mcap_frames.hpp)
};

/// "pcd", "points", "aeva" or "mcap"; std::invalid_argument otherwise.
InputFormat parse_input_format(const std::string& text);
const std::vector<std::string>& input_format_names();

struct InputOptions {
  InputFormat format = InputFormat::kPcd;
  AevaLayout aeva_layout = AevaLayout::kAuto;
  bool negate_velocity = false;  ///< points and aeva: flip the Doppler sign
  /// What the velocities are measured against; unset: the format's default (pcd and points:
  /// the file's "# fmcw_velocity_frame" comment, else sensor; aeva: ego-compensated, the
  /// convention of the public Aeva datasets).
  std::optional<core::VelocityFrame> velocity_frame;
  /// points and aeva: the grid. Rows by elevation for points, by line index for aeva.
  core::GridProjectionParams grid;
  McapInputOptions mcap;  ///< mcap: the topic and the Doppler field
};

/// The files of an input: itself, or a folder's frames (*.pcd, or *.bin for aeva), sorted.
std::vector<std::string> list_input_files(const std::string& input, InputFormat format);

struct InputFrame {
  core::Frame frame;
  /// The velocity frame the file itself says or its format implies, before any override.
  core::VelocityFrame file_velocity_frame = core::VelocityFrame::kSensor;
  /// Where file_velocity_frame came from: "the file's fmcw_velocity_frame comment", "the Aeva
  /// datasets' convention" or "the default".
  std::string velocity_frame_source;
  bool projected = false;          ///< the scan was made by project_to_grid
  core::GridProjectionStats stats; ///< when projected
};

/// Reads one file in the given format. Errors name the file.
InputFrame read_input_frame(const std::string& path, const InputOptions& options);

/// A cloud read from `source` as a frame: organized (HEIGHT > 1) as it is (frame_from_pcd), a
/// HEIGHT 1 cloud as points (points_from_pcd) projected onto the options' grid.
InputFrame frame_from_cloud(const PcdCloud& cloud, const std::string& source, const InputOptions& options);

/// A PCD's points with finite x, y, z as a point list: x y z v required, intensity and t taken
/// when present (each with COUNT 1), other fields ignored. Errors name the source.
core::PointList points_from_pcd(const PcdCloud& cloud, const std::string& source);

}  // namespace fmcw::io
