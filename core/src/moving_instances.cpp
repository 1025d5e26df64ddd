#include "fmcw/core/moving_instances.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include "fmcw/core/check.hpp"
#include "pixel_lists.hpp"

namespace fmcw::core {

void InstanceParams::validate() const {
  FMCW_CHECK_ARG(max_range_gap_m > 0.0 && range_gap_fraction >= 0.0 && max_doppler_step_mps > 0.0 && touching_gap_m >= 0.0,
                 "instances: gaps and steps must be positive");
  FMCW_CHECK_ARG(min_cluster_pixels >= 1, "instances: min_cluster_pixels must be >= 1, got ", min_cluster_pixels);
  FMCW_CHECK_ARG(edge_flatness >= 0.0 && edge_flatness < 1.0, "instances: edge_flatness must be in [0, 1), got ",
                 edge_flatness);
  FMCW_CHECK_ARG(cross_head_voxel_m > 0.0, "instances: cross_head_voxel_m must be > 0, got ",
                 cross_head_voxel_m);
  FMCW_CHECK_ARG(cross_head_share >= 0.0 && cross_head_share <= 1.0,
                 "instances: cross_head_share must be in [0, 1], got ", cross_head_share);
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

namespace {

// Relabels seg's instances by their roots (find(l), the lowest label of each joined set), the
// roots renumbered 1, 2, ... in label order: by first pixel, as the labels were.
template <class Find>
void renumber_joined(Segmentation& seg, const Find& find) {
  const std::size_t k = seg.cluster_sizes.size();
  std::vector<std::int32_t> renumber(k + 1, 0);
  std::vector<std::uint32_t> sizes;
  for (std::size_t l = 1; l <= k; ++l) {
    const auto r = static_cast<std::size_t>(find(static_cast<std::int32_t>(l)));
    if (r == l) {
      sizes.push_back(0);
      renumber[l] = static_cast<std::int32_t>(sizes.size());
    }
  }
  for (std::size_t l = 1; l <= k; ++l) {
    const std::int32_t nl = renumber[static_cast<std::size_t>(find(static_cast<std::int32_t>(l)))];
    renumber[l] = nl;
    sizes[static_cast<std::size_t>(nl - 1)] += seg.cluster_sizes[l - 1];
  }
  for (std::int32_t& l : seg.labels) {
    if (l >= 1) l = renumber[static_cast<std::size_t>(l)];
  }
  for (LabelRun& run : seg.runs) {
    if (run.label >= 1) run.label = renumber[static_cast<std::size_t>(run.label)];
  }
  seg.cluster_sizes = std::move(sizes);
}

// Per instance of seg: its heads (a bit each; heads past 63 share the last), and whether it may
// share space with an instance of other heads (their boxes, grown by a cube, meet).
struct HeadsOfInstances {
  std::vector<std::uint64_t> heads;
  std::vector<std::uint8_t> candidate;
  bool any = false;
};

HeadsOfInstances heads_of_instances(const Scan& scan, const Segmentation& seg,
                                    const InstanceParams& params) {
  const std::size_t k = seg.cluster_sizes.size();
  const auto cols = static_cast<std::size_t>(scan.cols);
  std::vector<int> head_of_col(cols, 0);
  for (std::size_t h = 0; h < scan.heads.size(); ++h) {
    for (int c = scan.heads[h].col_begin; c < scan.heads[h].col_end; ++c)
      head_of_col[static_cast<std::size_t>(c)] = static_cast<int>(h);
  }
  HeadsOfInstances out;
  out.heads.assign(k + 1, 0);
  out.candidate.assign(k + 1, 0);
  std::vector<Eigen::AlignedBox3f> box(k + 1);
  for (std::size_t r = 0; r < static_cast<std::size_t>(scan.rows); ++r) {
    for (std::size_t c = 0; c < cols; ++c) {
      const std::size_t i = r * cols + c;
      const std::int32_t l = seg.labels[i];
      if (l < 1) continue;
      out.heads[static_cast<std::size_t>(l)] |= std::uint64_t{1} << std::min(head_of_col[c], 63);
      box[static_cast<std::size_t>(l)].extend(
          Eigen::Vector3f(scan.x_m[i], scan.y_m[i], scan.z_m[i]));
    }
  }
  const auto grow = static_cast<float>(params.cross_head_voxel_m);
  for (std::size_t a = 1; a <= k; ++a) {
    for (std::size_t b = a + 1; b <= k; ++b) {
      if ((out.heads[a] & out.heads[b]) != 0) continue;
      Eigen::AlignedBox3f ga = box[a];
      ga.min().array() -= grow;
      ga.max().array() += grow;
      if (!ga.intersects(box[b])) continue;
      out.candidate[a] = out.candidate[b] = 1;
      out.any = true;
    }
  }
  return out;
}

}  // namespace

int join_instances_across_heads(const Scan& scan, Segmentation& seg, const InstanceParams& params) {
  const std::size_t k = seg.cluster_sizes.size();
  if (params.cross_head_share <= 0.0 || k < 2 || scan.heads.size() < 2) return 0;
  const HeadsOfInstances hoi = heads_of_instances(scan, seg, params);
  const std::vector<std::uint64_t>& heads_of = hoi.heads;
  const std::vector<std::uint8_t>& candidate = hoi.candidate;
  if (!hoi.any) return 0;
  // Per pixel of a candidate: its cube and its instance.
  struct Entry {
    std::uint64_t cube;
    std::int32_t label;
    bool operator<(const Entry& o) const {
      return cube != o.cube ? cube < o.cube : label < o.label;
    }
  };
  std::vector<Entry> entries;
  const double inv = 1.0 / params.cross_head_voxel_m;
  const auto cell = [&](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v * inv)) + (1 << 20)) &
           0x1fffff;
  };
  for (std::size_t i = 0; i < seg.labels.size(); ++i) {
    const std::int32_t l = seg.labels[i];
    if (l < 1 || candidate[static_cast<std::size_t>(l)] == 0) continue;
    entries.push_back(
        {(cell(scan.x_m[i]) << 42) | (cell(scan.y_m[i]) << 21) | cell(scan.z_m[i]), l});
  }
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end(),
                            [](const Entry& a, const Entry& b) {
                              return a.cube == b.cube && a.label == b.label;
                            }),
                entries.end());
  // Cubes per instance, and cubes shared per pair of instances of different heads.
  std::vector<std::uint32_t> cubes(k + 1, 0);
  std::map<std::pair<std::int32_t, std::int32_t>, std::uint32_t> shared;
  for (std::size_t a = 0; a < entries.size();) {
    std::size_t b = a;
    while (b < entries.size() && entries[b].cube == entries[a].cube)
      ++cubes[static_cast<std::size_t>(entries[b++].label)];
    for (std::size_t x = a; x < b; ++x) {
      for (std::size_t y = x + 1; y < b; ++y) {
        const std::int32_t la = entries[x].label, lb = entries[y].label;
        if ((heads_of[static_cast<std::size_t>(la)] & heads_of[static_cast<std::size_t>(lb)]) == 0)
          ++shared[{la, lb}];
      }
    }
    a = b;
  }
  // Joined: union-find, the root the lowest label (the first pixel of the joined set).
  std::vector<std::int32_t> root(k + 1);
  for (std::size_t l = 0; l <= k; ++l) root[l] = static_cast<std::int32_t>(l);
  const auto find = [&](std::int32_t l) {
    while (root[static_cast<std::size_t>(l)] != l)
      l = root[static_cast<std::size_t>(l)] =
          root[static_cast<std::size_t>(root[static_cast<std::size_t>(l)])];
    return l;
  };
  int joins = 0;
  for (const auto& [pair, n] : shared) {
    const std::uint32_t smaller = std::min(cubes[static_cast<std::size_t>(pair.first)],
                                           cubes[static_cast<std::size_t>(pair.second)]);
    if (static_cast<double>(n) < params.cross_head_share * static_cast<double>(smaller)) continue;
    const std::int32_t ra = find(pair.first), rb = find(pair.second);
    if (ra == rb) continue;
    root[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    ++joins;
  }
  if (joins == 0) return 0;
  renumber_joined(seg, find);
  return joins;
}

}  // namespace fmcw::core
