#pragma once
// Internal to the simulator: from the hits of a row's beams to the frame's pixels (Eq. 6
// Doppler, intensity, measurement noise, ground truth). Kept apart from the casting so that the
// per-pixel loop stays one tight function.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/sim/beam_divergence.hpp"
#include "fmcw/sim/measurement_model.hpp"
#include "fmcw/sim/scene.hpp"

namespace fmcw::sim::detail {

/// Raw pointers to a frame's arrays. The pixel loop stores through these: through the vectors,
/// every byte store (valid, moving) might alias a vector's data pointer and would force the
/// compiler to reload them all.
struct PixelArrays {
  PixelArrays(core::Scan& scan, core::PixelGroundTruth& gt);
  void set_no_return(std::size_t i) const {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    x[i] = y[i] = z[i] = range[i] = doppler[i] = nan;
    intensity[i] = 0.0f;
    valid[i] = 0;
    gt_range[i] = gt_doppler[i] = gt_vx[i] = gt_vy[i] = gt_vz[i] = nan;
    gt_instance[i] = 0;
    gt_moving[i] = 0;
    gt_class[i] = 0;
  }

  float* x;
  float* y;
  float* z;
  float* range;
  float* doppler;
  float* intensity;
  std::uint8_t* valid;
  float* gt_range;
  float* gt_doppler;
  float* gt_vx;
  float* gt_vy;
  float* gt_vz;
  std::uint32_t* gt_instance;
  std::uint8_t* gt_moving;
  std::uint16_t* gt_class;
};

/// What stays fixed while the beams of one instant are shaded.
struct ShadingContext {
  const Scene& scene;
  const MeasurementModel& measurement;
  const Eigen::Vector3f* directions_world;  ///< unit, per pixel, at this instant
  const Eigen::Vector3f* directions_rig;    ///< unit, per pixel
  Eigen::Matrix3d R_world_rig;
  double moving_threshold_sq;               ///< [m^2/s^2]
  PixelArrays out;
};

/// One head at this instant: its beam origin and the origin's velocity (world), its mount (rig).
struct HeadState {
  Eigen::Vector3d origin_world;
  Eigen::Vector3d origin_velocity_world;  ///< V_ego + omega_ego x r_mount
  Eigen::Vector3d mount_rig;
};

/// Pixels row + [c0, c1) from one ray per beam; hits[c] is column c's hit. The returns, in
/// column order, take their measurement noise from two standard normals each, drawn beforehand
/// (MeasurementModel::measure); returns the first normal not used. Counts actor pixels into
/// actor_pixels (per actor index).
const double* shade_beams(const ShadingContext& ctx, const HeadState& head, std::size_t row, int c0, int c1,
                          const RayHit* hits, const double* normals, int* actor_pixels);

/// The same for beams of several sub-rays: hits[c * sub + j] is sub-ray j of column c along
/// sub_directions[c * sub + j]; each beam reports its merged peak (beam_divergence.hpp).
/// actor_ids: (actor id, actor index), sorted.
struct SubRayShading {
  const SubRayPattern& pattern;
  const BeamDivergenceParams& divergence;
  const Eigen::Vector3f* sub_directions;
  const std::vector<std::pair<std::uint32_t, std::size_t>>& actor_ids;
};
void shade_sub_ray_beams(const ShadingContext& ctx, const SubRayShading& sub_rays, const HeadState& head, std::size_t row,
                         int c0, int c1, const RayHit* hits, core::Rng& rng, std::vector<SubReturn>& returns,
                         int* actor_pixels);

}  // namespace fmcw::sim::detail
