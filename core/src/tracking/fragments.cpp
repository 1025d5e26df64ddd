#include "fragments.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace fmcw::core::tracking {

void Footprints::add(std::size_t group, const Group& g) {
  if (size_.size() <= group) size_.resize(group + 1, 0);
  g.for_each_measured([&](std::uint32_t i) {
    if (group_of_[i] < 0) ++size_[group];
    group_of_[i] = static_cast<std::int32_t>(group);
  });
}

int Footprints::host(const Frame& frame, const std::vector<std::uint32_t>& fragment, const TrackerParams& p) const {
  const TrackerParams::Fragments& pf = p.fragments;
  const Scan& scan = frame.scan;
  const int cols = scan.cols;
  const int reach = pf.reach_px;
  std::map<std::int32_t, int> votes;  // few groups touch a fragment: ordered, deterministic
  for (const std::uint32_t i : fragment) {
    const int r = static_cast<int>(i / static_cast<std::uint32_t>(cols));
    const int c = static_cast<int>(i % static_cast<std::uint32_t>(cols));
    // The fragment's head: its neighbours in the image are those of the same head.
    const HeadInfo& head = scan.heads[static_cast<std::size_t>(scan.head_of_col(c))];
    const int c_lo = head.col_begin, c_hi = head.col_end - 1;
    const double range = scan.range_m[i];
    const double gap = std::max(pf.range_gap_m, pf.range_gap_fraction * range);
    std::int32_t best = -1;
    for (int rr = std::max(0, r - reach); rr <= std::min(scan.rows - 1, r + reach) && best < 0; ++rr) {
      for (int cc = std::max(c_lo, c - reach); cc <= std::min(c_hi, c + reach); ++cc) {
        const std::size_t j = scan.index(rr, cc);
        const std::int32_t g = group_of_[j];
        if (g < 0 || std::abs(static_cast<double>(scan.range_m[j]) - range) > gap) continue;
        best = g;
        break;
      }
    }
    if (best >= 0) ++votes[best];
  }
  int host = -1, most = 0;
  for (const auto& [g, n] : votes) {
    if (n <= most || static_cast<double>(size_[static_cast<std::size_t>(g)]) < pf.host_ratio * static_cast<double>(fragment.size()))
      continue;
    most = n;
    host = g;
  }
  return host;
}

}  // namespace fmcw::core::tracking
