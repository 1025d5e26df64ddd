#pragma once
// Internal to core: the pixels that pass a test, listed in ascending order without a branch
// per pixel (the predictor cannot learn where objects begin and end): every pixel is written at
// slot m, and m advances past the ones that pass only.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fmcw::core {

/// The i in [0, n) with passes(i), ascending, into out.
template <class Passes>
void list_pixels(std::size_t n, const Passes& passes, std::vector<std::uint32_t>& out) {
  out.resize(n + 1);  // one slot of slack for the writes after the last listed pixel
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; ++i) {
    out[m] = static_cast<std::uint32_t>(i);
    m += passes(i) ? 1 : 0;
  }
  out.resize(m);
}

}  // namespace fmcw::core
