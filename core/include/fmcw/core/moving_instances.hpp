#pragma once
// Moving pixels into object instances on the range image.

#include <cstdint>
#include <vector>

#include "fmcw/core/doppler_segmentation.hpp"
#include "fmcw/core/scan.hpp"

namespace fmcw::core {

struct InstanceParams {
  /// Neighbours join when |dr| < max(this, fraction * r) and |dv| < max_doppler_step_mps:
  /// surfaces seen at grazing angles step by metres from pixel to pixel, while an occluded
  /// vehicle is usually a vehicle length behind the one in front.
  double max_range_gap_m = 1.0;        ///< [m]
  double range_gap_fraction = 0.08;    ///< range-relative part of the gap above
  double max_doppler_step_mps = 1.0;   ///< [m/s]
  double touching_gap_m = 0.5;         ///< |dr| below this joins whatever the Doppler (wheels, limbs) [m]
  /// A larger step between two neighbours does not join them when it lies between two flat
  /// runs (see is_occlusion_edge): the range changes by less than this fraction of the step from
  /// each to the next pixel beyond it. That is the edge of one body in front of another, not a
  /// surface seen at a grazing angle. 0 turns the test off.
  double edge_flatness = 0.3;
  int min_cluster_pixels = 3;          ///< smaller groups of moving pixels are labelled static
  /// Instances smaller than this [pixels] (a roof or side seen edge-on breaks off in strips)
  /// join an adjacent larger instance whose rigid motion explains their Doppler to within
  /// fragment_residual_mps (median).
  int fragment_pixels = 60;
  double fragment_residual_mps = 0.25;
  /// One body seen by two heads whose views overlap (a narrow head inside a wide one, wide heads
  /// reaching into each other's view) is two groups of pixels in two column spans of the image,
  /// never neighbours. Instances of different heads join where they share space: at least
  /// cross_head_share of the smaller one's cubes of cross_head_voxel_m hold points of both
  /// (join_instances_across_heads; 0: never).
  double cross_head_voxel_m = 0.5;
  double cross_head_share = 0.3;

  void validate() const;
};

/// Whether the neighbours (r, c) and (r + dr, c + dc) lie across the edge of one body in front
/// of another: a range step of at least touching_gap_m between two flat runs (the next pixel
/// beyond each, along the row when the pair spans columns, changes by less than edge_flatness
/// times the step). A surface at a grazing angle steps about evenly instead. group_of: column
/// group of each column (pixels across a seam are not on one line). False when a pixel is
/// missing or the test is off.
bool is_occlusion_edge(const Scan& scan, const std::vector<int>& group_of, int r, int c, int dr, int dc,
                       const InstanceParams& params);

/// Groups the pixels flagged in `moving` (rows * cols) by 8-neighbour continuity in range and
/// Doppler, across stitched head seams. Labels: kInvalid where no return, kStatic for static
/// pixels and for groups below min_cluster_pixels, 1..k for instances numbered by their first
/// pixel in row-major order.
Segmentation label_moving_instances(const Scan& scan, const std::vector<std::uint8_t>& moving, const InstanceParams& params);

/// Joins instances of seg (labels 1..k, from label_moving_instances) seen by different heads
/// that share space (InstanceParams::cross_head_share), renumbering them by first pixel in
/// row-major order as label_moving_instances numbers them; cluster_sizes follow. Returns the
/// number of joins.
int join_instances_across_heads(const Scan& scan, Segmentation& seg, const InstanceParams& params);

}  // namespace fmcw::core
