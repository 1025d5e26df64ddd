#include "association.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "../pixel_lists.hpp"
#include "ctrv.hpp"
#include "fmcw/core/median.hpp"
#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core::tracking {

std::vector<std::vector<std::uint32_t>> pixels_of_clusters(const MotionEstimate& est) {
  std::vector<std::uint32_t> labelled;
  list_pixels(est.labels.size(), [&](std::size_t i) { return est.labels[i] >= 1; }, labelled);
  std::vector<std::size_t> count(est.clusters.size(), 0);
  for (const std::uint32_t i : labelled) ++count[static_cast<std::size_t>(est.labels[i] - 1)];
  std::vector<std::vector<std::uint32_t>> cluster_pixels(est.clusters.size());
  for (std::size_t c = 0; c < count.size(); ++c) cluster_pixels[c].reserve(count[c]);
  for (const std::uint32_t i : labelled) cluster_pixels[static_cast<std::size_t>(est.labels[i] - 1)].push_back(i);
  return cluster_pixels;
}

namespace {

// The track's motion explains the pixels' Doppler: their doppler_deviation is within
// association.doppler_tolerance_mps.
bool explains_doppler(const Frame& frame, const std::vector<std::uint32_t>& px, const Track& track,
                      const TrackerParams& p) {
  return doppler_deviation(frame, px, track) <= p.association.doppler_tolerance_mps;
}

// A cluster's pixels in the world plane, with their extent.
struct WorldPixels {
  std::vector<Eigen::Vector2d> q;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
};

WorldPixels world_pixels(const Frame& frame, const std::vector<std::uint32_t>& px) {
  WorldPixels w;
  w.q.resize(px.size());
  for (std::size_t n = 0; n < px.size(); ++n) {
    w.q[n] = frame.world_xy(frame.scan.position(px[n]));
    w.lo = w.lo.cwiseMin(w.q[n]);
    w.hi = w.hi.cwiseMax(w.q[n]);
  }
  return w;
}

// Whether box b (grown by claim_margin_m) can hold any pixel within the extent.
bool reaches(const Box& b, const WorldPixels& w, const TrackerParams& p) {
  const double reach = std::hypot(b.half_l, b.half_w) + p.claims.claim_margin_m;
  return (b.centre - (b.centre.cwiseMax(w.lo).cwiseMin(w.hi))).norm() <= reach;
}

// The pixels of a cluster a track must hold to keep its part of it: split_min_share of those it
// had last frame, and at least `least`.
double split_need(const Track& t, const TrackerParams& p, int least) {
  return std::max(static_cast<double>(least),
                  p.association.split_min_share * static_cast<double>(t.last_pixels));
}

// The pixels' own single-scan fit (planar, robust) on their ego-compensated Doppler.
VelocityEstimate planar_fit(const Frame& frame, const std::vector<std::uint32_t>& px,
                            const TrackerParams& p) {
  VelocityRows rows;
  rows.directions.reserve(px.size());
  rows.targets_mps.reserve(px.size());
  for (const std::uint32_t i : px) {
    rows.directions.push_back(frame.beams.e(i));
    rows.targets_mps.push_back(frame.row_of(i).y);
  }
  return solve_velocity_planar_robust(rows, p.measurement.doppler_sigma_mps);
}

// Pixels `part` become cluster `slot` (label slot + 1); a new slot (est.clusters.size()) starts
// as a copy of `whole`.
void assign_part(const Frame& frame, MotionEstimate& est, std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                 std::size_t slot, const ClusterEstimate& whole, std::vector<std::uint32_t> part) {
  if (slot == est.clusters.size()) {
    est.clusters.push_back(whole);
    est.clusters.back().id = static_cast<std::int32_t>(slot + 1);
    cluster_pixels.emplace_back();
  }
  ClusterEstimate& ce = est.clusters[slot];
  ce.num_pixels = static_cast<int>(part.size());
  ce.centroid_m = Eigen::Vector3d::Zero();
  for (const std::uint32_t i : part) {
    ce.centroid_m += frame.scan.position(i);
    est.labels[i] = static_cast<std::int32_t>(slot + 1);
  }
  ce.centroid_m /= static_cast<double>(part.size());
  cluster_pixels[slot] = std::move(part);
}

// Cluster c keeps `kept`; `rest` becomes a new cluster with velocity `fit`. Returns its slot.
std::size_t split_off(const Frame& frame, MotionEstimate& est,
                      std::vector<std::vector<std::uint32_t>>& cluster_pixels, std::size_t c,
                      std::vector<std::uint32_t> kept, std::vector<std::uint32_t> rest,
                      const VelocityEstimate& fit) {
  const ClusterEstimate whole = est.clusters[c];
  const std::size_t slot = est.clusters.size();
  assign_part(frame, est, cluster_pixels, slot, whole, std::move(rest));
  est.clusters[slot].velocity = fit;
  assign_part(frame, est, cluster_pixels, c, whole, std::move(kept));
  return slot;
}

// Whether track t's box (grown by claims.claim_margin_m) holds the centre of another track of
// `near`, or another's holds t's.
bool overlaps_another(std::size_t t, const std::vector<std::size_t>& near, const std::vector<Box>& boxes, const TrackerParams& p) {
  const double grow = p.claims.claim_margin_m;
  for (const std::size_t u : near) {
    if (u != t && (boxes[u].contains(boxes[t].centre, grow) || boxes[t].contains(boxes[u].centre, grow))) return true;
  }
  return false;
}

// The tracks (of `near`) whose boxes hold a share of the cluster's pixels q: per pixel its
// holder (-1: none), and the sharers.
std::vector<std::size_t> sharers_of(const Frame& frame, const std::vector<Eigen::Vector2d>& q, const std::vector<std::size_t>& near,
                                    const std::vector<Track>& tracks, const std::vector<Box>& boxes, const TrackerParams& p,
                                    std::vector<int>& holder) {
  holder.assign(q.size(), -1);
  std::vector<int> held(tracks.size(), 0);
  for (std::size_t n = 0; n < q.size(); ++n) {
    double best = std::numeric_limits<double>::infinity();
    for (const std::size_t t : near) {
      if (!boxes[t].contains(q[n], p.claims.claim_margin_m)) continue;
      const double d = (q[n] - boxes[t].centre).norm();
      if (d < best) {
        best = d;
        holder[n] = static_cast<int>(t);
      }
    }
    if (holder[n] >= 0) ++held[static_cast<std::size_t>(holder[n])];
  }
  std::vector<std::size_t> sharers;
  for (const std::size_t t : near) {
    // At least as many pixels as a track at its range needs (min_pixels_at: a far cyclist shows
    // 4-8 beside a car).
    const double range = (tracks[t].centre() - frame.position).norm();
    if (!(held[t] >= split_need(tracks[t], p, p.association.min_pixels_at(range)))) continue;
    // A part that only a far track's smaller minimum keeps must lie apart from the others: two
    // tracks each with its centre in the other's box are one far object seen twice (a car 110 m
    // away first seen in two pieces), not two bodies.
    if (held[t] < split_need(tracks[t], p, p.association.min_cluster_pixels) && overlaps_another(t, near, boxes, p)) continue;
    sharers.push_back(t);
  }
  return sharers;
}

// Splits cluster c's pixels between the sharers: the first part keeps the label.
void split_cluster(const Frame& frame, MotionEstimate& est, std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                   std::size_t c, const std::vector<Eigen::Vector2d>& q, const std::vector<int>& holder,
                   const std::vector<std::size_t>& sharers, const std::vector<Box>& boxes) {
  const std::vector<std::uint32_t>& px = cluster_pixels[c];
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
    assign_part(frame, est, cluster_pixels, s == 0 ? c : est.clusters.size(), whole, std::move(parts[s]));
  }
}

}  // namespace

void split_shared_clusters(const Frame& frame, MotionEstimate& est, std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                           const std::vector<Track>& tracks, const std::vector<Box>& boxes, const TrackerParams& p) {
  std::vector<std::size_t> eligible;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    if (tracks[t].confirmed && tracks[t].misses == 0) eligible.push_back(t);
  }
  if (eligible.size() < 2) return;
  const std::size_t k0 = est.clusters.size();
  std::vector<std::size_t> near;
  std::vector<int> holder;
  for (std::size_t c = 0; c < k0; ++c) {
    const std::vector<std::uint32_t>& px = cluster_pixels[c];
    if (static_cast<int>(px.size()) < 2 * p.association.min_pixels_at(est.clusters[c].centroid_m.head<2>().norm())) continue;
    const WorldPixels w = world_pixels(frame, px);
    // Only boxes that reach the cluster's extent can hold its pixels.
    near.clear();
    for (const std::size_t t : eligible) {
      if (reaches(boxes[t], w, p)) near.push_back(t);
    }
    if (near.size() < 2) continue;
    const std::vector<std::size_t> sharers = sharers_of(frame, w.q, near, tracks, boxes, p, holder);
    if (sharers.size() < 2) continue;
    split_cluster(frame, est, cluster_pixels, c, w.q, holder, sharers, boxes);
  }
}

void split_by_doppler(const Frame& frame, MotionEstimate& est, std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                      const std::vector<Track>& tracks, const std::vector<Box>& boxes, const TrackerParams& p) {
  const TrackerParams::Association& pa = p.association;
  if (!(pa.doppler_split_rms_mps > 0.0)) return;
  const std::size_t k0 = est.clusters.size();
  std::vector<std::uint32_t> explained, rest;
  for (std::size_t c = 0; c < k0; ++c) {
    const std::vector<std::uint32_t>& px = cluster_pixels[c];
    // Only a cluster that no one rigid motion explains.
    if (static_cast<int>(px.size()) < 2 * pa.min_cluster_pixels || !(est.clusters[c].velocity.residual_rms_mps > pa.doppler_split_rms_mps)) {
      continue;
    }
    const WorldPixels w = world_pixels(frame, px);
    // The track that explains the most of the cluster's pixels in its box, among those that do
    // not explain the cluster as a whole and explain at least split_min_share of their last
    // pixels.
    int best = -1;
    std::vector<std::uint32_t> best_explained, best_rest;
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      const Track& tr = tracks[t];
      if (!tr.confirmed || tr.misses != 0) continue;
      if (!reaches(boxes[t], w, p)) continue;                                       // no pixel in its box
      if (explains_doppler(frame, px, tr, p)) continue;  // the whole cluster is its
      explained.clear();
      rest.clear();
      for (std::size_t n = 0; n < px.size(); ++n) {
        const Row r = frame.row_of(px[n]);
        const bool mine = std::abs(r.y - predicted(r, tr.x)) <= pa.doppler_tolerance_mps &&
                          boxes[t].contains(w.q[n], p.claims.claim_margin_m);
        (mine ? explained : rest).push_back(px[n]);
      }
      if (static_cast<double>(explained.size()) < split_need(tr, p, pa.min_cluster_pixels) || static_cast<int>(rest.size()) < pa.min_cluster_pixels) continue;
      if (best < 0 || explained.size() > best_explained.size()) {
        best = static_cast<int>(t);
        best_explained.swap(explained);
        best_rest.swap(rest);
      }
    }
    if (best < 0) continue;
    // The rest, fitted on its own, must be one rigid motion too (explained as a track's motion
    // must explain a cluster): else no split.
    const VelocityEstimate rest_fit = planar_fit(frame, best_rest, p);
    if (!(rest_fit.residual_rms_mps <= pa.doppler_tolerance_mps)) continue;
    // The track's part keeps the label (the association finds its Doppler explained); the rest
    // is a cluster of its own, with that fit.
    split_off(frame, est, cluster_pixels, c, std::move(best_explained), std::move(best_rest),
              rest_fit);
  }
}

std::vector<int> split_off_companions(const Frame& frame, MotionEstimate& est,
                                      std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                                      const std::vector<Track>& tracks,
                                      const std::vector<Box>& boxes, const TrackerParams& p) {
  std::vector<int> companion_of(est.clusters.size(), -1);
  if (!p.small.split_companions || !(p.fragments.small_host_ratio > 0.0)) return companion_of;
  const std::size_t k0 = est.clusters.size();
  std::vector<std::uint32_t> mine, rest;
  for (std::size_t c = 0; c < k0; ++c) {
    const std::vector<std::uint32_t>& px = cluster_pixels[c];
    const int least = p.association.min_pixels_at(est.clusters[c].centroid_m.head<2>().norm());
    if (static_cast<int>(px.size()) < 2 * least) continue;
    const WorldPixels w = world_pixels(frame, px);
    // The walker whose box holds the most of the cluster's pixels, with enough outside it.
    int best = -1;
    std::vector<std::uint32_t> best_mine, best_rest;
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      const Track& tr = tracks[t];
      if (!tr.walker || !tr.confirmed || tr.misses != 0 || !reaches(boxes[t], w, p)) continue;
      mine.clear();
      rest.clear();
      for (std::size_t n = 0; n < px.size(); ++n) {
        (boxes[t].contains(w.q[n], p.claims.claim_margin_m) ? mine : rest).push_back(px[n]);
      }
      const auto n_mine = static_cast<double>(mine.size());
      const auto n_rest = static_cast<double>(rest.size());
      if (n_mine < least || n_rest < least || n_rest * p.fragments.small_host_ratio <= n_mine) {
        continue;
      }
      if (best < 0 || mine.size() > best_mine.size()) {
        best = static_cast<int>(t);
        best_mine.swap(mine);
        best_rest.swap(rest);
      }
    }
    if (best < 0) continue;
    const VelocityEstimate rest_fit = planar_fit(frame, best_rest, p);
    const std::size_t slot = split_off(frame, est, cluster_pixels, c, std::move(best_mine),
                                       std::move(best_rest), rest_fit);
    companion_of.resize(est.clusters.size(), -1);
    companion_of[slot] = best;
  }
  return companion_of;
}

double doppler_deviation(const Frame& frame, const std::vector<std::uint32_t>& px, const Track& track) {
  const std::size_t step = std::max<std::size_t>(1, px.size() / 256);
  std::vector<double> dev;
  dev.reserve(px.size() / step + 1);
  for (std::size_t n = 0; n < px.size(); n += step) {
    const Row r = frame.row_of(px[n]);
    dev.push_back(std::abs(r.y - predicted(r, track.x)));
  }
  return upper_median(dev);
}

namespace {

// The track whose box, grown by claim_margin_m and extra_margin_m, holds the point, the nearest
// by box distance (-1: none); only confirmed vehicles when vehicles_only.
int holding_box(const Eigen::Vector2d& q, const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                const TrackerParams& p, bool vehicles_only, std::size_t skip = std::numeric_limits<std::size_t>::max(),
                double extra_margin_m = 0.0) {
  // Tracks without a box yet are not holders.
  return nearest_holding_box(q, boxes, p.claims.claim_margin_m + extra_margin_m, [&](std::size_t t) {
    return t != skip && (!vehicles_only || (tracks[t].confirmed && tracks[t].vehicle(p)));
  });
}

// The host moves faster than a walker (at a walker's pace a long box may be walkers side by
// side, each with a track of its own) and the other track within same_motion_mps of it.
bool moves_with(const Track& host, const Track& other, const TrackerParams& p) {
  return host.velocity().norm() > p.small.walker_max_speed_mps &&
         (host.velocity() - other.velocity()).norm() <= p.fragments.same_motion_mps;
}

// TrackerParams::Fragments::twin_by_doppler: the host moves faster than a walker and its motion
// explains the Doppler of the group's pixels.
bool doppler_twin(const Frame& frame, const Group& g, const Track& host, const TrackerParams& p) {
  return p.fragments.twin_by_doppler && host.velocity().norm() > p.small.walker_max_speed_mps &&
         !g.found.empty() && explains_doppler(frame, g.found, host, p);
}

// How far beyond its predicted box a cluster may lie to join the track: the gate, wider by 3σ of
// the track's position (a young track's tangential velocity is hardly known).
double gate_of(const Track& t, const TrackerParams& p) {
  const double pos_var = t.P.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff();
  return p.association.gate_m + 3.0 * std::sqrt(std::max(0.0, pos_var));
}

// A track whose far end may not have been seen though its box is shorter than a vehicle's
// (TrackerParams::Association::cut_box_reach): confirmed, not small, faster than a walker, its
// last box cut by the view or an occluder (a bus alongside that fills one head, its front in the
// next). A second cluster joins it up to the gate from its box, as one joins a vehicle's.
bool reaches_unseen_part(const Track& t, const TrackerParams& p) {
  return p.association.cut_box_reach && t.confirmed && t.outline_cut && !t.small(p) &&
         t.velocity().norm() > p.small.walker_max_speed_mps;
}

// explains_doppler, but for a vehicle's track that missed its last update: within the
// tolerance and association.coasting_doppler_sigmas standard deviations of the Doppler its
// predicted state gives at the cluster's middle pixel, added in quadrature.
bool explains_doppler_in_gate(const Frame& frame, const std::vector<std::uint32_t>& px,
                              const Track& track, const TrackerParams& p) {
  const double k = p.association.coasting_doppler_sigmas;
  if (track.misses == 0 || !(k > 0.0) || !track.vehicle(p) || px.empty())
    return explains_doppler(frame, px, track, p);
  const Vec5 h = row_jacobian(frame.row_of(px[px.size() / 2]), track.x);
  const double sigma = std::sqrt(std::max(0.0, h.dot(track.P * h)));
  return doppler_deviation(frame, px, track) <=
         std::hypot(p.association.doppler_tolerance_mps, k * sigma);
}

// Per cluster: the track it joins and the one it would be absorbed into.
void gate_clusters(const Frame& frame, const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                   const std::vector<Eigen::Vector2d>& centroid, const std::vector<Track>& tracks,
                   const std::vector<Box>& boxes, const TrackerParams& p, Association& a) {
  const TrackerParams::Association& pa = p.association;
  for (std::size_t c = 0; c < centroid.size(); ++c) {
    if (static_cast<int>(cluster_pixels[c].size()) < pa.min_pixels_at((centroid[c] - frame.position).norm())) {
      // Too few pixels to measure anything: a crumb of a tracked object goes under its label.
      a.absorbed[c] = holding_box(centroid[c], tracks, boxes, p, false);
      continue;
    }
    double best = std::numeric_limits<double>::infinity();
    double best_absorb = best;
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      if (!boxes[t].contains(centroid[c], gate_of(tracks[t], p))) continue;
      // A large cluster beside a small track (a car passing a walker) is nearer the walker's
      // centre than its own box's: the box distance decides, the centre only breaks ties.
      const double d = boxes[t].distance(centroid[c]) + 1e-3 * (centroid[c] - boxes[t].centre).norm();
      if (explains_doppler_in_gate(frame, cluster_pixels[c], tracks[t], p)) {
        if (d < best) {
          best = d;
          a.owner[c] = static_cast<int>(t);
        }
      } else if (static_cast<int>(cluster_pixels[c].size()) <= pa.absorb_max_pixels &&
                 tracks[t].vehicle(p) && boxes[t].contains(centroid[c], p.claims.claim_margin_m) &&
                 d < best_absorb) {
        best_absorb = d;
        a.absorbed[c] = static_cast<int>(t);
      }
    }
    if (a.owner[c] >= 0) a.absorbed[c] = -1;
  }
}

}  // namespace

Association associate(const Frame& frame, const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                      const MotionEstimate& est, const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                      const TrackerParams& p, std::vector<Group>& groups) {
  const std::size_t k = est.clusters.size();
  std::vector<Eigen::Vector2d> centroid(k);
  for (std::size_t c = 0; c < k; ++c) centroid[c] = frame.world_xy(est.clusters[c].centroid_m);
  Association a{std::vector<int>(k, -1), std::vector<int>(k, -1)};
  gate_clusters(frame, cluster_pixels, centroid, tracks, boxes, p, a);
  // A track's nearest cluster always joins it; further ones only from inside its box grown by
  // claim_margin_m (walkers side by side move alike), a vehicle's by the gate (its far end may
  // not have been seen yet), and so a confirmed box cut by the view or an occluder
  // (reaches_unseen_part). The others start tracks.
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    std::vector<std::size_t> mine;
    for (std::size_t c = 0; c < k; ++c) {
      if (a.owner[c] == static_cast<int>(t)) mine.push_back(c);
    }
    std::sort(mine.begin(), mine.end(), [&](std::size_t x, std::size_t y) {
      const double dx = boxes[t].distance(centroid[x]);
      const double dy = boxes[t].distance(centroid[y]);
      return dx != dy ? dx < dy : x < y;
    });
    const bool vehicle = tracks[t].vehicle(p) || reaches_unseen_part(tracks[t], p);
    const bool small = tracks[t].small(p);
    for (std::size_t n = 0; n < mine.size(); ++n) {
      const std::size_t c = mine[n];
      // A walker's second cluster is a limb, much smaller than its body, or a piece of it
      // inside its box; one of comparable size beside the box is the walker next to it.
      const bool limb = !small || cluster_pixels[c].size() * 3 <= cluster_pixels[mine.front()].size();
      const double grow = vehicle ? p.association.gate_m : limb ? p.claims.claim_margin_m : 0.0;
      if (n > 0 && !boxes[t].contains(centroid[c], grow)) {
        a.owner[c] = -1;
        continue;
      }
      groups[t].clusters.push_back(static_cast<std::int32_t>(c + 1));
      groups[t].found.insert(groups[t].found.end(), cluster_pixels[c].begin(), cluster_pixels[c].end());
    }
  }
  for (std::size_t c = 0; c < k; ++c) {
    if (a.owner[c] < 0 && a.absorbed[c] >= 0)
      groups[static_cast<std::size_t>(a.absorbed[c])].absorbed.push_back(static_cast<std::int32_t>(c + 1));
  }
  return a;
}

void merge_nested_tracks(const Frame& frame, std::vector<Track>& tracks, const std::vector<Box>& boxes, const TrackerParams& p,
                         Association& a, std::vector<Group>& groups) {
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    if (groups[t].clusters.empty()) continue;
    int u = holding_box(boxes[t].centre, tracks, boxes, p, true, t);
    if (u < 0 && p.fragments.same_motion_margin_m > 0.0) {  // a face of the vehicle beside it, moving with it
      const int v = holding_box(boxes[t].centre, tracks, boxes, p, true, t, p.fragments.same_motion_margin_m);
      if (v >= 0 && moves_with(tracks[static_cast<std::size_t>(v)], tracks[t], p)) u = v;
    }
    const bool small_host = u < 0 && p.fragments.small_host_ratio > 0.0;
    if (small_host) u = holding_box(boxes[t].centre, tracks, boxes, p, false, t);
    if (u < 0) continue;
    const Track& host = tracks[static_cast<std::size_t>(u)];
    const double ratio = small_host ? p.fragments.small_host_ratio : p.fragments.host_ratio;
    // Two tracks born in one frame from two parts of a truck (the cab and its load) are as old:
    // the one that now finds a few times fewer pixels than the other follows a part.
    const bool much_larger = host.hits >= tracks[t].hits && host.last_pixels >= ratio * tracks[t].last_pixels;
    if (small_host && !(host.confirmed && much_larger)) continue;
    // As old and moving with it: a part of the vehicle too (a car first seen in two halves). Or
    // as old, its pixels' Doppler the host's motion (a turning truck first seen in two pieces:
    // the second piece's young filter holds a velocity of its own, the rigid body's Doppler does
    // not).
    const bool twin = !small_host && host.hits == tracks[t].hits &&
                      (moves_with(host, tracks[t], p) || doppler_twin(frame, groups[t], host, p));
    if (host.hits <= tracks[t].hits && !much_larger && !twin) continue;
    if (tracks[t].vehicle(p) && tracks[t].confirmed && !much_larger) continue;  // two vehicles: leave to the split
    // An established track whose pixels the vehicle's motion does not explain moves on its own
    // (a cyclist beside a turning car, inside its box): no part of it. Tested last: the Doppler
    // only of a track that would otherwise end here.
    if (!small_host && p.fragments.own_motion_hits > 0 && tracks[t].confirmed && tracks[t].hits >= p.fragments.own_motion_hits &&
        !groups[t].found.empty() && doppler_deviation(frame, groups[t].found, host) > p.association.doppler_tolerance_mps)
      continue;
    Group& into = groups[static_cast<std::size_t>(u)];
    for (const std::int32_t l : groups[t].clusters) {
      into.absorbed.push_back(l);
      a.owner[static_cast<std::size_t>(l - 1)] = -1;
      a.absorbed[static_cast<std::size_t>(l - 1)] = u;
    }
    into.absorbed.insert(into.absorbed.end(), groups[t].absorbed.begin(), groups[t].absorbed.end());
    for (const std::int32_t l : groups[t].absorbed) a.absorbed[static_cast<std::size_t>(l - 1)] = u;
    groups[t] = Group{};
    tracks[t].misses = p.lifecycle.max_misses + 1;  // pruned at the end of the frame
    tracks[t].merged = true;
  }
}

int inside_vehicle(const Frame& frame, const ClusterEstimate& ce, const std::vector<Track>& tracks,
                   const std::vector<Box>& boxes, const TrackerParams& p) {
  return holding_box(frame.world_xy(ce.centroid_m), tracks, boxes, p, true);
}

int lost_track_of(const Frame& frame, const Track& born, const std::vector<std::uint32_t>& pixels,
                  const std::vector<Track>& lost, const TrackerParams& p) {
  std::vector<Box> boxes(lost.size());
  for (std::size_t l = 0; l < lost.size(); ++l) boxes[l] = box_of(lost[l]);
  // The position of a track unseen for a second or two is known to metres: the gate grows with
  // it as the association's does, but to three times gate_m at most.
  const double widest = 3.0 * p.association.gate_m;
  return nearest_holding_box(
      born.centre(), boxes, [&](std::size_t l) { return std::min(gate_of(lost[l], p), widest); },
      [&](std::size_t l) { return explains_doppler(frame, pixels, lost[l], p); });
}

}  // namespace fmcw::core::tracking
