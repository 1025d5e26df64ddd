#pragma once
// Internal to core: the axis of an object's outline in the ground plane. A vehicle drives along
// its body axis (up to a small slip), so where its outline shows that axis, the direction of its
// velocity is known, and one scan's Doppler field, which fixes velocity and yaw rate only along
// a line, then fixes both (docs/METHODS.md, "The outline's axis").

#include <cstdint>
#include <vector>

#include "frame.hpp"

namespace fmcw::core::tracking {

/// The rectangle of an outline's footprint in the tracker's world whose edges its near side lies on.
struct OutlineAxis {
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();  ///< along the rectangle's long side (sign arbitrary)
  double length_m = 0.0;                            ///< the long side [m]
  double width_m = 0.0;                             ///< the short side [m]
  Eigen::Vector2d at = Eigen::Vector2d::Zero();     ///< a point of the outline (its first pixel's)
  /// The long side is at least TrackerParams::Heading::min_length_m (longer than a vehicle is
  /// wide, so it is the body's length) and min_aspect times the short one (a square-ish outline
  /// has no axis to tell).
  /// And its near side lies along the rectangle's edges
  /// (TrackerParams::Heading::max_edge_distance_m).
  bool informative = false;
  /// False where the long side is no side the near pixels show: they lie, on average, farther
  /// than Heading::max_edge_distance_m from the rectangle's edges. Nothing of such an outline is
  /// read (no axis, no face, no line).
  bool rectangle = true;
  int columns = 0;  ///< columns the outline spans (those with a pixel)
  /// The side the sensor sees (the nearest pixel of each column) alone, on the same rectangle:
  /// its long direction and extents. A car seen end-on from above its roof shows the roof
  /// behind its rear, which makes the whole outline square-ish; its rear alone is a line.
  Eigen::Vector2d side_axis = Eigen::Vector2d::UnitX();
  double side_length_m = 0.0;
  double side_width_m = 0.0;
};

/// The rectangle of the pixels' ground-plane footprint along whose edges the side the sensor sees
/// lies closest (the least sum of distances to the nearest edge; least area would not tell an L
/// from its hypotenuse). Within one column of a head every pixel lies on one ray from the head's
/// mount point in the ground plane: the nearest pixel of each column is the near side, the
/// nearest and the farthest hold the footprint's convex hull, which gives the extents. Searched
/// in 3 degree steps over a quarter turn, then in 0.25 degree steps about the best.
OutlineAxis outline_axis(const std::vector<std::uint32_t>& pixels, const Frame& frame, const TrackerParams::Heading& p);

/// The variance of the heading the axis measures [rad^2] (TrackerParams::Heading), seen from
/// the sensor (tracker world); cut: the view or an occluder cuts the outline.
double axis_heading_variance(const OutlineAxis& a, const Eigen::Vector2d& sensor, bool cut,
                             const TrackerParams::Heading& p);

/// |cos| of the angle between the side the sensor sees (OutlineAxis::side_axis) and the line of
/// sight from the sensor (tracker world) to the outline: 0 square to it, 1 along it.
double side_sight_cosine(const OutlineAxis& a, const Eigen::Vector2d& sensor);

/// Where no long side shows, a face across the body (TrackerParams::Heading, face_*): whether
/// the side the sensor sees (OutlineAxis::side_axis) is one, the track's velocity direction
/// `heading` (unit) and the sensor given (tracker world).
bool is_face(const OutlineAxis& a, const Eigen::Vector2d& sensor, const Eigen::Vector2d& heading,
             const TrackerParams::Heading& p);

/// The variance of the heading a face measures [rad^2] (its normal's direction), seen from the
/// sensor given (tracker world).
double face_heading_variance(const OutlineAxis& a, const Eigen::Vector2d& sensor, bool cut,
                             const TrackerParams::Heading& p);

}  // namespace fmcw::core::tracking
