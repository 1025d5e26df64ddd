#include "association.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "../pixel_lists.hpp"
#include "ctrv.hpp"
#include "fmcw/core/median.hpp"

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

bool explains_doppler(const Frame& frame, const std::vector<std::uint32_t>& px, const Track& track,
                      const TrackerParams& p) {
  return doppler_deviation(frame, px, track) <= p.association.doppler_tolerance_mps;
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

// Of the vehicles' tracks `inside` (their boxes hold the cluster's centroid, their motion
// explains its Doppler; in track order), the one whose box (grown by claims.claim_margin_m)
// holds the most of the cluster's pixels (Association::most_held_vehicle); the owner found by
// box distance where it is not among them, or the only one, or holds as many.
int most_held_vehicle(const Frame& frame, const std::vector<std::uint32_t>& px, int owner,
                      const std::vector<std::size_t>& inside, const std::vector<Box>& boxes,
                      const TrackerParams& p) {
  if (inside.size() < 2 ||
      std::find(inside.begin(), inside.end(), static_cast<std::size_t>(owner)) == inside.end())
    return owner;
  std::vector<Eigen::Vector2d> q;
  q.reserve(px.size());
  for (const std::uint32_t i : px) q.push_back(frame.world_xy(frame.scan.position(i)));
  const auto held = [&](std::size_t t) {
    int n = 0;
    for (const Eigen::Vector2d& x : q) n += boxes[t].contains(x, p.claims.claim_margin_m) ? 1 : 0;
    return n;
  };
  int most = held(static_cast<std::size_t>(owner));
  for (const std::size_t t : inside) {
    if (static_cast<int>(t) == owner) continue;
    const int n = held(t);
    if (n > most) {
      most = n;
      owner = static_cast<int>(t);
    }
  }
  return owner;
}

// Per cluster: the track it joins and the one it would be absorbed into.
void gate_clusters(const Frame& frame, const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                   const std::vector<Eigen::Vector2d>& centroid, const std::vector<Track>& tracks,
                   const std::vector<Box>& boxes, const TrackerParams& p, Association& a) {
  const TrackerParams::Association& pa = p.association;
  // Per cluster, the vehicles whose boxes hold its centroid and whose motion explains its Doppler.
  std::vector<std::size_t> inside;
  for (std::size_t c = 0; c < centroid.size(); ++c) {
    if (static_cast<int>(cluster_pixels[c].size()) < pa.min_pixels_at((centroid[c] - frame.position).norm())) {
      // Too few pixels to measure anything: a crumb of a tracked object goes under its label.
      a.absorbed[c] = holding_box(centroid[c], tracks, boxes, p, false);
      continue;
    }
    double best = std::numeric_limits<double>::infinity();
    double best_absorb = best;
    inside.clear();
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      if (!boxes[t].contains(centroid[c], gate_of(tracks[t], p))) continue;
      // A large cluster beside a small track (a car passing a walker) is nearer the walker's
      // centre than its own box's: the box distance decides, the centre only breaks ties.
      const double from_box = boxes[t].distance(centroid[c]);
      const double d = from_box + 1e-3 * (centroid[c] - boxes[t].centre).norm();
      if (explains_doppler_in_gate(frame, cluster_pixels[c], tracks[t], p)) {
        if (tracks[t].vehicle(p) && from_box == 0.0) inside.push_back(t);
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
    if (pa.most_held_vehicle)
      a.owner[c] = most_held_vehicle(frame, cluster_pixels[c], a.owner[c], inside, boxes, p);
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
