#include "band_growth.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "../vector_clones.hpp"
#include "track_box.hpp"

namespace fmcw::core::tracking {

namespace {

// Grows a region from seeds over the range image: a neighbour not yet taken (taken holds 1 for
// invalid pixels too), in the same column group, whose range continues the pixel it is reached
// from and that joins(i) accepts, is taken and appended to grown. inner[c]: columns c - 1 and
// c + 1 exist and share c's column group.
struct RegionGrower {
  const Scan& scan;
  const TrackerParams::Growth& p;
  std::vector<int> column_group;
  std::vector<std::uint8_t> inner;
  std::vector<std::uint8_t> taken;
  std::vector<std::uint32_t> stack;

  template <class Joins>
  void grow(const std::vector<std::uint32_t>& seeds, const Joins& joins, std::vector<std::uint32_t>& grown) {
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
        if (std::abs(rn - rq) >= std::max(p.range_gap_m, p.range_gap_fraction * std::min(rn, rq)) || !joins(n)) return;
        taken[n] = 1;
        grown.push_back(static_cast<std::uint32_t>(n));
        stack.push_back(static_cast<std::uint32_t>(n));
      });
    }
  }
};

// Taken: labelled or without a return.
FMCW_VECTOR_CLONES void labelled_or_empty(std::size_t n, const std::int32_t* labels, const std::uint8_t* valid,
                                          std::uint8_t* taken) {
  for (std::size_t i = 0; i < n; ++i) taken[i] = (labels[i] != 0) | (valid[i] == 0) ? 1 : 0;
}

RegionGrower make_grower(const Frame& frame, const MotionEstimate& est, const std::vector<Group>& groups,
                         const TrackerParams::Growth& p) {
  const Scan& scan = frame.scan;
  RegionGrower g{scan, p, scan.column_group_of(), {}, {}, {}};
  g.inner.assign(g.column_group.size(), 0);
  for (std::size_t c = 1; c + 1 < g.column_group.size(); ++c)
    g.inner[c] = g.column_group[c - 1] == g.column_group[c] && g.column_group[c + 1] == g.column_group[c] ? 1 : 0;
  g.taken.resize(est.labels.size());
  labelled_or_empty(est.labels.size(), est.labels.data(), scan.valid.data(), g.taken.data());
  for (const Group& group : groups) {
    group.for_each_measured([&](std::uint32_t i) { g.taken[i] = 1; });
    for (const std::uint32_t i : group.labelled) g.taken[i] = 1;
  }
  return g;
}

// Heights [z_lo, z_hi], world position inside, Doppler as the motion x gives it.
template <class Inside>
bool moves_with(const Frame& frame, std::size_t i, double z_lo, double z_hi, const Inside& inside, const Vec5& x,
                double tolerance) {
  const Eigen::Vector3d q = frame.scan.position(i);
  if (q.z() < z_lo || q.z() > z_hi || !inside(frame.world_xy(q))) return false;
  const Row r = frame.row_of(static_cast<std::uint32_t>(i));
  return std::abs(r.y - predicted(r, x)) <= tolerance;
}

}  // namespace

std::vector<std::pair<std::uint32_t, std::size_t>> grow_into_band(const Frame& frame, const MotionEstimate& est,
                                                                  const std::vector<std::vector<std::uint32_t>>& cluster_pixels,
                                                                  const std::vector<Track>& tracks,
                                                                  const std::vector<std::int32_t>& group_of_label,
                                                                  const TrackerParams& p, std::vector<Group>& groups) {
  std::vector<std::pair<std::uint32_t, std::size_t>> grown_untracked;
  if (p.growth.reach_m <= 0.0) return grown_untracked;
  RegionGrower grower = make_grower(frame, est, groups, p.growth);
  const double tolerance = p.claims.doppler_tolerance_mps;
  std::vector<std::uint32_t> grown;
  for (std::size_t c = 0; c < est.clusters.size(); ++c) {
    const ClusterEstimate& ce = est.clusters[c];
    if (!ce.velocity.valid) continue;
    Eigen::AlignedBox2d extent;
    double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
    for (const std::uint32_t i : cluster_pixels[c]) {
      const Eigen::Vector3d q = frame.scan.position(i);
      extent.extend(frame.world_xy(q));
      z_lo = std::min(z_lo, q.z());
      z_hi = std::max(z_hi, q.z());
    }
    if (extent.sizes().maxCoeff() < p.small.small_object_m) z_lo += p.claims.ground_clearance_m;
    const Eigen::AlignedBox2d reach(extent.min().array() - p.growth.reach_m, extent.max().array() + p.growth.reach_m);
    Vec5 x = Vec5::Zero();
    x.segment<2>(2) = frame.R * ce.velocity.velocity_mps.head<2>();
    const auto inside = [&](const Eigen::Vector2d& w) { return reach.contains(w); };
    const double z_top = z_hi + p.claims.claim_margin_m;
    grown.clear();
    grower.grow(cluster_pixels[c], [&](std::size_t i) { return moves_with(frame, i, z_lo, z_top, inside, x, tolerance); }, grown);
    const std::int32_t g = group_of_label[c + 1];
    for (const std::uint32_t i : grown) {
      if (g >= 0)
        groups[static_cast<std::size_t>(g)].labelled.push_back(i);
      else
        grown_untracked.emplace_back(i, c);
    }
  }
  std::vector<std::uint32_t> seeds;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    const Track& tr = tracks[t];
    Group& g = groups[t];
    if (!tr.carries(p) || g.found.empty()) continue;
    const Box box = box_of(tr);
    const double z_lo = tr.z_min_m + (tr.small(p) ? p.claims.ground_clearance_m : 0.0);
    const double z_top = tr.z_max_m + p.claims.claim_margin_m;
    const auto inside = [&](const Eigen::Vector2d& w) { return box.contains(w, p.growth.reach_m); };
    seeds.assign(g.found.begin(), g.found.end());
    seeds.insert(seeds.end(), g.claimed.begin(), g.claimed.end());
    grown.clear();
    grower.grow(seeds, [&](std::size_t i) { return moves_with(frame, i, z_lo, z_top, inside, tr.x, tolerance); }, grown);
    g.labelled.insert(g.labelled.end(), grown.begin(), grown.end());
  }
  return grown_untracked;
}

}  // namespace fmcw::core::tracking
