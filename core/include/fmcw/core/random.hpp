#pragma once
// Seeded, platform-independent random numbers: the same seed gives the same draws everywhere
// (std::*_distribution is implementation-defined, so it is not used where output is compared).

#include <cstdint>
#include <vector>

namespace fmcw::core {

/// splitmix64 step: mixes a 64-bit state into a well-distributed value. Also used to derive
/// independent seeds (per frame, per cluster) from one user seed.
std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b = 0);

/// xoshiro256** generator.
class Rng {
 public:
  explicit Rng(std::uint64_t seed);
  std::uint64_t next_u64();
  double uniform();                     ///< [0, 1)
  std::uint64_t uniform_below(std::uint64_t n);  ///< [0, n), unbiased
  /// Standard normal by the ziggurat method (128 layers): about 99 % of draws cost one
  /// generator step, a table lookup and a multiply; the rest fall back to exact rejection.
  double normal();

 private:
  double normal_slow(std::int64_t hz, int iz);
  std::uint64_t s_[4];
};

/// Indices of min(k, n) elements of [0, n) chosen uniformly without replacement, in ascending
/// order; all n indices when k == 0 or k >= n.
std::vector<std::uint32_t> subsample_indices(std::uint32_t n, std::uint32_t k, std::uint64_t seed);

}  // namespace fmcw::core
