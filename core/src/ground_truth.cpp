#include "fmcw/core/ground_truth.hpp"

#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::core {

PixelGroundTruth PixelGroundTruth::make_empty(std::size_t n) {
  PixelGroundTruth gt;
  const float nan = std::nanf("");
  gt.range_m.assign(n, nan);
  gt.radial_velocity_mps.assign(n, nan);
  gt.vx_mps.assign(n, nan);
  gt.vy_mps.assign(n, nan);
  gt.vz_mps.assign(n, nan);
  gt.instance.assign(n, 0);
  gt.moving.assign(n, 0);
  gt.semantic_class.assign(n, 0);
  return gt;
}

void PixelGroundTruth::validate(std::size_t n) const {
  const auto check = [n](std::size_t got, const char* field) {
    FMCW_CHECK_ARG(got == n, "ground truth: field '", field, "' has ", got, " values, expected ", n);
  };
  check(range_m.size(), "gt_range");
  check(radial_velocity_mps.size(), "gt_v");
  check(vx_mps.size(), "gt_vx");
  check(vy_mps.size(), "gt_vy");
  check(vz_mps.size(), "gt_vz");
  check(instance.size(), "instance");
  check(moving.size(), "moving");
  if (!semantic_class.empty()) check(semantic_class.size(), "class");
}

}  // namespace fmcw::core
