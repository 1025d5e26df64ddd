#include "scan_beams.hpp"

#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core {

void ScanBeams::assign(const Scan& scan) {
  origin = column_origins(scan);
  e.assign(scan.size(), Eigen::Vector3d::Zero());
  cols = static_cast<std::size_t>(scan.cols);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (scan.valid[i]) e[i] = (scan.position(i) - origin[i % cols]).normalized();
  }
}

}  // namespace fmcw::core
