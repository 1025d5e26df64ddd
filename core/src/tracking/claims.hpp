#pragma once
// Internal to core: carrying tracks claim the static pixels inside their predicted box that move
// as they do (the part of an object inside the Doppler blind band); with the rig standing, static
// pixels that have come into space the beams saw empty take the label of a carrying track near
// them, unmeasured.

#include <vector>

#include "fmcw/core/motion_pipeline.hpp"
#include "track_box.hpp"

namespace fmcw::core::tracking {

/// Adds claimed pixels (Group::claimed) and background-labelled pixels (Group::labelled) to the
/// groups of the carrying tracks.
void claim_pixels(const Frame& frame, const MotionEstimate& est, const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                  const BackgroundModel& background, const TrackerParams& p, std::vector<Group>& groups);

}  // namespace fmcw::core::tracking
