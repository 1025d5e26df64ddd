#include "track_birth.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "measurement.hpp"

namespace fmcw::core::tracking {

namespace {

// A small object's prior: the radial part as measured, the tangential part unknown, the yaw
// rate unrelated to either (a small object's Doppler does not see it).
void small_object_prior(Track& tr, const Eigen::Vector2d& v, const Eigen::Matrix2d& cov, const Eigen::Vector2d& d,
                        const TrackerParams& p) {
  const double floor = p.measurement.doppler_sigma_mps * p.measurement.doppler_sigma_mps;
  const Eigen::Vector2d radial = -d.normalized();
  const Eigen::Vector2d tangential(-radial.y(), radial.x());
  const double var_r = std::max(floor, radial.dot(cov * radial));
  const double st = p.small.initial_tangential_sigma_mps;
  tr.x.segment<2>(2) = radial.dot(v) * radial;
  tr.P.topLeftCorner<2, 2>() = Eigen::Matrix2d::Identity() * (p.small.position_sigma_m * p.small.position_sigma_m);
  tr.P.block<2, 2>(2, 2) = var_r * radial * radial.transpose() + st * st * tangential * tangential.transpose();
  tr.P.block<2, 1>(2, 4).setZero();
  tr.P.block<1, 2>(4, 2).setZero();
}

}  // namespace

Track start_track(const ClusterEstimate& ce, const Group& g, std::int32_t id, const Frame& frame, const ViewEdges& edges,
                  const TrackerParams& p) {
  Track tr;
  tr.id = id;
  const Eigen::Vector2d v = frame.R * ce.velocity.velocity_mps.head<2>();
  tr.x.segment<2>(2) = v;
  tr.heading_rad = v.norm() > 1.0 ? std::atan2(v.y(), v.x()) : 0.0;
  // The single-scan covariance, its unobservable direction capped, as the velocity prior.
  Eigen::Matrix2d cov = frame.R * ce.velocity.covariance.topLeftCorner<2, 2>() * frame.R.transpose();
  const double cap = p.motion.max_initial_velocity_sigma_mps * p.motion.max_initial_velocity_sigma_mps;
  if (!cov.allFinite()) cov = Eigen::Matrix2d::Identity() * cap;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(0.5 * (cov + cov.transpose()));
  const double floor = p.measurement.doppler_sigma_mps * p.measurement.doppler_sigma_mps;
  const Eigen::Vector2d ev = eig.eigenvalues().cwiseMax(floor).cwiseMin(cap);
  measure(tr, g, true, frame, edges, p);  // places the box
  const Eigen::Vector2d d = mean_origin(frame, g) - tr.centre();
  const Eigen::Vector2d sv(-d.y(), d.x());
  const double s0 = p.motion.initial_yaw_rate_sigma_rps;
  tr.P = Mat5::Zero();
  tr.P.topLeftCorner<2, 2>() = Eigen::Matrix2d::Identity() * (p.measurement.position_sigma_m * p.measurement.position_sigma_m);
  tr.P.block<2, 2>(2, 2) = eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose() + s0 * s0 * sv * sv.transpose();
  tr.P.block<2, 1>(2, 4) = -s0 * s0 * sv;
  tr.P.block<1, 2>(4, 2) = -s0 * s0 * sv.transpose();
  tr.P(4, 4) = s0 * s0;
  if (tr.small(p) && d.norm() > 0.0) small_object_prior(tr, v, cov, d, p);
  tr.hits = 1;
  tr.last_pixels = static_cast<int>(g.found.size());
  if (tr.hits >= p.lifecycle.confirm_hits) tr.confirmed = true;
  return tr;
}

}  // namespace fmcw::core::tracking
