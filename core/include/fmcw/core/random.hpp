#pragma once
// Seeded, platform-independent random numbers: the same seed gives the same draws everywhere
// (std::*_distribution is implementation-defined, so it is not used where output is compared).

#include <cstddef>
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
  std::uint64_t next_u64() { return step(s_[0], s_[1], s_[2], s_[3]); }
  double uniform();                     ///< [0, 1)
  std::uint64_t uniform_below(std::uint64_t n);  ///< [0, n), unbiased
  /// Standard normal by the ziggurat method (128 layers): about 99 % of draws cost one
  /// generator step, a table lookup and a multiply; the rest fall back to exact rejection.
  double normal() {
    const std::uint64_t bits = next_u64();
    double x;
    return ziggurat_fast(bits, x) ? x : normal_slow(bits);
  }
  /// n draws of normal() into out, the same values in the same order; faster for many draws
  /// (the generator's state stays in registers between them).
  void normals(double* out, std::size_t n);

 private:
  static std::uint64_t rotl(std::uint64_t v, int k) { return (v << k) | (v >> (64 - k)); }
  static std::uint64_t step(std::uint64_t& s0, std::uint64_t& s1, std::uint64_t& s2, std::uint64_t& s3) {
    const std::uint64_t result = rotl(s1 * 5, 7) * 9;
    const std::uint64_t t = s1 << 17;
    s2 ^= s0;
    s3 ^= s1;
    s1 ^= s2;
    s0 ^= s3;
    s2 ^= t;
    s3 = rotl(s3, 45);
    return result;
  }
  // The ziggurat's rectangle test: true (and x) for about 99 % of draws.
  static bool ziggurat_fast(std::uint64_t bits, double& x) {
    // Layer index from the low bits, signed value from the high 32 bits: independent bits.
    const int iz = static_cast<int>(bits & 127u);
    const auto hz = static_cast<std::int64_t>(static_cast<std::int32_t>(bits >> 32));
    const auto mag = static_cast<std::uint64_t>(hz < 0 ? -hz : hz);
    x = static_cast<double>(hz) * detail::kZiggurat.w[iz];
    return mag < detail::kZiggurat.k[iz];
  }
  double normal_slow(std::uint64_t bits);
  std::uint64_t s_[4];
};

/// Indices of min(k, n) elements of [0, n) chosen uniformly without replacement, in ascending
/// order; all n indices when k == 0 or k >= n.
std::vector<std::uint32_t> subsample_indices(std::uint32_t n, std::uint32_t k, std::uint64_t seed);

}  // namespace fmcw::core
