#pragma once
// Small analytic scenes shared by the core tests.

#include "fmcw/core/synthetic_scan.hpp"

namespace fmcw::test {

/// A walled courtyard around the rig, so every beam of the paper rig returns from static
/// surfaces: ground, walls 40 m ahead and 25 m to each side.
inline core::SyntheticSceneParams static_courtyard() {
  core::SyntheticSceneParams p;
  core::SyntheticBox front;
  front.center_m = {41.0, 0.0, 10.0};
  front.half_extent_m = {1.0, 80.0, 30.0};
  core::SyntheticBox left;
  left.center_m = {0.0, 26.0, 10.0};
  left.half_extent_m = {80.0, 1.0, 30.0};
  core::SyntheticBox right = left;
  right.center_m.y() = -26.0;
  p.static_boxes = {front, left, right};
  return p;
}

}  // namespace fmcw::test
