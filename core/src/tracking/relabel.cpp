#include "relabel.hpp"

#include <cmath>
#include <limits>

#include "../label_renumbering.hpp"
#include "../pixel_lists.hpp"
#include "measurement.hpp"
#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core::tracking {

std::vector<std::int32_t> group_of_labels(const std::vector<Group>& groups, std::size_t k) {
  std::vector<std::int32_t> group_of_label(k + 1, -1);
  for (std::size_t t = 0; t < groups.size(); ++t) {
    for (const std::int32_t l : groups[t].clusters) group_of_label[static_cast<std::size_t>(l)] = static_cast<std::int32_t>(t);
    for (const std::int32_t l : groups[t].absorbed) group_of_label[static_cast<std::size_t>(l)] = static_cast<std::int32_t>(t);
  }
  return group_of_label;
}

namespace {

// The track's velocity at its centre, as reported (rig axes). The yaw rate is seen only through
// the track's path (a rigid body turning about a fixed point has a time-invariant Doppler
// field), and each rad/s of it moves the centre's velocity by |o - c| m/s. Unless the turn is
// resolved (Track::turning), report the velocity the Doppler measures, v + omega z x (o - c),
// with no turn. A small object's Doppler pins only its radial velocity, the same for v and for
// v + omega z x (o - c): the track's own velocity is the better guess either way. o: the mean
// beam origin of the pixels the track measured this frame; of those it reports (reported_origin)
// where it measured none (its clusters only absorbed: a track coasting over them).
void report_track(const Frame& frame, const Track& tr, const Group& g, const MotionEstimate& est,
                  const TrackerParams& p, const Eigen::Vector2d& reported_origin,
                  ClusterEstimate& ce) {
  const Eigen::Matrix2d Rt = frame.R.transpose();
  const VelocityEstimate scan_estimate =
      g.clusters.empty() ? VelocityEstimate{} : est.clusters[static_cast<std::size_t>(g.clusters.front() - 1)].velocity;
  ce.scan_velocity_mps = g.clusters.empty() ? Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())
                                            : scan_estimate.velocity_mps;
  ce.track_id = tr.id;
  ce.track_hits = tr.hits;
  ce.carried_pixels = static_cast<int>(g.claimed.size() + g.labelled.size());
  ce.yaw_rate_rps = tr.yaw_rate();
  ce.centre_m = Eigen::Vector3d::Zero();
  ce.centre_m.head<2>() = Rt * (tr.centre() - frame.position);
  ce.centre_m.z() = 0.5 * (tr.z_min_m + tr.z_max_m);
  VelocityEstimate& v = ce.velocity;
  v = scan_estimate;
  const Eigen::Vector2d d = (g.empty() ? reported_origin : mean_origin(frame, g)) - tr.centre();
  Eigen::Matrix<double, 2, 3> J;
  J << 1.0, 0.0, -d.y(), 0.0, 1.0, d.x();
  Eigen::Vector2d vel = tr.velocity();
  // The filter's covariance, matched to the track's updates (TrackerParams::Calibration).
  const double c = tr.covariance_scale(p);
  Eigen::Matrix2d cov = tr.P.block<2, 2>(2, 2);
  Eigen::Matrix2d left_in = Eigen::Matrix2d::Zero();  // the yaw rate left in the velocity, (w - taken)^2 s s^T
  if (!tr.turning && tr.small(p)) {
    ce.yaw_rate_rps = 0.0;
  } else if (!tr.turning) {
    vel = J * tr.x.segment<3>(2);
    // The velocity the Doppler measures is the centre's only if the body does not turn: the
    // yaw rate taken as 0 here is off by the track's own (with its variance), and each rad/s of
    // it moves the centre's velocity by |o - c| m/s across the line of sight.
    const Eigen::Vector2d s = J.col(2);
    // A track whose outline's axis has been measured, whose box has settled (its path is then
    // the body's: settled()), or whose turn was released while its rate held up (turn_held())
    // knows its yaw rate as well as its variance says: the yaw rate, shrunk by its significance
    // (w^2 / (w^2 + k^2 sigma^2) of it: all of a resolved turn, little of one within its
    // noise), is taken off, and what is left of it is what the covariance carries.
    const double w = tr.x(4);
    const double k = p.turning.axis_shrink_sigmas;
    const double w2 = w * w + k * k * tr.P(4, 4);
    // Or a yaw rate too large to leave in (TrackerParams::Turning::max_left_in_mps): resolved
    // enough, and a velocity off by metres per second if it were left in.
    const double max_left_in = p.turning.max_left_in_mps;
    const bool too_large = max_left_in > 0.0 && std::abs(w) * s.norm() > max_left_in &&
                           std::abs(w) > p.turning.max_left_in_significance * tr.yaw_rate_sigma();
    const bool known = tr.axis_seen || settled(tr, p) || turn_held(tr, p) || too_large;
    // Or the line its outline shows says the filter's velocity is the body's and the Doppler's
    // is not: the rate is taken off in full (TrackerParams::Turning::line_max_angle_rad).
    const bool by_line = !known && line_says_turning(tr, vel, p.turning);
    // Unless its axes say it drives straight: then the Doppler's velocity, with the yaw rate of
    // the axes' line and its variance in the covariance in place of the filter's
    // (TrackerParams::Turning::straight_window_s).
    double b = 0.0, var_b = 0.0;
    const bool straight = known && !too_large && straight_by_axes(tr, p.turning, b, var_b);
    const double taken = by_line ? w : !straight && known && w2 > 0.0 ? w * w * w / w2 : 0.0;
    const double yaw_var = straight ? b * b + var_b : tr.P(4, 4);
    const double left = straight ? 0.0 : w - taken;
    vel -= taken * s;
    cov = J * tr.P.block<3, 3>(2, 2) * J.transpose() + yaw_var * s * s.transpose();
    left_in = left * left * s * s.transpose();
    ce.yaw_rate_rps = taken;
  }
  // The filter's share is scaled as its updates say; the yaw rate left in is not the filter's
  // uncertainty but the report's own choice, and stays as it is; so does a group's spread.
  cov = c * cov + left_in;
  // A group of walkers (Track::may_be_group): each walker's velocity differs from the group's by
  // up to a walker's pace, which no update of the track measures.
  if (tr.may_be_group(p))
    cov += p.small.group_sigma_mps * p.small.group_sigma_mps * Eigen::Matrix2d::Identity();
  v.velocity_mps = Eigen::Vector3d::Zero();
  v.velocity_mps.head<2>() = Rt * vel;
  v.covariance = Eigen::Matrix3d::Zero();
  v.covariance.topLeftCorner<2, 2>() = Rt * cov * frame.R;
  v.num_points = ce.num_pixels;
  // A track whose state has run off (it should not: births cap what one scan cannot see) is no
  // estimate to act on.
  v.valid = v.velocity_mps.allFinite() && v.velocity_mps.norm() <= kMaxPlausibleSpeedMps;
}

}  // namespace

void relabel_estimate(const Frame& frame, const std::vector<Track>& tracks, const std::vector<Group>& groups,
                      const std::vector<std::int32_t>& group_of_label,
                      const std::vector<std::pair<std::uint32_t, std::size_t>>& grown_untracked, const TrackerParams& p,
                      MotionEstimate& est) {
  const std::size_t n_groups = groups.size();
  // Static pixels that join an object: key of their object (group t -> t, untracked cluster c
  // -> n_groups + c).
  std::vector<std::int32_t> claimed_by(est.labels.size(), -1);
  for (const auto& [i, c] : grown_untracked) claimed_by[i] = static_cast<std::int32_t>(n_groups + c);
  for (std::size_t t = 0; t < n_groups; ++t) {
    for (const std::uint32_t i : groups[t].labelled) claimed_by[i] = static_cast<std::int32_t>(t);
    for (const std::uint32_t i : groups[t].claimed) claimed_by[i] = static_cast<std::int32_t>(t);
  }
  // The pixels of an object, now: labelled before or joining one.
  std::vector<std::uint32_t> object_pixels;
  list_pixels(est.labels.size(), [&](std::size_t i) { return (est.labels[i] >= 1) | (claimed_by[i] >= 0); }, object_pixels);
  // Key of a pixel's new object: group t -> t, untracked old label l -> n_groups + l - 1.
  int moved_to_moving = 0;
  const std::vector<std::int32_t> key_of_new = renumber_listed_by_first_pixel(
      est.labels, object_pixels, n_groups + est.clusters.size(), [&](std::size_t i) -> std::int32_t {
        const std::int32_t l = est.labels[i];
        if (l >= 1) {
          const std::int32_t g = group_of_label[static_cast<std::size_t>(l)];
          return g >= 0 ? g : static_cast<std::int32_t>(n_groups) + l - 1;
        }
        if (claimed_by[i] >= 0) ++moved_to_moving;
        return claimed_by[i];
      });
  est.num_static_pixels -= moved_to_moving;
  const auto next = static_cast<std::int32_t>(key_of_new.size()) - 1;
  std::vector<ClusterEstimate> out(static_cast<std::size_t>(next));
  std::vector<int> count(static_cast<std::size_t>(next), 0);
  std::vector<Eigen::Vector2d> origin(static_cast<std::size_t>(next), Eigen::Vector2d::Zero());
  for (const std::uint32_t i : object_pixels) {
    const std::int32_t l = est.labels[i];
    out[static_cast<std::size_t>(l - 1)].centroid_m += frame.scan.position(i);
    origin[static_cast<std::size_t>(l - 1)] += frame.world_xy(frame.beams.origin_of(i));
    ++count[static_cast<std::size_t>(l - 1)];
  }
  for (std::int32_t l = 1; l <= next; ++l) {
    ClusterEstimate& ce = out[static_cast<std::size_t>(l - 1)];
    const std::int32_t key = key_of_new[static_cast<std::size_t>(l)];
    ce.id = l;
    ce.num_pixels = count[static_cast<std::size_t>(l - 1)];
    ce.centroid_m /= static_cast<double>(ce.num_pixels);
    if (key >= static_cast<std::int32_t>(n_groups)) {  // untracked: as the single scan saw it
      const ClusterEstimate& old = est.clusters[static_cast<std::size_t>(key) - n_groups];
      ce.velocity = old.velocity;
      ce.scan_velocity_mps = old.velocity.velocity_mps;
      continue;
    }
    report_track(frame, tracks[static_cast<std::size_t>(key)],
                 groups[static_cast<std::size_t>(key)], est, p,
                 origin[static_cast<std::size_t>(l - 1)] / static_cast<double>(ce.num_pixels), ce);
  }
  est.clusters = std::move(out);
}

}  // namespace fmcw::core::tracking
