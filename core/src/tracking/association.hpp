#pragma once
// Internal to core: association of this frame's clusters to the predicted tracks: gating by the
// predicted box and the Doppler deviation of a cluster from a track's motion (the split of a
// cluster that two tracked objects share: cluster_split.hpp).

#include <vector>

#include "cluster_split.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "track_box.hpp"

namespace fmcw::core::tracking {

/// Pixels of each cluster of the estimate (label l at index l - 1), in pixel order.
std::vector<std::vector<std::uint32_t>> pixels_of_clusters(const MotionEstimate& est);

/// Median |Doppler - the track's prediction| over (at most about 256 of) the pixels.
double doppler_deviation(const Frame& frame, const std::vector<std::uint32_t>& pixels, const Track& track);

/// The track's motion explains the pixels' Doppler: their doppler_deviation is within
/// association.doppler_tolerance_mps.
bool explains_doppler(const Frame& frame, const std::vector<std::uint32_t>& pixels,
                      const Track& track, const TrackerParams& p);

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
