#include "measurement.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ctrv.hpp"
#include "fmcw/core/median.hpp"
#include "outline_axis.hpp"

namespace fmcw::core::tracking {

namespace {

// A walker's own pixels: those inside its predicted box, grown by claim_margin_m (the walker
// beside it may share its cluster).
Group walker_pixels(const Track& tr, const Group& whole, const Frame& frame, const TrackerParams& p) {
  Group mine;
  const Box b = box_of(tr);
  const auto inside = [&](std::uint32_t i) { return b.contains(frame.world_xy(frame.scan.position(i)), p.claims.claim_margin_m); };
  for (const std::uint32_t i : whole.found) {
    if (inside(i)) mine.found.push_back(i);
  }
  for (const std::uint32_t i : whole.claimed) {
    if (inside(i)) mine.claimed.push_back(i);
  }
  return mine;
}

// The Doppler rows of the group's pixels with their residuals against the prediction, and which
// of them move with the body: within outlier_sigmas robust deviations of the median residual.
struct DopplerRows {
  std::vector<Row> rows;
  double median = 0.0;
  double cut = 0.0;
  std::size_t used = 0;
  bool inlier(const Row& r) const { return std::abs(r.residual - median) <= cut; }
};

DopplerRows doppler_rows(const Track& tr, const Group& g, const Frame& frame, const TrackerParams::Measurement& p) {
  DopplerRows d;
  d.rows.reserve(g.found.size() + g.claimed.size());
  g.for_each_measured([&](std::uint32_t i) { d.rows.push_back(frame.row_of(i)); });
  std::vector<double> dev(d.rows.size());
  for (std::size_t n = 0; n < d.rows.size(); ++n) {
    d.rows[n].residual = d.rows[n].y - predicted(d.rows[n], tr.x);
    dev[n] = d.rows[n].residual;
  }
  d.median = upper_median(dev);
  for (double& v : dev) v = std::abs(v - d.median);
  d.cut = std::max(p.outlier_floor_mps, p.outlier_sigmas * 1.4826 * upper_median(dev));
  for (const Row& r : d.rows) d.used += d.inlier(r) ? 1 : 0;
  return d;
}

// Information and gradient of the Doppler rows for an update from the state `base`, linearised at
// x (x == base: the rows' residuals as found against the prediction; the inliers stay those). A
// small object: one row, the mean of the inlier rows, its noise the rows' spread over the square
// root of their effective count, floored (the gait phase moves the mean). Otherwise every inlier
// row, weighted as at most max_effective_rows independent ones.
void doppler_information(const DopplerRows& d, const Vec5& base, const Vec5& x, bool small,
                         const TrackerParams& p, Mat5& info, Vec5& grad) {
  // The residual of the row's line at x, taken from base: y - h(x) + H(x) (x - base).
  const bool at_base = x == base;
  const auto residual = [&](const Row& r, const Vec5& h) {
    return at_base ? r.residual : r.y - predicted(r, x) + h.dot(x - base);
  };
  const TrackerParams::Measurement& pm = p.measurement;
  if (small) {
    Vec5 h_mean = Vec5::Zero();
    double res_mean = 0.0;
    for (const Row& r : d.rows) {
      if (!d.inlier(r)) continue;
      const Vec5 h = row_jacobian(r, x);
      h_mean += h;
      res_mean += residual(r, h);
    }
    if (d.used == 0) return;
    h_mean /= static_cast<double>(d.used);
    res_mean /= static_cast<double>(d.used);
    const double spread = std::max(pm.doppler_sigma_mps, d.cut / pm.outlier_sigmas);
    const double n_eff = static_cast<double>(std::min<std::size_t>(d.used, static_cast<std::size_t>(pm.max_effective_rows)));
    const double sigma = std::max(p.small.doppler_floor_mps, spread / std::sqrt(n_eff));
    info = h_mean * h_mean.transpose() / (sigma * sigma);
    grad = h_mean * res_mean / (sigma * sigma);
    return;
  }
  const double sensor_w = 1.0 / (pm.doppler_sigma_mps * pm.doppler_sigma_mps);
  const double w = sensor_w * std::min(1.0, static_cast<double>(pm.max_effective_rows) /
                                                 static_cast<double>(std::max<std::size_t>(d.used, 1)));
  for (const Row& r : d.rows) {
    if (!d.inlier(r)) continue;
    const Vec5 h = row_jacobian(r, x);
    info.noalias() += w * h * h.transpose();
    grad += w * h * residual(r, h);
  }
}

}  // namespace

namespace {

// The along-body direction of an axis (n across the body, in the tracker's world), oriented
// with the track's velocity [rad].
double oriented_axis_angle(const Track& tr, const Eigen::Vector2d& n) {
  Eigen::Vector2d along(n.y(), -n.x());
  if (along.dot(tr.velocity()) < 0.0) along = -along;
  return std::atan2(along.y(), along.x());
}

// The earliest time of an axis the track keeps that still lies within the window
// (TrackerParams::Turning::straight_window_s) [s].
double window_start(const Track& tr, const TrackerParams::Turning& p) {
  return tr.clock_s - p.straight_window_s - 1e-9;
}

// Keeps the axis just measured for straight_by_axes(), and drops those older than the window.
void record_axis(Track& tr, const Eigen::Vector2d& n, double heading_var,
                 const TrackerParams::Turning& p) {
  if (!(p.straight_window_s > 0.0)) return;
  double angle = oriented_axis_angle(tr, n);
  if (!tr.axes.empty())
    angle += 2.0 * M_PI * std::round((tr.axes.back().angle_rad - angle) / (2.0 * M_PI));
  tr.axes.push_back({tr.clock_s, angle, heading_var});
  const double since = window_start(tr, p);
  const auto old = std::find_if(tr.axes.begin(), tr.axes.end(),
                                [since](const Track::AxisSample& s) { return s.t_s >= since; });
  tr.axes.erase(tr.axes.begin(), old);
}

}  // namespace

bool straight_by_axes(const Track& tr, const TrackerParams::Turning& p, double& b, double& var_b) {
  if (!(p.straight_window_s > 0.0)) return false;
  const double since = window_start(tr, p);
  // The axes of the window that carry a variance.
  const auto counts = [since](const Track::AxisSample& s) {
    return s.t_s >= since && s.var_rad2 > 0.0;
  };
  // Weighted means of time and angle over the window.
  double sw = 0.0, st = 0.0, sa = 0.0, t0 = std::numeric_limits<double>::infinity(), t1 = -t0;
  int n = 0;
  for (const Track::AxisSample& s : tr.axes) {
    if (!counts(s)) continue;
    const double q = 1.0 / s.var_rad2;
    sw += q;
    st += q * s.t_s;
    sa += q * s.angle_rad;
    t0 = std::min(t0, s.t_s);
    t1 = std::max(t1, s.t_s);
    ++n;
  }
  if (n < p.straight_min_axes || t1 - t0 < 0.5 * p.straight_window_s) return false;
  const double tm = st / sw, am = sa / sw;
  double stt = 0.0, sta = 0.0;
  for (const Track::AxisSample& s : tr.axes) {
    if (!counts(s)) continue;
    stt += (s.t_s - tm) * (s.t_s - tm) / s.var_rad2;
    sta += (s.t_s - tm) * (s.angle_rad - am) / s.var_rad2;
  }
  if (!(stt > 0.0)) return false;
  b = sta / stt;
  double chi2 = 0.0;
  for (const Track::AxisSample& s : tr.axes) {
    if (!counts(s)) continue;
    const double r = s.angle_rad - am - b * (s.t_s - tm);
    chi2 += r * r / s.var_rad2;
  }
  var_b = std::max(1.0, chi2 / (n - 2)) / stt;
  const double sigma_b = std::sqrt(var_b), sigma_w = tr.yaw_rate_sigma();
  return std::abs(b) <= p.straight_sigmas * sigma_b &&
         sigma_b <= p.straight_max_sigma_ratio * sigma_w &&
         std::abs(tr.yaw_rate() - b) <=
             p.straight_consistency_sigmas * std::sqrt(sigma_w * sigma_w + var_b);
}

namespace {

// An axis read beyond the gate (n across the body, its heading's variance var): whether the gate
// opens to it (TrackerParams::Heading::reopen_sigmas). It is kept as the track's last read
// beyond the gate either way.
bool gate_reopens(Track& tr, const Eigen::Vector2d& n, double var,
                  const TrackerParams::Heading& ph) {
  const Track::AxisSample before = tr.beyond_gate;
  tr.beyond_gate = {tr.clock_s, oriented_axis_angle(tr, n), var};
  if (!(ph.reopen_sigmas > 0.0)) return false;
  // How far apart two directions are, the older one (dt s before now) turned on by the yaw rate.
  const double w = tr.yaw_rate();
  const auto apart = [w](double now, double then, double dt) {
    return std::abs(std::remainder(now - then - w * dt, 2.0 * M_PI));
  };
  const double since = tr.clock_s - before.t_s;
  if (!(since <= ph.reopen_window_s) || apart(tr.beyond_gate.angle_rad, before.angle_rad, since) >
                                            ph.reopen_sigmas * std::sqrt(var + before.var_rad2))
    return false;
  // The axes the track keeps: those of the window before the last one it recorded (the gate
  // records none, so a heading the track measured before a run of reads beyond it still counts).
  const double heading = std::atan2(tr.velocity().y(), tr.velocity().x());
  const auto holds = [&](const Track::AxisSample& s) {
    return apart(heading, s.angle_rad, tr.clock_s - s.t_s) <=
           ph.reopen_sigmas * std::sqrt(s.var_rad2);
  };
  return std::count_if(tr.axes.begin(), tr.axes.end(), holds) < ph.reopen_support;
}

}  // namespace

bool axis_information(Track& tr, const std::vector<std::uint32_t>& pixels, const Frame& frame, const TrackerParams& p, Mat5& info,
                      Vec5& grad) {
  tr.axis_seen = false;
  tr.line_seen = false;
  // Only what moves faster than a walker: walkers side by side or in file make one cluster
  // longer than a car, whose long side need not be the way they go. (Not only tracks whose box
  // is already a vehicle's: a car seen first is measured along the Doppler's velocity, which a
  // turn may have swung 50 degrees off its axis.)
  if (tr.walker || tr.small(p) || pixels.empty() || tr.velocity().norm() <= p.small.walker_max_speed_mps) return false;
  const OutlineAxis a = outline_axis(pixels, frame, p.heading);
  const TrackerParams::Heading& ph = p.heading;
  // No long side: a face across the body (its rear or front, seen end-on), the axis its normal.
  const bool face = is_face(a, frame.position, tr.velocity().normalized(), ph);
  if (!a.informative && !face) {
    // Too short for an axis, no face: a line or an L the report may test its yaw rate by.
    const TrackerParams::Turning& pt = p.turning;
    tr.line_seen =
        a.rectangle && a.side_length_m >= pt.line_min_length_m && a.columns >= pt.line_min_columns;
    tr.line_axis = a.axis;
    return false;
  }
  // The direction across the body: across the long side, or along the face.
  const Eigen::Vector2d n = face ? a.side_axis : Eigen::Vector2d(-a.axis.y(), a.axis.x());
  const double heading_var = face ? face_heading_variance(a, frame.position, tr.outline_cut, ph)
                                  : axis_heading_variance(a, frame.position, tr.outline_cut, ph);
  const double speed = tr.velocity().norm();
  // A turning car's centre moves across its axis (it turns about its rear axle); a face is as
  // long as the body is wide, the body at least min_length_m long.
  const double body_m = face ? std::max(tr.length_m, ph.min_length_m) : a.length_m;
  const double lateral = ph.centre_offset_fraction * body_m * std::abs(tr.yaw_rate());
  const double slip = std::max(ph.slip_sigma_mps, ph.slip_sigma_rad * speed);
  const double var = speed * speed * heading_var + slip * slip + lateral * lateral;
  const double innovation = -n.dot(tr.velocity());
  const double spread = std::sqrt(n.dot(tr.P.block<2, 2>(2, 2) * n) + var);
  // An axis this far off the track's heading is another shape's (a far car's few columns read
  // the wrong way): not measured in this update, unless the heading is what no read holds and
  // the reads beyond the gate agree (gate_reopens). Within it, Huber-weighted beyond 3 standard
  // deviations of the innovation, as the centre is.
  if (ph.gate_sigmas > 0.0 && std::abs(innovation) > ph.gate_sigmas * spread &&
      !gate_reopens(tr, n, heading_var, ph))
    return false;
  tr.axis_seen = true;
  record_axis(tr, n, heading_var, p.turning);
  const double w = std::min(1.0, 3.0 * spread / std::max(std::abs(innovation), 1e-12)) / var;
  info.block<2, 2>(2, 2) += w * n * n.transpose();
  grad.segment<2>(2) += w * n * innovation;
  return true;
}

namespace {

// The update's information and gradient from the prior's mean `prior`: the Doppler rows
// linearised at `at`, plus the linear rest (the box centre and the axis, info_rest and grad_rest,
// measured from the prediction x0 and moved to that mean).
void update_information(const DopplerRows& d, const Vec5& x0, const Vec5& prior, const Vec5& at,
                        bool small, const Mat5& info_rest, const Vec5& grad_rest,
                        const TrackerParams& p, Mat5& info, Vec5& grad) {
  info.setZero();
  grad.setZero();
  doppler_information(d, prior, at, small, p, info, grad);
  info += info_rest;
  if (prior == x0) {
    grad += grad_rest;
  } else {
    grad += grad_rest + info_rest * (x0 - prior);
  }
}

// The update again, linearised at its result (TrackerParams::Measurement::relinearise_mps): a young
// track whose scan took a far turning body's yaw rate for velocity across the beams (the prior's
// line, omega ~ 0) moves by metres at its first update after birth, and linearised at the
// prediction, that update leaves its own pixels' Doppler unexplained by metres per second. Each
// pass takes the earlier state the last result implies (one smoother step back through the
// prediction), the prediction linearised there as the prior, and the rows linearised at the
// result (their residuals from that prior's mean; the inliers stay those of the prediction); the
// box centre and the axis are linear, their information kept. info and grad come in as the first
// pass made them and leave as the last; the track's state and covariance become that pass's
// prior.
void relinearise(Track& tr, const DopplerRows& d, bool small, const Mat5& info_rest,
                 const Vec5& grad_rest, const TrackerParams& p, Mat5& info, Vec5& grad) {
  const TrackerParams::Measurement& pm = p.measurement;
  if (pm.relinearise_iterations <= 0 || tr.hits > pm.relinearise_max_hits ||
      !(tr.dt_before > 0.0) || tr.velocity().norm() <= p.small.walker_max_speed_mps)
    return;
  const double dt = tr.dt_before;
  const Vec5 x0 = tr.x;  // the prediction
  Mat5 P_inv = tr.P.inverse();
  Vec5 prior = x0;
  Mat5 P = tr.P;
  Vec5 before = tr.x_before;  // the earlier state the prediction is linearised at
  Mat5 F = transition_jacobian(before, dt);
  Vec5 after = x0;  // the state the rows are linearised at
  bool moved = false;
  for (int k = 0; k < pm.relinearise_iterations; ++k) {
    const Mat5 P_post = (P_inv + info).inverse();
    const Vec5 next = prior + P_post * grad;
    const Vec5 dx = next - after;
    const double bound = std::abs(dx(4)) * (dx.head<2>().norm() + dt * dx.segment<2>(2).norm());
    if (!next.allFinite() || !(bound > pm.relinearise_mps)) break;
    // The earlier state the update implies (one step of the smoother), and the prediction
    // linearised there.
    const Vec5 smoothed = tr.x_before + tr.P_before * F.transpose() * P_inv * (next - prior);
    if (!smoothed.allFinite()) break;
    before = smoothed;
    after = next;
    F = transition_jacobian(before, dt);
    prior = propagate(before, dt) + F * (tr.x_before - before);
    P = F * tr.P_before * F.transpose() + tr.Q_before;
    P_inv = P.inverse();
    update_information(d, x0, prior, after, small, info_rest, grad_rest, p, info, grad);
    moved = true;
  }
  if (!moved) return;
  tr.x = prior;
  tr.P = 0.5 * (P + P.transpose());
}

}  // namespace

void measure(Track& tr, const Group& whole, bool born, const Frame& frame, const ViewEdges& edges, const TrackerParams& p) {
  Group mine;
  if (tr.walker && !born) mine = walker_pixels(tr, whole, frame, p);
  const Group& g = mine.empty() ? whole : mine;
  const BoxMeasurement box = measure_box(tr, g, born, frame, edges, p);
  if (born) {
    tr.x.head<2>() = box.centre;
    return;
  }
  const DopplerRows d = doppler_rows(tr, g, frame, p.measurement);
  const bool small = tr.small(p);  // the box may just have been measured
  // The box centre and the outline's axis, linear in the state (their blocks of the information
  // are apart).
  Mat5 info_rest = Mat5::Zero();
  Vec5 grad_rest = Vec5::Zero();
  // The box centre, Huber-weighted beyond 3 standard deviations of the innovation.
  const Eigen::Vector2d innovation = box.seen ? Eigen::Vector2d(box.centre - tr.x.head<2>()) : Eigen::Vector2d::Zero();
  const double pos_sigma = box.centre_from_claims ? p.measurement.claim_position_sigma_m
                           : small                ? p.small.position_sigma_m
                                                  : p.measurement.position_sigma_m;
  const double pos_w_here = 1.0 / (pos_sigma * pos_sigma);
  const Eigen::Matrix2d S = tr.P.topLeftCorner<2, 2>() + Eigen::Matrix2d::Identity() / pos_w_here;
  const double mahalanobis = std::sqrt(innovation.dot(S.inverse() * innovation));
  const double pw = box.seen ? pos_w_here * std::min(1.0, 3.0 / std::max(mahalanobis, 1e-12)) : 0.0;
  info_rest.topLeftCorner<2, 2>() += pw * Eigen::Matrix2d::Identity();
  grad_rest.head<2>() += pw * innovation;
  // The axis of the found pixels, unless the claimed ones (from the background, not this scan's
  // clusters) outnumber them.
  if (g.claimed.size() <= g.found.size()) {
    axis_information(tr, g.found, frame, p, info_rest, grad_rest);
  } else {
    tr.axis_seen = tr.line_seen = false;
  }
  Mat5 info;
  Vec5 grad;
  update_information(d, tr.x, tr.x, tr.x, small, info_rest, grad_rest, p, info, grad);
  relinearise(tr, d, small, info_rest, grad_rest, p, info, grad);
  information_update(tr, info, grad, p);
}

void update_track_state(Track& tr, const Group& g, const TrackerParams& p) {
  if (g.empty()) {
    ++tr.misses;
    tr.axis_seen = tr.line_seen = false;
  } else {
    ++tr.hits;
    tr.last_pixels = static_cast<int>(g.found.size());
    tr.misses = 0;
  }
  if (tr.hits >= p.lifecycle.confirm_hits) tr.confirmed = true;
  if (!g.empty()) {
    const double extent = std::min(std::max(tr.length_m, tr.width_m), tr.seen_extent_m);
    tr.small_hits = extent < p.small.small_object_m ? tr.small_hits + 1 : 0;
    note_extent(tr, p, false);
  }
  if (!g.empty()) {
    tr.fast_updates = tr.velocity().norm() > p.small.walker_max_speed_mps ? tr.fast_updates + 1 : 0;
    tr.vehicle_pace = tr.vehicle_pace || tr.fast_updates >= p.small.vehicle_pace_updates;
  }
  const bool slow = tr.velocity().norm() < p.small.walker_max_speed_mps;
  tr.walker = slow && (tr.walker || (p.small.walker_hits > 0 && tr.small_hits >= p.small.walker_hits));
  tr.slow_frames = tr.velocity().norm() < p.lifecycle.carry_min_speed_mps ? tr.slow_frames + 1 : 0;
  update_turning(tr, p);
}

void note_extent(Track& tr, const TrackerParams& p, bool born) {
  const double extent = tr.length_m + tr.width_m;
  if (born || extent > tr.settled_extent_m + p.turning.settle_growth_m) {
    tr.settled_extent_m = extent;
    tr.updates_settled = 0;
    return;
  }
  tr.settled_extent_m = std::min(tr.settled_extent_m, extent);
  ++tr.updates_settled;
}

bool settled(const Track& tr, const TrackerParams& p) {
  const TrackerParams::Turning& pt = p.turning;
  return pt.shrink_settled && !tr.outline_cut && tr.hits >= pt.min_turn_hits && tr.updates_settled >= pt.settle_updates &&
         tr.updates_since_turn > pt.release_hold_updates;
}

bool line_says_turning(const Track& tr, const Eigen::Vector2d& doppler_velocity,
                       const TrackerParams::Turning& p) {
  // Young: an older track whose rate is still unresolved has had the updates to resolve a turn.
  if (p.line_max_angle_rad <= 0.0 || !tr.line_seen || tr.hits >= p.min_turn_hits) return false;
  // A velocity's angle to the nearest of the rectangle's four directions.
  const double line = std::atan2(tr.line_axis.y(), tr.line_axis.x());
  const auto off = [line](const Eigen::Vector2d& v) {
    return std::abs(std::remainder(std::atan2(v.y(), v.x()) - line, 0.5 * M_PI));
  };
  return off(tr.velocity()) < p.line_max_angle_rad &&
         off(doppler_velocity) > p.line_doppler_angle_rad;
}

bool turn_held(const Track& tr, const TrackerParams& p) {
  const TrackerParams::Turning& pt = p.turning;
  const double w = tr.yaw_rate();
  const double last = tr.last_turn_rate_rps;
  return pt.hold_rate_fraction > 0.0 && !tr.turning &&
         tr.updates_since_turn <= pt.release_hold_updates && w * last > 0.0 &&
         std::abs(w) >= pt.hold_rate_fraction * std::abs(last);
}

void update_turning(Track& tr, const TrackerParams& p) {
  const TrackerParams::Turning& pt = p.turning;
  const double w = std::abs(tr.yaw_rate());
  const double w_sigma = tr.yaw_rate_sigma();
  const auto track_since = [&tr] {
    if (tr.turning) {
      tr.updates_since_turn = 0;
      tr.last_turn_rate_rps = tr.yaw_rate();
    } else if (tr.updates_since_turn != Track::kNever) {
      ++tr.updates_since_turn;
    }
  };
  // A track whose outline's axis was measured in this update reports its yaw rate shrunk by its
  // significance instead (relabel.cpp), at any age and rate.
  if (tr.axis_seen) {
    tr.turning = false;
    track_since();
    return;
  }
  // Otherwise turning once the yaw rate is resolved on a track of some age; still turning while
  // it stays above the minimum and turn_release_significance standard deviations (the box centre
  // of a near car jumps as its visible side changes, the position updates are then down-weighted
  // and the yaw rate's variance grows for a while, not its value).
  tr.turning = w >= pt.min_turn_rate_rps && (tr.turning ? w >= pt.turn_release_significance * w_sigma
                                                        : tr.hits >= pt.min_turn_hits && w >= pt.turn_significance * w_sigma);
  track_since();
}

}  // namespace fmcw::core::tracking
