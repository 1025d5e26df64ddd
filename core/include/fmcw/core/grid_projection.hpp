#pragma once
// Unorganized FMCW returns onto an organized range image. Sensors and other tools deliver point
// lists; the core's methods work on the image (Algorithm 1 grows regions over 8-neighbours).
// Rows come from each point's scan line when the list has one, else from its elevation;
// columns from its azimuth.

#include <cstdint>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

/// Returns in the sensor frame (x forward, y left, z up), one entry per return. x, y, z and
/// radial velocity are required; intensity, time_offset_s and line_index are optional: empty,
/// or one value per point.
struct PointList {
  std::vector<float> x_m, y_m, z_m;
  std::vector<float> radial_velocity_mps;  ///< Doppler [m/s], positive moving away (Eq. 6)
  std::vector<float> intensity;            ///< [arbitrary, >= 0]; empty: 0
  std::vector<float> time_offset_s;        ///< each return's time after the scan stamp [s]
  std::vector<std::int32_t> line_index;    ///< scan line of each return (row of the image)

  std::size_t size() const { return x_m.size(); }
};

/// The grid. Column c covers azimuth (fov_h/2 - (c+1) res_h, fov_h/2 - c res_h]: column 0 is the
/// left edge, as for HeadModel. By elevation, row r covers (fov_v/2 - (r+1) res_v,
/// fov_v/2 - r res_v]: row 0 is the top. By scan line, row r holds line r (line 0 on top).
struct GridProjectionParams {
  double fov_horizontal_deg = 120.0;        ///< [deg] azimuth span, centred on x forward
  double resolution_horizontal_deg = 0.2;   ///< [deg] azimuth bin
  double fov_vertical_deg = 30.0;           ///< [deg] elevation span (rows by elevation only)
  double resolution_vertical_deg = 0.2;     ///< [deg] elevation bin (rows by elevation only)
  /// Rows by scan line: number of lines; 0 = the largest line index present + 1. A line index
  /// at or above a non-zero count is an error (a corrupt record, or the wrong sensor setting).
  int lines = 0;

  /// Throws core::InputError (a std::invalid_argument) naming the field; core::LimitError when
  /// a bin count exceeds the 2^26 pixels a grid may have.
  void validate() const;
  int cols() const;
  int elevation_rows() const;
};

/// What the projection did. Every point is placed, lost in a collision, or outside the field of
/// view; placed + collisions + outside_fov == points.
struct GridProjectionStats {
  std::size_t points = 0;
  std::size_t placed = 0;
  std::size_t collisions = 0;  ///< points that lost their pixel to a nearer return
  std::size_t outside_fov = 0;
  bool rows_by_line = false;
};

struct GridProjection {
  Scan scan;  ///< one head at the sensor origin spanning every column
  GridProjectionStats stats;
  std::vector<std::int64_t> point_of_pixel;  ///< per pixel: the point placed there, -1 if none
  std::vector<std::int64_t> pixel_of_point;  ///< per point: its pixel, -1 if dropped
};

/// Bins every point into the grid. Where several points fall in one pixel the nearest (smallest
/// range) is kept, and among equal ranges the earliest in the list: the result depends only on
/// the input. Throws std::invalid_argument naming the point and field for arrays of different
/// lengths, non-finite values, a return at zero range, or a line index out of range
/// (core::InputError); core::LimitError for a grid of more than 2^26 pixels.
GridProjection project_to_grid(const PointList& points, const GridProjectionParams& params);

}  // namespace fmcw::core
