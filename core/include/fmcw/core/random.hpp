#pragma once
// Seeded, platform-independent random numbers: the same seed gives the same draws everywhere
// (std::*_distribution is implementation-defined, so it is not used where output is compared).

#include <cstdint>
#include <vector>

namespace fmcw::core {

/// splitmix64 step: mixes a 64-bit state into a well-distributed value. Also used to derive
/// independent seeds (per frame, per cluster) from one user seed.
std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b = 0);

namespace detail {
/// Ziggurat tables for the standard normal, 128 layers (see random.cpp).
struct ZigguratTables {
  std::uint32_t k[128];
  double w[128];
  double f[128];
  ZigguratTables();
};
extern const ZigguratTables kZiggurat;
}  // namespace detail

/// xoshiro256** generator.
class Rng {
 public:
  explicit Rng(std::uint64_t seed);
  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  double uniform();                     ///< [0, 1)
  std::uint64_t uniform_below(std::uint64_t n);  ///< [0, n), unbiased
  /// Standard normal by the ziggurat method (128 layers): about 99 % of draws cost one
  /// generator step, a table lookup and a multiply; the rest fall back to exact rejection.
  double normal() {
    // Layer index from the low bits, signed value from the high 32 bits: independent bits.
    const std::uint64_t bits = next_u64();
    const int iz = static_cast<int>(bits & 127u);
    const auto hz = static_cast<std::int64_t>(static_cast<std::int32_t>(bits >> 32));
    const auto mag = static_cast<std::uint64_t>(hz < 0 ? -hz : hz);
    if (mag < detail::kZiggurat.k[iz]) return static_cast<double>(hz) * detail::kZiggurat.w[iz];
    return normal_slow(hz, iz);
  }

 private:
  static std::uint64_t rotl(std::uint64_t v, int k) { return (v << k) | (v >> (64 - k)); }
  double normal_slow(std::int64_t hz, int iz);
  std::uint64_t s_[4];
};

/// Indices of min(k, n) elements of [0, n) chosen uniformly without replacement, in ascending
/// order; all n indices when k == 0 or k >= n.
std::vector<std::uint32_t> subsample_indices(std::uint32_t n, std::uint32_t k, std::uint64_t seed);

}  // namespace fmcw::core
