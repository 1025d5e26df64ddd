#pragma once
// Algorithm 1 of the paper: region growing on the range image by Doppler continuity.

#include <cstdint>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

/// Eq. 12-14: adjacent pixels of one rigid object differ in Doppler by at most
/// (|v_object| + |v_lidar|) * theta_res. With 0.2 deg pixels and 25 m/s each this is 0.1745 m/s,
/// the paper's 0.17 m/s.
double doppler_threshold_mps(double angular_resolution_rad, double max_object_speed_mps,
                             double max_ego_speed_mps);

/// How the connected regions are found. Both give identical labels: the regions are the
/// connected components of the graph whose edges join 8-neighbours with |dv| < v_th, numbered
/// by their first pixel in row-major order.
enum class RegionAlgorithm {
  kRegionGrowing,  ///< Algorithm 1 as written: seed, grow with a stack, next seed
  kUnionFind,      ///< horizontal runs, then union-find over runs joined to the row above
};

struct SegmentationParams {
  double velocity_threshold_mps = 0.17;  ///< v_th [m/s]: neighbours join when |dv| < v_th
  /// Regions smaller than this [pixels] are not reported as moving clusters; their pixels are
  /// labelled kUnassigned. 1 keeps every region, as Algorithm 1 does.
  int min_cluster_pixels = 1;
  RegionAlgorithm algorithm = RegionAlgorithm::kUnionFind;

  void validate() const;
};

/// Output of region growing. Labels: kInvalid for pixels with no return, kStatic for the
/// largest region, 1..num_clusters for the other regions in scan (row-major) order of their
/// first pixel, kUnassigned for regions below min_cluster_pixels.
/// A horizontal stretch of pixels with one label: row, columns [col_begin, col_end).
struct LabelRun {
  std::int32_t row = 0;
  std::int32_t col_begin = 0;
  std::int32_t col_end = 0;
  std::int32_t label = 0;
};

struct Segmentation {
  static constexpr std::int32_t kInvalid = -1;
  static constexpr std::int32_t kUnassigned = -2;
  static constexpr std::int32_t kStatic = 0;

  std::vector<std::int32_t> labels;          ///< rows * cols, row-major
  std::vector<std::uint32_t> cluster_sizes;  ///< [k - 1] = pixel count of cluster k
  std::uint32_t static_pixels = 0;
  std::uint32_t num_regions = 0;  ///< all regions grown, the static one included
  /// The labelled pixels as runs in scan order (kUnionFind only; empty for kRegionGrowing), so
  /// that later stages can sweep a label's pixels without testing every pixel's label.
  std::vector<LabelRun> runs;

  int num_clusters() const { return static_cast<int>(cluster_sizes.size()); }
};

/// Grows regions over the 8-neighbourhood; a pixel joins when |v_neighbour - v_current| < v_th.
/// Invalid pixels never join. Columns of neighbouring heads connect only across stitched seams.
/// Deterministic: the result depends only on the scan and the parameters. Checks array sizes
/// and, for valid pixels, that v is finite (std::invalid_argument naming the pixel).
class DopplerSegmenter {
 public:
  explicit DopplerSegmenter(const SegmentationParams& params = {});
  Segmentation segment(const Scan& scan);

 private:
  // Region growing on a padded copy: padded_labels_ gets region ids, region_size_ their sizes.
  void grow_regions(const Scan& scan, Segmentation& out);
  // Run-based union-find straight on the scan arrays.
  void union_find_regions(const Scan& scan, Segmentation& out);
  // Line 19 of Algorithm 1: the largest region is static; number the others; fills
  // cluster_sizes and static_pixels and returns the final label of each region.
  std::vector<std::int32_t> assign_labels(Segmentation& out) const;

  SegmentationParams params_;
  // Work buffers kept between calls so that steady-state frames allocate nothing.
  std::vector<std::int32_t> padded_labels_;
  std::vector<float> padded_velocity_;
  std::vector<std::int32_t> stack_;
  std::vector<std::int32_t> region_size_;
  std::vector<std::int32_t> run_parent_, run_region_, run_above_, run_here_;
  std::vector<LabelRun> run_list_;
};

}  // namespace fmcw::core
