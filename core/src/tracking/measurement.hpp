#pragma once
// Internal to core: the measurement update of a track with its pixels of this frame, and the
// bookkeeping after it (hits, misses, walker, turning).

#include "track_box.hpp"

namespace fmcw::core::tracking {

/// Measures the box (measure_box) and, unless the track is just born (its velocity prior then
/// holds this frame's Doppler), updates the filter with the Doppler rows of its pixels (without
/// those that do not move with the body) and the box centre (Huber-weighted beyond 3 standard
/// deviations of the innovation: the centre jumps when occlusion changes what is visible).
/// A walker is measured on its own pixels: those inside its predicted box.
void measure(Track& tr, const Group& whole, bool born, const Frame& frame, const ViewEdges& edges, const TrackerParams& p);

/// After the frame's updates: hits or misses, confirmation, walker and turning state.
void update_track_state(Track& tr, const Group& g, const TrackerParams& p);

/// Whether the track's turn is resolved (TrackerParams::Turning); counts the updates since it
/// last was.
void update_turning(Track& tr, const TrackerParams& p);

/// Counts the updates since the box's length plus width last grew by more than
/// Turning::settle_growth_m (born: from now).
void note_extent(Track& tr, const TrackerParams& p, bool born);

/// Its box has settled: the yaw rate its path gives is the body's (Turning::shrink_settled).
bool settled(const Track& tr, const TrackerParams& p);

/// Not turning, but its turn was released while its rate held up (Turning::hold_rate_fraction):
/// the yaw rate it holds is the body's.
bool turn_held(const Track& tr, const TrackerParams& p);

/// The line the last update's outline showed (Track::line_seen) says a young track's body drives
/// along the filter's velocity and not along the Doppler's, `doppler_velocity` (tracker world):
/// Turning::line_max_angle_rad.
bool line_says_turning(const Track& tr, const Eigen::Vector2d& doppler_velocity,
                       const TrackerParams::Turning& p);

/// Straight by its axes (TrackerParams::Turning::straight_window_s): the slope b of the line
/// through the outline's axes of the last window and its variance var_b are set where there are
/// enough of them; true where they say the body drives straight.
bool straight_by_axes(const Track& tr, const TrackerParams::Turning& p, double& b, double& var_b);

/// The outline's axis of the pixels (TrackerParams::Heading), where it is informative (or, where
/// no long side shows, a face across the body gives it as its normal) and the track is no
/// walker, not small and faster than a walker, as a measurement of the velocity's direction: its
/// information and gradient at the track's state are added. Sets Track::axis_seen; returns it.
bool axis_information(Track& tr, const std::vector<std::uint32_t>& pixels, const Frame& frame, const TrackerParams& p, Mat5& info,
                      Vec5& grad);

}  // namespace fmcw::core::tracking
