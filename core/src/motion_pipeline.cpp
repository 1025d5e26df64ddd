#include "fmcw/core/motion_pipeline.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "fmcw/core/check.hpp"
#include "fmcw/core/median.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/core/threads.hpp"

namespace fmcw::core {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

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
}  // namespace

void VelocityParams::validate() const {
  FMCW_CHECK_ARG(ego_max_points == 0 || ego_max_points >= 3,
                 "velocity: ego_max_points must be 0 (all) or >= 3, got ", ego_max_points);
  FMCW_CHECK_ARG(object_max_points == 0 || object_max_points >= 3,
                 "velocity: object_max_points must be 0 (all) or >= 3, got ", object_max_points);
  FMCW_CHECK_ARG(qr_condition_threshold >= 1.0, "velocity: qr_condition_threshold must be >= 1, got ",
                 qr_condition_threshold);
  FMCW_CHECK_ARG(ceres.max_iterations >= 1, "velocity: ceres.max_iterations must be >= 1");
}

void MotionPipelineParams::validate() const {
  segmentation.validate();
  velocity.validate();
  ego.validate();
  instances.validate();
  FMCW_CHECK_ARG(moving_sigma > 0.0, "pipeline: moving_sigma must be > 0, got ", moving_sigma);
  FMCW_CHECK_ARG(min_static_fraction >= 0.0 && min_static_fraction <= 1.0, "pipeline: min_static_fraction must be in [0, 1], got ",
                 min_static_fraction);
  FMCW_CHECK_ARG(num_threads >= 0 && num_threads <= kMaxThreads, "pipeline: num_threads (--threads) must be in [0, ", kMaxThreads,
                 "] (0: all cores), got ", num_threads);
  FMCW_CHECK_ARG(max_weak_sigma_mps > 0.0, "pipeline: max_weak_sigma_mps must be > 0, got ", max_weak_sigma_mps);
  FMCW_CHECK_ARG(!track_objects || approach == MotionApproach::kRobustEgo,
                 "pipeline: track_objects needs the robust-ego approach");
  tracking.validate();
}

MotionPipelineParams MotionPipelineParams::preset(const std::string& method) {
  MotionPipelineParams p;
  p.method = method;
  if (method == "paper") {
    p.segmentation.algorithm = RegionAlgorithm::kRegionGrowing;
    p.velocity.solver = VelocitySolver::kCeres;
    p.velocity.ego_max_points = 1000;
    p.velocity.object_max_points = 200;
  } else if (method == "robust") {
    p.approach = MotionApproach::kRobustEgo;
  } else if (method == "tracked") {
    p.approach = MotionApproach::kRobustEgo;
    p.track_objects = true;
    p.ego.lateral_velocity_sigma_mps = 0.1;  // a vehicle rig, its origin under the rear axle
  } else if (method == "fast") {
    p.velocity.solver = VelocitySolver::kClosedForm;
    p.velocity.ego_max_points = 0;
    p.velocity.object_max_points = 0;
  } else {
    std::string known;
    for (const auto& name : preset_names()) known += (known.empty() ? "" : ", ") + name;
    throw std::invalid_argument(concat("unknown method '", method, "' (known: ", known, ")"));
  }
  return p;
}

std::vector<std::string> MotionPipelineParams::preset_names() { return {"paper", "fast", "robust", "tracked"}; }

std::string MotionPipelineParams::default_method() { return "tracked"; }

std::string to_string(MotionStatus status) {
  switch (status) {
    case MotionStatus::kOk: return "ok";
    case MotionStatus::kNoValidPoints: return "no_valid_points";
    case MotionStatus::kTooFewStaticPoints: return "too_few_static_points";
  }
  return "unknown";
}

MotionPipeline::MotionPipeline(const MotionPipelineParams& params)
    : params_(params), segmenter_((params.validate(), params.segmentation)), tracker_(params.tracking) {}

namespace {

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

}  // namespace

namespace {

// Small instances that touch a larger one whose rigid motion explains their Doppler join it.
// rows[l - 1] holds instance l's rows (targets already ego-compensated). Returns whether any
// instance was merged; labels are updated in place (numbering may have gaps).
bool merge_fragments(const Scan& scan, const std::vector<VelocityRows>& rows, const std::vector<VelocityEstimate>& velocity,
                     const InstanceParams& params, std::vector<std::int32_t>& labels) {
  const int k = static_cast<int>(rows.size());
  std::vector<std::int32_t> target(static_cast<std::size_t>(k) + 1, 0);
  const std::vector<int> group_of = scan.column_group_of();
  // The largest instance touching each small one.
  for (int r = 0; r < scan.rows; ++r) {
    for (int c = 0; c < scan.cols; ++c) {
      const std::int32_t l = labels[scan.index(r, c)];
      if (l <= 0 || static_cast<int>(rows[static_cast<std::size_t>(l - 1)].size()) >= params.fragment_pixels) continue;
      for_each_neighbour(scan, group_of, r, c, [&](std::size_t n, int, int) {
        const std::int32_t m = labels[n];
        if (m <= 0 || m == l || rows[static_cast<std::size_t>(m - 1)].size() <= rows[static_cast<std::size_t>(l - 1)].size()) return;
        std::int32_t& t = target[static_cast<std::size_t>(l)];
        if (t == 0 || rows[static_cast<std::size_t>(m - 1)].size() > rows[static_cast<std::size_t>(t - 1)].size()) t = m;
      });
    }
  }
  bool merged = false;
  std::vector<double> residual;
  for (int l = 1; l <= k; ++l) {
    const std::int32_t t = target[static_cast<std::size_t>(l)];
    if (t == 0 || !velocity[static_cast<std::size_t>(t - 1)].valid) continue;
    const VelocityRows& rw = rows[static_cast<std::size_t>(l - 1)];
    const Eigen::Vector3d& v = velocity[static_cast<std::size_t>(t - 1)].velocity_mps;
    residual.clear();
    for (std::size_t q = 0; q < rw.size(); ++q) residual.push_back(std::abs(rw.targets_mps[q] - rw.directions[q].dot(v)));
    if (upper_median(residual) >= params.fragment_residual_mps) continue;
    target[static_cast<std::size_t>(l)] = -t;  // merge l into t
    merged = true;
  }
  if (!merged) return false;
  for (auto& lab : labels) {
    if (lab > 0 && target[static_cast<std::size_t>(lab)] < 0) lab = -target[static_cast<std::size_t>(lab)];
  }
  return true;
}

std::string no_static_world_message(int static_points, std::size_t valid, double min_fraction) {
  return concat("ego velocity not estimable: no static world in view (", static_points, " of ", valid,
                " valid points static, under the ", min_fraction * 100.0, " % minimum; is every point moving?)");
}

}  // namespace

MotionEstimate MotionPipeline::process_robust(const Scan& scan, std::uint64_t frame_index) {
  scan.validate();
  const auto t_start = Clock::now();
  MotionEstimate out;
  out.method = params_.method;
  out.rows = scan.rows;
  out.cols = scan.cols;
  if (scan.num_valid() == 0) {
    out.labels.assign(scan.size(), Segmentation::kInvalid);
    out.status = MotionStatus::kNoValidPoints;
    out.message = "scan has no valid pixels";
    out.timing.total_ms = ms_since(t_start);
    return out;
  }
  const std::uint64_t frame_seed = mix_seed(params_.seed, frame_index);
  // With tracking, the previous frame's twist bounds this one's (the rig's acceleration).
  TwistPrior prior;
  const double dt = scan.stamp_s - last_twist_stamp_s_;
  const bool use_prior = params_.track_objects && has_last_twist_ && dt > 0.0 && dt <= params_.tracking.max_gap_s;
  if (use_prior) {
    prior.velocity_mps = last_twist_velocity_;
    prior.yaw_rate_rps = last_twist_yaw_rate_;
    prior.max_velocity_change_mps = params_.tracking.ego_accel_mps2 * dt + params_.tracking.ego_velocity_margin_mps;
    prior.max_yaw_rate_change_rps = params_.tracking.ego_yaw_accel_rps2 * dt + params_.tracking.ego_yaw_rate_margin_rps;
  }
  EgoTwistEstimate twist = estimate_ego_twist(scan, params_.ego, frame_seed, use_prior ? &prior : nullptr);
  const std::size_t num_valid = scan.num_valid();
  const int world_points = twist.inliers;
  const bool no_world = twist.valid && world_points < params_.min_static_fraction * static_cast<double>(num_valid);
  if (no_world) twist = EgoTwistEstimate{};
  has_last_twist_ = twist.valid;
  last_twist_stamp_s_ = scan.stamp_s;
  last_twist_velocity_ = twist.velocity.velocity_mps;
  last_twist_yaw_rate_ = twist.angular_velocity_rps.z();
  out.ego = twist.velocity;
  out.ego_angular_velocity_rps = twist.angular_velocity_rps;
  out.ego_yaw_rate_estimated = twist.yaw_rate_estimated;
  out.ego_standing = twist.standing;
  out.timing.ego_ms = ms_since(t_start);

  // Moving: Doppler the ego twist does not explain, beyond noise and the twist's uncertainty.
  const auto t_cluster = Clock::now();
  const std::vector<Eigen::Vector3d> col_origin = column_origins(scan);
  std::vector<Eigen::Vector3d> head_velocity(static_cast<std::size_t>(scan.cols));
  for (int c = 0; c < scan.cols; ++c) head_velocity[static_cast<std::size_t>(c)] = twist.velocity_at(col_origin[static_cast<std::size_t>(c)]);
  const Eigen::Matrix3d cov = twist.velocity.covariance.allFinite() ? twist.velocity.covariance : Eigen::Matrix3d::Zero();
  const double sigma2 = params_.ego.noise_sigma_mps * params_.ego.noise_sigma_mps;
  std::vector<std::uint8_t> moving(scan.size(), 0);
  if (twist.valid) {
    for (int r = 0; r < scan.rows; ++r) {
      for (int c = 0; c < scan.cols; ++c) {
        const std::size_t i = scan.index(r, c);
        if (!scan.valid[i]) continue;
        const Eigen::Vector3d e = (scan.position(i) - col_origin[static_cast<std::size_t>(c)]).normalized();
        const double residual = scan.radial_velocity_mps[i] + e.dot(head_velocity[static_cast<std::size_t>(c)]);
        const double var = sigma2 + e.dot(cov * e);
        moving[i] = residual * residual > params_.moving_sigma * params_.moving_sigma * var ? 1 : 0;
      }
    }
  }
  Segmentation seg = label_moving_instances(scan, moving, params_.instances);
  out.labels = std::move(seg.labels);
  out.num_static_pixels = static_cast<int>(seg.static_pixels);
  out.timing.clustering_ms = ms_since(t_cluster);

  // Each instance's velocity (Eq. 22 with each head's own origin velocity V + omega x r).
  const auto t_obj = Clock::now();
  const auto solve_all = [&](int k, std::vector<VelocityRows>& rows, std::vector<Eigen::Vector3d>& centroid,
                             std::vector<VelocityEstimate>& velocity) {
    rows.assign(static_cast<std::size_t>(k), VelocityRows{});
    centroid.assign(static_cast<std::size_t>(k), Eigen::Vector3d::Zero());
    velocity.assign(static_cast<std::size_t>(k), VelocityEstimate{});
    for (int r = 0; r < scan.rows; ++r) {
      for (int c = 0; c < scan.cols; ++c) {
        const std::size_t i = scan.index(r, c);
        const std::int32_t l = out.labels[i];
        if (l <= 0) continue;
        const Eigen::Vector3d p = scan.position(i);
        const Eigen::Vector3d e = (p - col_origin[static_cast<std::size_t>(c)]).normalized();
        VelocityRows& rw = rows[static_cast<std::size_t>(l - 1)];
        rw.directions.push_back(e);
        rw.targets_mps.push_back(scan.radial_velocity_mps[i] + e.dot(head_velocity[static_cast<std::size_t>(c)]));
        centroid[static_cast<std::size_t>(l - 1)] += p;
      }
    }
    if (!twist.valid) return;
    for (int c = 0; c < k; ++c) {
      const VelocityRows& rw = rows[static_cast<std::size_t>(c)];
      velocity[static_cast<std::size_t>(c)] = params_.planar_objects
                                                  ? solve_velocity_planar_robust(rw, params_.ego.noise_sigma_mps)
                                                  : solve_velocity_closed_form(rw, params_.velocity.qr_condition_threshold);
    }
  };
  int k = seg.num_clusters();
  std::vector<VelocityRows> rows;
  std::vector<Eigen::Vector3d> centroid;
  std::vector<VelocityEstimate> velocity;
  solve_all(k, rows, centroid, velocity);
  if (twist.valid && k > 1 && merge_fragments(scan, rows, velocity, params_.instances, out.labels)) {
    // Renumber by first pixel and solve the merged instances again.
    std::vector<std::int32_t> renumber(static_cast<std::size_t>(k) + 1, 0);
    std::int32_t next = 0;
    for (auto& l : out.labels) {
      if (l <= 0) continue;
      if (renumber[static_cast<std::size_t>(l)] == 0) renumber[static_cast<std::size_t>(l)] = ++next;
      l = renumber[static_cast<std::size_t>(l)];
    }
    k = next;
    solve_all(k, rows, centroid, velocity);
  }
  out.clusters.resize(static_cast<std::size_t>(k));
  for (int c = 0; c < k; ++c) {
    ClusterEstimate& cluster = out.clusters[static_cast<std::size_t>(c)];
    cluster.id = c + 1;
    cluster.num_pixels = static_cast<int>(rows[static_cast<std::size_t>(c)].size());
    cluster.centroid_m = centroid[static_cast<std::size_t>(c)] / static_cast<double>(cluster.num_pixels);
    cluster.velocity = velocity[static_cast<std::size_t>(c)];
  }
  out.timing.objects_ms = ms_since(t_obj);
  if (no_world) {
    out.status = MotionStatus::kTooFewStaticPoints;
    out.message = no_static_world_message(world_points, num_valid, params_.min_static_fraction);
  } else if (!twist.valid) {
    out.status = MotionStatus::kTooFewStaticPoints;
    out.message = concat("ego velocity not estimable: ", twist.inliers, " points consistent with a static world");
  }
  out.timing.total_ms = ms_since(t_start);
  return out;
}

MotionEstimate MotionPipeline::process(const Scan& scan, std::uint64_t frame_index) {
  if (params_.approach == MotionApproach::kRobustEgo) {
    MotionEstimate out = process_robust(scan, frame_index);
    if (params_.track_objects) {
      const auto t0 = Clock::now();
      tracker_.update(scan, out);
      const double ms = ms_since(t0);
      out.timing.objects_ms += ms;
      out.timing.total_ms += ms;
    }
    // What one scan reports for an object without a track: a direction its fit hardly
    // observes zeroed. The tracker takes the fits as they are and caps their weak direction
    // itself; a track reports its own estimate.
    if (params_.planar_objects) {
      for (ClusterEstimate& ce : out.clusters) {
        if (ce.track_id == 0) zero_unobserved_direction(ce.velocity, params_.ego.noise_sigma_mps, params_.max_weak_sigma_mps);
      }
    }
    return out;
  }
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
  MotionEstimate out;
  out.method = params_.method;
  out.rows = scan.rows;
  out.cols = scan.cols;

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
    const int threads = params_.num_threads > 0 ? params_.num_threads : omp_get_max_threads();
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
  } else {
    // Algorithm 2 as published: random subsets of at most num_th^s and num_th^m points.
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
    const std::uint64_t frame_seed = mix_seed(params_.seed, frame_index);
    {
      VelocityRows rows;
      build_ego_rows(scan, col_origin, downsample(pixels_of(0), vp.ego_max_points, mix_seed(frame_seed, 0)), rows);
      out.ego = no_world ? VelocityEstimate{} : solve(rows, vp);
    }
    out.timing.ego_ms = ms_since(t_ego);

    // Lines 4-10: each moving cluster (Eq. 22), in parallel, one seed per cluster.
    const auto t_obj = Clock::now();
    const bool ego_ok = out.ego.valid;
    const int threads = params_.num_threads > 0 ? params_.num_threads : omp_get_max_threads();
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
