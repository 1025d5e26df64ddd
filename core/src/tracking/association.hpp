#pragma once
// Internal to core: association of this frame's clusters to the predicted tracks: gating by the
// predicted box, the Doppler deviation of a cluster from a track's motion, and the split of a
// cluster that two tracked objects share.

#include <vector>

#include "fmcw/core/motion_pipeline.hpp"
#include "track_box.hpp"

namespace fmcw::core::tracking {

/// Pixels of each cluster of the estimate (label l at index l - 1), in pixel order.
std::vector<std::vector<std::uint32_t>> pixels_of_clusters(const MotionEstimate& est);

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
void split_shared_clusters(const Frame& frame, MotionEstimate& est, std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                           const std::vector<Track>& tracks, const std::vector<Box>& boxes, const TrackerParams& p);

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
void split_by_doppler(const Frame& frame, MotionEstimate& est, std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                      const std::vector<Track>& tracks, const std::vector<Box>& boxes, const TrackerParams& p);

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

/// Median |Doppler - the track's prediction| over (at most about 256 of) the pixels.
double doppler_deviation(const Frame& frame, const std::vector<std::uint32_t>& pixels, const Track& track);

/// Which track each cluster joins (-1: none), and which it is absorbed into (-1: none).
struct Association {
  std::vector<int> owner;
  std::vector<int> absorbed;
};

/// Each cluster joins the track whose predicted box (grown by the gate, wider for an uncertain
/// position) holds its centroid, whose predicted motion explains its Doppler, and that lies
/// nearest to it; a small cluster inside a vehicle's box whose Doppler the track does not
/// explain (a wheel) is absorbed into its label, unmeasured, and so is a cluster too small to
/// measure (under min_pixels_at its range) inside any track's box grown by claim_margin_m. A track's nearest cluster always
/// joins it, further ones only from inside its box (grown by claim_margin_m, a vehicle's by the
/// gate). Fills each track's group with its clusters and their pixels.
Association associate(const Frame& frame, const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                      const MotionEstimate& est, const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                      const TrackerParams& p, std::vector<Group>& groups);

/// A track whose predicted centre lies inside an older confirmed vehicle's predicted box (grown by
/// claim_margin_m; by fragments.same_motion_margin_m more where the two move alike within
/// fragments.same_motion_mps) follows a piece of that vehicle (it was born from a wheel or a part seen
/// apart): its clusters go under the vehicle's label, unmeasured, and the track ends this frame.
/// So it does inside a vehicle as old whose last update found fragments.host_ratio times its
/// pixels (two tracks born in one frame from the cab and the load of a truck), or that is as old,
/// no vehicle itself, and moves with it (a car first seen in two halves). Two confirmed vehicles
/// are otherwise left alone (split_shared_clusters parts them), and so is a confirmed track of at
/// least fragments.own_motion_hits updates inside a vehicle's box whose pixels the vehicle's
/// motion does not explain (a cyclist riding beside a turning car).
void merge_nested_tracks(const Frame& frame, std::vector<Track>& tracks, const std::vector<Box>& boxes, const TrackerParams& p,
                         Association& a, std::vector<Group>& groups);

/// The confirmed vehicle track whose box (grown by claim_margin_m) holds the cluster's centroid,
/// or -1: a cluster there that no track took is a piece of that vehicle (a wheel, a mirror, a
/// part whose Doppler the track does not explain), not a new object.
/// boxes[t] is box_of(tracks[t]) after this frame's measurement; tracks born this frame have
/// none and hold nothing.
int inside_vehicle(const Frame& frame, const ClusterEstimate& ce, const std::vector<Track>& tracks,
                   const std::vector<Box>& boxes, const TrackerParams& p);

/// The lost track (TrackerParams::Lifecycle::reid_frames) whose id a track born this frame from
/// `pixels` takes: one whose predicted box, grown as the association gates (gate_m plus 3σ of
/// its position, at most 3 gate_m), holds the new track's centre and whose motion explains the
/// pixels' Doppler within doppler_tolerance_mps; the nearest by box distance. -1: none.
int lost_track_of(const Frame& frame, const Track& born, const std::vector<std::uint32_t>& pixels,
                  const std::vector<Track>& lost, const TrackerParams& p);

}  // namespace fmcw::core::tracking
