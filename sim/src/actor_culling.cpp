#include "fmcw/sim/actor_culling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace fmcw::sim {

namespace {

// Indices k in [0, count) whose angle a(k) = half_fov - (k + 0.5) resolution lies in [lo, hi],
// one more on each side for rounding: [begin, end), possibly empty.
std::pair<int, int> index_span(double lo, double hi, double half_fov, double resolution, int count) {
  const double first = (half_fov - hi) / resolution - 0.5;
  const double last = (half_fov - lo) / resolution - 0.5;
  const int begin = static_cast<int>(std::max(0.0, std::floor(first) - 1.0));
  const int end = static_cast<int>(std::min(static_cast<double>(count), std::ceil(last) + 2.0));
  return {begin, std::max(begin, end)};
}

}  // namespace

void actor_footprints(const std::vector<BoundingSphere>& bounds, const core::HeadModel& head, int col_begin,
                      const Eigen::Isometry3d& T_world_head, double margin_rad, std::vector<ActorFootprint>& out) {
  out.clear();
  const Eigen::Isometry3d T_head_world = T_world_head.inverse();
  const int rows = head.rows();
  const int cols = head.cols();
  for (const BoundingSphere& sphere : bounds) {
    if (!(sphere.radius_m > 0.0)) continue;
    const Eigen::Vector3d v = T_head_world * sphere.center;
    const double distance = v.norm();
    ActorFootprint fp{0, rows, col_begin, col_begin + cols, std::max(0.0, distance - sphere.radius_m)};
    if (fp.nearest_m > head.max_range_m) continue;
    if (distance > sphere.radius_m) {
      // The sphere fills a cone of half angle theta around its centre's direction. Within it,
      // elevation differs from the centre's by at most theta, and azimuth by at most
      // asin(sin theta / cos elevation) while the cone does not reach a pole.
      const double theta = std::asin(sphere.radius_m / distance) + margin_rad;
      const double elevation = std::atan2(v.z(), std::hypot(v.x(), v.y()));
      const auto row_span = index_span(elevation - theta, elevation + theta, 0.5 * head.fov_vertical_rad,
                                        head.resolution_vertical_rad, rows);
      fp.row_begin = row_span.first;
      fp.row_end = row_span.second;
      if (std::abs(elevation) + theta < 0.5 * M_PI) {
        const double half_width = std::asin(std::min(1.0, std::sin(theta) / std::cos(elevation)));
        // With the cone and the field of view each narrower than half a turn, the azimuths
        // meet without wrapping around.
        if (0.5 * head.fov_horizontal_rad + half_width < M_PI) {
          const double azimuth = std::atan2(v.y(), v.x());
          const auto col_span = index_span(azimuth - half_width, azimuth + half_width,
                                            0.5 * head.fov_horizontal_rad, head.resolution_horizontal_rad, cols);
          fp.col_begin = col_begin + col_span.first;
          fp.col_end = col_begin + col_span.second;
        }
      }
    }
    if (fp.row_begin < fp.row_end && fp.col_begin < fp.col_end) out.push_back(fp);
  }
}

double nearest_actor_m(const std::vector<ActorFootprint>& footprints, int r0, int r1, int c0, int c1) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const ActorFootprint& fp : footprints) {
    if (fp.row_begin < r1 && fp.row_end > r0 && fp.col_begin < c1 && fp.col_end > c0) {
      nearest = std::min(nearest, fp.nearest_m);
    }
  }
  return nearest;
}

}  // namespace fmcw::sim
