#pragma once
// Internal to core: the estimate rewritten by the tracks: one label per tracked group, the
// other clusters as they were, labels renumbered by first pixel, and each tracked cluster's
// velocity the track's.

#include <utility>
#include <vector>

#include "fmcw/core/motion_pipeline.hpp"
#include "frame.hpp"

namespace fmcw::core::tracking {

/// Per old label (1..k), the group it belongs to (-1: untracked).
std::vector<std::int32_t> group_of_labels(const std::vector<Group>& groups, std::size_t k);

/// Rewrites est.labels, est.num_static_pixels and est.clusters. grown_untracked: static pixels
/// that join an untracked cluster (pixel, cluster index). position: the rig in the tracker world.
void relabel_estimate(const Frame& frame, const std::vector<Track>& tracks, const std::vector<Group>& groups,
                      const std::vector<std::int32_t>& group_of_label,
                      const std::vector<std::pair<std::uint32_t, std::size_t>>& grown_untracked, const TrackerParams& p,
                      MotionEstimate& est);

}  // namespace fmcw::core::tracking
