#pragma once
// The median used by the robust estimators: the upper one, found in place.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace fmcw::core {

/// The upper median of v (the element at index size / 2 once sorted). Reorders v; v must not
/// be empty.
inline double upper_median(std::vector<double>& v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace fmcw::core
