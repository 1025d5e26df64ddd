#pragma once
// Internal to core: the pixels that pass a test, listed in ascending order without a branch
// per pixel (the predictor cannot learn where objects begin and end): every pixel of a block
// is written at slot m, and m advances past the ones that pass only. Blocks where no pixel
// passes (most of an image: the listed pixels are those of objects) are skipped after one
// test of the whole block, which runs in vectors.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fmcw::core {

/// The i in [0, n) with passes(i), ascending, into out.
template <class Passes>
void list_pixels(std::size_t n, const Passes& passes, std::vector<std::uint32_t>& out) {
  constexpr std::size_t kBlock = 64;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += passes(i) ? 1 : 0;
  // The writes of a block run at most a block past the last listed pixel.
  out.resize(count + kBlock);
  std::size_t m = 0;
  const auto list = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      out[m] = static_cast<std::uint32_t>(i);
      m += passes(i) ? 1 : 0;
    }
  };
  std::size_t begin = 0;
  for (; begin + kBlock <= n && m < count; begin += kBlock) {
    std::uint32_t in_block = 0;  // counted, not or-ed: the count runs in vectors
    for (std::size_t i = begin; i < begin + kBlock; ++i) in_block += passes(i) ? 1U : 0U;
    if (in_block != 0) list(begin, begin + kBlock);
  }
  if (m < count) list(begin, n);
  out.resize(count);
}

}  // namespace fmcw::core
