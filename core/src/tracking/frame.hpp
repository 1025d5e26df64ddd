#pragma once
// Internal to core: what every stage of the tracker shares about the current frame (the scan,
// its beams, the rig's pose in the tracker's world and its twist), the Doppler row of a pixel,
// and a tracked object's pixels of this frame.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "fmcw/core/object_tracker.hpp"
#include "fmcw/core/scan.hpp"
#include "../scan_beams.hpp"

namespace fmcw::core::tracking {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;

Eigen::Matrix2d rotation(double yaw);

/// One pixel's Doppler row in the tracker's world: y = e . v + omega * e . (z x (o - c)).
struct Row {
  Eigen::Vector2d e;  ///< horizontal part of the unit beam direction
  Eigen::Vector2d o;  ///< beam origin
  double y = 0.0;     ///< ego-compensated Doppler: e . (velocity of the point) [m/s]
  double residual = 0.0;
};

/// The Doppler a track in state x predicts for row r.
inline double predicted(const Row& r, const Vec5& x) {
  const Eigen::Vector2d d = r.o - x.head<2>();
  return r.e.dot(x.segment<2>(2)) + x(4) * (r.e.y() * d.x() - r.e.x() * d.y());
}

/// The current frame, as every stage reads it.
struct Frame {
  const Scan& scan;
  const ScanBeams& beams;
  Eigen::Matrix2d R;         ///< rig to tracker world (yaw)
  Eigen::Vector2d position;  ///< rig origin in the tracker world [m]
  Eigen::Vector3d V;         ///< ego velocity, rig frame [m/s]
  Eigen::Vector3d omega;     ///< ego angular velocity, rig frame [rad/s]

  Eigen::Vector2d world_xy(const Eigen::Vector3d& q) const { return R * q.head<2>() + position; }
  Row row_of(std::uint32_t i) const {
    const Eigen::Vector3d& o = beams.origin_of(i);
    const Eigen::Vector3d e = beams.e(i);
    Row r;
    r.e = R * e.head<2>();
    r.o = world_xy(o);
    r.y = scan.radial_velocity_mps[i] + e.dot(V + omega.cross(o));
    return r;
  }
};

/// A tracked object's pixels this frame.
struct Group {
  std::vector<std::uint32_t> found;     ///< of the clusters it took: pixels one scan found moving
  std::vector<std::uint32_t> claimed;   ///< static pixels it claimed in its predicted box (measured)
  std::vector<std::int32_t> clusters;   ///< labels merged into it
  std::vector<std::int32_t> absorbed;   ///< labels merged into its label but not measured
  std::vector<std::uint32_t> labelled;  ///< static pixels that take its label, not measured

  bool empty() const { return found.empty() && claimed.empty(); }
  /// Measured pixels: found, then claimed.
  template <class F>
  void for_each_measured(const F& f) const {
    for (const std::uint32_t i : found) f(i);
    for (const std::uint32_t i : claimed) f(i);
  }
};

/// Mean beam origin of a group's measured pixels, in the tracker world.
Eigen::Vector2d mean_origin(const Frame& frame, const Group& g);

}  // namespace fmcw::core::tracking
