#pragma once
// The median used by the robust estimators: the upper one, found in place.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace fmcw::core {

/// The upper median of v (the element at index size / 2 once sorted). Reorders v; v must not
/// be empty.
inline double upper_median(std::vector<double>& v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// upper_median of values that are all >= 0 (magnitudes: +0, not -0), the same value, found
/// by radix selection on their bit patterns, which order such doubles as unsigned integers
/// do: a histogram of the exponent, then of eleven mantissa bits at a time, each pass over
/// the values that share the median's leading bits, until few are left. keys is scratch.
/// Falls back to upper_median (which reorders v) for short inputs and for any NaN.
inline double upper_median_of_magnitudes(std::vector<double>& v, std::vector<std::uint64_t>& keys) {
  constexpr std::size_t kFew = 64;
  const std::size_t n = v.size();
  if (n <= 4 * kFew) return upper_median(v);
  keys.resize(n);
  std::memcpy(keys.data(), v.data(), n * sizeof(double));
  constexpr std::uint64_t kInfBits = 0x7ff0000000000000ULL;
  std::uint64_t highest = 0;
  for (const std::uint64_t k : keys) highest = std::max(highest, k);
  if (highest > kInfBits) return upper_median(v);  // a NaN (or a negative value's sign bit)
  std::size_t m = n, rank = n / 2;
  std::array<std::uint32_t, 2048> count{};
  for (int shift = 52; m > kFew && shift >= 0; shift -= 11) {
    count.fill(0);
    for (std::size_t i = 0; i < m; ++i) ++count[(keys[i] >> shift) & 2047U];
    std::size_t bin = 0, before = 0;
    while (before + count[bin] <= rank) before += count[bin++];
    std::size_t kept = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const std::uint64_t k = keys[i];
      keys[kept] = k;
      kept += ((k >> shift) & 2047U) == bin ? 1 : 0;
    }
    m = kept;
    rank -= before;
  }
  std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(rank), keys.begin() + static_cast<std::ptrdiff_t>(m));
  double out = 0.0;
  std::memcpy(&out, &keys[rank], sizeof out);
  return out;
}

}  // namespace fmcw::core
