#include "beam_shading.hpp"

#include <algorithm>
#include <cmath>

namespace fmcw::sim::detail {

namespace {

// What the receiver reports for one beam, noise-free, and its ground truth.
struct TrueReturn {
  double range_m;
  double doppler_mps;
  Eigen::Vector3d velocity_rig_mps;
  bool moving;
  float intensity;
  std::uint32_t instance;
  std::uint16_t semantic_class;
  double reflectance = 0.0;     // reflectivity x |cos incidence|, for the SNR model
  double compensation = 0.0;    // e . V_origin [m/s] added in the ego-compensated frame, else 0
};

// The loops below copy what they read into locals before calling this: a byte store (valid,
// moving) may alias anything reached through a reference, which would force reloads.
// Returns false when the measurement model drops the return (the pixel is then not written).
inline bool report(const PixelArrays& out, const MeasurementModel& measurement, const Eigen::Vector3f* directions_rig,
                   const Eigen::Vector3d& mount_rig, std::size_t i, const TrueReturn& t, const double* normals) {
  // Ego-compensated: v + e . V_origin, noise and truth alike, so that the truth is in the frame
  // of the scan it describes.
  const double doppler = t.doppler_mps + t.compensation;
  MeasurementModel::Reading m{};
  if (!measurement.measure_return(t.range_m, doppler, t.reflectance, 1.0, normals, m)) return false;
  // Reported along the beam's axis, in the rig frame of the beam's own instant (the motion skew
  // of a real sweep): T_rig_world (o + r e) = mount + r e_rig.
  const Eigen::Vector3d p_rig = mount_rig + m.range_m * directions_rig[i].cast<double>();
  out.x[i] = static_cast<float>(p_rig.x());
  out.y[i] = static_cast<float>(p_rig.y());
  out.z[i] = static_cast<float>(p_rig.z());
  out.range[i] = static_cast<float>(m.range_m);
  out.doppler[i] = static_cast<float>(m.radial_velocity_mps);
  out.intensity[i] = t.intensity;
  out.valid[i] = 1;
  out.gt_range[i] = static_cast<float>(t.range_m);
  out.gt_doppler[i] = static_cast<float>(doppler);
  out.gt_vx[i] = static_cast<float>(t.velocity_rig_mps.x());
  out.gt_vy[i] = static_cast<float>(t.velocity_rig_mps.y());
  out.gt_vz[i] = static_cast<float>(t.velocity_rig_mps.z());
  out.gt_instance[i] = t.instance;
  out.gt_moving[i] = t.moving ? 1 : 0;
  out.gt_class[i] = t.semantic_class;
  return true;
}

}  // namespace

PixelArrays::PixelArrays(core::Scan& scan, core::PixelGroundTruth& gt)
    : x(scan.x_m.data()),
      y(scan.y_m.data()),
      z(scan.z_m.data()),
      range(scan.range_m.data()),
      doppler(scan.radial_velocity_mps.data()),
      intensity(scan.intensity.data()),
      valid(scan.valid.data()),
      gt_range(gt.range_m.data()),
      gt_doppler(gt.radial_velocity_mps.data()),
      gt_vx(gt.vx_mps.data()),
      gt_vy(gt.vy_mps.data()),
      gt_vz(gt.vz_mps.data()),
      gt_instance(gt.instance.data()),
      gt_moving(gt.moving.data()),
      gt_class(gt.semantic_class.data()) {}

const double* shade_beams(const ShadingContext& ctx, const HeadState& head, std::size_t row, int c0, int c1,
                          const RayHit* hits, const double* normals, int* actor_pixels) {
  const Scene& scene = ctx.scene;
  const PixelArrays out = ctx.out;
  const Eigen::Vector3f* const directions_world = ctx.directions_world;
  const Eigen::Vector3f* const directions_rig = ctx.directions_rig;
  const Eigen::Matrix3d R_world_rig = ctx.R_world_rig;
  const double moving_threshold_sq = ctx.moving_threshold_sq;
  const HeadState h = head;
  const bool compensate = ctx.measurement.params().velocity_frame == core::VelocityFrame::kEgoCompensated;
  const std::size_t per_return = static_cast<std::size_t>(ctx.measurement.normals_per_return());
  for (int c = c0; c < c1; ++c) {
    const std::size_t i = row + static_cast<std::size_t>(c);
    const RayHit& ray = hits[c];
    if (!std::isfinite(ray.distance_m)) {
      out.set_no_return(i);
      continue;
    }
    const Eigen::Vector3d e = directions_world[i].cast<double>();
    TrueReturn t{ray.distance_m, 0.0, Eigen::Vector3d::Zero(), false, 0.0f, 0, 0};
    double cos_incidence = 0.0;
    float reflectivity = 0.0f;
    if (ray.slot == 0) {
      // Eq. 6 with the static world at rest: v = -e . V_lidar.
      t.doppler_mps = -e.dot(h.origin_velocity_world);
      cos_incidence = e.dot(scene.static_normal(ray.primitive).cast<double>());
      reflectivity = scene.static_reflectivity(ray.primitive);
      t.semantic_class = scene.static_class(ray.primitive);
    } else {
      const SlotMotion& part = scene.slot(ray.slot);
      const Eigen::Vector3d p = h.origin_world + t.range_m * e;
      const Eigen::Vector3d v = part.velocity(ray, p);
      // Eq. 6: v = e . (V_point - V_lidar), both in the world frame (the dot product does not
      // depend on the frame it is evaluated in).
      t.doppler_mps = e.dot(v - h.origin_velocity_world);
      // Normals transform with the inverse transpose (parts may be scaled).
      cos_incidence = e.dot((part.normal_matrix * ray.normal_object.cast<double>()).normalized());
      reflectivity = part.reflectivity[ray.primitive];
      t.instance = part.actor_id;
      t.semantic_class = part.class_id;
      t.velocity_rig_mps = R_world_rig.transpose() * v;
      t.moving = v.squaredNorm() > moving_threshold_sq;
      ++actor_pixels[part.actor_index];
    }
    t.intensity = return_intensity(reflectivity, cos_incidence, t.range_m);
    t.reflectance = reflectivity * std::abs(cos_incidence);
    t.compensation = compensate ? e.dot(h.origin_velocity_world) : 0.0;
    if (!report(out, ctx.measurement, directions_rig, h.mount_rig, i, t, normals)) {
      out.set_no_return(i);  // too weak to detect (SNR model)
      if (ray.slot != 0) --actor_pixels[scene.slot(ray.slot).actor_index];
    }
    normals += per_return;
  }
  return normals;
}

void shade_sub_ray_beams(const ShadingContext& ctx, const SubRayShading& sub_rays, const HeadState& head, std::size_t row,
                         int c0, int c1, const RayHit* hits, core::Rng& rng, std::vector<SubReturn>& returns,
                         int* actor_pixels) {
  const std::size_t sub = sub_rays.pattern.offsets.size();
  for (int c = c0; c < c1; ++c) {
    const std::size_t i = row + static_cast<std::size_t>(c);
    returns.clear();
    for (std::size_t j = 0; j < sub; ++j) {
      const std::size_t k = static_cast<std::size_t>(c) * sub + j;
      const RayHit& ray = hits[k];
      if (!std::isfinite(ray.distance_m)) continue;
      const Eigen::Vector3d d = sub_rays.sub_directions[k].cast<double>();
      const SurfaceSample s = ctx.scene.resolve(ray, head.origin_world + ray.distance_m * d);
      returns.push_back({ray.distance_m, d.dot(s.velocity_world_mps - head.origin_velocity_world), s.velocity_world_mps,
                         sub_rays.pattern.weights[j] * return_intensity(s.reflectivity, d.dot(s.normal_world), ray.distance_m),
                         s.actor_id, s.semantic_class});
    }
    MergedReturn merged;
    if (!merge_sub_returns(returns, sub_rays.divergence, merged)) {
      ctx.out.set_no_return(i);
      continue;
    }
    // The merged energy is reflectivity x |cos| x the intensity falloff (return_intensity):
    // undone for the SNR model, which applies its own 1 / R^2.
    const double falloff = return_intensity(1.0f, 1.0, merged.range_m);
    const bool compensate = ctx.measurement.params().velocity_frame == core::VelocityFrame::kEgoCompensated;
    const TrueReturn t{merged.range_m,
                       merged.doppler_mps,
                       ctx.R_world_rig.transpose() * merged.velocity_world_mps,
                       merged.velocity_world_mps.squaredNorm() > ctx.moving_threshold_sq,
                       static_cast<float>(merged.energy),
                       merged.instance,
                       merged.semantic_class,
                       merged.energy / falloff,
                       compensate ? ctx.directions_world[i].cast<double>().dot(head.origin_velocity_world) : 0.0};
    double normals[3] = {rng.normal(), rng.normal(), 0.0};
    if (ctx.measurement.normals_per_return() == 3) normals[2] = rng.normal();
    if (!report(ctx.out, ctx.measurement, ctx.directions_rig, head.mount_rig, i, t, normals)) {
      ctx.out.set_no_return(i);  // too weak to detect (SNR model)
      continue;
    }
    if (t.instance != 0) {
      const auto it = std::lower_bound(sub_rays.actor_ids.begin(), sub_rays.actor_ids.end(),
                                       std::make_pair(t.instance, std::size_t{0}));
      ++actor_pixels[it->second];
    }
  }
}

}  // namespace fmcw::sim::detail
