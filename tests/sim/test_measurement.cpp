#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "fmcw/sim/measurement_model.hpp"

namespace fmcw::sim {
namespace {

TEST(BeatFrequencyModel, ReproducesThePapersResolutions) {
  MeasurementParams p;
  p.model = MeasurementParams::Model::kBeatFrequency;
  const MeasurementModel m(p);
  // Section III-B: 1550 nm, 6 GHz sweep, 50 us period -> 0.025 m and 0.031 m/s.
  EXPECT_NEAR(m.range_resolution_m(), 0.025, 1e-4);
  EXPECT_NEAR(m.velocity_resolution_mps(), 0.031, 1e-4);
  EXPECT_NEAR(m.fft_bin_hz(), 40e3, 1e-6);
}

TEST(BeatFrequencyModel, BeatFrequenciesInvertExactly) {
  MeasurementParams p;
  p.model = MeasurementParams::Model::kBeatFrequency;
  const MeasurementModel m(p);
  for (const double range : {1.0, 17.3, 149.9}) {
    for (const double v : {-25.0, -0.4, 0.0, 3.3, 30.0}) {
      const BeatFrequencies f = m.beat_frequencies(range, v);
      // Eq. 4: f_bd - f_bu = 4 v / lambda; a receding target (v > 0) raises the down-ramp beat.
      EXPECT_NEAR(f.down_hz - f.up_hz, 4.0 * v / p.wavelength_m, 1e-3);
      const auto back = m.from_beat_frequencies(f);
      EXPECT_NEAR(back.range_m, range, 1e-9);
      EXPECT_NEAR(back.radial_velocity_mps, v, 1e-9);
    }
  }
}

TEST(BeatFrequencyModel, QuantisationStaysWithinTheResolutionAndIsDeterministic) {
  MeasurementParams p;
  p.model = MeasurementParams::Model::kBeatFrequency;
  const MeasurementModel m(p);
  core::Rng rng(1);
  double max_dr = 0.0, max_dv = 0.0;
  std::set<double> distinct_ranges;
  for (int k = 0; k < 20000; ++k) {
    const double range = 2.0 + 0.0137 * k;
    const double v = -20.0 + 0.0021 * k;
    const auto r = m.measure(range, v, rng);
    max_dr = std::max(max_dr, std::abs(r.range_m - range));
    max_dv = std::max(max_dv, std::abs(r.radial_velocity_mps - v));
    if (k < 200) distinct_ranges.insert(r.range_m);
  }
  // Rounding each beat to its bin moves range by at most half of the 0.025 m step of Eq. 3
  // and velocity by at most half of the 0.031 m/s step of Eq. 5.
  EXPECT_LE(max_dr, 0.5 * m.range_resolution_m() + 1e-9);
  EXPECT_LE(max_dv, 0.5 * m.velocity_resolution_mps() + 1e-9);
  EXPECT_GT(max_dr, 0.4 * m.range_resolution_m()) << "quantisation must be visible";
  EXPECT_GT(distinct_ranges.size(), 50u);
  // Identical inputs give identical outputs (no randomness without jitter).
  core::Rng a(3), b(4);
  EXPECT_EQ(m.measure(12.345, 1.234, a).range_m, m.measure(12.345, 1.234, b).range_m);
}

TEST(GaussianModel, AddsSeededNoise) {
  const MeasurementModel m{MeasurementParams{}};
  core::Rng a(9), b(9);
  const auto x = m.measure(10.0, 2.0, a);
  const auto y = m.measure(10.0, 2.0, b);
  EXPECT_EQ(x.range_m, y.range_m);
  EXPECT_EQ(x.radial_velocity_mps, y.radial_velocity_mps);
  EXPECT_NE(x.range_m, 10.0);
}

TEST(MeasurementParams, RejectsNegativeSigmasAndUnknownModels) {
  MeasurementParams p;
  p.range_sigma_m = -0.1;
  EXPECT_THROW(MeasurementModel{p}, std::invalid_argument);
  try {
    measurement_model_from_string("laser");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown model 'laser'"), std::string::npos);
  }
}

TEST(ReturnIntensity, FallsWithIncidenceAndRange) {
  EXPECT_FLOAT_EQ(return_intensity(0.5f, 1.0, 5.0), 0.5f);
  EXPECT_FLOAT_EQ(return_intensity(0.5f, 0.5, 5.0), 0.25f);
  EXPECT_NEAR(return_intensity(0.5f, 1.0, 20.0), 0.125f, 1e-6);
}

}  // namespace
}  // namespace fmcw::sim
