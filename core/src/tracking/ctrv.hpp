#pragma once
// Internal to core: the constant-turn-rate filter of a track. State: centre x, y [m], velocity
// x, y [m/s], yaw rate [rad/s], in the tracker's world.

#include "frame.hpp"

namespace fmcw::core::tracking {

/// Constant turn rate over dt: the centre moves along an arc, the velocity turns by omega dt.
Vec5 propagate(const Vec5& x, double dt);

/// The Jacobian of propagate(x, dt) with respect to x.
Mat5 transition_jacobian(const Vec5& x, double dt);

/// Propagates the track's state, covariance (Jacobian by central differences, white
/// acceleration and yaw-acceleration noise) and box axes by dt > 0.
void predict(Track& t, double dt, const TrackerParams::Motion& p);

/// Noise matched to the innovations (TrackerParams::Motion::min_noise_scale): moves the track's
/// noise scale by the update's correction dx^T P^-1 dx (`correction`) against what a consistent
/// filter expects of it (`expected`); back to 1 for a small, slow or turning track.
void adapt_noise(Track& t, double correction, double expected, const TrackerParams& p);

/// Adds an update's correction dx^T P^-1 dx and what a consistent filter expects of it to the
/// track's sums (TrackerParams::Calibration; nothing when it is off); a correction that is
/// negative or not finite, or an expectation that is not finite and positive, is left out.
void follow_corrections(Track& t, double correction, double expected, const TrackerParams::Calibration& p);

/// Information-form update: with the measurements' information and gradient at the current
/// state, x += (P^-1 + info)^-1 grad, P = (P^-1 + info)^-1; the yaw rate stays within bounds;
/// then the track's sums follow the correction (follow_corrections) and so does its noise
/// scale (adapt_noise).
void information_update(Track& t, const Mat5& info, const Vec5& grad, const TrackerParams& p);

/// Another track's velocity and yaw rate, with their covariance, as a measurement of the
/// track's (information form; the position stays the track's own): a lost vehicle's predicted
/// motion for the track that takes its id (TrackerParams::Lifecycle::reid_motion). Nothing when
/// that covariance is singular or the result not finite.
void fuse_motion_prior(Track& t, const Track& prior);

/// The Doppler row's Jacobian with respect to the state at x.
inline Vec5 row_jacobian(const Row& r, const Vec5& x) {
  const Eigen::Vector2d d = r.o - x.head<2>();
  Vec5 h;
  h << -x(4) * r.e.y(), x(4) * r.e.x(), r.e.x(), r.e.y(), r.e.y() * d.x() - r.e.x() * d.y();
  return h;
}

}  // namespace fmcw::core::tracking
