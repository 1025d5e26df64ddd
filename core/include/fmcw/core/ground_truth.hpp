#pragma once
// What only a simulator knows, per pixel, beside the Scan a sensor delivers.

#include <cstdint>
#include <optional>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

/// Per-pixel truth, arrays of rows * cols in the Scan's order. Velocities in the rig frame.
struct PixelGroundTruth {
  std::vector<float> range_m;              ///< noise-free range [m]; NaN where no return
  std::vector<float> radial_velocity_mps;  ///< noise-free Doppler (Eq. 6) [m/s]
  std::vector<float> vx_mps, vy_mps, vz_mps;  ///< true surface velocity [m/s] (world motion, rig axes)
  std::vector<std::uint32_t> instance;     ///< 0 = static world, else actor id
  std::vector<std::uint8_t> moving;        ///< 1 where the surface's absolute speed exceeds the threshold

  static PixelGroundTruth make_empty(std::size_t n);
  /// Throws std::invalid_argument when a field does not hold n values.
  void validate(std::size_t n) const;
};

/// One frame: the scan and, for simulated data, its ground truth.
struct Frame {
  Scan scan;
  std::optional<PixelGroundTruth> truth;
};

}  // namespace fmcw::core
