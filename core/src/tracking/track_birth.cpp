#include "track_birth.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "ctrv.hpp"
#include "fragments.hpp"
#include "measurement.hpp"
#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core::tracking {

namespace {

// A small object's prior: the radial part as measured, the tangential part unknown (or, for a
// walker's companion whose radial velocity agrees with the walker's, the walker's), the yaw rate
// unrelated to either (a small object's Doppler does not see it).
void small_object_prior(Track& tr, const Eigen::Vector2d& v, const Eigen::Matrix2d& cov,
                        const Eigen::Vector2d& d, const Track* companion, const TrackerParams& p) {
  const double floor = p.measurement.doppler_sigma_mps * p.measurement.doppler_sigma_mps;
  const Eigen::Vector2d radial = -d.normalized();
  const Eigen::Vector2d tangential(-radial.y(), radial.x());
  const double var_r = std::max(floor, radial.dot(cov * radial));
  double st = p.small.initial_tangential_sigma_mps;
  double vt = 0.0;
  if (companion != nullptr) {
    const Eigen::Vector2d vw = companion->velocity();
    const Eigen::Matrix2d pw = companion->P.block<2, 2>(2, 2);
    const double pace = p.small.companion_sigma_mps * p.small.companion_sigma_mps;
    const double apart = radial.dot(v - vw);
    if (apart * apart <= 9.0 * (var_r + radial.dot(pw * radial) + pace)) {
      vt = tangential.dot(vw);
      st = std::min(st, std::sqrt(tangential.dot(pw * tangential) + pace));
    }
  }
  tr.x.segment<2>(2) = radial.dot(v) * radial + vt * tangential;
  tr.P.topLeftCorner<2, 2>() = Eigen::Matrix2d::Identity() * (p.small.position_sigma_m * p.small.position_sigma_m);
  tr.P.block<2, 2>(2, 2) = var_r * radial * radial.transpose() + st * st * tangential * tangential.transpose();
  tr.P.block<2, 1>(2, 4).setZero();
  tr.P.block<1, 2>(4, 2).setZero();
}

// The scan resolved the patch's whole velocity (largest variance of the two axes: max_variance)
// as one rigid motion, faster than a walker by three standard deviations.
bool rigid_fast_patch(const VelocityEstimate& scan, const Eigen::Vector2d& v, double max_variance, const TrackerParams& p) {
  const double limit = p.small.rigid_patch_sigma_mps;
  if (!(limit > 0.0) || !(max_variance >= 0.0) || !(scan.residual_rms_mps <= p.measurement.doppler_sigma_mps)) return false;
  const double sigma = std::sqrt(max_variance);
  return sigma <= limit && v.norm() - 3.0 * sigma > p.small.walker_max_speed_mps;
}

}  // namespace

Track start_track(const ClusterEstimate& ce, const Group& g, std::int32_t id, const Frame& frame,
                  const ViewEdges& edges, const TrackerParams& p, const Track* companion) {
  Track tr;
  tr.id = id;
  // The single-scan covariance, its unobservable direction capped, as the velocity prior. Along a
  // direction the fit observes no better than the cap (a standard deviation above
  // max_initial_velocity_sigma_mps) the velocity is taken as 0, as unknown as the cap says: the
  // fit's value there is no measurement (a fit on a few pixels 130 m away can put 10^9 m/s
  // there, and one over two walkers side by side, 30-60 m/s).
  Eigen::Matrix2d cov = frame.R * ce.velocity.covariance.topLeftCorner<2, 2>() * frame.R.transpose();
  const double cap = p.motion.max_initial_velocity_sigma_mps * p.motion.max_initial_velocity_sigma_mps;
  const bool has_covariance = cov.allFinite();
  if (!has_covariance) cov = Eigen::Matrix2d::Identity() * cap;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(0.5 * (cov + cov.transpose()));
  Eigen::Vector2d v = frame.R * ce.velocity.velocity_mps.head<2>();
  if (!has_covariance || !v.allFinite()) v.setZero();
  for (int k = 0; k < 2; ++k) {
    if (eig.eigenvalues()(k) > cap) {
      v -= eig.eigenvectors().col(k).dot(v) * eig.eigenvectors().col(k);
    }
  }
  tr.x.segment<2>(2) = v;
  tr.heading_rad = v.norm() > 1.0 ? std::atan2(v.y(), v.x()) : 0.0;
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
  // A small patch cut sideways by the view or an occluder, faster than a walker, may be the corner
  // of a car coming into view: its tangential velocity and yaw rate are then no walker's. So is a
  // patch whose scan resolved its whole velocity as one rigid motion faster than a walker
  // (TrackerParams::Small::rigid_patch_sigma_mps).
  const bool corner = (tr.outline_cut && std::abs(v.dot(d.normalized())) > p.small.walker_max_speed_mps) ||
                      rigid_fast_patch(ce.velocity, v, eig.eigenvalues()(1), p);
  if (tr.small(p) && !corner && d.norm() > 0.0) small_object_prior(tr, v, cov, d, companion, p);
  // Where the outline shows the body's axis, the prior's line of velocity and yaw rate meets it.
  Mat5 info = Mat5::Zero();
  Vec5 grad = Vec5::Zero();
  if (axis_information(tr, g.found, frame, p, info, grad)) information_update(tr, info, grad, p);
  tr.hits = 1;
  tr.last_pixels = static_cast<int>(g.found.size());
  if (tr.hits >= p.lifecycle.confirm_hits) tr.confirmed = true;
  note_extent(tr, p, true);
  update_turning(tr, p);
  return tr;
}

namespace {
// Whose pixels hold the pieces beside them: an object larger than a walker, or faster than one
// (a car coming into view shows less than a walker's width of itself at first).
bool holds_pieces(const Track& t, const TrackerParams& p) {
  return !t.small(p) || (!t.walker && t.velocity().norm() > p.small.walker_max_speed_mps);
}

// A confirmed walker (a small track that holds no pieces by the image: taken for a walker, or
// no faster than one), seen this frame, whose update found at least fragments.small_host_ratio
// times n pixels, and whose box holds q: a limb of it swung off the body. -1: none.
int holding_walker(const Eigen::Vector2d& q, std::size_t n, const std::vector<Track>& tracks,
                   const std::vector<Box>& boxes, const std::vector<Group>& groups, const TrackerParams& p) {
  if (!(p.fragments.small_host_ratio > 0.0)) return -1;
  const double least = p.fragments.small_host_ratio * static_cast<double>(n);
  return nearest_holding_box(q, boxes, p.claims.claim_margin_m, [&](std::size_t t) {
    return tracks[t].confirmed && !holds_pieces(tracks[t], p) && static_cast<double>(groups[t].found.size()) >= least;
  });
}
}  // namespace

void birth_tracks(const Frame& frame, const ViewEdges& edges, const MotionEstimate& est,
                  const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                  const std::vector<int>& companion_of, const TrackerParams& p, Association& assoc,
                  std::vector<Track>& tracks, std::vector<Group>& groups, std::int32_t& next_id) {
  const std::size_t measured = tracks.size();
  std::vector<Box> measured_boxes(measured);
  for (std::size_t t = 0; t < measured; ++t) measured_boxes[t] = box_of(tracks[t]);
  Footprints footprints(frame.scan.size());
  // Walkers side by side are as near in the image as a body and its wheel: only the pixels of
  // objects larger or faster than a walker hold fragments (holds_pieces).
  for (std::size_t t = 0; t < groups.size(); ++t) {
    if (holds_pieces(tracks[t], p)) footprints.add(t, groups[t]);
  }
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < est.clusters.size(); ++c) {
    if (assoc.owner[c] < 0 && assoc.absorbed[c] < 0) order.push_back(c);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cluster_pixels[a].size() > cluster_pixels[b].size(); });
  const auto absorb = [&](std::size_t c, int into) {
    assoc.absorbed[c] = into;
    groups[static_cast<std::size_t>(into)].absorbed.push_back(static_cast<std::int32_t>(c + 1));
  };
  for (const std::size_t c : order) {
    const int n = static_cast<int>(cluster_pixels[c].size());
    if (n <= p.fragments.max_pixels) {
      int host = footprints.host(frame, cluster_pixels[c], p);
      if (host < 0) {
        host = holding_walker(frame.world_xy(est.clusters[c].centroid_m), cluster_pixels[c].size(), tracks,
                              measured_boxes, groups, p);
      }
      if (host >= 0) {
        absorb(c, host);
        continue;
      }
    }
    if (n < p.association.min_pixels_at(est.clusters[c].centroid_m.head<2>().norm()) || !est.clusters[c].velocity.valid) continue;
    const int vehicle = inside_vehicle(frame, est.clusters[c], tracks, measured_boxes, p);
    if (vehicle >= 0) {
      absorb(c, vehicle);
      continue;
    }
    Group g;
    g.clusters.push_back(static_cast<std::int32_t>(c + 1));
    g.found = cluster_pixels[c];
    const int walker = c < companion_of.size() ? companion_of[c] : -1;
    const Track* companion = walker >= 0 ? &tracks[static_cast<std::size_t>(walker)] : nullptr;
    tracks.push_back(start_track(est.clusters[c], g, next_id++, frame, edges, p, companion));
    assoc.owner[c] = static_cast<int>(tracks.size()) - 1;
    if (holds_pieces(tracks.back(), p)) footprints.add(groups.size(), g);
    groups.push_back(std::move(g));
  }
}

}  // namespace fmcw::core::tracking
