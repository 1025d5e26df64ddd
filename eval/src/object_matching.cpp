#include "fmcw/eval/object_matching.hpp"

#include <map>

#include "fmcw/core/check.hpp"
#include "point_overlaps.hpp"

namespace fmcw::eval {

void ObjectMatchParams::validate() const {
  FMCW_CHECK_ARG(min_moving_pixels >= 1, "objects: min_moving_pixels must be >= 1, got ", min_moving_pixels);
}

namespace {
// Actor pixels inside one cluster and the sum of their true velocities.
struct ClusterShare {
  int pixels = 0;
  Eigen::Vector3d velocity_sum = Eigen::Vector3d::Zero();
};

struct ActorPixels {
  int pixels = 0;
  int moving = 0;
  std::map<std::int32_t, ClusterShare> clusters;  // label -> share; ordered for deterministic ties
};
}  // namespace

std::vector<ObjectMatch> match_objects(const core::PixelGroundTruth& gt, const std::vector<std::uint8_t>& valid,
                                       const core::FrameTruth& truth, const core::MotionEstimate& estimate,
                                       const ObjectMatchParams& params) {
  params.validate();
  const std::size_t n = valid.size();
  gt.validate(n);
  FMCW_CHECK_ARG(estimate.labels.size() == n, "match_objects: estimate has ", estimate.labels.size(),
                 " labels for ", n, " pixels");
  std::map<std::uint32_t, ActorPixels> seen;
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid[i] || gt.instance[i] == 0) continue;
    ActorPixels& a = seen[gt.instance[i]];
    ++a.pixels;
    if (gt.moving[i]) ++a.moving;
    const std::int32_t label = estimate.labels[i];
    if (label >= 1) {
      ClusterShare& share = a.clusters[label];
      ++share.pixels;
      share.velocity_sum += Eigen::Vector3d(gt.vx_mps[i], gt.vy_mps[i], gt.vz_mps[i]);
    }
  }

  const ActorIndex actors(truth, "match_objects");
  std::vector<ObjectMatch> out;
  for (const auto& [id, a] : seen) {
    const core::ActorTruth& t = actors[id];
    ObjectMatch m;
    m.actor_id = id;
    m.class_name = t.class_name;
    m.pixels = a.pixels;
    m.moving_pixels = a.moving;
    m.distance_m = t.position_rig_m.norm();
    m.evaluated = a.moving >= params.min_moving_pixels;
    m.reference_mps = t.velocity_rig_mps;
    m.position_m = t.position_rig_m;
    m.yaw_rate_rps = t.angular_velocity_rig_rps.z();
    const ClusterShare* best = nullptr;
    for (const auto& [label, share] : a.clusters) {
      if (best == nullptr || share.pixels > best->pixels) {  // ties: the lower label
        best = &share;
        m.cluster = label;
      }
    }
    if (best != nullptr) {
      const auto k = static_cast<std::size_t>(m.cluster - 1);
      FMCW_CHECK_ARG(k < estimate.clusters.size() && estimate.clusters[k].id == m.cluster, "match_objects: label ",
                     m.cluster, " has no cluster in the estimate (", estimate.clusters.size(), " clusters)");
      const core::ClusterEstimate& c = estimate.clusters[k];
      m.pixels_in_cluster = best->pixels;
      m.cluster_pixels = c.num_pixels;
      m.detected = 2 * best->pixels > a.pixels;
      m.truth_mean_mps = best->velocity_sum / static_cast<double>(best->pixels);
      m.estimate_valid = m.detected && c.velocity.valid;
      if (m.estimate_valid) {
        m.estimate_mps = c.velocity.velocity_mps;
        m.estimate_centre_m = c.centre_m;
        m.estimate_yaw_rate_rps = c.yaw_rate_rps;
        m.estimate_track_id = c.track_id;
        m.estimate_covariance = c.velocity.covariance;
      }
    }
    out.push_back(m);
  }
  return out;
}

InstanceCounts count_instances(const core::PixelGroundTruth& gt, const std::vector<std::uint8_t>& valid,
                               const core::MotionEstimate& estimate, const ObjectMatchParams& params) {
  params.validate();
  const PointOverlaps po = point_overlaps(gt, valid, estimate.labels, "count_instances");
  const auto& cluster = po.clusters;
  const auto& overlap = po.overlaps;
  InstanceCounts c;
  c.clusters = static_cast<int>(cluster.size());
  std::map<std::int32_t, bool> cluster_matched;
  for (const auto& [id, counts] : po.actors) {
    if (counts.moving < params.min_moving_pixels) continue;
    ++c.actors;
    for (auto it = overlap.lower_bound({id, 0}); it != overlap.end() && it->first.first == id; ++it) {
      const int inter = it->second;
      const int uni = counts.pixels + cluster.at(it->first.second) - inter;
      if (2 * inter > uni) {  // IoU > 0.5: at most one cluster per actor and one actor per cluster
        ++c.actors_matched;
        cluster_matched[it->first.second] = true;
      }
    }
  }
  c.clusters_matched = static_cast<int>(cluster_matched.size());
  return c;
}

std::vector<BlindBandActor> blind_band_actors(const core::Scan& scan, const core::PixelGroundTruth& gt,
                                              const core::FrameTruth& truth, const core::MotionEstimate& estimate,
                                              double band_mps) {
  FMCW_CHECK_ARG(band_mps > 0.0, "blind band: band_mps must be > 0, got ", band_mps);
  const std::size_t n = scan.size();
  gt.validate(n);
  FMCW_CHECK_ARG(estimate.labels.size() == n, "blind band: estimate has ", estimate.labels.size(), " labels for ",
                 n, " pixels");
  const ActorIndex bodies(truth, "blind band");
  std::map<std::uint32_t, BlindBandActor> actors;
  // An actor's pixels come in runs along a row: look it up when the instance changes.
  std::uint32_t current = 0;
  const core::ActorTruth* body = nullptr;
  BlindBandActor* tally = nullptr;
  for (int r = 0; r < scan.rows; ++r) {
    for (int col = 0; col < scan.cols; ++col) {
      const std::size_t i = scan.index(r, col);
      if (!scan.valid[i] || !gt.moving[i] || gt.instance[i] == 0) continue;
      if (gt.instance[i] != current) {
        current = gt.instance[i];
        body = &bodies[current];
        tally = &actors[current];
        tally->actor_id = current;
      }
      const core::ActorTruth& t = *body;
      const Eigen::Vector3d p = scan.position(i);
      const Eigen::Vector3d e = (p - scan.beam_origin(i)).normalized();
      const Eigen::Vector3d v_body = t.velocity_rig_mps + t.angular_velocity_rig_rps.cross(p - t.position_rig_m);
      const bool detected = estimate.labels[i] >= 1;
      BlindBandActor& a = *tally;
      if (std::abs(e.dot(v_body)) < band_mps) {
        ++a.band_pixels;
        a.band_detected += detected ? 1 : 0;
        continue;
      }
      ++a.visible_pixels;
      const double own = e.dot(Eigen::Vector3d(gt.vx_mps[i], gt.vy_mps[i], gt.vz_mps[i]));
      if (std::abs(own) < band_mps) {
        ++a.part_band_pixels;
        a.part_band_detected += detected ? 1 : 0;
      }
    }
  }
  std::vector<BlindBandActor> out;
  for (const auto& [id, a] : actors) out.push_back(a);
  return out;
}

}  // namespace fmcw::eval
