#pragma once
// Internal to core: a new track from a cluster no track took, with its priors.

#include "fmcw/core/motion_pipeline.hpp"
#include "association.hpp"
#include "track_box.hpp"

namespace fmcw::core::tracking {

/// The track a cluster starts (its group holds the cluster's pixels): velocity from the
/// single-scan estimate, box placed on the pixels, and priors that say what one scan leaves
/// open. One scan measures v_app = v + omega z x (o - c): velocity and yaw rate are known only
/// along that line, so omega ~ N(0, s0^2) and v = v_app - omega z x (o - c) are correlated from
/// the start, and later positions move the estimate along the line instead of fighting the
/// Doppler. A small object's tangential velocity is not trusted at all: its prior is 0, or the
/// tangential velocity of `companion` (the walker it was split off, split_off_companions, if
/// not null) where their radial velocities agree (TrackerParams::Small::companion_sigma_mps).
Track start_track(const ClusterEstimate& ce, const Group& g, std::int32_t id, const Frame& frame,
                  const ViewEdges& edges, const TrackerParams& p, const Track* companion = nullptr);

/// The births of a frame, from the clusters no track took, the largest first (a body before its
/// wheels). A cluster of at most fragments.max_pixels pixels beside a larger tracked group's
/// pixels in the image (Footprints::host) is a piece of that object: it goes under its label,
/// unmeasured, and so does one that small inside a confirmed walker's box whose update found
/// fragments.small_host_ratio times its pixels (a limb), and one inside a confirmed vehicle's
/// measured box (inside_vehicle). The
/// others with min_cluster_pixels and a valid single-scan velocity start tracks (appended to
/// tracks and groups, ids from next_id); companion_of names, for each cluster, the walker it was
/// split off (-1: none; clusters beyond its size have none).
void birth_tracks(const Frame& frame, const ViewEdges& edges, const MotionEstimate& est,
                  const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                  const std::vector<int>& companion_of, const TrackerParams& p, Association& assoc,
                  std::vector<Track>& tracks, std::vector<Group>& groups, std::int32_t& next_id);

}  // namespace fmcw::core::tracking
