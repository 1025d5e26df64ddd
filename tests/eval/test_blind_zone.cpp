// The blind-zone study reproduces the paper's example (5 m/s: a blind band of about 88 to 92 deg)
// for a near-point target, and explains the wider band of a car-sized one.

#include <gtest/gtest.h>

#include "fmcw/eval/blind_zone_study.hpp"

namespace fmcw::eval {
namespace {

// A coarse but adequate sweep around 90 deg: 0.5 deg steps, then bisection of each edge.
BlindZoneStudyParams sweep_5mps(const std::string& target, const Eigen::Vector3d& box, double distance) {
  BlindZoneStudyParams p;
  p.speeds_mps = {5.0};
  p.targets = {{target, box, {distance}, ""}};
  p.phi_min_deg = 80.0;
  p.phi_max_deg = 100.0;
  p.phi_step_deg = 0.5;
  p.fine_step_deg = 0.5;
  p.refine_iterations = 5;
  p.methods = {"fast"};
  return p;
}

const BlindZoneBand& band(const BlindZoneStudyResult& r, const std::string& method, bool noise) {
  for (const BlindZoneBand& b : r.bands) {
    if (b.method == method && b.noise == noise) return b;
  }
  throw std::runtime_error("no band");
}

TEST(BlindZone, SmallTargetAt5MpsReproducesThePapersBand) {
  BlindZoneStudyParams p = sweep_5mps("small_box", Eigen::Vector3d(0.5, 0.5, 0.5), 40.0);
  p.scene.measurement.velocity_sigma_mps = 0.0;  // Eq. 15 is a statement about noise-free Doppler
  p.scene.measurement.range_sigma_m = 0.0;
  p.noise_free_too = false;
  const BlindZoneStudyResult r = run_blind_zone_study(p);
  ASSERT_EQ(r.methods, (std::vector<std::string>{"paper", "fast"}));
  for (const std::string& m : r.methods) {
    const BlindZoneBand& b = band(r, m, true);
    ASSERT_TRUE(b.measured.found) << m;
    EXPECT_NEAR(b.measured.lower_deg, 88.0, 1.0) << m;
    EXPECT_NEAR(b.measured.upper_deg, 92.0, 1.0) << m;
    EXPECT_NEAR(b.theory.lower_deg, 88.05, 0.01);
    // The band is never narrower than Eq. 15 (an edge pixel sees the same heading or a worse one).
    EXPECT_LE(b.measured.lower_deg, b.theory.lower_deg + 0.05);
    EXPECT_GE(b.measured.upper_deg, b.theory.upper_deg - 0.05);
  }
}

TEST(BlindZone, CarSizedBoxWidensTheBandAsItsSilhouettePredicts) {
  BlindZoneStudyParams p = sweep_5mps("car_box", Eigen::Vector3d(4.5, 1.8, 1.5), 40.0);
  p.phi_min_deg = 78.0;
  p.phi_max_deg = 102.0;
  p.methods = {"paper"};
  const BlindZoneStudyResult r = run_blind_zone_study(p);
  const BlindZoneBand& clean = band(r, "paper", false);
  const BlindZoneBand& noisy = band(r, "paper", true);
  ASSERT_TRUE(clean.measured.found && clean.silhouette.found && noisy.measured.found);
  // Eq. 15 at the silhouette pixels predicts the noise-free band (to the bisection's resolution).
  EXPECT_NEAR(clean.measured.lower_deg, clean.silhouette.lower_deg, 0.1);
  EXPECT_NEAR(clean.measured.upper_deg, clean.silhouette.upper_deg, 0.1);
  // A 4.5 m box broadside at 40 m spans about +-3.2 deg: the band widens by about that much.
  EXPECT_NEAR(clean.theory.lower_deg - clean.measured.lower_deg, 3.2, 0.6);
  EXPECT_NEAR(clean.measured.upper_deg - clean.theory.upper_deg, 3.2, 0.6);
  // Noise widens it further, never narrows it by more than the sampling step.
  EXPECT_LE(noisy.measured.lower_deg, clean.measured.lower_deg + 0.5);
  EXPECT_GE(noisy.measured.upper_deg, clean.measured.upper_deg - 0.5);
}

TEST(BlindZone, SamplesDoNotDependOnTheThreadCount) {
  BlindZoneStudyParams p = sweep_5mps("small_box", Eigen::Vector3d(0.5, 0.5, 0.5), 20.0);
  p.phi_min_deg = 86.0;
  p.phi_max_deg = 94.0;
  p.phi_step_deg = 1.0;
  p.refine_iterations = 2;
  p.scene.num_threads = 1;
  const BlindZoneStudyResult one = run_blind_zone_study(p);
  p.scene.num_threads = 2;
  const BlindZoneStudyResult two = run_blind_zone_study(p);
  ASSERT_EQ(one.samples.size(), two.samples.size());
  for (std::size_t k = 0; k < one.samples.size(); ++k) {
    EXPECT_EQ(one.samples[k].phi_deg, two.samples[k].phi_deg);
    EXPECT_EQ(one.samples[k].recall, two.samples[k].recall);
    EXPECT_EQ(one.samples[k].object_pixels, two.samples[k].object_pixels);
  }
}

TEST(BlindZone, BadParametersAreNamed) {
  BlindZoneStudyParams p;
  p.targets[0].distances_m = {500.0};
  EXPECT_THROW(p.validate(), std::invalid_argument);
  BlindZoneStudyParams q;
  q.phi_step_deg = 2.0;
  EXPECT_THROW(q.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace fmcw::eval
