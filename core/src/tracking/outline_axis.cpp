#include "outline_axis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fmcw::core::tracking {

namespace {

// The bounds of the points' projections on u = (cos, sin) of the angle and on w, u turned a
// quarter to the left.
struct Bounds {
  Eigen::Vector2d u, w;
  double a0 = std::numeric_limits<double>::infinity(), a1 = -a0, b0 = a0, b1 = -a0;

  Bounds(const std::vector<Eigen::Vector2d>& pts, double angle) : u(std::cos(angle), std::sin(angle)), w(-u.y(), u.x()) {
    for (const Eigen::Vector2d& q : pts) {
      const double a = q.dot(u);
      const double b = q.dot(w);
      a0 = std::min(a0, a);
      a1 = std::max(a1, a);
      b0 = std::min(b0, b);
      b1 = std::max(b1, b);
    }
  }
};

// How far the outline's near points lie from the rectangle's edges at the angle: each point's
// distance to the nearest edge, summed. The near side of a body lies on its rectangle's edges;
// least area alone does not tell an L from its hypotenuse (the rectangle on a right triangle's
// hypotenuse has the area of the one on its legs).
double edge_distance(const std::vector<Eigen::Vector2d>& near, double angle) {
  const Bounds e(near, angle);
  double sum = 0.0;
  for (const Eigen::Vector2d& q : near) {
    const double a = q.dot(e.u);
    const double b = q.dot(e.w);
    sum += std::min(std::min(a - e.a0, e.a1 - a), std::min(b - e.b0, e.b1 - b));
  }
  return sum;
}

// The angle in [from, from + steps * step) whose edges the near points lie closest to (the first
// of equal ones), and their summed distance there (edge_distance).
struct ClosestEdges {
  double angle;
  double sum;
};

ClosestEdges closest_edges(const std::vector<Eigen::Vector2d>& near, double from, double step,
                           int steps) {
  ClosestEdges best{from, std::numeric_limits<double>::infinity()};
  for (int k = 0; k < steps; ++k) {
    const double angle = from + k * step;
    const double sum = edge_distance(near, angle);
    if (sum < best.sum) best = {angle, sum};
  }
  return best;
}

// The nearest and the farthest pixel of each column (horizontal distance from the column's beam
// origin), relative to the first pixel's position to keep the sums small: the near ones are the
// side the sensor sees, both hold the footprint's convex hull.
struct Candidates {
  Eigen::Vector2d ref;
  std::vector<Eigen::Vector2d> near;
  std::vector<Eigen::Vector2d> all;
};

Candidates hull_candidates(const std::vector<std::uint32_t>& pixels, const Frame& frame) {
  const auto cols = static_cast<std::uint32_t>(frame.scan.cols);
  std::uint32_t c0 = cols, c1 = 0;
  for (const std::uint32_t i : pixels) {
    c0 = std::min(c0, i % cols);
    c1 = std::max(c1, i % cols);
  }
  const std::size_t span = c1 - c0 + 1;
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> nearest(span, kNone), farthest(span, kNone);
  std::vector<double> near_d(span, std::numeric_limits<double>::infinity()), far_d(span, -1.0);
  for (const std::uint32_t i : pixels) {
    const std::size_t c = i % cols - c0;
    const double d = (frame.scan.position(i) - frame.beams.origin_of(i)).head<2>().norm();
    if (d < near_d[c]) {
      near_d[c] = d;
      nearest[c] = i;
    }
    if (d > far_d[c]) {
      far_d[c] = d;
      farthest[c] = i;
    }
  }
  Candidates out;
  out.near.reserve(span);
  out.all.reserve(2 * span);
  const Eigen::Vector2d ref = frame.world_xy(frame.scan.position(pixels.front()));
  out.ref = ref;
  for (std::size_t c = 0; c < span; ++c) {
    if (nearest[c] == kNone) continue;
    out.near.push_back(frame.world_xy(frame.scan.position(nearest[c])) - ref);
    out.all.push_back(out.near.back());
    if (farthest[c] != nearest[c]) out.all.push_back(frame.world_xy(frame.scan.position(farthest[c])) - ref);
  }
  return out;
}

}  // namespace

OutlineAxis outline_axis(const std::vector<std::uint32_t>& pixels, const Frame& frame, const TrackerParams::Heading& p) {
  OutlineAxis out;
  if (pixels.size() < 3) return out;
  const Candidates pts = hull_candidates(pixels, frame);
  constexpr double kDeg = M_PI / 180.0;
  const double coarse = closest_edges(pts.near, 0.0, 3.0 * kDeg, 30).angle;
  const ClosestEdges fine = closest_edges(pts.near, coarse - 3.0 * kDeg, 0.25 * kDeg, 25);
  const double angle = fine.angle;
  const Bounds bounds(pts.all, angle);
  const double along = bounds.a1 - bounds.a0, across = bounds.b1 - bounds.b0;
  const bool along_is_long = along >= across;
  const double a = along_is_long ? angle : angle + 0.5 * M_PI;
  out.axis = Eigen::Vector2d(std::cos(a), std::sin(a));
  out.length_m = std::max(along, across);
  out.width_m = std::min(along, across);
  out.at = pts.ref;
  out.columns = static_cast<int>(pts.near.size());
  const bool long_side =
      p.use_outline && out.length_m >= p.min_length_m && out.length_m >= p.min_aspect * out.width_m;
  // A long side the near pixels do not lie along is a rectangle drawn over several surfaces: a
  // van seen head-on, the front of its upper part a metre behind its lower front and one column
  // of its side behind them, fits a diagonal 34 degrees off its axis.
  out.rectangle = !long_side || !(p.max_edge_distance_m > 0.0) ||
                  fine.sum <= p.max_edge_distance_m * static_cast<double>(pts.near.size());
  out.informative = long_side && out.rectangle;
  // The side the sensor sees alone, on the same rectangle.
  const Bounds side(pts.near, angle);
  const double side_along = side.a1 - side.a0, side_across = side.b1 - side.b0;
  const double s = side_along >= side_across ? angle : angle + 0.5 * M_PI;
  out.side_axis = Eigen::Vector2d(std::cos(s), std::sin(s));
  out.side_length_m = std::max(side_along, side_across);
  out.side_width_m = std::min(side_along, side_across);
  return out;
}

double axis_heading_variance(const OutlineAxis& a, const Eigen::Vector2d& sensor, bool cut,
                             const TrackerParams::Heading& p) {
  const Eigen::Vector2d sight = a.at - sensor;
  const double range = sight.norm();
  // The ends' scatter over the length, as far as the side is seen end-on.
  double end = p.end_sigma_per_m * range / a.length_m;
  end *= std::abs(a.axis.dot(sight.normalized()));
  const double floor =
      range / a.length_m < p.near_range_lengths ? std::max(p.sigma_rad, p.near_sigma_rad) : p.sigma_rad;
  const double factor = cut ? p.cut_sigma_factor : 1.0;
  return factor * factor * (floor * floor + end * end);
}

double side_sight_cosine(const OutlineAxis& a, const Eigen::Vector2d& sensor) {
  return std::abs(a.side_axis.dot((a.at - sensor).normalized()));
}

bool is_face(const OutlineAxis& a, const Eigen::Vector2d& sensor, const Eigen::Vector2d& heading,
             const TrackerParams::Heading& p) {
  if (!p.use_outline || p.face_min_length_m <= 0.0 || a.informative || !a.rectangle) return false;
  // The side the sensor sees: not long enough for a body's length, long enough for its width, a
  // line (a car's roof behind its rear, seen from above it, is no part of the face).
  const bool line = a.side_length_m >= p.face_min_length_m && a.side_length_m < p.min_length_m &&
                    a.side_length_m >= p.min_aspect * a.side_width_m &&
                    a.columns >= p.face_min_columns;
  // Square to the line of sight, and to the track's velocity.
  return line && side_sight_cosine(a, sensor) <= p.face_sight_cosine &&
         std::abs(a.side_axis.dot(heading)) <= std::sin(p.face_max_angle_rad);
}

double face_heading_variance(const OutlineAxis& a, const Eigen::Vector2d& sensor, bool cut,
                             const TrackerParams::Heading& p) {
  const double factor = cut ? p.cut_sigma_factor : 1.0;
  const double oblique = p.face_oblique_sigma_rad * side_sight_cosine(a, sensor);
  return factor * factor *
             (p.sigma_rad * p.sigma_rad + p.face_sigma_rad * p.face_sigma_rad / a.columns) +
         oblique * oblique;
}

}  // namespace fmcw::core::tracking
