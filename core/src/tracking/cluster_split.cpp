#include "cluster_split.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "association.hpp"
#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core::tracking {

namespace {

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
void assign_part(const Frame& frame, MotionEstimate& est,
                 std::vector<std::vector<std::uint32_t>>& cluster_pixels, std::size_t slot,
                 const ClusterEstimate& whole, std::vector<std::uint32_t> part) {
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
bool overlaps_another(std::size_t t, const std::vector<std::size_t>& near,
                      const std::vector<Box>& boxes, const TrackerParams& p) {
  const double grow = p.claims.claim_margin_m;
  for (const std::size_t u : near) {
    if (u != t &&
        (boxes[u].contains(boxes[t].centre, grow) || boxes[t].contains(boxes[u].centre, grow)))
      return true;
  }
  return false;
}

// The tracks (of `near`) whose boxes hold a share of the cluster's pixels q: per pixel its
// holder (-1: none), and the sharers.
std::vector<std::size_t> sharers_of(const Frame& frame, const std::vector<Eigen::Vector2d>& q,
                                    const std::vector<std::size_t>& near,
                                    const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                                    const TrackerParams& p, std::vector<int>& holder) {
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
    if (held[t] < split_need(tracks[t], p, p.association.min_cluster_pixels) &&
        overlaps_another(t, near, boxes, p))
      continue;
    sharers.push_back(t);
  }
  return sharers;
}

// Splits cluster c's pixels between the sharers: the first part keeps the label.
void split_cluster(const Frame& frame, MotionEstimate& est,
                   std::vector<std::vector<std::uint32_t>>& cluster_pixels, std::size_t c,
                   const std::vector<Eigen::Vector2d>& q, const std::vector<int>& holder,
                   const std::vector<std::size_t>& sharers, const std::vector<Box>& boxes) {
  const std::vector<std::uint32_t>& px = cluster_pixels[c];
  std::vector<std::vector<std::uint32_t>> parts(sharers.size());
  for (std::size_t n = 0; n < px.size(); ++n) {
    std::size_t part = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < sharers.size(); ++s) {
      const double d =
          static_cast<int>(sharers[s]) == holder[n] ? -1.0 : boxes[sharers[s]].distance(q[n]);
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
    assign_part(frame, est, cluster_pixels, s == 0 ? c : est.clusters.size(), whole,
                std::move(parts[s]));
  }
}

}  // namespace

void split_shared_clusters(const Frame& frame, MotionEstimate& est,
                           std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                           const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                           const TrackerParams& p) {
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
    if (static_cast<int>(px.size()) <
        2 * p.association.min_pixels_at(est.clusters[c].centroid_m.head<2>().norm()))
      continue;
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

void split_by_doppler(const Frame& frame, MotionEstimate& est,
                      std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                      const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                      const TrackerParams& p) {
  const TrackerParams::Association& pa = p.association;
  if (!(pa.doppler_split_rms_mps > 0.0)) return;
  const std::size_t k0 = est.clusters.size();
  std::vector<std::uint32_t> explained, rest;
  for (std::size_t c = 0; c < k0; ++c) {
    const std::vector<std::uint32_t>& px = cluster_pixels[c];
    // Only a cluster that no one rigid motion explains.
    if (static_cast<int>(px.size()) < 2 * pa.min_cluster_pixels ||
        !(est.clusters[c].velocity.residual_rms_mps > pa.doppler_split_rms_mps)) {
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
      if (!reaches(boxes[t], w, p)) continue;            // no pixel in its box
      if (explains_doppler(frame, px, tr, p)) continue;  // the whole cluster is its
      explained.clear();
      rest.clear();
      for (std::size_t n = 0; n < px.size(); ++n) {
        const Row r = frame.row_of(px[n]);
        const bool mine = std::abs(r.y - predicted(r, tr.x)) <= pa.doppler_tolerance_mps &&
                          boxes[t].contains(w.q[n], p.claims.claim_margin_m);
        (mine ? explained : rest).push_back(px[n]);
      }
      if (static_cast<double>(explained.size()) < split_need(tr, p, pa.min_cluster_pixels) ||
          static_cast<int>(rest.size()) < pa.min_cluster_pixels)
        continue;
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

}  // namespace fmcw::core::tracking
