#pragma once
// Internal to core: a track's box. Its oriented rectangle for point-in-box tests, where the view
// cuts an object's outline, and the measurement of the box on this frame's pixels: heading,
// extents, heights and the centre, anchored at the visible end when less than the whole length
// is seen.

#include <cmath>
#include <limits>
#include <vector>

#include "frame.hpp"

namespace fmcw::core::tracking {

/// Oriented box in the tracker's world.
struct Box {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d u = Eigen::Vector2d::UnitX();  ///< along the heading
  double half_l = 0.0;
  double half_w = 0.0;
  bool contains(const Eigen::Vector2d& q, double grow) const {
    const Eigen::Vector2d d = q - centre;
    const double a = d.dot(u);
    const double b = -d.x() * u.y() + d.y() * u.x();
    return std::abs(a) <= half_l + grow && std::abs(b) <= half_w + grow;
  }
  double distance(const Eigen::Vector2d& q) const;  ///< 0 inside
};

/// The track's predicted box (at least 0.4 m on each side).
Box box_of(const Track& t);

/// Of the boxes t that accept(t) takes and that, grown by grow_m(t), hold q: the nearest by box
/// distance, the distance to its centre breaking ties (a point inside two boxes). -1: none.
template <class Grow, class Accept>
int nearest_holding_box(const Eigen::Vector2d& q, const std::vector<Box>& boxes, Grow grow_m, Accept accept) {
  int holder = -1;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < boxes.size(); ++t) {
    if (!boxes[t].contains(q, grow_m(t)) || !accept(t)) continue;
    const double d = boxes[t].distance(q) + 1e-3 * (q - boxes[t].centre).norm();
    if (d < best) {
      best = d;
      holder = static_cast<int>(t);
    }
  }
  return holder;
}

/// The same with every box grown by grow_m.
template <class Accept>
int nearest_holding_box(const Eigen::Vector2d& q, const std::vector<Box>& boxes, double grow_m, Accept accept) {
  return nearest_holding_box(q, boxes, [grow_m](std::size_t) { return grow_m; }, accept);
}

/// Where the view cuts an outline: at an edge pixel (the top and bottom rows and each head's
/// first and last column), the direction away from the view, in the ground plane; and where
/// something nearer beside a pixel in its row hides what lies beyond it (an occluder).
struct Cut {
  Eigen::Vector2d direction;
  Eigen::Vector2d at;  ///< the edge pixel, world plane
  bool sideways = true;  ///< a head's column edge or an occluder beside it, not the top or bottom row
};

class ViewEdges {
 public:
  /// occlusion_gap_m: TrackerParams::Box::occlusion_gap_m (0: no occluders).
  ViewEdges(const Scan& scan, double occlusion_gap_m);
  /// The cuts at pixel i (world point `at`), if it is on the edge: away from the head's axis at
  /// a column edge, towards the sensor at the bottom row (row 0 is the top; what lies lower and
  /// nearer is unseen), away from it at the top row. A corner cuts both ways. A neighbour in the
  /// row (same head) nearer by occlusion_gap_m cuts towards its side, across the beam.
  void add_cuts(const Frame& frame, std::uint32_t i, const Eigen::Vector2d& at, std::vector<Cut>& cuts) const;

 private:
  double occlusion_gap_m_ = 0.0;
  std::vector<int> edge_head_;  ///< per column, the head whose edge it is (-1 inside a head)
};

/// What measure_box found.
struct BoxMeasurement {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< measured centre (the predicted one when unseen)
  bool seen = false;                ///< pixels gave the centre
  bool centre_from_claims = false;  ///< a small object found by its claims alone
};

/// Measures the track's box on the group's pixels (TrackerParams::Box): the heading follows the
/// velocity once the object moves, extents are measured along it on the pixels one scan found
/// moving (claimed ones would let the box grow over its neighbours), and the centre is anchored
/// at an end of the outline that is the body's own. Updates the track's heading, extents and
/// heights.
BoxMeasurement measure_box(Track& tr, const Group& g, bool born, const Frame& frame, const ViewEdges& edges,
                           const TrackerParams& p);

}  // namespace fmcw::core::tracking
