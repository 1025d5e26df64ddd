#include "fmcw/core/scan.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "fmcw/core/check.hpp"
#include "vector_clones.hpp"

namespace fmcw::core {

namespace {

// Finite: the exponent bits are not all set (NaN and Inf have them all set). Integer tests, so
// that the pass runs as vector code.
inline std::uint32_t finite_bit(float x) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  return (bits & 0x7f800000u) != 0x7f800000u ? 1u : 0u;
}

// Whether every valid pixel holds finite values and a positive range: one branch-free pass.
FMCW_VECTOR_CLONES bool valid_pixels_finite(const Scan& scan) {
  const std::size_t n = scan.size();
  const float *x = scan.x_m.data(), *y = scan.y_m.data(), *z = scan.z_m.data(), *v = scan.radial_velocity_mps.data();
  const float *in = scan.intensity.data(), *range = scan.range_m.data();
  const std::uint8_t* valid = scan.valid.data();
  std::uint32_t all_good = 1;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t good = finite_bit(x[i]) & finite_bit(y[i]) & finite_bit(z[i]) & finite_bit(v[i]) & finite_bit(in[i]) &
                               finite_bit(range[i]) & (range[i] > 0.0f ? 1u : 0u);
    all_good &= good | (valid[i] == 0 ? 1u : 0u);
  }
  return all_good != 0;
}

}  // namespace

const char* to_string(VelocityFrame frame) {
  return frame == VelocityFrame::kSensor ? "sensor" : "ego_compensated";
}

VelocityFrame velocity_frame_from_string(const std::string& name) {
  if (name == "sensor" || name == "raw") return VelocityFrame::kSensor;
  if (name == "ego_compensated" || name == "compensated") return VelocityFrame::kEgoCompensated;
  throw InputError(concat("velocity frame must be sensor (raw) or ego_compensated (compensated), got '", name, "'"));
}

Scan Scan::make_empty(int rows, int cols) {
  FMCW_CHECK_ARG(rows >= 0 && cols >= 0, "Scan::make_empty: rows and cols must be >= 0, got ", rows,
                 " x ", cols);
  Scan scan;
  scan.rows = rows;
  scan.cols = cols;
  const std::size_t n = scan.size();
  const float nan = std::nanf("");
  scan.x_m.assign(n, nan);
  scan.y_m.assign(n, nan);
  scan.z_m.assign(n, nan);
  scan.range_m.assign(n, nan);
  scan.radial_velocity_mps.assign(n, nan);
  scan.intensity.assign(n, 0.0f);
  scan.valid.assign(n, 0);
  HeadInfo head;
  head.name = "head0";
  head.col_begin = 0;
  head.col_end = cols;
  scan.heads.push_back(head);
  return scan;
}

namespace {
// Nonzero bytes of v, counted in 32-bit lanes over blocks of 2^16 (no lane overflows): a byte
// count widened to 64 bits at once runs at a quarter of the speed.
FMCW_VECTOR_CLONES std::size_t count_nonzero(const std::uint8_t* v, std::size_t n) {
  constexpr std::size_t kBlock = std::size_t{1} << 16;
  std::size_t total = 0;
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t end = n - b < kBlock ? n : b + kBlock;
    std::uint32_t count = 0;
    for (std::size_t i = b; i < end; ++i) count += v[i] != 0 ? 1U : 0U;
    total += count;
  }
  return total;
}
}  // namespace

std::size_t Scan::num_valid() const { return count_nonzero(valid.data(), valid.size()); }

int Scan::head_of_col(int col) const {
  for (std::size_t h = 0; h < heads.size(); ++h) {
    if (col >= heads[h].col_begin && col < heads[h].col_end) return static_cast<int>(h);
  }
  throw InputError(concat("Scan: column ", col, " belongs to no head"));
}

Eigen::Vector3d Scan::beam_origin(std::size_t i) const {
  return heads[static_cast<std::size_t>(head_of_col(static_cast<int>(i % static_cast<std::size_t>(cols))))]
      .origin_m();
}

std::vector<std::pair<int, int>> Scan::connected_column_groups() const {
  std::vector<std::pair<int, int>> groups;
  for (std::size_t h = 0; h < heads.size(); ++h) {
    if (h > 0 && heads[h - 1].stitched_to_next) {
      groups.back().second = heads[h].col_end;
    } else {
      groups.emplace_back(heads[h].col_begin, heads[h].col_end);
    }
  }
  return groups;
}

std::vector<int> Scan::column_group_of() const {
  std::vector<int> group_of(static_cast<std::size_t>(cols), 0);
  const auto groups = connected_column_groups();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (int c = groups[g].first; c < groups[g].second; ++c) group_of[static_cast<std::size_t>(c)] = static_cast<int>(g);
  }
  return group_of;
}

void Scan::validate_layout() const {
  FMCW_CHECK_ARG(rows >= 0 && cols >= 0, "scan: negative size ", rows, " x ", cols);
  // A NaN stamp would make every frame interval NaN, and tracking start over at every frame.
  FMCW_CHECK_ARG(std::isfinite(stamp_s), "scan: stamp_s is ", stamp_s, ", expected a finite time [s]");
  const std::size_t n = size();
  const auto check_size = [n](std::size_t got, const char* field) {
    FMCW_CHECK_ARG(got == n, "scan: field '", field, "' has ", got, " values, expected rows*cols = ", n);
  };
  check_size(x_m.size(), "x");
  check_size(y_m.size(), "y");
  check_size(z_m.size(), "z");
  check_size(range_m.size(), "range");
  check_size(radial_velocity_mps.size(), "v");
  check_size(intensity.size(), "intensity");
  check_size(valid.size(), "valid");
  FMCW_CHECK_ARG(time_offset_s.empty() || time_offset_s.size() == n, "scan: field 't' has ", time_offset_s.size(),
                 " values, expected 0 or rows*cols = ", n);
  FMCW_CHECK_ARG(line_index.empty() || line_index.size() == n, "scan: field 'line_index' has ", line_index.size(),
                 " values, expected 0 or rows*cols = ", n);
  FMCW_CHECK_ARG(velocity_frame == VelocityFrame::kSensor || velocity_frame == VelocityFrame::kEgoCompensated,
                 "scan: unknown velocity frame ", static_cast<int>(velocity_frame));
  FMCW_CHECK_ARG(!heads.empty() || n == 0, "scan: no heads describe the ", cols, " columns");
  int expected_begin = 0;
  for (std::size_t h = 0; h < heads.size(); ++h) {
    const HeadInfo& head = heads[h];
    FMCW_CHECK_ARG(head.col_begin == expected_begin && head.col_end > head.col_begin,
                   "scan: head ", h, " ('", head.name, "') spans columns [", head.col_begin, ", ",
                   head.col_end, "), expected a non-empty span starting at ", expected_begin);
    expected_begin = head.col_end;
  }
  FMCW_CHECK_ARG(heads.empty() || expected_begin == cols, "scan: heads cover ", expected_begin,
                 " columns but the scan has ", cols);
}

void Scan::validate() const {
  validate_layout();
  // One branch-free pass; the slow search for the pixel to name runs only on failure.
  if (valid_pixels_finite(*this)) return;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = index(r, c);
      if (!valid[i]) continue;
      const bool finite = std::isfinite(x_m[i]) && std::isfinite(y_m[i]) && std::isfinite(z_m[i]) &&
                          std::isfinite(range_m[i]) && std::isfinite(radial_velocity_mps[i]) &&
                          std::isfinite(intensity[i]);
      FMCW_CHECK_ARG(finite, "scan: valid pixel (row ", r, ", col ", c,
                     ") holds a NaN or Inf in x, y, z, range, v or intensity");
      FMCW_CHECK_ARG(range_m[i] > 0.0f, "scan: valid pixel (row ", r, ", col ", c,
                     ") has non-positive range ", range_m[i]);
    }
  }
}

}  // namespace fmcw::core
