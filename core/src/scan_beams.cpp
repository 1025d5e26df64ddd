#include "scan_beams.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fmcw/core/velocity_lsq.hpp"
#include "vector_clones.hpp"

namespace fmcw::core {

namespace {

// e = (p - o) / |p - o| in the operations Eigen's normalized() performs (squared norm summed x,
// y, z; three divisions by its square root), zero where invalid: the beams are the same bit for
// bit whichever instruction set runs the loop. A block of a row without any return (sky) is
// only zeroed: the divisions are most of the cost.
FMCW_VECTOR_CLONES void unit_beams(const Scan& scan, const double* ox, const double* oy, const double* oz, double* ex,
                                   double* ey, double* ez) {
  constexpr std::size_t kBlock = 64;
  const std::size_t cols = static_cast<std::size_t>(scan.cols);
  for (std::size_t row = 0; row < static_cast<std::size_t>(scan.rows); ++row) {
    const std::size_t first = row * cols;
    const float *x = scan.x_m.data() + first, *y = scan.y_m.data() + first, *z = scan.z_m.data() + first;
    const std::uint8_t* valid = scan.valid.data() + first;
    double *outx = ex + first, *outy = ey + first, *outz = ez + first;
    for (std::size_t b = 0; b < cols; b += kBlock) {
      const std::size_t end = std::min(cols, b + kBlock);
      std::uint8_t any = 0;
      for (std::size_t c = b; c < end; ++c) any |= valid[c];
      if (any == 0) {
        for (std::size_t c = b; c < end; ++c) outx[c] = outy[c] = outz[c] = 0.0;
        continue;
      }
#pragma omp simd
      for (std::size_t c = b; c < end; ++c) {
        const double dx = static_cast<double>(x[c]) - ox[c], dy = static_cast<double>(y[c]) - oy[c],
                     dz = static_cast<double>(z[c]) - oz[c];
        const double n2 = dx * dx + dy * dy + dz * dz;
        const bool keep = valid[c] != 0;
        const bool use = keep & (n2 > 0.0);
        const double s = std::sqrt(use ? n2 : 1.0);  // n2 >= 0: no error to report
        const double qx = dx / s, qy = dy / s, qz = dz / s;
        outx[c] = use ? qx : (keep ? dx : 0.0);  // invalid pixels hold NaN positions
        outy[c] = use ? qy : (keep ? dy : 0.0);
        outz[c] = use ? qz : (keep ? dz : 0.0);
      }
    }
  }
}

}  // namespace

void ScanBeams::assign(const Scan& scan) {
  origin = column_origins(scan);
  cols = static_cast<std::size_t>(scan.cols);
  ex.resize(scan.size());
  ey.resize(scan.size());
  ez.resize(scan.size());
  std::vector<double> ox(cols), oy(cols), oz(cols);
  for (std::size_t c = 0; c < cols; ++c) {
    ox[c] = origin[c].x();
    oy[c] = origin[c].y();
    oz[c] = origin[c].z();
  }
  if (scan.size() > 0) unit_beams(scan, ox.data(), oy.data(), oz.data(), ex.data(), ey.data(), ez.data());
}

}  // namespace fmcw::core
