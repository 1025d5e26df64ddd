#include "frame.hpp"

#include <algorithm>
#include <cmath>

namespace fmcw::core::tracking {

Eigen::Matrix2d rotation(double yaw) {
  Eigen::Matrix2d r;
  r << std::cos(yaw), -std::sin(yaw), std::sin(yaw), std::cos(yaw);
  return r;
}

Eigen::Vector2d mean_origin(const Frame& frame, const Group& g) {
  Eigen::Vector2d o_mean = Eigen::Vector2d::Zero();
  g.for_each_measured([&](std::uint32_t i) { o_mean += frame.row_of(i).o; });
  return o_mean / static_cast<double>(std::max<std::size_t>(g.found.size() + g.claimed.size(), 1));
}

}  // namespace fmcw::core::tracking
