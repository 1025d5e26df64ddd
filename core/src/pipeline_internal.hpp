#pragma once
// Internal to core: what the pipeline's methods share (stage timing, messages).

#include <chrono>
#include <cstddef>
#include <string>

#include "fmcw/core/check.hpp"
#include "fmcw/core/motion_pipeline.hpp"

namespace fmcw::core {

using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

/// An estimate of the scan's shape, by the method, still empty.
inline MotionEstimate estimate_of(const Scan& scan, const std::string& method) {
  MotionEstimate out;
  out.method = method;
  out.rows = scan.rows;
  out.cols = scan.cols;
  return out;
}

inline std::string no_static_world_message(int static_points, std::size_t valid, double min_fraction) {
  return concat("ego velocity not estimable: no static world in view (", static_points, " of ", valid,
                " valid points static, under the ", min_fraction * 100.0, " % minimum; is every point moving?)");
}

}  // namespace fmcw::core
