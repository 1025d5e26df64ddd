// The per-pixel passes the methods share, against plain loops that give the answer by
// definition: neighbours of every pixel (image edges, column groups) and listed pixels (masks
// of every density, sizes around the block length).

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <tuple>
#include <vector>

#include "fmcw/core/scan.hpp"
#include "pixel_lists.hpp"

namespace fmcw::core {
namespace {

using Visit = std::tuple<std::size_t, int, int>;

// By definition: the eight offsets in row-major order, kept inside the image and the group.
std::vector<Visit> neighbours_by_definition(const Scan& scan, const std::vector<int>& group_of, int r, int c) {
  std::vector<Visit> out;
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      const int rr = r + dr, cc = c + dc;
      if ((dr == 0 && dc == 0) || rr < 0 || rr >= scan.rows || cc < 0 || cc >= scan.cols) continue;
      if (group_of[static_cast<std::size_t>(cc)] != group_of[static_cast<std::size_t>(c)]) continue;
      out.emplace_back(static_cast<std::size_t>(rr) * static_cast<std::size_t>(scan.cols) + static_cast<std::size_t>(cc), dr, dc);
    }
  }
  return out;
}

TEST(PixelPasses, NeighboursAreTheEightInsideTheImageAndGroupInOrder) {
  // Groups of width 1, 2 and 4 columns: interior pixels, edges, and columns beside a seam.
  const Scan scan = Scan::make_empty(5, 7);
  const std::vector<int> group_of = {0, 1, 1, 2, 2, 2, 2};
  std::size_t interior = 0;
  for (int r = 0; r < scan.rows; ++r) {
    for (int c = 0; c < scan.cols; ++c) {
      std::vector<Visit> seen;
      for_each_neighbour(scan, group_of, r, c, [&](std::size_t n, int dr, int dc) { seen.emplace_back(n, dr, dc); });
      EXPECT_EQ(seen, neighbours_by_definition(scan, group_of, r, c)) << "pixel (" << r << ", " << c << ")";
      interior += seen.size() == 8 ? 1 : 0;
    }
  }
  EXPECT_EQ(interior, 3u * 2u);  // rows 1-3, columns 4 and 5: the only pixels with all eight
}

TEST(PixelPasses, ListedPixelsAreThosePassingInOrder) {
  std::mt19937 rng(7);
  for (const std::size_t n : {0u, 1u, 63u, 64u, 65u, 127u, 128u, 1000u, 4099u}) {
    for (const double density : {0.0, 0.001, 0.05, 0.5, 1.0}) {
      std::bernoulli_distribution passes(density);
      std::vector<std::uint8_t> mask(n);
      for (auto& m : mask) m = passes(rng) ? 1 : 0;
      std::vector<std::uint32_t> expected;
      for (std::size_t i = 0; i < n; ++i) {
        if (mask[i] != 0) expected.push_back(static_cast<std::uint32_t>(i));
      }
      std::vector<std::uint32_t> listed = {42u, 43u};  // whatever it held before is replaced
      list_pixels(n, [&](std::size_t i) { return mask[i] != 0; }, listed);
      EXPECT_EQ(listed, expected) << n << " pixels, density " << density;
    }
  }
  // The last pixel alone, after many empty blocks.
  std::vector<std::uint8_t> mask(1000, 0);
  mask.back() = 1;
  std::vector<std::uint32_t> listed;
  list_pixels(mask.size(), [&](std::size_t i) { return mask[i] != 0; }, listed);
  EXPECT_EQ(listed, std::vector<std::uint32_t>{999u});
}

}  // namespace
}  // namespace fmcw::core
