#pragma once
// Internal to core: pieces of a tracked object seen apart in the range image. A wheel, a mirror
// or a swinging limb has a Doppler of its own and makes a small cluster of its own beside the
// body's; it is a part of that object, not a new one, and must neither start a track nor stand
// as an object of its own.

#include <vector>

#include "frame.hpp"

namespace fmcw::core::tracking {

/// Which group's pixels each pixel of the scan is (-1: none), to find the group a fragment
/// touches in the image.
class Footprints {
 public:
  explicit Footprints(std::size_t pixels) : group_of_(pixels, -1) {}
  /// Marks the group's found and claimed pixels as its own and counts them.
  void add(std::size_t group, const Group& g);
  /// The group whose pixels lie within TrackerParams::Fragments::reach_px pixels of the
  /// fragment's in the image (not across a head's edge) at a range within range_gap_m (or
  /// range_gap_fraction of the range) of them, and that holds at least host_ratio times the
  /// fragment's pixels; the one with the most such neighbours. -1: none.
  int host(const Frame& frame, const std::vector<std::uint32_t>& fragment, const TrackerParams& p) const;

 private:
  std::vector<std::int32_t> group_of_;
  std::vector<std::size_t> size_;
};

}  // namespace fmcw::core::tracking
