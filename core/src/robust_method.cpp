// The robust methods (robust, tracked): the ego twist first, moving = the points it does not
// explain, instances by range and Doppler continuity, each instance's velocity in closed form.

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include "ego_twist_beams.hpp"
#include "fmcw/core/median.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/random.hpp"
#include "label_renumbering.hpp"
#include "pipeline_internal.hpp"
#include "pipeline_workspace.hpp"
#include "pixel_lists.hpp"
#include "vector_clones.hpp"

namespace fmcw::core {

namespace {

// Small instances that touch a larger one whose rigid motion explains their Doppler join it.
// rows[l - 1] holds instance l's rows (targets already ego-compensated). Returns whether any
// instance was merged; labels are updated in place (numbering may have gaps), and grew[l] is 1
// for each instance l that took a fragment. labelled: the pixels with a positive label,
// ascending.
bool merge_fragments(const Scan& scan, const std::vector<VelocityRows>& rows, const std::vector<VelocityEstimate>& velocity,
                     const InstanceParams& params, const std::vector<std::uint32_t>& labelled,
                     std::vector<std::int32_t>& labels, std::vector<std::uint8_t>& grew) {
  const int k = static_cast<int>(rows.size());
  std::vector<std::int32_t> target(static_cast<std::size_t>(k) + 1, 0);
  const std::vector<int> group_of = scan.column_group_of();
  const auto cols = static_cast<std::uint32_t>(scan.cols);
  // The largest instance touching each small one.
  for (const std::uint32_t i : labelled) {
    const std::int32_t l = labels[i];
    if (static_cast<int>(rows[static_cast<std::size_t>(l - 1)].size()) >= params.fragment_pixels) continue;
    for_each_neighbour(scan, group_of, static_cast<int>(i / cols), static_cast<int>(i % cols), [&](std::size_t n, int, int) {
      const std::int32_t m = labels[n];
      if (m <= 0 || m == l || rows[static_cast<std::size_t>(m - 1)].size() <= rows[static_cast<std::size_t>(l - 1)].size()) return;
      std::int32_t& t = target[static_cast<std::size_t>(l)];
      if (t == 0 || rows[static_cast<std::size_t>(m - 1)].size() > rows[static_cast<std::size_t>(t - 1)].size()) t = m;
    });
  }
  bool merged = false;
  std::vector<double> residual;
  std::vector<std::uint64_t> keys;
  for (int l = 1; l <= k; ++l) {
    const std::int32_t t = target[static_cast<std::size_t>(l)];
    if (t == 0 || !velocity[static_cast<std::size_t>(t - 1)].valid) continue;
    const VelocityRows& rw = rows[static_cast<std::size_t>(l - 1)];
    const Eigen::Vector3d& v = velocity[static_cast<std::size_t>(t - 1)].velocity_mps;
    residual.resize(rw.size());
    for (std::size_t q = 0; q < rw.size(); ++q) residual[q] = std::abs(rw.targets_mps[q] - rw.directions[q].dot(v));
    if (upper_median_of_magnitudes(residual, keys) >= params.fragment_residual_mps) continue;
    target[static_cast<std::size_t>(l)] = -t;  // merge l into t
    grew[static_cast<std::size_t>(t)] = 1;
    merged = true;
  }
  if (!merged) return false;
  for (const std::uint32_t i : labelled) {
    std::int32_t& lab = labels[i];
    if (target[static_cast<std::size_t>(lab)] < 0) lab = -target[static_cast<std::size_t>(lab)];
  }
  return true;
}



// Per pixel of one image row: 1 where the Doppler, compensated by the velocity of its head's
// origin (hx, hy, hz per column), exceeds ms2 = moving_sigma^2 variances, the variance being the
// sensor's sigma2 and the twist's covariance c (row-major) along the beam. The sums run in the
// order Eigen's e.dot(h) and e.dot(cov * e) take (the results are the same bit for bit).
FMCW_VECTOR_CLONES void moving_row(std::size_t cols, const std::uint8_t* valid, const float* v, const double* ex,
                                   const double* ey, const double* ez, const double* hx, const double* hy,
                                   const double* hz, const double (&c)[9], double sigma2, double ms2,
                                   std::uint8_t* moving) {
  for (std::size_t k = 0; k < cols; ++k) {
    const double e0 = ex[k], e1 = ey[k], e2 = ez[k];
    const double residual = static_cast<double>(v[k]) + ((e0 * hx[k] + e1 * hy[k]) + e2 * hz[k]);
    const double c0 = c[0] * e0 + c[1] * e1 + c[2] * e2;
    const double c1 = c[3] * e0 + c[4] * e1 + c[5] * e2;
    const double c2 = c[6] * e0 + (c[7] * e1 + c[8] * e2);
    const double var = sigma2 + ((e0 * c0 + e1 * c1) + e2 * c2);
    moving[k] = (valid[k] != 0) & (residual * residual > ms2 * var) ? 1 : 0;
  }
}

// Pixel i's Doppler compensated by the velocity h of its head's origin: what the ego twist does
// not explain (moving_row's residual, one pixel at a time).
double doppler_residual(const Scan& scan, const ScanBeams& beams, const Eigen::Vector3d& h,
                        std::size_t i) {
  return static_cast<double>(scan.radial_velocity_mps[i]) + beams.e(i).dot(h);
}

// The range band of a pixel (MotionPipelineParams::range_noise_band_m > 0).
std::size_t range_band(float range_m, const MotionPipelineParams& params) {
  const auto bands = static_cast<std::size_t>(params.range_noise_bands);
  return std::min(bands - 1, static_cast<std::size_t>(static_cast<double>(range_m) /
                                                      params.range_noise_band_m));
}

// The spread of [first, last) (reordered): its median |residual| over a unit normal's, or 0
// where that is within range_noise_margin times the nominal sigma.
double noise_spread(float* first, float* last, const MotionPipelineParams& params) {
  constexpr double kNormalMedian = 0.6744897501960817;  // P(|x| < q) = 1/2, unit normal
  float* q = first + (last - first) / 2;
  std::nth_element(first, q, last);
  const double s = static_cast<double>(*q) / kNormalMedian;
  return s > params.range_noise_margin * params.ego.noise_sigma_mps ? s : 0.0;
}

// Whether any range band shows more noise than the nominal, in every fourth row (in bands of
// range_noise_min_pixels there or more): the root mean square of the residuals within the
// nominal threshold (`moving` 0). Not robust, but cheap: where what moves inflates it, the
// robust spreads of cell_sigmas decide; a sensor whose noise is the nominal one everywhere costs
// no more than this pass.
bool any_band_noisier(const Scan& scan, const ScanBeams& beams,
                      const std::vector<Eigen::Vector3d>& head_velocity,
                      const std::vector<std::uint8_t>& moving, const MotionPipelineParams& params) {
  const auto bands = static_cast<std::size_t>(params.range_noise_bands);
  const auto cols = static_cast<std::size_t>(scan.cols);
  std::vector<double> sum_sq(bands, 0.0);
  std::vector<std::size_t> count(bands, 0);
  for (std::size_t r = 0; r < static_cast<std::size_t>(scan.rows); r += 4) {
    for (std::size_t c = 0; c < cols; ++c) {
      const std::size_t i = r * cols + c;
      if (!scan.valid[i] || moving[i] != 0) continue;
      const double res = doppler_residual(scan, beams, head_velocity[c], i);
      const std::size_t b = range_band(scan.range_m[i], params);
      sum_sq[b] += res * res;
      ++count[b];
    }
  }
  const double limit = params.range_noise_margin * params.ego.noise_sigma_mps;
  for (std::size_t b = 0; b < bands; ++b) {
    if (count[b] >= static_cast<std::size_t>(params.range_noise_min_pixels) &&
        sum_sq[b] > limit * limit * static_cast<double>(count[b]))
      return true;
  }
  return false;
}

// The sensor's sigma where the static world shows more noise than the nominal
// (MotionPipelineParams::range_noise_band_m), per cell of one image row and one range band (a
// row sees a surface at about one incidence there: the ground at a grazing angle, a wall), or,
// in a cell of too few pixels, of the band's pixels in every row: the spread of the residuals of
// the pixels within the threshold (the nominal one, then the cell's), so that what moves does
// not count. Every other column is counted (half the pixels measure a spread as well).
// Indexed by row * range_noise_bands + band; 0 where a cell shows no more than the nominal;
// empty where none does (and where no band does in any_band_noisier).
std::vector<double> cell_sigmas(const Scan& scan, const ScanBeams& beams,
                                const std::vector<Eigen::Vector3d>& head_velocity,
                                const Eigen::Matrix3d& cov, const std::vector<std::uint8_t>& moving,
                                const MotionPipelineParams& params) {
  if (!(params.range_noise_band_m > 0.0) ||
      !any_band_noisier(scan, beams, head_velocity, moving, params))
    return {};
  const auto bands = static_cast<std::size_t>(params.range_noise_bands);
  const auto cols = static_cast<std::size_t>(scan.cols);
  const auto rows = static_cast<std::size_t>(scan.rows);
  const auto min_pixels = static_cast<std::size_t>(params.range_noise_min_pixels);
  const double nominal = params.ego.noise_sigma_mps;
  const double ms2 = params.moving_sigma * params.moving_sigma;
  // Each counted pixel: |residual|, the twist's variance along its beam, and its cell.
  std::vector<float> spread, twist_var;
  std::vector<std::uint32_t> cell_of;
  spread.reserve(scan.size() / 2 + 1);
  twist_var.reserve(scan.size() / 2 + 1);
  cell_of.reserve(scan.size() / 2 + 1);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < cols; c += 2) {
      const std::size_t i = r * cols + c;
      if (!scan.valid[i]) continue;
      const Eigen::Vector3d e = beams.e(i);
      spread.push_back(
          static_cast<float>(std::abs(doppler_residual(scan, beams, head_velocity[c], i))));
      twist_var.push_back(static_cast<float>(e.dot(cov * e)));
      cell_of.push_back(
          static_cast<std::uint32_t>(r * bands + range_band(scan.range_m[i], params)));
    }
  }
  const std::size_t cells = rows * bands;
  std::vector<double> sigma(cells, 0.0);
  std::vector<std::size_t> start(cells + 1);
  std::vector<float> within(spread.size()), band;
  bool any = false;
  for (int pass = 0; pass < 2; ++pass) {
    // The pixels within the threshold, grouped by cell (a counting sort).
    const auto inside = [&](std::size_t n) {
      const double s = std::max(nominal, sigma[cell_of[n]]);
      const double r = spread[n];
      return r * r <= ms2 * (s * s + twist_var[n]);
    };
    std::fill(start.begin(), start.end(), 0);
    for (std::size_t n = 0; n < spread.size(); ++n) start[cell_of[n] + 1] += inside(n) ? 1 : 0;
    for (std::size_t k = 0; k < cells; ++k) start[k + 1] += start[k];
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t n = 0; n < spread.size(); ++n) {
      if (inside(n)) within[next[cell_of[n]]++] = spread[n];
    }
    any = false;
    for (std::size_t b = 0; b < bands; ++b) {
      band.clear();
      for (std::size_t r = 0; r < rows; ++r) {
        band.insert(band.end(), within.begin() + static_cast<std::ptrdiff_t>(start[r * bands + b]),
                    within.begin() + static_cast<std::ptrdiff_t>(start[r * bands + b + 1]));
      }
      const double whole = band.size() >= min_pixels
                               ? noise_spread(band.data(), band.data() + band.size(), params)
                               : 0.0;
      for (std::size_t r = 0; r < rows; ++r) {
        const std::size_t k = r * bands + b;
        const bool own = start[k + 1] - start[k] >= min_pixels;
        sigma[k] =
            own ? noise_spread(within.data() + start[k], within.data() + start[k + 1], params)
                : whole;
        any = any || sigma[k] > 0.0;
      }
    }
    if (!any) break;
  }
  if (!any) sigma.clear();
  return sigma;
}

std::vector<std::uint8_t> moving_mask(const Scan& scan, const ScanBeams& beams, const std::vector<Eigen::Vector3d>& head_velocity,
                                      const EgoTwistEstimate& twist, const MotionPipelineParams& params) {
  std::vector<std::uint8_t> moving(scan.size(), 0);
  if (!twist.valid || scan.size() == 0) return moving;
  const Eigen::Matrix3d cov = twist.velocity.covariance.allFinite() ? twist.velocity.covariance : Eigen::Matrix3d::Zero();
  const double c[9] = {cov(0, 0), cov(0, 1), cov(0, 2), cov(1, 0), cov(1, 1), cov(1, 2), cov(2, 0), cov(2, 1), cov(2, 2)};
  const double sigma2 = params.ego.noise_sigma_mps * params.ego.noise_sigma_mps;
  const double ms2 = params.moving_sigma * params.moving_sigma;
  const std::size_t cols = static_cast<std::size_t>(scan.cols);
  std::vector<double> hx(cols), hy(cols), hz(cols);
  for (std::size_t k = 0; k < cols; ++k) {
    hx[k] = head_velocity[k].x();
    hy[k] = head_velocity[k].y();
    hz[k] = head_velocity[k].z();
  }
  for (int r = 0; r < scan.rows; ++r) {
    const std::size_t first = scan.index(r, 0);
    moving_row(cols, scan.valid.data() + first, scan.radial_velocity_mps.data() + first, beams.ex.data() + first,
               beams.ey.data() + first, beams.ez.data() + first, hx.data(), hy.data(), hz.data(), c, sigma2, ms2,
               moving.data() + first);
  }
  // Where a cell's noise exceeds the nominal, its moving pixels are tested against it instead.
  const std::vector<double> cell_sigma =
      cell_sigmas(scan, beams, head_velocity, cov, moving, params);
  if (cell_sigma.empty()) return moving;
  const auto bands = static_cast<std::size_t>(params.range_noise_bands);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (moving[i] == 0) continue;
    const double s = cell_sigma[(i / cols) * bands + range_band(scan.range_m[i], params)];
    if (s == 0.0) continue;
    const Eigen::Vector3d e = beams.e(i);
    const double residual = doppler_residual(scan, beams, head_velocity[i % cols], i);
    moving[i] = residual * residual > ms2 * (s * s + e.dot(cov * e)) ? 1 : 0;
  }
  return moving;
}

// Rows (ego-compensated), centroid sums and, with an ego, velocities of the k instances.
struct Instances {
  std::vector<VelocityRows> rows;
  std::vector<Eigen::Vector3d> centroid;
  std::vector<VelocityEstimate> velocity;
};

// labelled: the pixels with a positive label, ascending. With redo non-empty, only the
// instances l with redo[l - 1] are built and solved; the others keep what in holds.
void solve_all(const Scan& scan, const ScanBeams& beams, const std::vector<Eigen::Vector3d>& head_velocity, bool with_ego,
               int k, const MotionPipelineParams& params, const std::vector<std::int32_t>& labels,
               const std::vector<std::uint32_t>& labelled, const std::vector<std::uint8_t>& redo, Instances& in) {
  const auto todo = [&](std::size_t c) { return redo.empty() || redo[c] != 0; };
  in.rows.resize(static_cast<std::size_t>(k));
  in.centroid.resize(static_cast<std::size_t>(k));
  in.velocity.resize(static_cast<std::size_t>(k));
  // Each instance's pixels in image order: counted first, then written in place.
  std::vector<std::size_t> fill(static_cast<std::size_t>(k), 0);
  for (const std::uint32_t i : labelled) ++fill[static_cast<std::size_t>(labels[i] - 1)];
  for (std::size_t c = 0; c < fill.size(); ++c) {
    if (todo(c)) {
      in.rows[c].directions.resize(fill[c]);
      in.rows[c].targets_mps.resize(fill[c]);
      in.centroid[c].setZero();
      in.velocity[c] = VelocityEstimate{};
    }
    fill[c] = 0;
  }
  for (const std::uint32_t i : labelled) {
    const auto c = static_cast<std::size_t>(labels[i] - 1);
    if (!todo(c)) continue;
    const Eigen::Vector3d e = beams.e(i);
    VelocityRows& rw = in.rows[c];
    const std::size_t q = fill[c]++;
    rw.directions[q] = e;
    rw.targets_mps[q] = scan.radial_velocity_mps[i] + e.dot(head_velocity[i % beams.cols]);
    in.centroid[c] += scan.position(i);
  }
  if (!with_ego) return;
  for (std::size_t c = 0; c < static_cast<std::size_t>(k); ++c) {
    if (!todo(c)) continue;
    const VelocityRows& rw = in.rows[c];
    in.velocity[c] = params.planar_objects ? solve_velocity_planar_robust(rw, params.ego.noise_sigma_mps)
                                           : solve_velocity_closed_form(rw, params.velocity.qr_condition_threshold);
  }
}

// Every instance's velocity; small fragments that a larger neighbour's motion explains are
// merged into it first (labels renumbered by first pixel).
std::vector<ClusterEstimate> solve_instances(const Scan& scan, const ScanBeams& beams, const std::vector<Eigen::Vector3d>& head_velocity,
                                             bool with_ego, int k, const MotionPipelineParams& params,
                                             std::vector<std::int32_t>& labels) {
  Instances in;
  // Merging relabels instances but keeps the set of labelled pixels.
  std::vector<std::uint32_t> labelled;
  list_pixels(labels.size(), [&](std::size_t i) { return labels[i] > 0; }, labelled);
  solve_all(scan, beams, head_velocity, with_ego, k, params, labels, labelled, {}, in);
  std::vector<std::uint8_t> grew(static_cast<std::size_t>(k) + 1, 0);
  if (with_ego && k > 1 && merge_fragments(scan, in.rows, in.velocity, params.instances, labelled, labels, grew)) {
    const std::vector<std::int32_t>& old = labels;
    const std::vector<std::int32_t> key_of_new = renumber_listed_by_first_pixel(
        labels, labelled, static_cast<std::size_t>(k) + 1, [&](std::size_t i) { return old[i]; });
    // An instance that took no fragment has the same rows in the same order: it keeps its
    // solution (moved to its new number, which is never above its old one).
    k = static_cast<int>(key_of_new.size()) - 1;
    std::vector<std::uint8_t> redo(static_cast<std::size_t>(k));
    for (std::size_t l = 1; l < key_of_new.size(); ++l) {
      const auto from = static_cast<std::size_t>(key_of_new[l]);
      redo[l - 1] = grew[from];
      if (redo[l - 1] != 0 || from == l) continue;
      in.rows[l - 1] = std::move(in.rows[from - 1]);
      in.centroid[l - 1] = in.centroid[from - 1];
      in.velocity[l - 1] = in.velocity[from - 1];
    }
    solve_all(scan, beams, head_velocity, with_ego, k, params, labels, labelled, redo, in);
  }
  std::vector<ClusterEstimate> clusters(static_cast<std::size_t>(k));
  for (int c = 0; c < k; ++c) {
    ClusterEstimate& cluster = clusters[static_cast<std::size_t>(c)];
    cluster.id = c + 1;
    cluster.num_pixels = static_cast<int>(in.rows[static_cast<std::size_t>(c)].size());
    cluster.centroid_m = in.centroid[static_cast<std::size_t>(c)] / static_cast<double>(cluster.num_pixels);
    cluster.velocity = in.velocity[static_cast<std::size_t>(c)];
  }
  return clusters;
}

// Why a frame whose window held no world has no ego velocity: the fit without the window lay
// too far from the last twist.
std::string rejected_fallback_message(const EgoTwistEstimate& twist, const TwistPrior& prior,
                                      double dt, double windows) {
  std::ostringstream m;
  const Eigen::Vector3d& v = twist.rejected_velocity_mps;
  m << std::fixed << std::setprecision(2) << "ego velocity not estimable: " << twist.inliers
    << " sampled points are consistent with a static world within " << prior.max_velocity_change_mps
    << " m/s of the last estimate (" << dt << " s before); the fit without that bound (" << v.x()
    << ", " << v.y() << ", " << v.z() << " m/s, " << twist.rejected_inliers << " points) lies "
    << (v - prior.velocity_mps).norm() << " m/s from it, over " << windows
    << " times that: taken for traffic filling the view, not for the world";
  return m.str();
}

}  // namespace

MotionEstimate MotionPipeline::process_robust(const Scan& scan, std::uint64_t frame_index) {
  scan.validate();
  const auto t_start = Clock::now();
  MotionEstimate out = estimate_of(scan, params_.method);
  if (scan.num_valid() == 0) {
    out.labels.assign(scan.size(), Segmentation::kInvalid);
    out.status = MotionStatus::kNoValidPoints;
    out.message = "scan has no valid pixels";
    out.timing.total_ms = ms_since(t_start);
    return out;
  }
  const std::uint64_t frame_seed = mix_seed(params_.seed, frame_index);
  // With tracking, the last twist bounds this one's (the rig's acceleration since). Held through
  // frames without one, it bounds them all until the world shows again.
  TwistPrior prior;
  const TwistPriorParams& pp = params_.ego_prior;
  const double dt = scan.stamp_s - last_twist_stamp_s_;
  const bool continues = has_last_twist_ && dt > 0.0;
  const bool use_prior = params_.track_objects && continues &&
                         (pp.hold_across_failures || dt <= params_.tracking.lifecycle.max_gap_s);
  if (use_prior) {
    prior.velocity_mps = last_twist_velocity_;
    prior.yaw_rate_rps = last_twist_yaw_rate_;
    prior.max_velocity_change_mps = pp.accel_mps2 * dt + pp.velocity_margin_mps;
    prior.max_yaw_rate_change_rps = pp.yaw_accel_rps2 * dt + pp.yaw_rate_margin_rps;
    prior.max_fallback_change_mps = pp.fallback_max_windows * prior.max_velocity_change_mps;
  }
  PipelineWorkspace& ws = buffers_.get();
  ws.beams.assign(scan);
  const ScanBeams& beams = ws.beams;
  EgoTwistEstimate twist = estimate_ego_twist(scan, beams, params_.ego, frame_seed, use_prior ? &prior : nullptr, ws.ego);
  const std::size_t num_valid = scan.num_valid();
  const int world_points = twist.inliers;
  const bool no_world = twist.valid && world_points < params_.min_static_fraction * static_cast<double>(num_valid);
  if (no_world) twist = EgoTwistEstimate{};
  if (twist.valid || !pp.hold_across_failures || !continues) {
    has_last_twist_ = twist.valid;
    last_twist_stamp_s_ = scan.stamp_s;
    last_twist_velocity_ = twist.velocity.velocity_mps;
    last_twist_yaw_rate_ = twist.angular_velocity_rps.z();
  }
  out.ego = twist.velocity;
  out.ego_angular_velocity_rps = twist.angular_velocity_rps;
  out.ego_yaw_rate_estimated = twist.yaw_rate_estimated;
  out.ego_standing = twist.standing;
  out.timing.ego_ms = ms_since(t_start);

  // Moving: Doppler the ego twist does not explain, beyond noise and the twist's uncertainty.
  const auto t_cluster = Clock::now();
  std::vector<Eigen::Vector3d> head_velocity(static_cast<std::size_t>(scan.cols));
  for (int c = 0; c < scan.cols; ++c) head_velocity[static_cast<std::size_t>(c)] = twist.velocity_at(beams.origin[static_cast<std::size_t>(c)]);
  const std::vector<std::uint8_t> moving = moving_mask(scan, beams, head_velocity, twist, params_);
  Segmentation seg = label_moving_instances(scan, moving, params_.instances);
  join_instances_across_heads(scan, seg, params_.instances);
  out.labels = std::move(seg.labels);
  out.num_static_pixels = static_cast<int>(seg.static_pixels);
  out.timing.clustering_ms = ms_since(t_cluster);

  // Each instance's velocity (Eq. 22 with each head's own origin velocity V + omega x r).
  const auto t_obj = Clock::now();
  out.clusters = solve_instances(scan, beams, head_velocity, twist.valid, seg.num_clusters(), params_, out.labels);
  out.timing.objects_ms = ms_since(t_obj);
  if (no_world) {
    out.status = MotionStatus::kTooFewStaticPoints;
    out.message = no_static_world_message(world_points, num_valid, params_.min_static_fraction);
  } else if (twist.fallback_rejected) {
    out.status = MotionStatus::kTooFewStaticPoints;
    out.message = rejected_fallback_message(twist, prior, dt, pp.fallback_max_windows);
  } else if (!twist.valid) {
    out.status = MotionStatus::kTooFewStaticPoints;
    out.message = concat("ego velocity not estimable: ", twist.inliers, " points consistent with a static world");
  }
  out.timing.total_ms = ms_since(t_start);
  return out;
}

}  // namespace fmcw::core
