// The ego twist's rows, gathered from the scan and its beams (ego_twist_beams.hpp).

#include <algorithm>
#include <cstring>

#include "ego_twist_beams.hpp"
#include "vector_clones.hpp"

namespace fmcw::core {

namespace {

// The rows of a span of pixels that are all valid, written from slot 0 of the r* arrays.
FMCW_VECTOR_CLONES void full_row(std::size_t cols, const double* __restrict ex, const double* __restrict ey,
                                 const double* __restrict ez, const float* __restrict v, const double* __restrict ox,
                                 const double* __restrict oy, const std::uint16_t* __restrict cell_col, std::uint16_t cell_row,
                                 double* __restrict rx, double* __restrict ry, double* __restrict rz, double* __restrict rw,
                                 double* __restrict rv, std::uint16_t* __restrict rc) {
  for (std::size_t c = 0; c < cols; ++c) {
    rx[c] = ex[c];
    ry[c] = ey[c];
    rz[c] = ez[c];
    rw[c] = ox[c] * ey[c] - oy[c] * ex[c];  // the yaw-rate term, as in gather_rows
    rv[c] = static_cast<double>(v[c]);
    rc[c] = static_cast<std::uint16_t>(cell_row + cell_col[c]);
  }
}

}  // namespace

void gather_rows(const Scan& scan, const ScanBeams& beams, TwistRows& rows) {
  const std::size_t cols = static_cast<std::size_t>(scan.cols);
  // Per column: the yaw-rate lever (o_x, o_y) and the grid column.
  std::vector<double> ox(cols), oy(cols);
  std::vector<std::uint16_t> cell_col(cols);
  for (std::size_t c = 0; c < cols; ++c) {
    ox[c] = beams.origin[c].x();
    oy[c] = beams.origin[c].y();
    cell_col[c] = static_cast<std::uint16_t>(static_cast<int>(c) * kCellCols / scan.cols);
  }
  // A span of a row is copied whole, in vectors, where all its pixels are valid (below the
  // horizon: most of an image), skipped where none is (the sky). In the others every pixel
  // is written at slot k and k advances over the valid ones only (no branch on validity, which
  // the predictor cannot learn at the edges of returns); one slot of slack takes the writes
  // after the last valid pixel. The same values land in the same slots either way.
  constexpr std::size_t kSpan = 64;
  const std::size_t num_valid = scan.num_valid();
  rows.resize(num_valid + 1);
  std::size_t k = 0;
  for (int r = 0; r < scan.rows; ++r) {
    const auto cell_row = static_cast<std::uint16_t>((r * kCellRows / scan.rows) * kCellCols);
    const std::size_t first = scan.index(r, 0);
    const std::uint8_t* valid = scan.valid.data() + first;
    const auto copy = [&](std::size_t c0, std::size_t c1) {
      const std::size_t i = first + c0;
      full_row(c1 - c0, beams.ex.data() + i, beams.ey.data() + i, beams.ez.data() + i, scan.radial_velocity_mps.data() + i,
               ox.data() + c0, oy.data() + c0, cell_col.data() + c0, cell_row, rows.ex.data() + k, rows.ey.data() + k,
               rows.ez.data() + k, rows.ew.data() + k, rows.v.data() + k, rows.cell.data() + k);
      k += c1 - c0;
    };
    if (std::memchr(valid, 0, cols) == nullptr) {
      copy(0, cols);
      continue;
    }
    for (std::size_t c0 = 0; c0 < cols; c0 += kSpan) {
      const std::size_t c1 = std::min(cols, c0 + kSpan);
      std::uint32_t in_span = 0;
      for (std::size_t c = c0; c < c1; ++c) in_span += valid[c] != 0 ? 1U : 0U;
      if (in_span == c1 - c0) {
        copy(c0, c1);
        continue;
      }
      if (in_span == 0) continue;
      for (std::size_t c = c0; c < c1; ++c) {
        const std::size_t i = first + c;
        const double ex = beams.ex[i], ey = beams.ey[i];
        // Yaw rate term: e . (omega_z z x o) = omega_z (o_x e_y - o_y e_x).
        rows.set(k, ex, ey, beams.ez[i], ox[c] * ey - oy[c] * ex, scan.radial_velocity_mps[i],
                 static_cast<std::uint16_t>(cell_row + cell_col[c]));
        k += valid[c] != 0 ? 1 : 0;
      }
    }
  }
  rows.resize(num_valid);
}

}  // namespace fmcw::core
