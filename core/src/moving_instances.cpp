#include "fmcw/core/moving_instances.hpp"

#include <cmath>

#include "fmcw/core/check.hpp"
#include "pixel_lists.hpp"

namespace fmcw::core {

void InstanceParams::validate() const {
  FMCW_CHECK_ARG(max_range_gap_m > 0.0 && range_gap_fraction >= 0.0 && max_doppler_step_mps > 0.0 && touching_gap_m >= 0.0,
                 "instances: gaps and steps must be positive");
  FMCW_CHECK_ARG(min_cluster_pixels >= 1, "instances: min_cluster_pixels must be >= 1, got ", min_cluster_pixels);
  FMCW_CHECK_ARG(edge_flatness >= 0.0 && edge_flatness < 1.0, "instances: edge_flatness must be in [0, 1), got ",
                 edge_flatness);
}

bool is_occlusion_edge(const Scan& scan, const std::vector<int>& group_of, int r, int c, int dr, int dc,
                       const InstanceParams& params) {
  if (params.edge_flatness <= 0.0) return false;
  // Range of the pixel (rr, cc) when it is valid and on column c's side of any seam.
  const auto range_at = [&](int rr, int cc, double& out) {
    if (rr < 0 || rr >= scan.rows || cc < 0 || cc >= scan.cols) return false;
    if (group_of[static_cast<std::size_t>(cc)] != group_of[static_cast<std::size_t>(c)]) return false;
    const std::size_t i = scan.index(rr, cc);
    if (!scan.valid[i]) return false;
    out = scan.range_m[i];
    return true;
  };
  // The runs go along the row when the pair spans columns (a diagonal pair at the top of a body
  // would otherwise run off it into the background), along the column otherwise.
  const int run_r = dc != 0 ? 0 : dr;
  double ra = 0.0, rb = 0.0, before = 0.0, after = 0.0;
  if (!range_at(r, c, ra) || !range_at(r + dr, c + dc, rb) || !range_at(r - run_r, c - dc, before) ||
      !range_at(r + dr + run_r, c + 2 * dc, after))
    return false;
  const double step = std::abs(ra - rb);
  if (step < params.touching_gap_m) return false;
  const double flat = params.edge_flatness * step;
  return std::abs(ra - before) < flat && std::abs(after - rb) < flat;
}

Segmentation label_moving_instances(const Scan& scan, const std::vector<std::uint8_t>& moving, const InstanceParams& params) {
  FMCW_CHECK_ARG(moving.size() == scan.size(), "instances: moving mask has ", moving.size(), " values, expected ", scan.size());
  Segmentation out;
  // Labels: invalid or static; the moving pixels are pending until a region takes them, and
  // listed.
  const std::size_t n = scan.size();
  out.labels.resize(n);
  std::vector<std::uint8_t> pending_at(n);
  std::size_t valid_pixels = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool valid = scan.valid[i] != 0;
    out.labels[i] = valid ? Segmentation::kStatic : Segmentation::kInvalid;
    pending_at[i] = valid & (moving[i] != 0) ? 1 : 0;
    valid_pixels += valid ? 1 : 0;
  }
  std::vector<std::uint32_t> pending;
  list_pixels(n, [&](std::size_t i) { return pending_at[i] != 0; }, pending);
  // Column group of each column, for neighbours across stitched seams only.
  const std::vector<int> group_of = scan.column_group_of();
  // a = (r, c), b = (r + dr, c + dc): neighbours.
  const auto joins = [&](std::size_t a, std::size_t b, int r, int c, int dr, int dc) {
    const double ra = scan.range_m[a], rb = scan.range_m[b];
    const double step = std::abs(ra - rb);
    if (step < params.touching_gap_m) return true;
    const double gap = std::max(params.max_range_gap_m, params.range_gap_fraction * std::min(ra, rb));
    if (step >= gap || std::abs(scan.radial_velocity_mps[a] - scan.radial_velocity_mps[b]) >= params.max_doppler_step_mps)
      return false;
    return !is_occlusion_edge(scan, group_of, r, c, dr, dc, params);
  };
  std::vector<std::uint32_t> members;
  std::vector<std::uint32_t> stack;
  std::int32_t next = 0;
  std::size_t labelled = 0;
  for (const std::uint32_t seed : pending) {
    if (pending_at[seed] == 0) continue;
    members.clear();
    stack.assign(1, static_cast<std::uint32_t>(seed));
    pending_at[seed] = 0;
    while (!stack.empty()) {
      const std::uint32_t q = stack.back();
      stack.pop_back();
      members.push_back(q);
      const int r = static_cast<int>(q / static_cast<std::uint32_t>(scan.cols));
      const int c = static_cast<int>(q % static_cast<std::uint32_t>(scan.cols));
      for_each_neighbour(scan, group_of, r, c, [&](std::size_t nq, int dr, int dc) {
        if (pending_at[nq] == 0 || !joins(q, nq, r, c, dr, dc)) return;
        pending_at[nq] = 0;
        stack.push_back(static_cast<std::uint32_t>(nq));
      });
    }
    ++next;
    if (static_cast<int>(members.size()) < params.min_cluster_pixels) continue;  // left static
    out.cluster_sizes.push_back(static_cast<std::uint32_t>(members.size()));
    const auto label = static_cast<std::int32_t>(out.cluster_sizes.size());
    for (const std::uint32_t m : members) out.labels[m] = label;
    labelled += members.size();
  }
  out.num_regions = static_cast<std::uint32_t>(next) + 1;
  out.static_pixels = static_cast<decltype(out.static_pixels)>(valid_pixels - labelled);
  return out;
}

}  // namespace fmcw::core
