#include "fmcw/core/object_tracker.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "fmcw/core/check.hpp"
#include "fmcw/core/median.hpp"
#include "fmcw/core/motion_pipeline.hpp"

namespace fmcw::core {

void TrackerParams::validate() const {
  FMCW_CHECK_ARG(doppler_sigma_mps > 0.0, "tracking: doppler_sigma_mps must be > 0, got ",
                 doppler_sigma_mps);
  FMCW_CHECK_ARG(max_effective_rows >= 1, "tracking: max_effective_rows must be >= 1, got ",
                 max_effective_rows);
  FMCW_CHECK_ARG(outlier_sigmas > 0.0 && outlier_floor_mps > 0.0,
                 "tracking: outlier thresholds must be > 0");
  FMCW_CHECK_ARG(position_sigma_m > 0.0, "tracking: position_sigma_m must be > 0, got ",
                 position_sigma_m);
  FMCW_CHECK_ARG(small_object_m >= 0.0 && small_position_sigma_m > 0.0 && small_doppler_floor_mps > 0.0 &&
                     small_initial_tangential_sigma_mps > 0.0,
                 "tracking: small_object_m must be >= 0, the small-object noises > 0");
  FMCW_CHECK_ARG(walker_hits >= 0 && walker_max_speed_mps > 0.0,
                 "tracking: walker_hits must be >= 0 (0: no walkers), walker_max_speed_mps > 0");
  FMCW_CHECK_ARG(accel_sigma_mps2 > 0.0 && yaw_accel_sigma_rps2 > 0.0,
                 "tracking: process noise must be > 0");
  FMCW_CHECK_ARG(initial_yaw_rate_sigma_rps > 0.0 && max_initial_velocity_sigma_mps > 0.0,
                 "tracking: initial uncertainties must be > 0");
  FMCW_CHECK_ARG(min_turn_rate_rps >= 0.0 && turn_significance >= turn_release_significance &&
                     turn_release_significance >= 0.0 && min_turn_hits >= 1,
                 "tracking: min_turn_rate_rps must be >= 0, turn_significance >= turn_release_significance >= 0, "
                 "min_turn_hits >= 1");
  FMCW_CHECK_ARG(gate_m >= 0.0 && claim_margin_m >= 0.0,
                 "tracking: gate_m and claim_margin_m must be >= 0");
  FMCW_CHECK_ARG(min_cluster_pixels >= 3, "tracking: min_cluster_pixels must be >= 3, got ",
                 min_cluster_pixels);
  FMCW_CHECK_ARG(confirm_hits >= 1 && max_misses >= 0 && release_slow_frames >= 1,
                 "tracking: confirm_hits and release_slow_frames must be >= 1, max_misses >= 0");
  FMCW_CHECK_ARG(associate_doppler_tolerance_mps > 0.0 && absorb_max_pixels >= 0 && max_yaw_rate_rps > 0.0 &&
                     vehicle_length_m > 0.0 && claim_position_sigma_m > 0.0,
                 "tracking: associate_doppler_tolerance_mps, max_yaw_rate_rps, vehicle_length_m and "
                 "claim_position_sigma_m must be > 0, absorb_max_pixels >= 0");
  FMCW_CHECK_ARG(claim_doppler_tolerance_mps > 0.0,
                 "tracking: claim_doppler_tolerance_mps must be > 0");
  FMCW_CHECK_ARG(background_min_frames >= 0 && background_margin_m > 0.0 && background_label_m >= 0.0,
                 "tracking: background_min_frames must be >= 0 (0: no background), background_margin_m > 0, "
                 "background_label_m >= 0");
  FMCW_CHECK_ARG(grow_reach_m >= 0.0 && grow_range_gap_m > 0.0 && grow_range_gap_fraction >= 0.0,
                 "tracking: grow_reach_m must be >= 0 (0: no growth), grow_range_gap_m > 0, "
                 "grow_range_gap_fraction >= 0");
  FMCW_CHECK_ARG(max_length_m > 0.0 && max_width_m > 0.0, "tracking: box size caps must be > 0");
  FMCW_CHECK_ARG(split_min_share > 0.0, "tracking: split_min_share must be > 0 (above 1: never split), got ",
                 split_min_share);
  FMCW_CHECK_ARG(view_cut_cosine >= 0.0 && view_cut_cosine < 1.0,
                 "tracking: view_cut_cosine must be in [0, 1), got ", view_cut_cosine);
  FMCW_CHECK_ARG(view_cut_end_m >= 0.0, "tracking: view_cut_end_m must be >= 0, got ", view_cut_end_m);
  FMCW_CHECK_ARG(max_gap_s > 0.0, "tracking: max_gap_s must be > 0, got ", max_gap_s);
  FMCW_CHECK_ARG(ego_accel_mps2 > 0.0 && ego_velocity_margin_mps >= 0.0 && ego_yaw_accel_rps2 > 0.0 &&
                     ego_yaw_rate_margin_rps >= 0.0,
                 "tracking: ego acceleration bounds must be > 0 and margins >= 0");
}

namespace {
using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::Matrix2d rotation(double yaw) {
  Eigen::Matrix2d r;
  r << std::cos(yaw), -std::sin(yaw), std::sin(yaw), std::cos(yaw);
  return r;
}

// Constant turn rate over dt: the centre moves along an arc, the velocity turns by omega dt.
Vec5 propagate(const Vec5& x, double dt) {
  Vec5 out = x;
  const double w = x(4);
  const double a = w * dt;
  const double s = std::sin(a);
  const double c = std::cos(a);
  const double vx = x(2);
  const double vy = x(3);
  if (std::abs(w) < 1e-9) {
    out(0) += vx * dt;
    out(1) += vy * dt;
  } else {
    out(0) += (s * vx - (1.0 - c) * vy) / w;
    out(1) += ((1.0 - c) * vx + s * vy) / w;
  }
  out(2) = c * vx - s * vy;
  out(3) = s * vx + c * vy;
  return out;
}

void predict(Track& t, double dt, const TrackerParams& p) {
  if (dt <= 0.0) return;
  // Jacobian by central differences: the model is smooth and five columns are cheap.
  Mat5 F;
  for (int k = 0; k < 5; ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(t.x(k)));
    Vec5 a = t.x;
    Vec5 b = t.x;
    a(k) += h;
    b(k) -= h;
    F.col(k) = (propagate(a, dt) - propagate(b, dt)) / (2.0 * h);
  }
  const double q = p.accel_sigma_mps2 * p.accel_sigma_mps2;
  Mat5 Q = Mat5::Zero();
  for (int k = 0; k < 2; ++k) {
    Q(k, k) = q * dt * dt * dt * dt / 4.0;
    Q(k, k + 2) = Q(k + 2, k) = q * dt * dt * dt / 2.0;
    Q(k + 2, k + 2) = q * dt * dt;
  }
  Q(4, 4) = p.yaw_accel_sigma_rps2 * p.yaw_accel_sigma_rps2 * dt * dt;
  t.x = propagate(t.x, dt);
  t.P = F * t.P * F.transpose() + Q;
  t.heading_rad += t.x(4) * dt;
  t.extents_heading_rad += t.x(4) * dt;
}

// Oriented box in the tracker's world, for point-in-box tests.
struct Box {
  Eigen::Vector2d centre;
  Eigen::Vector2d u;  // along the heading
  double half_l = 0.0;
  double half_w = 0.0;
  bool contains(const Eigen::Vector2d& q, double grow) const {
    const Eigen::Vector2d d = q - centre;
    const double a = d.dot(u);
    const double b = -d.x() * u.y() + d.y() * u.x();
    return std::abs(a) <= half_l + grow && std::abs(b) <= half_w + grow;
  }
  double distance(const Eigen::Vector2d& q) const {  // 0 inside
    const Eigen::Vector2d d = q - centre;
    const double a = std::max(0.0, std::abs(d.dot(u)) - half_l);
    const double b = std::max(0.0, std::abs(-d.x() * u.y() + d.y() * u.x()) - half_w);
    return std::hypot(a, b);
  }
};

Box box_of(const Track& t) {
  Box b;
  b.centre = t.centre();
  b.u = Eigen::Vector2d(std::cos(t.heading_rad), std::sin(t.heading_rad));
  b.half_l = 0.5 * std::max(t.length_m, 0.4);
  b.half_w = 0.5 * std::max(t.width_m, 0.4);
  return b;
}

// A cluster that two tracked objects share (two cars nose to tail at one speed touch in the
// image and in Doppler) is split between them when each one's predicted box holds a good share
// of the pixels it had last time: a pixel goes to the box that holds it (the nearest centre
// where boxes overlap), else to the nearest of those boxes. The first part keeps the label,
// the others get new ones; each part keeps the cluster's single-scan estimate.
template <class ToWorld>
void split_shared_clusters(const Scan& scan, MotionEstimate& est,
                           std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                           const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                           const TrackerParams& p, const ToWorld& world_xy) {
  std::vector<std::size_t> eligible;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    if (tracks[t].confirmed && tracks[t].misses == 0) eligible.push_back(t);
  }
  if (eligible.size() < 2) return;
  const std::size_t k0 = est.clusters.size();
  std::vector<std::size_t> near;
  for (std::size_t c = 0; c < k0; ++c) {
    const std::vector<std::uint32_t>& px = cluster_pixels[c];
    if (static_cast<int>(px.size()) < 2 * p.min_cluster_pixels) continue;
    std::vector<Eigen::Vector2d> q(px.size());
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo;
    for (std::size_t n = 0; n < px.size(); ++n) {
      q[n] = world_xy(scan.position(px[n]));
      lo = lo.cwiseMin(q[n]);
      hi = hi.cwiseMax(q[n]);
    }
    // Only boxes that reach the cluster's extent can hold its pixels.
    near.clear();
    for (std::size_t t : eligible) {
      const Box& b = boxes[t];
      const double reach = std::hypot(b.half_l, b.half_w) + p.claim_margin_m;
      if ((b.centre - (b.centre.cwiseMax(lo).cwiseMin(hi))).norm() <= reach) near.push_back(t);
    }
    if (near.size() < 2) continue;
    std::vector<int> holder(px.size(), -1);
    std::vector<int> held(tracks.size(), 0);
    for (std::size_t n = 0; n < px.size(); ++n) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t t : near) {
        if (!boxes[t].contains(q[n], p.claim_margin_m)) continue;
        const double d = (q[n] - boxes[t].centre).norm();
        if (d < best) {
          best = d;
          holder[n] = static_cast<int>(t);
        }
      }
      if (holder[n] >= 0) ++held[static_cast<std::size_t>(holder[n])];
    }
    std::vector<std::size_t> sharers;
    for (std::size_t t : near) {
      const double need = std::max(static_cast<double>(p.min_cluster_pixels),
                                   p.split_min_share * static_cast<double>(tracks[t].last_pixels));
      if (held[t] >= need) sharers.push_back(t);
    }
    if (sharers.size() < 2) continue;
    std::vector<std::vector<std::uint32_t>> parts(sharers.size());
    for (std::size_t n = 0; n < px.size(); ++n) {
      std::size_t part = 0;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t s = 0; s < sharers.size(); ++s) {
        const double d = static_cast<int>(sharers[s]) == holder[n] ? -1.0 : boxes[sharers[s]].distance(q[n]);
        if (d < best) {
          best = d;
          part = s;
        }
      }
      parts[part].push_back(px[n]);
    }
    const ClusterEstimate whole = est.clusters[c];
    for (std::size_t s = 0; s < parts.size(); ++s) {
      if (parts[s].empty()) continue;
      const bool first = s == 0;
      const std::size_t slot = first ? c : est.clusters.size();
      if (!first) {
        est.clusters.push_back(whole);
        est.clusters.back().id = static_cast<std::int32_t>(slot + 1);
        cluster_pixels.emplace_back();
      }
      ClusterEstimate& ce = est.clusters[slot];
      ce.num_pixels = static_cast<int>(parts[s].size());
      ce.centroid_m = Eigen::Vector3d::Zero();
      for (std::uint32_t i : parts[s]) {
        ce.centroid_m += scan.position(i);
        est.labels[i] = static_cast<std::int32_t>(slot + 1);
      }
      ce.centroid_m /= static_cast<double>(parts[s].size());
      cluster_pixels[slot] = std::move(parts[s]);
    }
  }
}

// One pixel's Doppler row in the tracker's world: y = e . v + omega * e . (z x (o - c)).
struct Row {
  Eigen::Vector2d e;  // horizontal part of the unit beam direction
  Eigen::Vector2d o;  // beam origin
  double y = 0.0;     // ego-compensated Doppler: e . (velocity of the point)
  double residual = 0.0;
};

double predicted(const Row& r, const Vec5& x) {
  const Eigen::Vector2d d = r.o - x.head<2>();
  return r.e.dot(x.segment<2>(2)) + x(4) * (r.e.y() * d.x() - r.e.x() * d.y());
}

// A group of pixels measured as one object this frame.
struct Group {
  std::vector<std::uint32_t> pixels;
  std::vector<std::int32_t> clusters;  // labels merged into it
  std::vector<std::int32_t> absorbed;  // labels merged into its label but not measured
  int claimed = 0;
  std::vector<std::uint32_t> labelled;  // static pixels that take its label, not measured
};

// Grows a region from seeds over the range image (see TrackerParams::grow_reach_m): a
// neighbour not yet taken (taken holds 1 for invalid pixels too), in the same column group,
// whose range continues the pixel it is reached from and that joins(i) accepts, is taken and
// appended to grown. inner[c]: columns c - 1 and c + 1 exist and share c's column group.
template <class Joins>
void grow_region(const Scan& scan, const std::vector<int>& column_group, const std::vector<std::uint8_t>& inner,
                 const std::vector<std::uint32_t>& seeds, const TrackerParams& p, const Joins& joins,
                 std::vector<std::uint8_t>& taken, std::vector<std::uint32_t>& stack,
                 std::vector<std::uint32_t>& grown) {
  const auto cols = static_cast<std::size_t>(scan.cols);
  stack.assign(seeds.begin(), seeds.end());
  while (!stack.empty()) {
    const std::uint32_t q = stack.back();
    stack.pop_back();
    const int r = static_cast<int>(q / static_cast<std::uint32_t>(scan.cols));
    const int c = static_cast<int>(q % static_cast<std::uint32_t>(scan.cols));
    // Most seeds lie inside their object: every neighbour taken.
    if (r > 0 && r + 1 < scan.rows && inner[static_cast<std::size_t>(c)]) {
      const std::uint8_t* above = &taken[q - cols - 1];
      const std::uint8_t* here = &taken[q - 1];
      const std::uint8_t* below = &taken[q + cols - 1];
      if ((above[0] & above[1] & above[2] & here[0] & here[2] & below[0] & below[1] & below[2]) != 0) continue;
    }
    const double rq = scan.range_m[q];
    for_each_neighbour(scan, column_group, r, c, [&](std::size_t n, int, int) {
      if (taken[n]) return;
      const double rn = scan.range_m[n];
      if (std::abs(rn - rq) >= std::max(p.grow_range_gap_m, p.grow_range_gap_fraction * std::min(rn, rq)) || !joins(n))
        return;
      taken[n] = 1;
      grown.push_back(static_cast<std::uint32_t>(n));
      stack.push_back(static_cast<std::uint32_t>(n));
    });
  }
}
}  // namespace

ObjectTracker::ObjectTracker(const TrackerParams& params) : params_(params) { params_.validate(); }

void ObjectTracker::reset() {
  tracks_.clear();
  has_pose_ = false;
  yaw_ = 0.0;
  position_.setZero();
  last_ego_velocity_.setZero();
  last_ego_yaw_rate_ = 0.0;
  background_range_m_.clear();
  background_frames_ = 0;
}

void ObjectTracker::update(const Scan& scan, MotionEstimate& est) {
  const TrackerParams& p = params_;
  if (!est.ok() || !est.ego.valid) {  // nothing to compensate the Doppler with: start over
    reset();
    return;
  }
  const Eigen::Vector3d V = est.ego.velocity_mps;
  const double w_ego = est.ego_yaw_rate_estimated ? est.ego_angular_velocity_rps.z() : 0.0;
  double dt = 0.0;
  if (has_pose_) {
    dt = scan.stamp_s - last_stamp_s_;
    if (!(dt > 0.0) || dt > p.max_gap_s) reset();
  }
  if (has_pose_ && dt > 0.0) {
    // Midpoint rule on the mean of the two frames' twists.
    const double w_mean = 0.5 * (w_ego + last_ego_yaw_rate_);
    const Eigen::Vector2d v_mean = 0.5 * (V.head<2>() + last_ego_velocity_.head<2>());
    position_ += rotation(yaw_ + 0.5 * w_mean * dt) * v_mean * dt;
    yaw_ += w_mean * dt;
    for (Track& t : tracks_) predict(t, dt, p);
  } else {
    dt = 0.0;
  }
  // The background is the farthest range per pixel since the rig stopped; it starts again
  // whenever the rig moves (or the scan's shape changes).
  if ((!est.ego_standing && background_frames_ > 0) || background_range_m_.size() != scan.size()) {
    background_range_m_.assign(scan.size(), 0.0f);
    background_frames_ = 0;
  }
  const bool background_ready = p.background_min_frames > 0 && background_frames_ >= p.background_min_frames;
  // Nearer than the farthest range its 3 x 3 neighbourhood has seen (by the margin): something
  // has come into space the beams saw empty. The neighbourhood's least such range keeps the
  // edge of a static body, whose pixels see it in one frame and what lies behind in the next,
  // out of it.
  auto foreground = [&](std::size_t i) {
    const int r0 = static_cast<int>(i / static_cast<std::size_t>(scan.cols));
    const int c0 = static_cast<int>(i % static_cast<std::size_t>(scan.cols));
    float far = std::numeric_limits<float>::infinity();
    for (int r = std::max(r0 - 1, 0); r <= std::min(r0 + 1, scan.rows - 1); ++r) {
      for (int c = std::max(c0 - 1, 0); c <= std::min(c0 + 1, scan.cols - 1); ++c)
        far = std::min(far, background_range_m_[scan.index(r, c)]);
    }
    return static_cast<double>(scan.range_m[i]) < static_cast<double>(far) - p.background_margin_m;
  };
  has_pose_ = true;
  last_stamp_s_ = scan.stamp_s;
  last_ego_velocity_ = V;
  last_ego_yaw_rate_ = w_ego;

  const Eigen::Matrix2d R = rotation(yaw_);
  const Eigen::Vector3d omega(0.0, 0.0, w_ego);
  const std::vector<Eigen::Vector3d> col_origin = column_origins(scan);
  // The edge of the view: the top and bottom rows and each head's first and last column. An
  // object's outline that runs there is cut by the view, not by the body. Per column, the head
  // whose edge it is (-1 inside a head).
  std::vector<int> edge_head(static_cast<std::size_t>(scan.cols), -1);
  for (std::size_t h = 0; h < scan.heads.size(); ++h) {
    edge_head[static_cast<std::size_t>(scan.heads[h].col_begin)] = static_cast<int>(h);
    edge_head[static_cast<std::size_t>(scan.heads[h].col_end - 1)] = static_cast<int>(h);
  }
  struct Cut {
    Eigen::Vector2d direction;
    Eigen::Vector2d at;  // the edge pixel, world plane
  };
  // Where the view cuts at pixel i (world point `at`), if it is on the edge: away from the
  // head's axis at a column edge, towards the sensor at the bottom row (row 0 is the top; what
  // lies lower and nearer is unseen), away from it at the top row. A corner cuts both ways.
  auto add_cuts = [&](std::uint32_t i, const Eigen::Vector2d& at, std::vector<Cut>& cuts) {
    const int c = static_cast<int>(i % static_cast<std::uint32_t>(scan.cols));
    const int r = static_cast<int>(i / static_cast<std::uint32_t>(scan.cols));
    const int head = edge_head[static_cast<std::size_t>(c)];
    if (head < 0 && r != 0 && r != scan.rows - 1) return;
    const Eigen::Vector3d ray = scan.position(i) - col_origin[static_cast<std::size_t>(c)];
    const Eigen::Vector2d d = (R * ray.head<2>()).normalized();
    if (head >= 0) {
      const Eigen::Vector2d axis = R * scan.heads[static_cast<std::size_t>(head)].T_rig_head.linear().col(0).head<2>();
      const Eigen::Vector2d n(-d.y(), d.x());
      cuts.push_back({n.dot(axis) > 0.0 ? Eigen::Vector2d(-n) : n, at});
    }
    if (r == scan.rows - 1) cuts.push_back({-d, at});
    if (r == 0) cuts.push_back({d, at});
  };
  auto world_xy = [&](const Eigen::Vector3d& q) -> Eigen::Vector2d {
    return R * q.head<2>() + position_;
  };
  auto row_of = [&](std::uint32_t i) {
    const auto c = static_cast<std::size_t>(i % static_cast<std::uint32_t>(scan.cols));
    const Eigen::Vector3d o = col_origin[c];
    const Eigen::Vector3d e = (scan.position(i) - o).normalized();
    Row r;
    r.e = R * e.head<2>();
    r.o = world_xy(o);
    r.y = scan.radial_velocity_mps[i] + e.dot(V + omega.cross(o));
    return r;
  };

  // Pixels of each cluster.
  std::vector<std::vector<std::uint32_t>> cluster_pixels(est.clusters.size());
  for (std::size_t i = 0; i < est.labels.size(); ++i) {
    const std::int32_t l = est.labels[i];
    if (l >= 1)
      cluster_pixels[static_cast<std::size_t>(l - 1)].push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<Box> boxes(tracks_.size());
  for (std::size_t t = 0; t < tracks_.size(); ++t) boxes[t] = box_of(tracks_[t]);
  split_shared_clusters(scan, est, cluster_pixels, tracks_, boxes, p, world_xy);
  const std::size_t k = est.clusters.size();
  std::vector<Eigen::Vector2d> cluster_centroid(k);
  for (std::size_t c = 0; c < k; ++c) cluster_centroid[c] = world_xy(est.clusters[c].centroid_m);

  // Association: each cluster joins the track whose predicted box (grown by the gate) holds
  // its centroid, whose predicted motion explains its Doppler (median deviation), and that
  // lies nearest to it (distance to the box, zero inside; then to its centre). A vehicle split
  // by the blind band or by an occluder thus stays one object. A small cluster inside a box
  // whose Doppler the track does not explain (a wheel, a swinging arm) is absorbed into the
  // object's label but not measured.
  std::vector<Group> groups(tracks_.size());
  std::vector<int> owner(k, -1);
  std::vector<int> absorbed(k, -1);
  auto doppler_deviation = [&](std::size_t c, const Track& tr) {
    const std::vector<std::uint32_t>& px = cluster_pixels[c];
    const std::size_t step = std::max<std::size_t>(1, px.size() / 256);
    std::vector<double> dev;
    dev.reserve(px.size() / step + 1);
    for (std::size_t n = 0; n < px.size(); n += step) {
      const Row r = row_of(px[n]);
      dev.push_back(std::abs(r.y - predicted(r, tr.x)));
    }
    return upper_median(dev);
  };
  for (std::size_t c = 0; c < k; ++c) {
    if (static_cast<int>(cluster_pixels[c].size()) < p.min_cluster_pixels) continue;
    double best = std::numeric_limits<double>::infinity();
    double best_absorb = best;
    for (std::size_t t = 0; t < tracks_.size(); ++t) {
      // The gate widens with the track's position uncertainty: a young track's tangential
      // velocity is hardly known.
      const double pos_var = tracks_[t].P.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff();
      const double gate = p.gate_m + 3.0 * std::sqrt(std::max(0.0, pos_var));
      if (!boxes[t].contains(cluster_centroid[c], gate)) continue;
      // A large cluster beside a small track (a car passing a walker) is nearer the walker's
      // centre than its own box's: the box distance decides, the centre only breaks ties.
      const double d = boxes[t].distance(cluster_centroid[c]) +
                       1e-3 * (cluster_centroid[c] - boxes[t].centre).norm();
      if (doppler_deviation(c, tracks_[t]) <= p.associate_doppler_tolerance_mps) {
        if (d < best) {
          best = d;
          owner[c] = static_cast<int>(t);
        }
      } else if (static_cast<int>(cluster_pixels[c].size()) <= p.absorb_max_pixels &&
                 tracks_[t].vehicle(p) &&
                 boxes[t].contains(cluster_centroid[c], p.claim_margin_m) && d < best_absorb) {
        best_absorb = d;
        absorbed[c] = static_cast<int>(t);
      }
    }
    if (owner[c] >= 0) absorbed[c] = -1;
  }
  // A track's nearest cluster always joins it; further ones only from inside its box grown by
  // claim_margin_m (walkers side by side move alike), a vehicle's by the gate (its far end may
  // not have been seen yet). The others start tracks.
  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    std::vector<std::size_t> mine;
    for (std::size_t c = 0; c < k; ++c) {
      if (owner[c] == static_cast<int>(t)) mine.push_back(c);
    }
    std::sort(mine.begin(), mine.end(), [&](std::size_t a, std::size_t b) {
      const double da = boxes[t].distance(cluster_centroid[a]);
      const double db = boxes[t].distance(cluster_centroid[b]);
      return da != db ? da < db : a < b;
    });
    const bool vehicle = tracks_[t].vehicle(p);
    const bool small = tracks_[t].small(p);
    for (std::size_t n = 0; n < mine.size(); ++n) {
      const std::size_t c = mine[n];
      // A walker's second cluster is a limb, much smaller than its body, or a piece of it inside
      // its box; one of comparable size beside the box is the walker next to it.
      const bool limb = !small || cluster_pixels[c].size() * 3 <= cluster_pixels[mine.front()].size();
      const double grow = vehicle ? p.gate_m : limb ? p.claim_margin_m : 0.0;
      if (n > 0 && !boxes[t].contains(cluster_centroid[c], grow)) {
        owner[c] = -1;
        continue;
      }
      groups[t].clusters.push_back(static_cast<std::int32_t>(c + 1));
      groups[t].pixels.insert(groups[t].pixels.end(), cluster_pixels[c].begin(), cluster_pixels[c].end());
    }
  }
  for (std::size_t c = 0; c < k; ++c) {
    if (owner[c] < 0 && absorbed[c] >= 0)
      groups[static_cast<std::size_t>(absorbed[c])].absorbed.push_back(static_cast<std::int32_t>(c + 1));
  }

  // Carrying tracks claim static pixels inside their predicted box that move as they do: the
  // part of an object inside the Doppler blind band.
  std::vector<std::size_t> carrying;
  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    if (tracks_[t].carries(p)) carrying.push_back(t);
  }
  // Besides, with the rig standing, static pixels that have come into space the beams saw empty
  // take the label of the first carrying track near them (background_label_m), unmeasured.
  if (!carrying.empty()) {
    // Each carrying box's reach, as half sides of an axis-aligned rectangle: a cheap first test.
    const double reach = std::max(p.claim_margin_m, background_ready ? p.background_label_m : 0.0);
    std::vector<Eigen::Vector2d> half_sides;
    for (std::size_t t : carrying) {
      const Box& b = boxes[t];
      const double l = b.half_l + reach;
      const double w = b.half_w + reach;
      half_sides.emplace_back(std::abs(b.u.x()) * l + std::abs(b.u.y()) * w, std::abs(b.u.y()) * l + std::abs(b.u.x()) * w);
    }
    for (std::size_t i = 0; i < est.labels.size(); ++i) {
      if (est.labels[i] != 0) continue;
      const Eigen::Vector3d q = scan.position(i);
      const Eigen::Vector2d qw = world_xy(q);
      int fg = background_ready ? -1 : 0;  // foreground: -1 not yet known, else 0 / 1
      std::int32_t near_fg = -1;
      bool taken = false;
      for (std::size_t n = 0; n < carrying.size(); ++n) {
        const std::size_t t = carrying[n];
        const Eigen::Vector2d off = (qw - boxes[t].centre).cwiseAbs();
        if (off.x() > half_sides[n].x() || off.y() > half_sides[n].y()) continue;
        const Track& tr = tracks_[t];
        if (q.z() < tr.z_min_m + p.claim_ground_clearance_m ||
            q.z() > tr.z_max_m + p.claim_margin_m)
          continue;
        if (fg != 0 && near_fg < 0 && boxes[t].contains(qw, p.background_label_m)) {
          if (fg < 0) fg = foreground(i) ? 1 : 0;
          if (fg > 0) near_fg = static_cast<std::int32_t>(t);
        }
        if (!boxes[t].contains(qw, p.claim_margin_m)) continue;
        const Row r = row_of(static_cast<std::uint32_t>(i));
        if (std::abs(r.y - predicted(r, tr.x)) > p.claim_doppler_tolerance_mps) continue;
        groups[t].pixels.push_back(static_cast<std::uint32_t>(i));
        ++groups[t].claimed;
        taken = true;
        break;
      }
      if (!taken && near_fg >= 0) groups[static_cast<std::size_t>(near_fg)].labelled.push_back(static_cast<std::uint32_t>(i));
    }
  }

  // Measurement update of every track that has pixels this frame.
  const double sensor_w = 1.0 / (p.doppler_sigma_mps * p.doppler_sigma_mps);
  auto measure = [&](Track& tr, const Group& whole, bool born) {
    // A walker's own pixels: those inside its predicted box, grown by claim_margin_m (the
    // walker beside it may share its cluster). Found pixels first, then claimed, as in whole.
    Group mine;
    if (tr.walker && !born) {
      const Box b = box_of(tr);
      const std::size_t found = whole.pixels.size() - static_cast<std::size_t>(whole.claimed);
      for (std::size_t n = 0; n < whole.pixels.size(); ++n) {
        if (!b.contains(world_xy(scan.position(whole.pixels[n])), p.claim_margin_m)) continue;
        mine.pixels.push_back(whole.pixels[n]);
        if (n >= found) ++mine.claimed;
      }
    }
    const Group& g = mine.pixels.empty() ? whole : mine;
    // Box: heading from the velocity once the object moves, extents in that frame, centre
    // anchored at the visible end when less than the whole length is seen.
    const Eigen::Vector2d v = tr.velocity();
    bool resize = born;
    if (v.norm() > 1.0) {
      const double heading = std::atan2(v.y(), v.x());
      // Extents measured along a heading that has since swung, beyond what the yaw rate
      // turned the body (a poor first velocity, corrected over a few frames), say nothing
      // about the box along the new one: measure them afresh.
      resize = resize || std::abs(std::remainder(heading - tr.extents_heading_rad, 2.0 * M_PI)) >
                             p.heading_reset_rad;
      tr.heading_rad = heading;
    }
    if (resize) tr.extents_heading_rad = tr.heading_rad;
    const Eigen::Vector2d u(std::cos(tr.heading_rad), std::sin(tr.heading_rad));
    const Eigen::Vector2d wv(-u.y(), u.x());
    // The box is measured on the pixels one scan found moving: claimed pixels are inside the
    // predicted box by construction and would let it grow over whatever stands next to it.
    // When the track claimed more than one scan found moving, what moved is a Doppler slice of
    // the object (the rest is in the blind band), not its visible outline: the box is then
    // left as predicted.
    const std::size_t found = g.pixels.size() - static_cast<std::size_t>(g.claimed);
    std::size_t own = born || static_cast<std::size_t>(g.claimed) <= found ? found : 0;
    // A small object wholly inside the band (a walker crossing the beams) is found by its claims
    // alone; they lie in its predicted box, which is tight, and give its centre (not its size).
    const bool small_track = tr.small(p);
    const bool centre_from_claims = !born && found == 0 && g.claimed > 0 && small_track;
    const std::size_t first = centre_from_claims ? found : 0;
    if (centre_from_claims) own = g.pixels.size();
    Eigen::Vector2d ref = Eigen::Vector2d::Zero();
    std::vector<Eigen::Vector2d> pts;
    pts.reserve(own);
    double zmin = std::numeric_limits<double>::infinity();
    double zmax = -zmin;
    std::vector<Cut> cuts;
    for (std::size_t n = first; n < own; ++n) {
      const Eigen::Vector3d q = scan.position(g.pixels[n]);
      pts.push_back(world_xy(q));
      add_cuts(g.pixels[n], pts.back(), cuts);
      ref += pts.back();
      zmin = std::min(zmin, q.z());
      zmax = std::max(zmax, q.z());
    }
    ref /= static_cast<double>(std::max<std::size_t>(own - first, 1));
    double a0 = 0.0, a1 = 0.0, b0 = 0.0, b1 = 0.0;
    for (const Eigen::Vector2d& q : pts) {
      const Eigen::Vector2d d = q - ref;
      a0 = std::min(a0, d.dot(u));
      a1 = std::max(a1, d.dot(u));
      b0 = std::min(b0, d.dot(wv));
      b1 = std::max(b1, d.dot(wv));
    }
    Eigen::Vector2d centre = tr.centre();
    if (own > first) {
      if (!centre_from_claims) {
        // A walker stays small (just under small_object_m: the limbs reach out of its box).
        const double walker_cap = std::nextafter(p.small_object_m, 0.0);
        const double cap_l = tr.walker ? walker_cap : p.max_length_m;
        const double cap_w = tr.walker ? walker_cap : p.max_width_m;
        tr.length_m = std::min(resize ? a1 - a0 : std::max(tr.length_m, a1 - a0), cap_l);
        tr.width_m = std::min(resize ? b1 - b0 : std::max(tr.width_m, b1 - b0), cap_w);
        tr.z_min_m = zmin;  // this frame's: the ground under an object changes at curbs
        // A walker inside the band shows only its swinging limbs: its top stays where it was.
        tr.z_max_m = small_track && !born ? std::max(zmax, tr.z_max_m) : zmax;
      }
      // Less than the whole size seen along an axis: the centre lies in [hi - size/2, lo +
      // size/2]. An end of the outline is the body's own where the sensor sees that face or
      // the silhouette, unless the view cuts it there (a car beside the ego, its rear beyond a
      // head's edge). Anchored at such an end; with none, the predicted centre, brought into
      // the interval, stands for the measurement.
      const Eigen::Vector2d s = position_ - ref;  // the sensor, relative to ref
      const Eigen::Vector2d pc = tr.centre() - ref;
      auto anchor = [&](const Eigen::Vector2d& axis, double lo, double hi, double size) {
        if (hi - lo >= size) return 0.5 * (lo + hi);
        // A cut counts at the end its pixel lies at (a seam between stitched heads runs
        // through an object that spans it, away from its ends).
        const double near_end = p.view_cut_end_m + 0.05 * (hi - lo);
        bool cut_lo = false, cut_hi = false;
        for (const Cut& cut : cuts) {
          const double along = (cut.at - ref).dot(axis);
          cut_lo = cut_lo || (cut.direction.dot(axis) < -p.view_cut_cosine && along <= lo + near_end);
          cut_hi = cut_hi || (cut.direction.dot(axis) > p.view_cut_cosine && along >= hi - near_end);
        }
        const double sensor = s.dot(axis);
        const bool lo_own = !cut_lo && sensor <= hi;
        const bool hi_own = !cut_hi && sensor >= lo;
        if (lo_own && hi_own) return 0.5 * (lo + hi);
        if (lo_own) return lo + 0.5 * size;
        if (hi_own) return hi - 0.5 * size;
        if (born) return 0.5 * (lo + hi);
        return std::clamp(pc.dot(axis), hi - 0.5 * size, lo + 0.5 * size);
      };
      if (tr.walker) {
        std::vector<double> cu, cw;
        cu.reserve(pts.size());
        cw.reserve(pts.size());
        for (const Eigen::Vector2d& q : pts) {
          cu.push_back((q - ref).dot(u));
          cw.push_back((q - ref).dot(wv));
        }
        centre = ref + upper_median(cu) * u + upper_median(cw) * wv;
      } else {
        centre = ref + anchor(u, a0, a1, tr.length_m) * u + anchor(wv, b0, b1, tr.width_m) * wv;
      }
    }
    if (born) {  // the velocity prior already holds this frame's Doppler
      tr.x.head<2>() = centre;
      return;
    }

    // Doppler rows, without the pixels that do not move with the body.
    std::vector<Row> rows;
    rows.reserve(g.pixels.size());
    for (std::uint32_t i : g.pixels) rows.push_back(row_of(i));
    std::vector<double> dev(rows.size());
    for (std::size_t n = 0; n < rows.size(); ++n) {
      rows[n].residual = rows[n].y - predicted(rows[n], tr.x);
      dev[n] = rows[n].residual;
    }
    const double med = upper_median(dev);
    for (double& d : dev) d = std::abs(d - med);
    const double cut = std::max(p.outlier_floor_mps, p.outlier_sigmas * 1.4826 * upper_median(dev));
    std::size_t used = 0;
    for (const Row& r : rows) used += std::abs(r.residual - med) <= cut ? 1 : 0;
    const bool small = tr.small(p);  // the box may just have been measured
    Mat5 info = Mat5::Zero();
    Vec5 grad = Vec5::Zero();
    const Vec5& x = tr.x;
    auto row_jacobian = [&](const Row& r) {
      const Eigen::Vector2d d = r.o - x.head<2>();
      Vec5 h;
      h << -x(4) * r.e.y(), x(4) * r.e.x(), r.e.x(), r.e.y(), r.e.y() * d.x() - r.e.x() * d.y();
      return h;
    };
    if (small) {
      // One row: the mean of the inlier rows. Its noise is the rows' spread over the square
      // root of their effective count, floored (the gait phase moves the mean).
      Vec5 h_mean = Vec5::Zero();
      double res_mean = 0.0;
      for (const Row& r : rows) {
        if (std::abs(r.residual - med) > cut) continue;
        h_mean += row_jacobian(r);
        res_mean += r.residual;
      }
      if (used > 0) {
        h_mean /= static_cast<double>(used);
        res_mean /= static_cast<double>(used);
        const double spread = std::max(p.doppler_sigma_mps, cut / p.outlier_sigmas);
        const double n_eff = static_cast<double>(std::min<std::size_t>(used, static_cast<std::size_t>(p.max_effective_rows)));
        const double sigma = std::max(p.small_doppler_floor_mps, spread / std::sqrt(n_eff));
        info = h_mean * h_mean.transpose() / (sigma * sigma);
        grad = h_mean * res_mean / (sigma * sigma);
      }
    } else {
      const double w =
          sensor_w * std::min(1.0, static_cast<double>(p.max_effective_rows) /
                                       static_cast<double>(std::max<std::size_t>(used, 1)));
      for (const Row& r : rows) {
        if (std::abs(r.residual - med) > cut) continue;
        const Vec5 h = row_jacobian(r);
        info.noalias() += w * h * h.transpose();
        grad += w * h * r.residual;
      }
    }
    // The box centre jumps when occlusion changes what is visible: Huber-weighted beyond 3
    // standard deviations of the innovation, so a jump does not drag velocity and yaw rate.
    const Eigen::Vector2d innovation =
        own > 0 ? Eigen::Vector2d(centre - x.head<2>()) : Eigen::Vector2d::Zero();
    const double pos_sigma = centre_from_claims ? p.claim_position_sigma_m
                             : small            ? p.small_position_sigma_m
                                                : p.position_sigma_m;
    const double pos_w_here = 1.0 / (pos_sigma * pos_sigma);
    const Eigen::Matrix2d S = tr.P.topLeftCorner<2, 2>() + Eigen::Matrix2d::Identity() / pos_w_here;
    const double mahalanobis = std::sqrt(innovation.dot(S.inverse() * innovation));
    const double pw = own > 0 ? pos_w_here * std::min(1.0, 3.0 / std::max(mahalanobis, 1e-12)) : 0.0;
    info.topLeftCorner<2, 2>() += pw * Eigen::Matrix2d::Identity();
    grad.head<2>() += pw * innovation;
    const Mat5 P_inv = tr.P.inverse();
    const Mat5 P_new = (P_inv + info).inverse();
    tr.x += P_new * grad;
    tr.x(4) = std::clamp(tr.x(4), -p.max_yaw_rate_rps, p.max_yaw_rate_rps);
    tr.P = 0.5 * (P_new + P_new.transpose());
  };

  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    Track& tr = tracks_[t];
    if (groups[t].pixels.empty()) {
      ++tr.misses;
    } else {
      measure(tr, groups[t], false);
      ++tr.hits;
      tr.last_pixels = static_cast<int>(groups[t].pixels.size()) - groups[t].claimed;
      tr.misses = 0;
    }
    if (tr.hits >= p.confirm_hits) tr.confirmed = true;
    if (!groups[t].pixels.empty())
      tr.small_hits = std::max(tr.length_m, tr.width_m) < p.small_object_m ? tr.small_hits + 1 : 0;
    const bool slow = tr.velocity().norm() < p.walker_max_speed_mps;
    tr.walker = slow && (tr.walker || (p.walker_hits > 0 && tr.small_hits >= p.walker_hits));
    tr.slow_frames = tr.velocity().norm() < p.carry_min_speed_mps ? tr.slow_frames + 1 : 0;
    // Turning once the yaw rate is resolved on a track of some age; still turning while it
    // stays above the minimum and turn_release_significance standard deviations (the box
    // centre of a near car jumps as its visible side changes, the position updates are then
    // down-weighted and the yaw rate's variance grows for a while, not its value).
    const double w = std::abs(tr.yaw_rate());
    const double w_sigma = std::sqrt(std::max(0.0, tr.P(4, 4)));
    tr.turning = w >= p.min_turn_rate_rps &&
                 (tr.turning ? w >= p.turn_release_significance * w_sigma
                             : tr.hits >= p.min_turn_hits && w >= p.turn_significance * w_sigma);
  }

  // New tracks from the clusters no track took.
  for (std::size_t c = 0; c < k; ++c) {
    const ClusterEstimate& ce = est.clusters[c];
    if (owner[c] >= 0 || absorbed[c] >= 0 ||
        static_cast<int>(cluster_pixels[c].size()) < p.min_cluster_pixels ||
        !ce.velocity.valid)
      continue;
    Track tr;
    tr.id = next_id_++;
    const Eigen::Vector2d v = R * ce.velocity.velocity_mps.head<2>();
    tr.x.segment<2>(2) = v;
    tr.heading_rad = v.norm() > 1.0 ? std::atan2(v.y(), v.x()) : 0.0;
    // The single-scan covariance, its unobservable direction capped, as the velocity prior.
    Eigen::Matrix2d cov = R * ce.velocity.covariance.topLeftCorner<2, 2>() * R.transpose();
    if (!cov.allFinite())
      cov = Eigen::Matrix2d::Identity() * p.max_initial_velocity_sigma_mps *
            p.max_initial_velocity_sigma_mps;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(0.5 * (cov + cov.transpose()));
    const double cap = p.max_initial_velocity_sigma_mps * p.max_initial_velocity_sigma_mps;
    const double floor = p.doppler_sigma_mps * p.doppler_sigma_mps;
    const Eigen::Vector2d ev = eig.eigenvalues().cwiseMax(floor).cwiseMin(cap);
    Group g;
    g.clusters.push_back(static_cast<std::int32_t>(c + 1));
    g.pixels = cluster_pixels[c];
    measure(tr, g, true);  // places the box
    // One scan measures v_app = v + omega z x (o - c): velocity and yaw rate are known only
    // along that line. The prior says so: omega ~ N(0, s0^2) and v = v_app - omega z x (o - c),
    // correlated from the start, so later positions move the estimate along the line instead
    // of fighting the Doppler.
    Eigen::Vector2d o_mean = Eigen::Vector2d::Zero();
    for (std::uint32_t i : g.pixels) o_mean += row_of(i).o;
    o_mean /= static_cast<double>(g.pixels.size());
    const Eigen::Vector2d d = o_mean - tr.centre();
    const Eigen::Vector2d sv(-d.y(), d.x());
    const double s0 = p.initial_yaw_rate_sigma_rps;
    tr.P = Mat5::Zero();
    tr.P.topLeftCorner<2, 2>() =
        Eigen::Matrix2d::Identity() * (p.position_sigma_m * p.position_sigma_m);
    tr.P.block<2, 2>(2, 2) = eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose() +
                             s0 * s0 * sv * sv.transpose();
    tr.P.block<2, 1>(2, 4) = -s0 * s0 * sv;
    tr.P.block<1, 2>(4, 2) = -s0 * s0 * sv.transpose();
    tr.P(4, 4) = s0 * s0;
    if (tr.small(p) && d.norm() > 0.0) {
      // A small object: its single-scan tangential velocity is not to be trusted (see
      // small_object_m). Prior: the radial part as measured, the tangential part unknown, the
      // yaw rate unrelated to either (a small object's Doppler does not see it).
      const Eigen::Vector2d radial = -d.normalized();
      const Eigen::Vector2d tangential(-radial.y(), radial.x());
      const double var_r = std::max(floor, radial.dot(cov * radial));
      const double st = p.small_initial_tangential_sigma_mps;
      tr.x.segment<2>(2) = radial.dot(v) * radial;
      tr.P.topLeftCorner<2, 2>() =
          Eigen::Matrix2d::Identity() * (p.small_position_sigma_m * p.small_position_sigma_m);
      tr.P.block<2, 2>(2, 2) = var_r * radial * radial.transpose() + st * st * tangential * tangential.transpose();
      tr.P.block<2, 1>(2, 4).setZero();
      tr.P.block<1, 2>(4, 2).setZero();
    }
    tr.hits = 1;
    tr.last_pixels = static_cast<int>(g.pixels.size());
    if (tr.hits >= p.confirm_hits) tr.confirmed = true;
    owner[c] = static_cast<int>(tracks_.size());
    tracks_.push_back(tr);
    groups.push_back(g);
  }

  // Rewrite the estimate: one label per tracked group, the others as they were; labels
  // renumbered by first pixel (row-major), as the pipeline numbers them.
  const std::size_t n_groups = groups.size();
  std::vector<std::int32_t> group_of_label(k + 1, -1);  // old label -> group
  for (std::size_t t = 0; t < n_groups; ++t) {
    for (std::int32_t l : groups[t].clusters)
      group_of_label[static_cast<std::size_t>(l)] = static_cast<std::int32_t>(t);
    for (std::int32_t l : groups[t].absorbed)
      group_of_label[static_cast<std::size_t>(l)] = static_cast<std::int32_t>(t);
  }
  // Growth into the blind band (grow_reach_m): each cluster by its single-scan velocity, then
  // each carrying track that found pixels by its updated state. A tracked cluster's growth
  // joins its group's labelled pixels, an untracked one's keeps its label.
  std::vector<std::pair<std::uint32_t, std::size_t>> grown_untracked;  // pixel, cluster
  if (p.grow_reach_m > 0.0) {
    const std::vector<int> column_group = scan.column_group_of();
    std::vector<std::uint8_t> inner(column_group.size(), 0);
    for (std::size_t c = 1; c + 1 < column_group.size(); ++c)
      inner[c] = column_group[c - 1] == column_group[c] && column_group[c + 1] == column_group[c] ? 1 : 0;
    std::vector<std::uint8_t> taken(est.labels.size(), 0);
    for (std::size_t i = 0; i < est.labels.size(); ++i) taken[i] = est.labels[i] != 0 || !scan.valid[i] ? 1 : 0;
    for (const Group& g : groups) {
      for (std::uint32_t i : g.pixels) taken[i] = 1;
      for (std::uint32_t i : g.labelled) taken[i] = 1;
    }
    std::vector<std::uint32_t> stack, grown;
    // Heights [z_lo, z_hi], world position inside, Doppler as the motion x gives it.
    auto moves_with = [&](std::size_t i, double z_lo, double z_hi, const auto& inside, const Vec5& x) {
      const Eigen::Vector3d q = scan.position(i);
      if (q.z() < z_lo || q.z() > z_hi || !inside(world_xy(q))) return false;
      const Row r = row_of(static_cast<std::uint32_t>(i));
      return std::abs(r.y - predicted(r, x)) <= p.claim_doppler_tolerance_mps;
    };
    for (std::size_t c = 0; c < k; ++c) {
      const ClusterEstimate& ce = est.clusters[c];
      if (!ce.velocity.valid) continue;
      Eigen::AlignedBox2d extent;
      double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
      for (std::uint32_t i : cluster_pixels[c]) {
        const Eigen::Vector3d q = scan.position(i);
        extent.extend(world_xy(q));
        z_lo = std::min(z_lo, q.z());
        z_hi = std::max(z_hi, q.z());
      }
      if (extent.sizes().maxCoeff() < p.small_object_m) z_lo += p.claim_ground_clearance_m;
      Eigen::AlignedBox2d reach(extent.min().array() - p.grow_reach_m, extent.max().array() + p.grow_reach_m);
      Vec5 x = Vec5::Zero();
      x.segment<2>(2) = R * ce.velocity.velocity_mps.head<2>();
      auto inside = [&](const Eigen::Vector2d& w) { return reach.contains(w); };
      grown.clear();
      grow_region(scan, column_group, inner, cluster_pixels[c], p,
                  [&](std::size_t i) { return moves_with(i, z_lo, z_hi + p.claim_margin_m, inside, x); }, taken,
                  stack, grown);
      const std::int32_t g = group_of_label[c + 1];
      for (std::uint32_t i : grown) {
        if (g >= 0)
          groups[static_cast<std::size_t>(g)].labelled.push_back(i);
        else
          grown_untracked.emplace_back(i, c);
      }
    }
    for (std::size_t t = 0; t < tracks_.size(); ++t) {
      const Track& tr = tracks_[t];
      Group& g = groups[t];
      if (!tr.carries(p) || g.pixels.size() == static_cast<std::size_t>(g.claimed)) continue;
      const Box box = box_of(tr);
      const double z_lo = tr.z_min_m + (tr.small(p) ? p.claim_ground_clearance_m : 0.0);
      auto inside = [&](const Eigen::Vector2d& w) { return box.contains(w, p.grow_reach_m); };
      grown.clear();
      grow_region(scan, column_group, inner, g.pixels, p,
                  [&](std::size_t i) { return moves_with(i, z_lo, tr.z_max_m + p.claim_margin_m, inside, tr.x); },
                  taken, stack, grown);
      g.labelled.insert(g.labelled.end(), grown.begin(), grown.end());
    }
  }
  std::vector<std::int32_t> claimed_by(est.labels.size(), -1);
  for (const auto& [i, c] : grown_untracked) claimed_by[i] = static_cast<std::int32_t>(n_groups + c);
  for (std::size_t t = 0; t < n_groups; ++t) {
    for (std::uint32_t i : groups[t].labelled) claimed_by[i] = static_cast<std::int32_t>(t);
    for (std::size_t n = groups[t].pixels.size() - static_cast<std::size_t>(groups[t].claimed);
         n < groups[t].pixels.size(); ++n) {
      claimed_by[groups[t].pixels[n]] = static_cast<std::int32_t>(t);
    }
  }
  // Key of a pixel's new object: group t -> t, untracked old label l -> n_groups + l - 1.
  std::vector<std::int32_t> new_label(n_groups + k, 0);
  std::vector<std::int32_t> key_of_new(1, -1);
  std::int32_t next = 0;
  int moved_to_moving = 0;
  for (std::size_t i = 0; i < est.labels.size(); ++i) {
    std::int32_t key = -1;
    const std::int32_t l = est.labels[i];
    if (l >= 1) {
      const std::int32_t g = group_of_label[static_cast<std::size_t>(l)];
      key = g >= 0 ? g : static_cast<std::int32_t>(n_groups) + l - 1;
    } else if (claimed_by[i] >= 0) {
      key = claimed_by[i];
      ++moved_to_moving;
    }
    if (key < 0) continue;
    std::int32_t& nl = new_label[static_cast<std::size_t>(key)];
    if (nl == 0) {
      nl = ++next;
      key_of_new.push_back(key);
    }
    est.labels[i] = nl;
  }
  est.num_static_pixels -= moved_to_moving;

  std::vector<ClusterEstimate> out(static_cast<std::size_t>(next));
  std::vector<int> count(static_cast<std::size_t>(next), 0);
  for (std::size_t i = 0; i < est.labels.size(); ++i) {
    const std::int32_t l = est.labels[i];
    if (l < 1) continue;
    ClusterEstimate& ce = out[static_cast<std::size_t>(l - 1)];
    ce.centroid_m += scan.position(i);
    ++count[static_cast<std::size_t>(l - 1)];
  }
  const Eigen::Matrix2d Rt = R.transpose();
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
    const Track& tr = tracks_[static_cast<std::size_t>(key)];
    const Group& g = groups[static_cast<std::size_t>(key)];
    ce.scan_velocity_mps =
        g.clusters.empty()
            ? Eigen::Vector3d::Constant(kNaN)
            : est.clusters[static_cast<std::size_t>(g.clusters.front() - 1)].velocity.velocity_mps;
    ce.track_id = tr.id;
    ce.track_hits = tr.hits;
    ce.carried_pixels = g.claimed + static_cast<int>(g.labelled.size());
    ce.yaw_rate_rps = tr.yaw_rate();
    ce.centre_m = Eigen::Vector3d::Zero();
    ce.centre_m.head<2>() = Rt * (tr.centre() - position_);
    ce.centre_m.z() = 0.5 * (tr.z_min_m + tr.z_max_m);
    VelocityEstimate& v = ce.velocity;
    v = g.clusters.empty()
            ? VelocityEstimate{}
            : est.clusters[static_cast<std::size_t>(g.clusters.front() - 1)].velocity;
    // The yaw rate is seen only through the track's path (a rigid body turning about a fixed
    // point has a time-invariant Doppler field), and each rad/s of it moves the centre's
    // velocity by |o - c| m/s. Unless the turn is resolved, report the velocity the Doppler
    // measures, v + omega z x (o - c), with no turn.
    Eigen::Vector2d o_mean = Eigen::Vector2d::Zero();
    for (std::uint32_t i : g.pixels) o_mean += row_of(i).o;
    o_mean /= static_cast<double>(std::max<std::size_t>(g.pixels.size(), 1));
    const Eigen::Vector2d d = o_mean - tr.centre();
    Eigen::Matrix<double, 2, 3> J;
    J << 1.0, 0.0, -d.y(), 0.0, 1.0, d.x();
    Eigen::Vector2d vel = tr.velocity();
    Eigen::Matrix2d cov = tr.P.block<2, 2>(2, 2);
    // A small object's Doppler pins only its radial velocity, the same for v and for
    // v + omega z x (o - c): the track's own velocity is the better guess either way.
    if (!tr.turning && tr.small(p)) {
      ce.yaw_rate_rps = 0.0;
    } else if (!tr.turning) {
      vel = J * tr.x.segment<3>(2);
      cov = J * tr.P.block<3, 3>(2, 2) * J.transpose();
      ce.yaw_rate_rps = 0.0;
    }
    v.velocity_mps = Eigen::Vector3d::Zero();
    v.velocity_mps.head<2>() = Rt * vel;
    v.covariance = Eigen::Matrix3d::Zero();
    v.covariance.topLeftCorner<2, 2>() = Rt * cov * R;
    v.num_points = ce.num_pixels;
    v.valid = true;
  }
  est.clusters = std::move(out);

  if (est.ego_standing && p.background_min_frames > 0) {  // no return: the whole range empty
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const float range = scan.valid[i] ? scan.range_m[i] : std::numeric_limits<float>::infinity();
      background_range_m_[i] = std::max(background_range_m_[i], range);
    }
    ++background_frames_;
  }

  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const Track& t) { return t.misses > p.max_misses; }),
                tracks_.end());
}

}  // namespace fmcw::core
