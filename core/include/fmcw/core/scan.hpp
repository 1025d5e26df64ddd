#pragma once
// The organized FMCW scan: a range image, one pixel per beam, as a real sensor delivers it.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace fmcw::core {

/// One sensor head of a rig. Heads sit side by side in the image, each owning a column span.
struct HeadInfo {
  std::string name;
  Eigen::Isometry3d T_rig_head = Eigen::Isometry3d::Identity();  ///< mount pose, head -> rig
  int col_begin = 0;  ///< first image column of this head
  int col_end = 0;    ///< one past the last image column
  /// True when this head's right edge meets the next head's left edge in azimuth, so that
  /// region growing may cross the seam between them.
  bool stitched_to_next = false;

  int cols() const { return col_end - col_begin; }
  Eigen::Vector3d origin_m() const { return T_rig_head.translation(); }
};

/// What a scan's radial velocity is measured against.
enum class VelocityFrame : std::uint8_t {
  /// The raw Doppler of Eq. 6, v = e . (V_point - V_origin): the static world reads -e . V_origin.
  kSensor,
  /// Ego-motion compensated ("absolute") radial velocity, v + e . V_origin = e . V_point: the
  /// static world reads about 0. What the public Aeva datasets ship (HeLiPR, HeRCULES,
  /// AevaScenes).
  kEgoCompensated,
};
/// "sensor" or "ego_compensated".
const char* to_string(VelocityFrame frame);
/// "sensor" or "raw" -> kSensor; "ego_compensated" or "compensated" -> kEgoCompensated;
/// core::InputError otherwise.
VelocityFrame velocity_frame_from_string(const std::string& name);

/// Organized scan in the rig frame (ISO: x forward, y left, z up), row-major, struct of arrays.
/// Sign of radial velocity (Eq. 6): v = e . (V_point - V_origin), v > 0 moves away.
struct Scan {
  int rows = 0;
  int cols = 0;
  double stamp_s = 0.0;  ///< [s] the scan's time; finite
  std::vector<float> x_m, y_m, z_m;       ///< hit position, rig frame [m]; NaN where invalid
  std::vector<float> range_m;             ///< distance from the beam origin [m]
  std::vector<float> radial_velocity_mps; ///< Doppler velocity [m/s]
  std::vector<float> intensity;           ///< reflected intensity [arbitrary, >= 0]
  std::vector<std::uint8_t> valid;        ///< 1 where the beam returned
  /// Optional: each beam's time after stamp_s [s] for sweeping sensors; empty when every beam
  /// shares the stamp.
  std::vector<float> time_offset_s;
  /// Optional: each pixel's scan line as the sensor numbers it (Aeva's line_index); empty when
  /// the sensor reports none.
  std::vector<std::uint16_t> line_index;
  /// Which velocity radial_velocity_mps holds. On kEgoCompensated scans the methods segment and
  /// estimate objects directly; the ego velocity is not measurable from them (NaN) unless the
  /// compensation is undone first (uncompensate_ego_velocity, ego_motion.hpp).
  VelocityFrame velocity_frame = VelocityFrame::kSensor;
  std::vector<HeadInfo> heads;            ///< ordered by col_begin, covering [0, cols)

  /// Allocates rows x cols pixels, all invalid, with one head spanning every column.
  static Scan make_empty(int rows, int cols);

  std::size_t size() const { return static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols); }
  std::size_t index(int row, int col) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(col);
  }
  Eigen::Vector3d position(std::size_t i) const { return {x_m[i], y_m[i], z_m[i]}; }
  std::size_t num_valid() const;

  /// Index into heads of the head that owns an image column.
  int head_of_col(int col) const;
  /// Beam origin of a pixel in the rig frame: the mount point of the head that owns its column.
  Eigen::Vector3d beam_origin(std::size_t i) const;

  /// Column spans that are one connected image: heads joined by stitched seams, [begin, end).
  std::vector<std::pair<int, int>> connected_column_groups() const;
  /// For each image column, the index of its span in connected_column_groups(): two columns
  /// are image neighbours only within one group.
  std::vector<int> column_group_of() const;

  /// Checks array sizes, head spans and that the stamp is finite. Throws std::invalid_argument
  /// naming the field.
  void validate_layout() const;
  /// validate_layout(), and that valid pixels hold finite values and a positive range.
  /// Throws std::invalid_argument naming the field or the (row, col) pixel at fault.
  void validate() const;
};

/// Calls f(n, dr, dc) for each of pixel (r, c)'s eight neighbours (r + dr, c + dc) that lies in
/// the image and in column c's group (group_of: Scan::column_group_of()); n is its index.
template <class F>
void for_each_neighbour(const Scan& scan, const std::vector<int>& group_of, int r, int c, F&& f) {
  const auto col = static_cast<std::size_t>(c);
  if (r > 0 && r + 1 < scan.rows && c > 0 && c + 1 < scan.cols && group_of[col - 1] == group_of[col] &&
      group_of[col + 1] == group_of[col]) {
    // Inside the image and its group: all eight, in the order of the loop below, unchecked.
    const std::size_t i = scan.index(r, c);
    const auto w = static_cast<std::size_t>(scan.cols);
    for (int dr = -1; dr <= 1; ++dr) {
      const std::size_t row = dr < 0 ? i - w : (dr > 0 ? i + w : i);
      f(row - 1, dr, -1);
      if (dr != 0) f(row, dr, 0);
      f(row + 1, dr, 1);
    }
    return;
  }
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      const int rr = r + dr, cc = c + dc;
      if ((dr == 0 && dc == 0) || rr < 0 || rr >= scan.rows || cc < 0 || cc >= scan.cols) continue;
      if (group_of[static_cast<std::size_t>(cc)] != group_of[static_cast<std::size_t>(c)]) continue;
      f(scan.index(rr, cc), dr, dc);
    }
  }
}

}  // namespace fmcw::core
