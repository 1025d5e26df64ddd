#include "fmcw/core/grid_projection.hpp"

#include <algorithm>
#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::core {

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;
// A grid larger than this is a resolution typo, not a sensor: refuse it before allocating.
constexpr std::int64_t kMaxPixels = std::int64_t{64} * 1024 * 1024;

// Bins a span must divide into: whole, so that bins do not depend on rounding. Counted in
// double and bounded before the conversion to int, so that a bin typed in the wrong unit is
// refused with the size it would give, not an overflowed int.
int whole_bins(double span_deg, double bin_deg, const char* span_name, const char* bin_name, const char* bins) {
  const double n = span_deg / bin_deg;
  FMCW_CHECK_LIMIT(n <= static_cast<double>(kMaxPixels), "grid projection: ", bin_name, " ", bin_deg, " over ", span_name,
                   " ", span_deg, " gives ", n, " ", bins, ", more than the ", kMaxPixels,
                   " pixels a grid may have; choose a coarser resolution");
  FMCW_CHECK_ARG(std::abs(n - std::round(n)) < 1e-6 * std::max(1.0, n), "grid projection: ", span_name, " (",
                 span_deg, ") must be a whole multiple of ", bin_name, " (", bin_deg, ")");
  return static_cast<int>(std::round(n));
}

void check_optional_size(std::size_t got, std::size_t n, const char* field) {
  FMCW_CHECK_ARG(got == 0 || got == n, "points: field '", field, "' has ", got, " values, expected 0 or ", n);
}

void check_finite(float value, std::size_t point, const char* field) {
  FMCW_CHECK_ARG(std::isfinite(value), "points: point ", point, ": field '", field, "' is ", value,
                 ", expected a finite number");
}
}  // namespace

void GridProjectionParams::validate() const {
  FMCW_CHECK_ARG(fov_horizontal_deg > 0.0 && fov_horizontal_deg <= 360.0,
                 "grid projection: fov_horizontal_deg must be in (0, 360], got ", fov_horizontal_deg);
  FMCW_CHECK_ARG(fov_vertical_deg > 0.0 && fov_vertical_deg <= 180.0,
                 "grid projection: fov_vertical_deg must be in (0, 180], got ", fov_vertical_deg);
  FMCW_CHECK_ARG(resolution_horizontal_deg > 0.0 && resolution_horizontal_deg <= fov_horizontal_deg,
                 "grid projection: resolution_horizontal_deg must be in (0, fov_horizontal_deg], got ",
                 resolution_horizontal_deg);
  FMCW_CHECK_ARG(resolution_vertical_deg > 0.0 && resolution_vertical_deg <= fov_vertical_deg,
                 "grid projection: resolution_vertical_deg must be in (0, fov_vertical_deg], got ",
                 resolution_vertical_deg);
  FMCW_CHECK_ARG(lines >= 0, "grid projection: lines must be >= 0 (0 = from the data), got ", lines);
  // Whole numbers of bins, each within the pixel limit.
  cols();
  elevation_rows();
}

int GridProjectionParams::cols() const {
  return whole_bins(fov_horizontal_deg, resolution_horizontal_deg, "fov_horizontal_deg", "resolution_horizontal_deg",
                    "columns");
}

int GridProjectionParams::elevation_rows() const {
  return whole_bins(fov_vertical_deg, resolution_vertical_deg, "fov_vertical_deg", "resolution_vertical_deg", "rows");
}

GridProjection project_to_grid(const PointList& points, const GridProjectionParams& params) {
  params.validate();
  const std::size_t n = points.size();
  FMCW_CHECK_ARG(points.y_m.size() == n && points.z_m.size() == n && points.radial_velocity_mps.size() == n,
                 "points: x, y, z and v must have one value per point, got ", n, ", ", points.y_m.size(), ", ",
                 points.z_m.size(), " and ", points.radial_velocity_mps.size());
  check_optional_size(points.intensity.size(), n, "intensity");
  check_optional_size(points.time_offset_s.size(), n, "t");
  check_optional_size(points.line_index.size(), n, "line_index");
  const bool by_line = !points.line_index.empty();

  int rows = params.elevation_rows();
  if (by_line) {
    std::int32_t max_line = -1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t line = points.line_index[i];
      FMCW_CHECK_ARG(line >= 0, "points: point ", i, ": line index ", line, " is negative");
      FMCW_CHECK_ARG(params.lines == 0 || line < params.lines, "points: point ", i, ": line index ", line,
                     " is out of range [0, ", params.lines, ")");
      max_line = std::max(max_line, line);
    }
    rows = params.lines > 0 ? params.lines : max_line + 1;
  }
  const int cols = params.cols();
  const double pixels = static_cast<double>(rows) * static_cast<double>(cols);
  FMCW_CHECK_LIMIT(pixels <= static_cast<double>(kMaxPixels), "grid projection: ", rows, " x ", cols, " pixels (", pixels,
                   ") is more than the ", kMaxPixels, " a grid may have; choose a coarser resolution");

  GridProjection out;
  out.stats.points = n;
  out.stats.rows_by_line = by_line;
  out.point_of_pixel.assign(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols), -1);
  out.pixel_of_point.assign(n, -1);
  std::vector<float> range(n, 0.0f);

  const double half_h = 0.5 * params.fov_horizontal_deg;
  const double half_v = 0.5 * params.fov_vertical_deg;
  const bool full_circle = params.fov_horizontal_deg == 360.0;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = points.x_m[i], y = points.y_m[i], z = points.z_m[i];
    check_finite(x, i, "x");
    check_finite(y, i, "y");
    check_finite(z, i, "z");
    check_finite(points.radial_velocity_mps[i], i, "v");
    if (!points.intensity.empty()) check_finite(points.intensity[i], i, "intensity");
    if (!points.time_offset_s.empty()) check_finite(points.time_offset_s[i], i, "t");
    const double horizontal = std::hypot(static_cast<double>(x), static_cast<double>(y));
    range[i] = static_cast<float>(std::hypot(horizontal, static_cast<double>(z)));
    FMCW_CHECK_ARG(range[i] > 0.0f, "points: point ", i, " is at the sensor origin (zero range)");

    const double azimuth_deg = std::atan2(static_cast<double>(y), static_cast<double>(x)) * kRadToDeg;
    double u = (half_h - azimuth_deg) / params.resolution_horizontal_deg;
    // A full circle wraps: azimuth -180 deg is the same column as +180 deg.
    if (full_circle && u >= cols) u -= cols;
    if (full_circle && u < 0.0) u += cols;
    double row_u = 0.0;
    if (by_line) {
      row_u = points.line_index[i];
    } else {
      row_u = (half_v - std::atan2(static_cast<double>(z), horizontal) * kRadToDeg) / params.resolution_vertical_deg;
    }
    if (u < 0.0 || u >= cols || row_u < 0.0 || row_u >= rows) {
      ++out.stats.outside_fov;
      continue;
    }
    const std::size_t pixel =
        static_cast<std::size_t>(row_u) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(u);
    std::int64_t& holder = out.point_of_pixel[pixel];
    if (holder < 0) {
      holder = static_cast<std::int64_t>(i);
      continue;
    }
    ++out.stats.collisions;
    // Nearest return wins; on equal range the earlier point stays, so order alone decides ties.
    if (range[i] < range[static_cast<std::size_t>(holder)]) holder = static_cast<std::int64_t>(i);
  }

  Scan& scan = out.scan;
  scan = Scan::make_empty(rows, cols);
  scan.heads.front().name = "sensor";
  if (!points.time_offset_s.empty()) scan.time_offset_s.assign(scan.size(), 0.0f);
  for (std::size_t p = 0; p < scan.size(); ++p) {
    const std::int64_t holder = out.point_of_pixel[p];
    if (holder < 0) continue;
    const auto i = static_cast<std::size_t>(holder);
    out.pixel_of_point[i] = static_cast<std::int64_t>(p);
    ++out.stats.placed;
    scan.x_m[p] = points.x_m[i];
    scan.y_m[p] = points.y_m[i];
    scan.z_m[p] = points.z_m[i];
    scan.range_m[p] = range[i];
    scan.radial_velocity_mps[p] = points.radial_velocity_mps[i];
    scan.intensity[p] = points.intensity.empty() ? 0.0f : points.intensity[i];
    if (!points.time_offset_s.empty()) scan.time_offset_s[p] = points.time_offset_s[i];
    scan.valid[p] = 1;
  }
  return out;
}

}  // namespace fmcw::core
