// The largest-region methods (paper, fast): Algorithm 1, then Algorithm 2 as published
// (random subsets, Ceres) or in closed form on every point, gathered in one pass.

#include <omp.h>

#include <cmath>

#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/random.hpp"
#include "pipeline_internal.hpp"

namespace fmcw::core {

namespace {

// Chooses up to cap of the given pixels at random (Algorithm 2, P.downSample(num)).
std::vector<std::uint32_t> downsample(const std::vector<std::uint32_t>& pixels, int cap, std::uint64_t seed) {
  if (cap <= 0 || pixels.size() <= static_cast<std::size_t>(cap)) return pixels;
  const auto picks = subsample_indices(static_cast<std::uint32_t>(pixels.size()), static_cast<std::uint32_t>(cap), seed);
  std::vector<std::uint32_t> out(picks.size());
  for (std::size_t k = 0; k < picks.size(); ++k) out[k] = pixels[picks[k]];
  return out;
}

VelocityEstimate solve(const VelocityRows& rows, const VelocityParams& params) {
  return params.solver == VelocitySolver::kCeres
             ? solve_velocity_ceres(rows, params.ceres)
             : solve_velocity_closed_form(rows, params.qr_condition_threshold);
}

// Per-label first and second moments of the beam directions and Doppler, gathered in one pass
// over the image: everything the closed form needs for the ego and every cluster.
struct LabelMoments {
  double ee[6] = {0, 0, 0, 0, 0, 0};  // sum e e^T: xx xy xz yy yz zz
  double ev[3] = {0, 0, 0};           // sum e v
  double vv = 0.0;                    // sum v^2
  double p[3] = {0, 0, 0};            // sum of positions
  int n = 0;
  std::uint32_t first = 0, last = 0;  // pixel index range holding the label

  Eigen::Matrix3d EE() const {
    Eigen::Matrix3d m;
    m << ee[0], ee[1], ee[2], ee[1], ee[3], ee[4], ee[2], ee[4], ee[5];
    return m;
  }
  Eigen::Vector3d Ev() const { return {ev[0], ev[1], ev[2]}; }
};

// Moments of every label, swept run by run: each run is summed in registers and added to its
// label once. The summation order is fixed, so results are reproducible.
void gather_moments(const Scan& scan, const std::vector<LabelRun>& runs, const std::vector<Eigen::Vector3d>& col_origin,
                    std::vector<LabelMoments>& moments) {
  for (const LabelRun& run : runs) {
    if (run.label < 0) continue;
    double ee0 = 0, ee1 = 0, ee2 = 0, ee3 = 0, ee4 = 0, ee5 = 0, ev0 = 0, ev1 = 0, ev2 = 0, vv = 0;
    double p0 = 0, p1 = 0, p2 = 0;
    const std::size_t row = scan.index(run.row, 0);
    for (int c = run.col_begin; c < run.col_end; ++c) {
      const std::size_t i = row + static_cast<std::size_t>(c);
      const Eigen::Vector3d& o = col_origin[static_cast<std::size_t>(c)];
      const double px = scan.x_m[i], py = scan.y_m[i], pz = scan.z_m[i];
      const double dx = px - o.x(), dy = py - o.y(), dz = pz - o.z();
      const double inv = 1.0 / std::sqrt(dx * dx + dy * dy + dz * dz);
      const double ex = dx * inv, ey = dy * inv, ez = dz * inv;
      const double v = scan.radial_velocity_mps[i];
      ee0 += ex * ex;
      ee1 += ex * ey;
      ee2 += ex * ez;
      ee3 += ey * ey;
      ee4 += ey * ez;
      ee5 += ez * ez;
      ev0 += ex * v;
      ev1 += ey * v;
      ev2 += ez * v;
      vv += v * v;
      p0 += px;
      p1 += py;
      p2 += pz;
    }
    LabelMoments& m = moments[static_cast<std::size_t>(run.label)];
    m.ee[0] += ee0;
    m.ee[1] += ee1;
    m.ee[2] += ee2;
    m.ee[3] += ee3;
    m.ee[4] += ee4;
    m.ee[5] += ee5;
    m.ev[0] += ev0;
    m.ev[1] += ev1;
    m.ev[2] += ev2;
    m.vv += vv;
    m.p[0] += p0;
    m.p[1] += p1;
    m.p[2] += p2;
    if (m.n == 0) m.first = static_cast<std::uint32_t>(row) + static_cast<std::uint32_t>(run.col_begin);
    m.last = static_cast<std::uint32_t>(row) + static_cast<std::uint32_t>(run.col_end - 1);
    m.n += run.col_end - run.col_begin;
  }
}

// The same for segmentations without runs: one run per labelled pixel.
std::vector<LabelRun> pixel_runs(const Scan& scan, const std::vector<std::int32_t>& labels) {
  std::vector<LabelRun> runs;
  for (int r = 0; r < scan.rows; ++r) {
    for (int c = 0; c < scan.cols; ++c) {
      const std::int32_t l = labels[scan.index(r, c)];
      if (l >= 0) runs.push_back(LabelRun{r, c, c + 1, l});
    }
  }
  return runs;
}

std::vector<std::uint32_t> pixels_with_label(const std::vector<std::int32_t>& labels, std::int32_t label,
                                             const LabelMoments& m) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t i = m.first; i <= m.last; ++i) {
    if (labels[i] == label) out.push_back(i);
  }
  return out;
}


// Closed form on every point: one pass gathers the moments of all labels, then each problem is
// a 3x3 solve. Rows are rebuilt only when a system needs the QR fallback.
void fused_velocities(const Scan& scan, const Segmentation& seg, const std::vector<Eigen::Vector3d>& col_origin, bool no_world,
                      const MotionPipelineParams& params, MotionEstimate& out) {
  const VelocityParams& vp = params.velocity;
  const int k = static_cast<int>(out.clusters.size());
  // Closed form on every point: one pass gathers the moments of all labels, then each
  // problem is a 3x3 solve. Rows are rebuilt only when a system needs the QR fallback.
  const auto t_ego = Clock::now();
  std::vector<LabelMoments> moments(static_cast<std::size_t>(k) + 1);
  gather_moments(scan, seg.runs.empty() ? pixel_runs(scan, out.labels) : seg.runs, col_origin, moments);
  for (const LabelMoments& m : moments) {
    if (!std::isfinite(m.ee[0] + m.ee[3] + m.ee[5] + m.p[0] + m.p[1] + m.p[2])) scan.validate();  // names the pixel
  }
  const LabelMoments& s = moments[0];
  NormalEquations ego_ne;  // Eq. 20: y = -v
  ego_ne.AtA = s.EE();
  ego_ne.Aty = -s.Ev();
  ego_ne.yty = s.vv;
  ego_ne.n = s.n;
  out.ego = solve_normal_equations(ego_ne, vp.qr_condition_threshold, [&] {
    VelocityRows rows;
    build_ego_rows(scan, col_origin, pixels_with_label(out.labels, 0, s), rows);
    return rows;
  });
  if (no_world) out.ego = VelocityEstimate{};
  out.timing.ego_ms = ms_since(t_ego);
  const auto t_obj = Clock::now();
  const Eigen::Vector3d V = out.ego.velocity_mps;
  // A 3x3 solve per cluster takes about a microsecond: threads only pay off for many
  // clusters. Each cluster is independent, so the result does not depend on the thread count.
  const int threads = params.num_threads > 0 ? params.num_threads : omp_get_max_threads();
#pragma omp parallel for schedule(static) num_threads(threads) if (k >= 256 && threads > 1)
  for (int c = 0; c < k; ++c) {
    const LabelMoments& m = moments[static_cast<std::size_t>(c) + 1];
    ClusterEstimate& cluster = out.clusters[static_cast<std::size_t>(c)];
    cluster.id = c + 1;
    cluster.num_pixels = m.n;
    cluster.centroid_m = Eigen::Vector3d(m.p[0], m.p[1], m.p[2]) / m.n;
    if (!out.ego.valid) continue;
    // Eq. 22 with y = v + e.V_self: A^T y = sum e v + (sum e e^T) V_self, and
    // y^T y = sum v^2 + 2 V_self . sum e v + V_self^T (sum e e^T) V_self.
    const Eigen::Matrix3d EE = m.EE();
    const Eigen::Vector3d Ev = m.Ev();
    NormalEquations ne;
    ne.AtA = EE;
    ne.Aty = Ev + EE * V;
    ne.yty = m.vv + 2.0 * V.dot(Ev) + V.dot(EE * V);
    ne.n = m.n;
    cluster.velocity = solve_normal_equations(ne, vp.qr_condition_threshold, [&] {
      VelocityRows rows;
      build_object_rows(scan, col_origin, pixels_with_label(out.labels, c + 1, m), V, rows);
      return rows;
    });
  }
  out.timing.objects_ms = ms_since(t_obj);
}

// Algorithm 2 as published: random subsets of at most num_th^s and num_th^m points.
void published_velocities(const Scan& scan, const Segmentation& seg, const std::vector<Eigen::Vector3d>& col_origin,
                          bool no_world, const MotionPipelineParams& params, std::uint64_t frame_index, MotionEstimate& out) {
  const VelocityParams& vp = params.velocity;
  const int k = static_cast<int>(out.clusters.size());
    const auto t_ego = Clock::now();
  std::vector<std::uint32_t> offset(static_cast<std::size_t>(k) + 2, 0);
  offset[1] = seg.static_pixels;
  for (int c = 0; c < k; ++c) {
    offset[static_cast<std::size_t>(c) + 2] = offset[static_cast<std::size_t>(c) + 1] + seg.cluster_sizes[static_cast<std::size_t>(c)];
  }
  std::vector<std::uint32_t> order(offset.back());
  {
    std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
    for (std::uint32_t i = 0; i < out.labels.size(); ++i) {
      const std::int32_t l = out.labels[i];
      if (l >= 0) order[fill[static_cast<std::size_t>(l)]++] = i;
    }
  }
  const auto pixels_of = [&](int label) {
    return std::vector<std::uint32_t>(order.begin() + offset[static_cast<std::size_t>(label)],
                                      order.begin() + offset[static_cast<std::size_t>(label) + 1]);
  };
  const std::uint64_t frame_seed = mix_seed(params.seed, frame_index);
  {
    VelocityRows rows;
    build_ego_rows(scan, col_origin, downsample(pixels_of(0), vp.ego_max_points, mix_seed(frame_seed, 0)), rows);
    out.ego = no_world ? VelocityEstimate{} : solve(rows, vp);
  }
  out.timing.ego_ms = ms_since(t_ego);

  // Lines 4-10: each moving cluster (Eq. 22), in parallel, one seed per cluster.
  const auto t_obj = Clock::now();
  const bool ego_ok = out.ego.valid;
  const int threads = params.num_threads > 0 ? params.num_threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (k > 1 && threads > 1)
  for (int c = 0; c < k; ++c) {
    ClusterEstimate& cluster = out.clusters[static_cast<std::size_t>(c)];
    cluster.id = c + 1;
    const std::vector<std::uint32_t> all = pixels_of(c + 1);
    cluster.num_pixels = static_cast<int>(all.size());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const std::uint32_t i : all) sum += scan.position(i);
    cluster.centroid_m = sum / static_cast<double>(all.size());
    if (!ego_ok) continue;
    VelocityRows rows;
    build_object_rows(scan, col_origin,
                      downsample(all, vp.object_max_points, mix_seed(frame_seed, static_cast<std::uint64_t>(c) + 1)),
                      out.ego.velocity_mps, rows);
    cluster.velocity = solve(rows, vp);
  }
  out.timing.objects_ms = ms_since(t_obj);
}

}  // namespace

MotionEstimate MotionPipeline::process_regions(const Scan& scan, std::uint64_t frame_index) {
  const VelocityParams& vp = params_.velocity;
  const bool fused = vp.solver == VelocitySolver::kClosedForm && vp.ego_max_points == 0 && vp.object_max_points == 0;
  // The fused path reads only valid, v and x, y, z; it checks v during segmentation and
  // x, y, z through its sums, and calls validate() only to name a bad pixel. Other paths check
  // every pixel first.
  if (fused) {
    scan.validate_layout();
  } else {
    scan.validate();
  }
  const auto t_start = Clock::now();
  MotionEstimate out = estimate_of(scan, params_.method);

  // Algorithm 1.
  Segmentation seg = segmenter_.segment(scan);
  out.labels = std::move(seg.labels);
  out.num_static_pixels = static_cast<int>(seg.static_pixels);
  out.timing.clustering_ms = ms_since(t_start);
  if (seg.num_regions == 0) {
    out.status = MotionStatus::kNoValidPoints;
    out.message = "scan has no valid pixels";
    out.timing.total_ms = ms_since(t_start);
    return out;
  }
  const int k = seg.num_clusters();
  const std::vector<Eigen::Vector3d> col_origin = column_origins(scan);
  out.clusters.resize(static_cast<std::size_t>(k));
  const std::size_t num_valid = scan.num_valid();
  const bool no_world = seg.static_pixels < params_.min_static_fraction * static_cast<double>(num_valid);

  if (fused) {
    fused_velocities(scan, seg, col_origin, no_world, params_, out);
  } else {
    published_velocities(scan, seg, col_origin, no_world, params_, frame_index, out);
  }

  for (ClusterEstimate& c : out.clusters) flag_meaningless(c.velocity, params_.max_valid_sigma_mps);

  if (no_world) {
    out.status = MotionStatus::kTooFewStaticPoints;
    out.message = no_static_world_message(out.num_static_pixels, num_valid, params_.min_static_fraction);
  } else if (!out.ego.valid) {
    out.status = MotionStatus::kTooFewStaticPoints;
    out.message = concat("ego velocity not estimable: ", out.num_static_pixels,
                         " static points (need >= 3 spanning 3 directions)");
  }
  out.timing.total_ms = ms_since(t_start);
  return out;
}

}  // namespace fmcw::core
