// Band edges of recall curves and the theoretical band of Eq. 15.

#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/eval/band_edges.hpp"

namespace fmcw::eval {
namespace {

TEST(BandEdges, InterpolatesTheLevelCrossingsAroundTheCentre) {
  // Unsorted on purpose; a blind dip 88..92 and a spurious one-sample dip at 40.
  const std::vector<double> phi = {95, 85, 40, 89, 91, 87, 93, 90, 20};
  const std::vector<double> recall = {1, 1, 0, 0, 0, 1, 1, 0, 1};
  const BandEdges e = find_blind_band(phi, recall, 0.5);
  ASSERT_TRUE(e.found);
  EXPECT_DOUBLE_EQ(e.lower_deg, 88.0);  // halfway between 87 (1) and 89 (0)
  EXPECT_DOUBLE_EQ(e.upper_deg, 92.0);
  const BandEdges partial = find_blind_band({86, 88, 90}, {1.0, 0.25, 0.0}, 0.5);
  EXPECT_NEAR(partial.lower_deg, 86.0 + 2.0 * 0.5 / 0.75, 1e-12);
  EXPECT_TRUE(std::isnan(partial.upper_deg));  // the band runs off the sampled range
}

TEST(BandEdges, NoDipAndBadInput) {
  EXPECT_FALSE(find_blind_band({80, 90, 100}, {1, 0.9, 1}).found);
  EXPECT_THROW(find_blind_band({80, 90}, {1}), std::invalid_argument);
  EXPECT_THROW(find_blind_band({80, NAN}, {1, 1}), std::invalid_argument);
}

TEST(BandEdges, TheoryGivesThePapersExample) {
  const BandEdges e = theoretical_blind_band(5.0, 0.17);  // paper: about 88 to 92 deg
  EXPECT_NEAR(e.lower_deg, std::acos(0.034) * 180.0 / M_PI, 1e-12);
  EXPECT_NEAR(e.lower_deg, 88.05, 0.01);
  EXPECT_NEAR(e.upper_deg, 91.95, 0.01);
  const BandEdges slow = theoretical_blind_band(0.1, 0.17);
  EXPECT_DOUBLE_EQ(slow.lower_deg, 0.0);
  EXPECT_DOUBLE_EQ(slow.upper_deg, 180.0);
}

}  // namespace
}  // namespace fmcw::eval
