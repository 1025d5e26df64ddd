#include "fmcw/sim/beam_divergence.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::sim {

void BeamDivergenceParams::validate() const {
  FMCW_CHECK_ARG(sub_rays == 1 || sub_rays == 7 || sub_rays == 19 || sub_rays == 37,
                 "beam divergence: sub_rays must be 1, 7, 19 or 37, got ", sub_rays);
  FMCW_CHECK_ARG(std::isfinite(divergence_rad) && divergence_rad > 0.0 && divergence_rad < 0.5,
                 "beam divergence: divergence must be in (0, 0.5) rad, got ", divergence_rad);
  FMCW_CHECK_ARG(merge_range_m >= 0.0 && merge_velocity_mps >= 0.0,
                 "beam divergence: merge_range_m and merge_velocity_mps must be >= 0");
}

SubRayPattern make_sub_ray_pattern(int sub_rays) {
  int rings = 0;
  while (1 + 3 * rings * (rings + 1) < sub_rays) ++rings;
  FMCW_CHECK_ARG(1 + 3 * rings * (rings + 1) == sub_rays, "sub-ray pattern: ", sub_rays, " is not 1, 7, 19, 37, ...");
  SubRayPattern p;
  p.offsets.emplace_back(0.0, 0.0);
  for (int k = 1; k <= rings; ++k) {
    const double radius = static_cast<double>(k) / rings;
    for (int j = 0; j < 6 * k; ++j) {
      const double a = 2.0 * M_PI * j / (6 * k);
      p.offsets.emplace_back(radius * std::cos(a), radius * std::sin(a));
    }
  }
  // Gaussian profile, 1/e^2 at the cone's edge (radius 1): w = exp(-2 r^2).
  double sum = 0.0;
  for (const auto& o : p.offsets) {
    p.weights.push_back(std::exp(-2.0 * o.squaredNorm()));
    sum += p.weights.back();
  }
  for (auto& w : p.weights) w /= sum;
  return p;
}

void sub_ray_directions(const Eigen::Vector3d& axis, const SubRayPattern& pattern, double divergence_rad,
                        Eigen::Vector3f* out) {
  // An orthonormal frame around the axis.
  const Eigen::Vector3d helper = std::abs(axis.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d u = axis.cross(helper).normalized();
  const Eigen::Vector3d w = axis.cross(u);
  const double half = 0.5 * divergence_rad;
  for (std::size_t k = 0; k < pattern.offsets.size(); ++k) {
    const Eigen::Vector2d& o = pattern.offsets[k];
    const double angle = half * o.norm();
    const double phi = std::atan2(o.y(), o.x());
    const Eigen::Vector3d d =
        std::cos(angle) * axis + std::sin(angle) * (std::cos(phi) * u + std::sin(phi) * w);
    out[k] = d.normalized().cast<float>();
  }
}

bool merge_sub_returns(std::vector<SubReturn>& returns, const BeamDivergenceParams& params, MergedReturn& merged) {
  if (returns.empty()) return false;
  // Sorted by range (then Doppler, for a deterministic order); single linkage in both.
  std::sort(returns.begin(), returns.end(), [](const SubReturn& a, const SubReturn& b) {
    return a.range_m != b.range_m ? a.range_m < b.range_m : a.doppler_mps < b.doppler_mps;
  });
  const std::size_t n = returns.size();
  std::vector<std::size_t> group(n);
  for (std::size_t i = 0; i < n; ++i) group[i] = i;
  const auto root = [&](std::size_t x) {
    while (group[x] != x) x = group[x] = group[group[x]];
    return x;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n && returns[j].range_m - returns[i].range_m <= params.merge_range_m; ++j) {
      if (std::abs(returns[j].doppler_mps - returns[i].doppler_mps) <= params.merge_velocity_mps) {
        const std::size_t a = root(i), b = root(j);
        group[std::max(a, b)] = std::min(a, b);
      }
    }
  }
  std::vector<double> energy(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) energy[root(i)] += returns[i].energy;
  std::size_t best = n;
  merged.peaks = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (root(i) != i) continue;
    ++merged.peaks;
    if (best == n || energy[i] > energy[best]) best = i;  // ties: the nearer peak
  }
  if (best == n || !(energy[best] > 0.0)) return false;
  merged = MergedReturn{0.0, 0.0, Eigen::Vector3d::Zero(), energy[best], 0, 0, merged.peaks};
  double strongest = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (root(i) != best) continue;
    const double w = returns[i].energy / energy[best];
    merged.range_m += w * returns[i].range_m;
    merged.doppler_mps += w * returns[i].doppler_mps;
    merged.velocity_world_mps += w * returns[i].velocity_world_mps;
    if (returns[i].energy > strongest) {
      strongest = returns[i].energy;
      merged.instance = returns[i].instance;
      merged.semantic_class = returns[i].semantic_class;
    }
  }
  return true;
}

}  // namespace fmcw::sim
