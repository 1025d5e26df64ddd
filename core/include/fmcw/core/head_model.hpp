#pragma once
// Beam geometry of one FMCW head and of a rig of heads laid side by side in one image.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

/// A raster head: columns sweep azimuth from +fov/2 (left, column 0) to -fov/2 (right), rows
/// sweep elevation from +fov/2 (top, row 0) to -fov/2. Beam (r, c) points through the pixel
/// centre: azimuth = fov_h/2 - (c + 0.5) res_h, elevation = fov_v/2 - (r + 0.5) res_v, and in
/// the head frame (x forward, y left, z up) its direction is
/// (cos el cos az, cos el sin az, sin el).
struct HeadModel {
  std::string name = "head";
  Eigen::Isometry3d T_rig_head = Eigen::Isometry3d::Identity();  ///< mount pose, head -> rig
  double fov_horizontal_rad = 40.0 * M_PI / 180.0;   ///< [rad] Table I: 40 deg
  double fov_vertical_rad = 30.0 * M_PI / 180.0;     ///< [rad] Table I: 30 deg
  double resolution_horizontal_rad = 0.2 * M_PI / 180.0;  ///< [rad] Table I: 0.2 deg
  double resolution_vertical_rad = 0.2 * M_PI / 180.0;    ///< [rad] Table I: 0.2 deg
  double max_range_m = 150.0;  ///< [m] Table I
  double rate_hz = 10.0;       ///< [Hz] Table I

  /// At most this many pixels per head (2^24, over 180 times Table I's rig): a resolution
  /// typed in the wrong unit is an error, not a multi-terabyte allocation.
  static constexpr long long kMaxPixels = 16777216;

  /// Throws core::InputError (a std::invalid_argument) naming the head and the bad field;
  /// core::LimitError when the head would have more than kMaxPixels pixels.
  void validate() const;
  int cols() const;
  int rows() const;
  double azimuth_rad(int col) const;
  double elevation_rad(int row) const;
  /// Unit beam direction in the head frame.
  Eigen::Vector3d direction_head(int row, int col) const;
};

/// Several heads side by side; their images are concatenated left to right in the given order.
struct RigModel {
  std::vector<HeadModel> heads;
  /// The heads report each point's scan line and time offset, as Aeva sensors do: the scans
  /// carry Scan::line_index (a head's row) and the files line_index and time_offset_ns.
  bool scan_lines = false;

  void validate() const;  ///< heads agree on rows; each head valid
  int rows() const;
  int cols() const;
  /// Column spans, mount poses, and seams stitched where neighbouring heads meet in azimuth
  /// (within half a pixel) with the same rows.
  std::vector<HeadInfo> head_infos() const;
  /// Precomputed unit beam directions in the rig frame, row-major rows() x cols().
  std::vector<Eigen::Vector3f> directions_rig() const;

  /// Table I rig of the paper: three 40 x 30 deg heads yawed +40, 0, -40 deg, 0.2 x 0.2 deg,
  /// 150 m, 10 Hz: a 600 x 150 image over 120 x 30 deg. The heads sit at separate points on the
  /// roof (rig origin on the ground under the rear axle), which makes beam origins differ.
  static RigModel paper_rig();
};

}  // namespace fmcw::core
