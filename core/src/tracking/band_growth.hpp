#pragma once
// Internal to core: growth of moving objects into the Doppler blind band (TrackerParams::Growth).

#include <utility>
#include <vector>

#include "fmcw/core/motion_pipeline.hpp"
#include "frame.hpp"

namespace fmcw::core::tracking {

/// Each cluster grows by its single-scan velocity, then each carrying track that found pixels
/// by its updated state. A tracked cluster's growth joins its group's labelled pixels; an
/// untracked one's is returned as (pixel, cluster index).
std::vector<std::pair<std::uint32_t, std::size_t>> grow_into_band(const Frame& frame, const MotionEstimate& est,
                                                                  const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                                                                  const std::vector<Track>& tracks,
                                                                  const std::vector<std::int32_t>& group_of_label,
                                                                  const TrackerParams& p, std::vector<Group>& groups);

}  // namespace fmcw::core::tracking
