#pragma once
// Pixel counts of actors, moving clusters and their overlaps in one frame (private to
// fmcw::eval): what instance matching and tracking metrics are computed from.

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "fmcw/core/check.hpp"
#include "fmcw/core/ground_truth.hpp"

namespace fmcw::eval {

struct PointOverlaps {
  struct Actor {
    int pixels = 0;  ///< valid pixels
    int moving = 0;  ///< of which truly moving
  };
  std::map<std::uint32_t, Actor> actors;       ///< actor id -> counts
  std::map<std::int32_t, int> clusters;        ///< label >= 1 -> valid pixels
  std::map<std::int32_t, int> on_actors;       ///< label -> of which on some actor
  std::map<std::pair<std::uint32_t, std::int32_t>, int> overlaps;  ///< (actor, label) -> valid pixels in both
};

// The frame's truth of each actor id; `who` names the caller in the error for an id it lacks.
class ActorIndex {
 public:
  ActorIndex(const core::FrameTruth& truth, const char* who) : who_(who) {
    for (const core::ActorTruth& a : truth.actors) actors_[a.id] = &a;
  }
  const core::ActorTruth& operator[](std::uint32_t id) const {
    const auto it = actors_.find(id);
    FMCW_CHECK_ARG(it != actors_.end(), who_, ": pixels hit actor ", id, " but the frame's truth lists no such actor");
    return *it->second;
  }

 private:
  std::map<std::uint32_t, const core::ActorTruth*> actors_;
  const char* who_;
};

/// `who` names the caller in the error when sizes disagree.
inline PointOverlaps point_overlaps(const core::PixelGroundTruth& gt, const std::vector<std::uint8_t>& valid,
                                    const std::vector<std::int32_t>& labels, const char* who) {
  const std::size_t n = valid.size();
  gt.validate(n);
  FMCW_CHECK_ARG(labels.size() == n, who, ": estimate has ", labels.size(), " labels for ", n, " pixels");
  PointOverlaps p;
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    const std::int32_t l = labels[i];
    if (l >= 1) ++p.clusters[l];
    const std::uint32_t a = gt.instance[i];
    if (a == 0) continue;
    PointOverlaps::Actor& counts = p.actors[a];
    ++counts.pixels;
    counts.moving += gt.moving[i] ? 1 : 0;
    if (l >= 1) {
      ++p.overlaps[{a, l}];
      ++p.on_actors[l];
    }
  }
  return p;
}

}  // namespace fmcw::eval
