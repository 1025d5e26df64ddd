#include "fmcw/eval/object_matching.hpp"

#include <map>

#include "fmcw/core/check.hpp"

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

  std::map<std::uint32_t, const core::ActorTruth*> actors;
  for (const core::ActorTruth& a : truth.actors) actors[a.id] = &a;
  std::vector<ObjectMatch> out;
  for (const auto& [id, a] : seen) {
    const auto it = actors.find(id);
    FMCW_CHECK_ARG(it != actors.end(), "match_objects: pixels hit actor ", id, " but the frame's truth lists no such actor");
    const core::ActorTruth& t = *it->second;
    ObjectMatch m;
    m.actor_id = id;
    m.class_name = t.class_name;
    m.pixels = a.pixels;
    m.moving_pixels = a.moving;
    m.distance_m = t.position_rig_m.norm();
    m.evaluated = a.moving >= params.min_moving_pixels;
    m.reference_mps = t.velocity_rig_mps;
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
      if (m.estimate_valid) m.estimate_mps = c.velocity.velocity_mps;
    }
    out.push_back(m);
  }
  return out;
}

}  // namespace fmcw::eval
