#pragma once
// Beam divergence: a beam is a cone, not a line. Sub-rays sample the cone; their returns are
// merged the way an FMCW receiver sees them.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace fmcw::sim {

struct BeamDivergenceParams {
  /// Sub-rays per beam: 1 (off), or a hexagonal pattern of 7, 19 or 37 (rings of 6, 12, 18).
  int sub_rays = 1;
  double divergence_rad = 0.1 * M_PI / 180.0;  ///< full cone angle at 1/e^2 intensity [rad]
  /// Returns closer than this in range and in Doppler fall in one FMCW spectral peak and mix;
  /// others stay separate peaks. Defaults: the range and velocity resolutions of Eq. 3 and 5.
  double merge_range_m = 0.025;
  double merge_velocity_mps = 0.031;

  void validate() const;  ///< std::invalid_argument naming the field
};

/// Unit offsets of the sub-rays in the cone's cross-section (radius 1 = cone edge) and their
/// Gaussian weights, summing to 1. The first sub-ray is the beam's axis.
struct SubRayPattern {
  std::vector<Eigen::Vector2d> offsets;
  std::vector<double> weights;
};
SubRayPattern make_sub_ray_pattern(int sub_rays);

/// Directions of the sub-rays of a unit beam direction, for a cone of full angle divergence.
void sub_ray_directions(const Eigen::Vector3d& axis, const SubRayPattern& pattern, double divergence_rad,
                        Eigen::Vector3f* out);

/// One sub-ray's return.
struct SubReturn {
  double range_m;
  double doppler_mps;                 ///< noise-free, Eq. 6
  Eigen::Vector3d velocity_world_mps;
  double energy;                      ///< beam weight x return intensity
  std::uint32_t instance;
  std::uint16_t semantic_class = 0;
};

/// The peak an FMCW receiver reports for one beam: sub-returns are grouped (single linkage)
/// when within merge_range_m and merge_velocity_mps of each other; the group with the most
/// energy wins and reports its energy-weighted range, Doppler and velocity, and the instance of
/// its strongest sub-return. Returns false when there is nothing to report.
struct MergedReturn {
  double range_m = 0.0;
  double doppler_mps = 0.0;
  Eigen::Vector3d velocity_world_mps = Eigen::Vector3d::Zero();
  double energy = 0.0;          ///< of the winning peak
  std::uint32_t instance = 0;
  std::uint16_t semantic_class = 0;  ///< of its strongest sub-return, as the instance
  int peaks = 0;                ///< how many separate peaks the beam saw
};
bool merge_sub_returns(std::vector<SubReturn>& returns, const BeamDivergenceParams& params, MergedReturn& merged);

}  // namespace fmcw::sim
