#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fmcw/core/ceres_velocity.hpp"
#include "fmcw/core/median.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core {
namespace {

// Rows from directions spread over the given azimuth/elevation half-widths, with exact targets
// e . V plus optional noise.
VelocityRows rows_for(const Eigen::Vector3d& v, int n, double az_half_rad, double el_half_rad, double noise,
                      std::uint64_t seed) {
  Rng rng(seed);
  VelocityRows rows;
  for (int k = 0; k < n; ++k) {
    const double az = (2.0 * rng.uniform() - 1.0) * az_half_rad;
    const double el = (2.0 * rng.uniform() - 1.0) * el_half_rad;
    const Eigen::Vector3d e(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    rows.directions.push_back(e);
    rows.targets_mps.push_back(e.dot(v) + noise * rng.normal());
  }
  return rows;
}

TEST(ClosedForm, RecoversExactVelocityWithoutNoise) {
  const Eigen::Vector3d v(7.5, -1.25, 0.3);
  const VelocityRows rows = rows_for(v, 500, 1.0, 0.26, 0.0, 1);
  const VelocityEstimate est = solve_velocity_closed_form(rows);
  ASSERT_TRUE(est.valid);
  EXPECT_LT((est.velocity_mps - v).norm(), 1e-9);
  EXPECT_EQ(est.num_points, 500);
  // RSS comes from the normal-equation sums, whose cancellation leaves a floor near 1e-7 m/s.
  EXPECT_LT(est.residual_rms_mps, 1e-6);
  EXPECT_FALSE(est.used_qr);
}

TEST(ClosedForm, AgreesWithCeresTo1eMinus6OnTheSamePoints) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Eigen::Vector3d v(10.0 * seed, -3.0, 0.5);
    const VelocityRows rows = rows_for(v, 200, 0.35, 0.1, 0.031, seed);
    const VelocityEstimate fast = solve_velocity_closed_form(rows);
    const VelocityEstimate ceres = solve_velocity_ceres(rows);
    ASSERT_TRUE(fast.valid);
    ASSERT_TRUE(ceres.valid);
    EXPECT_LT((fast.velocity_mps - ceres.velocity_mps).cwiseAbs().maxCoeff(), 1e-6) << "seed " << seed;
    EXPECT_GT(ceres.iterations, 0);
  }
}

TEST(ClosedForm, CovarianceMatchesTheNoiseAndFlagsTheWeakAxis) {
  // A narrow patch straight ahead (like a distant object): x is well observed, y and z are not.
  const Eigen::Vector3d v(5.0, 1.0, 0.0);
  const VelocityRows rows = rows_for(v, 400, 0.02, 0.01, 0.031, 3);
  const VelocityEstimate est = solve_velocity_closed_form(rows);
  ASSERT_TRUE(est.valid);
  const Eigen::Vector3d sd = est.axis_std_mps();
  EXPECT_LT(sd.x(), 0.01);
  EXPECT_GT(sd.y(), 20.0 * sd.x());
  EXPECT_GT(sd.z(), sd.y());
  EXPECT_GT(est.condition_number, 1e3);
  EXPECT_NEAR(est.residual_rms_mps, 0.031, 0.005);
}

TEST(ClosedForm, IllConditionedSystemUsesQrAndStillMatchesCeres) {
  const Eigen::Vector3d v(3.0, 0.5, -0.2);
  const VelocityRows rows = rows_for(v, 300, 0.004, 0.004, 0.0, 9);
  const VelocityEstimate est = solve_velocity_closed_form(rows, /*qr_condition_threshold=*/10.0);
  EXPECT_TRUE(est.used_qr);
  ASSERT_TRUE(est.valid);
  EXPECT_LT((est.velocity_mps - v).norm(), 1e-5);
}

TEST(ClosedForm, TooFewOrDegenerateRowsAreInvalidNotACrash) {
  VelocityRows rows;
  EXPECT_FALSE(solve_velocity_closed_form(rows).valid);
  EXPECT_FALSE(solve_velocity_ceres(rows).valid);
  rows.directions = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  rows.targets_mps = {1.0, 2.0};
  EXPECT_FALSE(solve_velocity_closed_form(rows).valid);
  // Three rows, all the same direction: rank 1.
  rows.directions = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX()};
  rows.targets_mps = {1.0, 1.0, 1.0};
  const VelocityEstimate est = solve_velocity_closed_form(rows);
  EXPECT_FALSE(est.valid);
  EXPECT_TRUE(std::isinf(est.condition_number) || est.condition_number > 1e12);
}

TEST(Subsample, IsSeededAndWithoutReplacement) {
  const auto a = subsample_indices(1000, 200, 42);
  const auto b = subsample_indices(1000, 200, 42);
  const auto c = subsample_indices(1000, 200, 43);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  ASSERT_EQ(a.size(), 200u);
  for (std::size_t k = 1; k < a.size(); ++k) EXPECT_LT(a[k - 1], a[k]);
  EXPECT_EQ(subsample_indices(10, 0, 1).size(), 10u);
  EXPECT_EQ(subsample_indices(10, 20, 1).size(), 10u);
}

// The sparse shuffle draws exactly the sample of a partial Fisher-Yates over the whole index
// array (the definition), for small and large n, k near n and k = 1.
TEST(Subsample, EqualsTheDenseFisherYatesShuffle) {
  const std::uint32_t cases[][2] = {{10, 1}, {10, 9}, {1000, 200}, {1000, 999}, {90000, 3000}, {70000, 1000}};
  for (const auto& nk : cases) {
    for (std::uint64_t seed : {1u, 42u, 7777u}) {
      const std::uint32_t n = nk[0], k = nk[1];
      std::vector<std::uint32_t> dense(n);
      for (std::uint32_t i = 0; i < n; ++i) dense[i] = i;
      Rng rng(seed);
      for (std::uint32_t i = 0; i < k; ++i) std::swap(dense[i], dense[i + static_cast<std::uint32_t>(rng.uniform_below(n - i))]);
      dense.resize(k);
      std::sort(dense.begin(), dense.end());
      EXPECT_EQ(subsample_indices(n, k, seed), dense) << "n " << n << " k " << k << " seed " << seed;
    }
  }
}

// The radix selection returns the value nth_element puts at size / 2 (the definition): spread
// and narrow magnitudes, many ties, zeros, infinities, short inputs, odd and even sizes; a NaN
// or a negative value takes the fallback, which is the definition itself.
TEST(Median, MagnitudesEqualTheUpperMedian) {
  Rng rng(11);
  std::vector<std::uint64_t> keys;
  const std::size_t sizes[] = {1, 2, 7, 256, 257, 1000, 4096, 4097, 20000};
  for (const std::size_t n : sizes) {
    for (int kind = 0; kind < 6; ++kind) {
      std::vector<double> v(n);
      for (auto& x : v) {
        const double g = std::abs(rng.normal());
        switch (kind) {
          case 0: x = g * std::pow(10.0, 6.0 * rng.uniform() - 3.0); break;  // spread over decades
          case 1: x = 1.0 + 1e-12 * g; break;                             // one exponent, low bits differ
          case 2: x = std::floor(4.0 * rng.uniform()) * 0.25; break;         // ties and zeros
          case 3: x = rng.uniform() < 0.1 ? std::numeric_limits<double>::infinity() : g; break;
          case 4: x = rng.uniform() < 0.5 ? 0.0 : g * 1e-310; break;        // zeros and subnormals
          default: x = rng.uniform() < 0.01 ? std::numeric_limits<double>::quiet_NaN() : -g; break;
        }
      }
      std::vector<double> a = v, b = v;
      const double want = upper_median(a);
      const double got = upper_median_of_magnitudes(b, keys);
      if (std::isnan(want)) {
        EXPECT_TRUE(std::isnan(got)) << "n " << n << " kind " << kind;
      } else {
        EXPECT_EQ(want, got) << "n " << n << " kind " << kind;
      }
    }
  }
}

TEST(Rng, NormalMatchesTheStandardNormalAndIsReproducible) {
  Rng rng(5);
  double sum = 0.0, sum2 = 0.0, sum4 = 0.0;
  int beyond1 = 0, beyond2 = 0, beyond3 = 0, beyond_r = 0;
  const int n = 2000000;
  for (int k = 0; k < n; ++k) {
    const double x = rng.normal();
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
    const double a = std::abs(x);
    beyond1 += a > 1.0;
    beyond2 += a > 2.0;
    beyond3 += a > 3.0;
    beyond_r += a > 3.6;  // the ziggurat's exact tail starts at r = 3.44
  }
  EXPECT_NEAR(sum / n, 0.0, 0.003);
  EXPECT_NEAR(sum2 / n, 1.0, 0.005);
  EXPECT_NEAR(sum4 / n, 3.0, 0.05);  // kurtosis of a normal
  // Two-sided tail probabilities: 0.3173, 0.0455, 0.0027, 0.000318.
  EXPECT_NEAR(beyond1 / static_cast<double>(n), 0.3173, 0.002);
  EXPECT_NEAR(beyond2 / static_cast<double>(n), 0.0455, 0.0006);
  EXPECT_NEAR(beyond3 / static_cast<double>(n), 0.0027, 0.00015);
  EXPECT_NEAR(beyond_r / static_cast<double>(n), 0.000318, 0.00005);
  Rng a(11);
  Rng b(11);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(a.next_u64(), b.next_u64());
}

TEST(Rng, BatchNormalsAreTheSameDrawsAsOneByOne) {
  Rng one(23), batch(23);
  std::vector<double> drawn(100003);  // about a thousand of them take the ziggurat's slow path
  batch.normals(drawn.data(), 3);
  batch.normals(drawn.data() + 3, drawn.size() - 3);
  std::size_t beyond_r = 0;
  for (const double x : drawn) {
    ASSERT_EQ(x, one.normal());
    beyond_r += std::abs(x) > 3.44;
  }
  EXPECT_GT(beyond_r, 10u);  // the exact tail was drawn too
  EXPECT_EQ(one.next_u64(), batch.next_u64());
}

}  // namespace
}  // namespace fmcw::core
