#include <algorithm>
#include <limits>

#include "fmcw/core/object_tracker.hpp"
#include "../vector_clones.hpp"

namespace fmcw::core {

namespace {
// The farthest range seen per pixel; no return counts as infinitely far.
FMCW_VECTOR_CLONES void keep_farthest(std::size_t n, const std::uint8_t* valid, const float* range, float* farthest) {
  for (std::size_t i = 0; i < n; ++i) {
    const float r = valid[i] != 0 ? range[i] : std::numeric_limits<float>::infinity();
    farthest[i] = farthest[i] < r ? r : farthest[i];  // std::max(farthest, r)
  }
}
}  // namespace

void BackgroundModel::reset() {
  range_m_.clear();
  frames_ = 0;
}

void BackgroundModel::begin_frame(const Scan& scan, bool standing) {
  if ((!standing && frames_ > 0) || range_m_.size() != scan.size()) {
    range_m_.assign(scan.size(), 0.0f);
    frames_ = 0;
  }
}

bool BackgroundModel::foreground(const Scan& scan, std::size_t i, double margin_m) const {
  const int r0 = static_cast<int>(i / static_cast<std::size_t>(scan.cols));
  const int c0 = static_cast<int>(i % static_cast<std::size_t>(scan.cols));
  float far = std::numeric_limits<float>::infinity();
  for (int r = std::max(r0 - 1, 0); r <= std::min(r0 + 1, scan.rows - 1); ++r) {
    for (int c = std::max(c0 - 1, 0); c <= std::min(c0 + 1, scan.cols - 1); ++c) far = std::min(far, range_m_[scan.index(r, c)]);
  }
  return static_cast<double>(scan.range_m[i]) < static_cast<double>(far) - margin_m;
}

void BackgroundModel::add(const Scan& scan) {
  keep_farthest(scan.size(), scan.valid.data(), scan.range_m.data(), range_m_.data());
  ++frames_;
}

}  // namespace fmcw::core
