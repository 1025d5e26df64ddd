#include "fmcw/core/random.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace fmcw::core {

std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = a + 0x9E3779B97F4A7C15ULL * (b + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

Rng::Rng(std::uint64_t seed) {
  std::uint64_t x = seed;
  for (auto& s : s_) {
    x = mix_seed(x, 0x5EED);
    s = x;
  }
}

double Rng::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

std::uint64_t Rng::uniform_below(std::uint64_t n) {
  // Rejection on the top of the range keeps the draw unbiased.
  const std::uint64_t limit = n == 0 ? 0 : (~std::uint64_t{0}) - (~std::uint64_t{0}) % n;
  std::uint64_t x = next_u64();
  while (x >= limit) x = next_u64();
  return x % n;
}

namespace {

// Ziggurat tables for the standard normal with 128 layers of equal area v, the base strip
// ending at r (Marsaglia and Tsang, 2000). Values are drawn as 32-bit signed integers hz scaled
// by w[i]; |hz| < k[i] means the point lies inside the layer's inner rectangle.
constexpr double kZigR = 3.442619855899;
constexpr double kZigV = 9.91256303526217e-3;

}  // namespace

namespace detail {

ZigguratTables::ZigguratTables() {
  const double m = 2147483648.0;  // 2^31
  double dn = kZigR;
  double tn = dn;
  const double q = kZigV / std::exp(-0.5 * dn * dn);
  k[0] = static_cast<std::uint32_t>((dn / q) * m);
  k[1] = 0;
  w[0] = q / m;
  w[127] = dn / m;
  f[0] = 1.0;
  f[127] = std::exp(-0.5 * dn * dn);
  for (int i = 126; i >= 1; --i) {
    dn = std::sqrt(-2.0 * std::log(kZigV / dn + std::exp(-0.5 * dn * dn)));
    k[i + 1] = static_cast<std::uint32_t>((dn / tn) * m);
    tn = dn;
    f[i] = std::exp(-0.5 * dn * dn);
    w[i] = dn / m;
  }
}

// Built during static initialisation of this file: draws must not happen in other files'
// static initialisers.
const ZigguratTables kZiggurat;

}  // namespace detail

void Rng::normals(double* out, std::size_t n) {
  std::uint64_t s0 = s_[0], s1 = s_[1], s2 = s_[2], s3 = s_[3];
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint64_t bits = step(s0, s1, s2, s3);
    if (ziggurat_fast(bits, out[k])) continue;
    s_[0] = s0, s_[1] = s1, s_[2] = s2, s_[3] = s3;
    out[k] = normal_slow(bits);
    s0 = s_[0], s1 = s_[1], s2 = s_[2], s3 = s_[3];
  }
  s_[0] = s0, s_[1] = s1, s_[2] = s2, s_[3] = s3;
}

double Rng::normal_slow(std::uint64_t bits) {
  const detail::ZigguratTables& t = detail::kZiggurat;
  int iz = static_cast<int>(bits & 127u);
  auto hz = static_cast<std::int64_t>(static_cast<std::int32_t>(bits >> 32));
  for (;;) {
    const double x = static_cast<double>(hz) * t.w[iz];
    if (iz == 0) {
      // Base strip: sample the tail beyond r exactly.
      double tail = 0.0;
      double y = 0.0;
      do {
        double u1 = uniform();
        while (u1 <= 0.0) u1 = uniform();
        double u2 = uniform();
        while (u2 <= 0.0) u2 = uniform();
        tail = -std::log(u1) / kZigR;
        y = -std::log(u2);
      } while (y + y < tail * tail);
      return hz > 0 ? kZigR + tail : -kZigR - tail;
    }
    // Wedge between the layer's rectangle and the curve: accept under the density.
    if (t.f[iz] + uniform() * (t.f[iz - 1] - t.f[iz]) < std::exp(-0.5 * x * x)) return x;
    const std::uint64_t next = next_u64();
    double y;
    if (ziggurat_fast(next, y)) return y;
    iz = static_cast<int>(next & 127u);
    hz = static_cast<std::int64_t>(static_cast<std::int32_t>(next >> 32));
  }
}

namespace {

// The slots of [0, n) that a partial Fisher-Yates shuffle has touched, in an open-addressing
// table: an untouched slot x holds x. The swaps write at most 2k slots, so a table of 4k or more
// entries never fills, and the shuffle costs O(k) instead of O(n).
class SparseShuffle {
 public:
  explicit SparseShuffle(std::uint32_t k) {
    std::size_t size = 16;
    while (size < 4 * static_cast<std::size_t>(k)) size *= 2;
    keys_.assign(size, kEmpty);
    values_.resize(size);
  }
  std::uint32_t& at(std::uint32_t x) {
    std::size_t h = (static_cast<std::size_t>(x) * 0x9E3779B1u) & (keys_.size() - 1);
    while (keys_[h] != kEmpty && keys_[h] != x) h = (h + 1) & (keys_.size() - 1);
    if (keys_[h] == kEmpty) {
      keys_[h] = x;
      values_[h] = x;
    }
    return values_[h];
  }

 private:
  static constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
  std::vector<std::uint32_t> keys_, values_;
};

// Ascending order of values below 2^32: three stable 11-bit radix passes.
void radix_sort(std::vector<std::uint32_t>& v) {
  std::vector<std::uint32_t> tmp(v.size());
  for (int shift = 0; shift < 33; shift += 11) {
    std::array<std::size_t, 2049> start{};
    for (const std::uint32_t x : v) ++start[((x >> shift) & 0x7FFu) + 1];
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    for (const std::uint32_t x : v) tmp[start[(x >> shift) & 0x7FFu]++] = x;
    v.swap(tmp);
  }
}

}  // namespace

std::vector<std::uint32_t> subsample_indices(std::uint32_t n, std::uint32_t k, std::uint64_t seed) {
  if (k == 0 || k >= n) {
    std::vector<std::uint32_t> idx(n);
    std::iota(idx.begin(), idx.end(), 0u);
    return idx;
  }
  // Partial Fisher-Yates: the first k slots end up a uniform sample without replacement.
  Rng rng(seed);
  SparseShuffle slots(k);
  std::vector<std::uint32_t> idx(k);
  for (std::uint32_t i = 0; i < k; ++i) {
    const auto j = i + static_cast<std::uint32_t>(rng.uniform_below(n - i));
    std::uint32_t& a = slots.at(i);
    std::uint32_t& b = slots.at(j);
    std::swap(a, b);
    idx[i] = a;
  }
  radix_sort(idx);
  return idx;
}

}  // namespace fmcw::core
