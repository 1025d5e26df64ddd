#include "fmcw/core/doppler_segmentation.hpp"

#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::core {

namespace {
constexpr std::int32_t kBlocked = -1;    // padding and invalid pixels
constexpr std::int32_t kUnvisited = -2;  // valid pixel not yet in a region

void check_sizes(const Scan& scan) {
  FMCW_CHECK_ARG(scan.rows >= 0 && scan.cols >= 0 && scan.valid.size() == scan.size() &&
                     scan.radial_velocity_mps.size() == scan.size(),
                 "segmentation: scan of ", scan.rows, " x ", scan.cols, " has ", scan.valid.size(),
                 " validity flags and ", scan.radial_velocity_mps.size(), " velocities");
}
}  // namespace

double doppler_threshold_mps(double angular_resolution_rad, double max_object_speed_mps,
                             double max_ego_speed_mps) {
  FMCW_CHECK_ARG(angular_resolution_rad > 0.0, "doppler_threshold_mps: resolution must be > 0 rad, got ",
                 angular_resolution_rad);
  FMCW_CHECK_ARG(max_object_speed_mps >= 0.0 && max_ego_speed_mps >= 0.0,
                 "doppler_threshold_mps: speeds must be >= 0 m/s");
  // Eq. 14: dv_same <= (|v_model| + |v_lidar|) * theta_res.
  return (max_object_speed_mps + max_ego_speed_mps) * angular_resolution_rad;
}

void SegmentationParams::validate() const {
  FMCW_CHECK_ARG(std::isfinite(velocity_threshold_mps) && velocity_threshold_mps > 0.0,
                 "segmentation: velocity_threshold_mps must be > 0, got ", velocity_threshold_mps);
  FMCW_CHECK_ARG(min_cluster_pixels >= 1, "segmentation: min_cluster_pixels must be >= 1, got ",
                 min_cluster_pixels);
}

DopplerSegmenter::DopplerSegmenter(const SegmentationParams& params) : params_(params) {
  params_.validate();
}

Segmentation DopplerSegmenter::segment(const Scan& scan) {
  check_sizes(scan);
  Segmentation out;
  out.labels.assign(scan.size(), Segmentation::kInvalid);
  if (scan.size() == 0) return out;
  if (params_.algorithm == RegionAlgorithm::kRegionGrowing) {
    grow_regions(scan, out);
  } else {
    union_find_regions(scan, out);
  }
  return out;
}

std::vector<std::int32_t> DopplerSegmenter::assign_labels(Segmentation& out) const {
  out.num_regions = static_cast<std::uint32_t>(region_size_.size());
  std::vector<std::int32_t> final_label(region_size_.size(), Segmentation::kUnassigned);
  if (region_size_.empty()) return final_label;
  // Line 19: the largest region is the static background (ties: the first found).
  std::size_t static_region = 0;
  for (std::size_t k = 1; k < region_size_.size(); ++k) {
    if (region_size_[k] > region_size_[static_region]) static_region = k;
  }
  final_label[static_region] = Segmentation::kStatic;
  out.static_pixels = static_cast<std::uint32_t>(region_size_[static_region]);
  for (std::size_t k = 0; k < region_size_.size(); ++k) {
    if (k == static_region || region_size_[k] < params_.min_cluster_pixels) continue;
    out.cluster_sizes.push_back(static_cast<std::uint32_t>(region_size_[k]));
    final_label[k] = static_cast<std::int32_t>(out.cluster_sizes.size());
  }
  return final_label;
}

void DopplerSegmenter::grow_regions(const Scan& scan, Segmentation& out) {
  const int rows = scan.rows;
  const int cols = scan.cols;
  // Padded image: one blocked row above and below, one blocked column at each side and one
  // between heads whose seam is not stitched. Neighbour offsets then need no bounds checks.
  std::vector<int> padded_col(static_cast<std::size_t>(cols));
  int pc = 1;
  for (std::size_t h = 0; h < scan.heads.size(); ++h) {
    const HeadInfo& head = scan.heads[h];
    for (int c = head.col_begin; c < head.col_end; ++c) padded_col[static_cast<std::size_t>(c)] = pc++;
    if (h + 1 < scan.heads.size() && !head.stitched_to_next) ++pc;
  }
  const std::int32_t stride = pc + 1;
  const std::size_t padded_size = static_cast<std::size_t>(rows + 2) * static_cast<std::size_t>(stride);
  padded_labels_.assign(padded_size, kBlocked);
  padded_velocity_.assign(padded_size, 0.0f);
  bool finite = true;
  for (int r = 0; r < rows; ++r) {
    const std::size_t prow = static_cast<std::size_t>(r + 1) * static_cast<std::size_t>(stride);
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = scan.index(r, c);
      const std::size_t p = prow + static_cast<std::size_t>(padded_col[static_cast<std::size_t>(c)]);
      if (scan.valid[i]) {
        padded_labels_[p] = kUnvisited;
        padded_velocity_[p] = scan.radial_velocity_mps[i];
        finite &= std::isfinite(scan.radial_velocity_mps[i]);
      }
    }
  }
  if (!finite) scan.validate();  // throws, naming the pixel

  const std::int32_t offsets[8] = {-stride - 1, -stride, -stride + 1, -1, 1, stride - 1, stride, stride + 1};
  const float threshold = static_cast<float>(params_.velocity_threshold_mps);
  stack_.resize(padded_size);
  region_size_.clear();
  std::int32_t* labels = padded_labels_.data();
  const float* velocity = padded_velocity_.data();
  // Algorithm 1, lines 4-18: seed at each unvisited pixel in scan order, grow until no
  // unprocessed pixel of the region has an unvisited neighbour within v_th.
  for (std::size_t seed = static_cast<std::size_t>(stride); seed < padded_size - static_cast<std::size_t>(stride); ++seed) {
    if (labels[seed] != kUnvisited) continue;
    const auto region = static_cast<std::int32_t>(region_size_.size());
    std::int32_t top = 0;
    std::int32_t count = 0;
    labels[seed] = region;
    stack_[static_cast<std::size_t>(top++)] = static_cast<std::int32_t>(seed);
    while (top > 0) {
      const std::int32_t q = stack_[static_cast<std::size_t>(--top)];
      ++count;
      const float vq = velocity[q];
      for (const std::int32_t off : offsets) {
        const std::int32_t nq = q + off;
        if (labels[nq] == kUnvisited && std::fabs(velocity[nq] - vq) < threshold) {
          labels[nq] = region;
          stack_[static_cast<std::size_t>(top++)] = nq;
        }
      }
    }
    region_size_.push_back(count);
  }
  const std::vector<std::int32_t> final_label = assign_labels(out);
  for (int r = 0; r < rows; ++r) {
    const std::size_t prow = static_cast<std::size_t>(r + 1) * static_cast<std::size_t>(stride);
    for (int c = 0; c < cols; ++c) {
      const std::int32_t l = labels[prow + static_cast<std::size_t>(padded_col[static_cast<std::size_t>(c)])];
      if (l >= 0) out.labels[scan.index(r, c)] = final_label[static_cast<std::size_t>(l)];
    }
  }
}

void DopplerSegmenter::union_find_regions(const Scan& scan, Segmentation& out) {
  const float threshold = static_cast<float>(params_.velocity_threshold_mps);
  const auto groups = scan.connected_column_groups();
  const std::uint8_t* valid = scan.valid.data();
  const float* vel = scan.radial_velocity_mps.data();
  // Runs: maximal horizontal stretches joined pixel to pixel, numbered in scan order. A union
  // keeps the smaller id as root, so every root is its region's first run.
  run_parent_.clear();
  run_list_.clear();
  run_above_.assign(static_cast<std::size_t>(scan.cols), -1);
  run_here_.assign(static_cast<std::size_t>(scan.cols), -1);
  const auto find = [this](std::int32_t x) {
    std::int32_t* parent = run_parent_.data();
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];  // path halving
      x = parent[x];
    }
    return x;
  };
  bool finite = true;
  for (int r = 0; r < scan.rows; ++r) {
    const std::size_t row = scan.index(r, 0);
    const std::uint8_t* ok = valid + row;
    const float* v = vel + row;
    const float* v_up = r > 0 ? v - scan.cols : v;  // read only when r > 0
    std::int32_t* here = run_here_.data();
    const std::int32_t* above = run_above_.data();
    for (const auto& [b, e] : groups) {
      // Runs of this row within the group.
      for (int c = b; c < e;) {
        if (!ok[c]) {
          here[c++] = -1;
          continue;
        }
        const auto id = static_cast<std::int32_t>(run_parent_.size());
        run_parent_.push_back(id);
        const int start = c;
        finite &= std::isfinite(v[c]);
        here[c++] = id;
        while (c < e && ok[c] && std::fabs(v[c] - v[c - 1]) < threshold) {
          finite &= std::isfinite(v[c]);
          here[c++] = id;
        }
        run_list_.push_back(LabelRun{r, start, c, id});
      }
      if (r == 0) continue;
      // Edges to the row above (NW, N, NE). Along a run the run above rarely changes, so a
      // union is attempted only when the (run, run above) pair differs from the last one.
      std::int32_t last_a = -1;
      std::int32_t last_b = -1;
      for (int c = b; c < e; ++c) {
        const std::int32_t a = here[c];
        if (a < 0) continue;
        const int lo = c > b ? c - 1 : c;
        const int hi = c + 1 < e ? c + 1 : c;
        for (int q = lo; q <= hi; ++q) {
          const std::int32_t bq = above[q];
          if (bq < 0 || (a == last_a && bq == last_b) || !(std::fabs(v[c] - v_up[q]) < threshold)) continue;
          std::int32_t ra = find(a);
          std::int32_t rb = find(bq);
          if (ra != rb) {
            if (ra > rb) std::swap(ra, rb);
            run_parent_[static_cast<std::size_t>(rb)] = ra;
          }
          last_a = a;
          last_b = bq;
        }
      }
    }
    run_above_.swap(run_here_);
  }
  if (!finite) scan.validate();  // throws, naming the pixel

  // Regions numbered by their first run, i.e. their first pixel in scan order.
  region_size_.clear();
  run_region_.resize(run_parent_.size());
  for (std::size_t k = 0; k < run_parent_.size(); ++k) {
    const std::int32_t root = find(static_cast<std::int32_t>(k));
    if (root == static_cast<std::int32_t>(k)) {
      run_region_[k] = static_cast<std::int32_t>(region_size_.size());
      region_size_.push_back(0);
    } else {
      run_region_[k] = run_region_[static_cast<std::size_t>(root)];
    }
    const LabelRun& run = run_list_[k];
    region_size_[static_cast<std::size_t>(run_region_[k])] += run.col_end - run.col_begin;
  }
  const std::vector<std::int32_t> final_label = assign_labels(out);
  out.runs.reserve(run_list_.size());
  for (std::size_t k = 0; k < run_list_.size(); ++k) {
    LabelRun run = run_list_[k];
    run.label = final_label[static_cast<std::size_t>(run_region_[k])];
    std::int32_t* dst = out.labels.data() + scan.index(run.row, 0);
    std::fill(dst + run.col_begin, dst + run.col_end, run.label);
    out.runs.push_back(run);
  }
}

}  // namespace fmcw::core
