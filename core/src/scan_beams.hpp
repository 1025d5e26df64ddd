#pragma once
// Internal to core: each valid pixel's unit beam direction, computed once per scan and shared
// by the stages of the robust and tracked methods (ego twist, moving test, object rows, tracker)
// instead of each normalising it again.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

struct ScanBeams {
  std::vector<Eigen::Vector3d> origin;  ///< per column: its head's mount point, rig frame [m]
  /// Per pixel, by component: unit direction from its origin; zero where invalid. By component
  /// so that the per-pixel passes load and store whole vectors of one component.
  std::vector<double> ex, ey, ez;
  std::size_t cols = 0;

  ScanBeams() = default;
  explicit ScanBeams(const Scan& scan) { assign(scan); }
  /// Computes the beams of scan, reusing the storage.
  void assign(const Scan& scan);
  const Eigen::Vector3d& origin_of(std::size_t i) const { return origin[i % cols]; }
  Eigen::Vector3d e(std::size_t i) const { return {ex[i], ey[i], ez[i]}; }
};

}  // namespace fmcw::core
