#pragma once
// Internal to core: the split of a cluster that two tracked objects share, by their boxes, by
// the Doppler, and a walker's companion split off.

#include <vector>

#include "fmcw/core/motion_pipeline.hpp"
#include "track_box.hpp"

namespace fmcw::core::tracking {

/// A cluster that two tracked objects share (two cars nose to tail at one speed touch in the
/// image and in Doppler) is split between them when each one's predicted box holds a good share
/// of the pixels it had last time: a pixel goes to the box that holds it (the nearest centre
/// where boxes overlap), else to the nearest of those boxes. The first part keeps the label, the
/// others get new ones; each part keeps the cluster's single-scan estimate. A good share is
/// split_min_share, and at least as many pixels as association.min_pixels_at the track's range
/// asks (a cyclist 60 m away shows 4-8 beside a car). A track that holds fewer than
/// min_cluster_pixels keeps a part only if its box (grown by claims.claim_margin_m) holds the
/// centre of no other track whose box reaches the cluster, nor such a track's box its centre
/// (two such tracks are one far object seen twice).
void split_shared_clusters(const Frame& frame, MotionEstimate& est,
                           std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                           const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                           const TrackerParams& p);

/// A cluster of two bodies moving otherwise (a car passing a cyclist at arm's length: one cluster
/// in the image, two motions in its Doppler) is split by the Doppler. Only a cluster that no one
/// rigid motion explains: its single-scan fit leaves a residual RMS above
/// association.doppler_split_rms_mps. A confirmed track seen last frame whose motion does not
/// explain the cluster as a whole (doppler_deviation above association.doppler_tolerance_mps), but
/// explains, within that tolerance, at least association.split_min_share of its last pixels
/// inside its predicted box (grown by claims.claim_margin_m), keeps those pixels under the label;
/// the rest becomes a cluster of its own with its own single-scan fit (planar, robust), if that
/// fit explains it as one rigid motion (residual RMS at most doppler_tolerance_mps). Of several
/// such tracks, the one that explains the most pixels.
void split_by_doppler(const Frame& frame, MotionEstimate& est,
                      std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                      const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                      const TrackerParams& p);

/// A confirmed walker's cluster (the walker seen this frame) holding, outside the walker's
/// predicted box grown by claims.claim_margin_m, at least as many pixels as
/// association.min_pixels_at its range asks and more than a fragments.small_host_ratio-th of
/// those inside (a walker beside it, not a limb): the pixels outside become a cluster of their
/// own, with their own single-scan fit. Of several such walkers, the one whose box holds the
/// most. Returns, for each cluster, the walker it was split off (-1: none). Off when
/// small.split_companions is false or fragments.small_host_ratio is 0.
std::vector<int> split_off_companions(const Frame& frame, MotionEstimate& est,
                                      std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                                      const std::vector<Track>& tracks,
                                      const std::vector<Box>& boxes, const TrackerParams& p);

}  // namespace fmcw::core::tracking
