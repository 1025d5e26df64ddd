#include "scan_beams.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

#include "fmcw/core/velocity_lsq.hpp"
#include "vector_clones.hpp"

namespace fmcw::core {

namespace {

// e = (p - o) / |p - o| in the operations Eigen's normalized() performs (squared norm summed x,
// y, z; three divisions by its square root), zero where invalid: the beams are the same bit for
// bit whichever instruction set runs the loop.
FMCW_VECTOR_CLONES void unit_beams(const Scan& scan, const double* ox, const double* oy, const double* oz, double* e) {
  const std::size_t cols = static_cast<std::size_t>(scan.cols);
  for (std::size_t row = 0; row < static_cast<std::size_t>(scan.rows); ++row) {
    const std::size_t first = row * cols;
    const float *x = scan.x_m.data() + first, *y = scan.y_m.data() + first, *z = scan.z_m.data() + first;
    const std::uint8_t* valid = scan.valid.data() + first;
    double* out = e + 3 * first;
#pragma omp simd
    for (std::size_t c = 0; c < cols; ++c) {
      const double dx = static_cast<double>(x[c]) - ox[c], dy = static_cast<double>(y[c]) - oy[c],
                   dz = static_cast<double>(z[c]) - oz[c];
      const double n2 = dx * dx + dy * dy + dz * dz;
      const bool keep = valid[c] != 0;
      const bool use = keep & (n2 > 0.0);
      const double s = std::sqrt(use ? n2 : 1.0);  // n2 >= 0: no error to report
      const double qx = dx / s, qy = dy / s, qz = dz / s;
      out[3 * c] = use ? qx : (keep ? dx : 0.0);  // invalid pixels hold NaN positions
      out[3 * c + 1] = use ? qy : (keep ? dy : 0.0);
      out[3 * c + 2] = use ? qz : (keep ? dz : 0.0);
    }
  }
}

}  // namespace

void ScanBeams::assign(const Scan& scan) {
  origin = column_origins(scan);
  cols = static_cast<std::size_t>(scan.cols);
  e.resize(scan.size());
  std::vector<double> ox(cols), oy(cols), oz(cols);
  for (std::size_t c = 0; c < cols; ++c) {
    ox[c] = origin[c].x();
    oy[c] = origin[c].y();
    oz[c] = origin[c].z();
  }
  if (!e.empty()) unit_beams(scan, ox.data(), oy.data(), oz.data(), e.front().data());
}

}  // namespace fmcw::core
