#include "fmcw/eval/blind_zone_study.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>

#include "fmcw/core/check.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/eval/evaluator.hpp"
#include "fmcw/eval/motion_confusion.hpp"

namespace fmcw::eval {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Fraction of the actor's (instance 1) valid pixels labelled moving.
double actor_recall(const core::Frame& frame, const std::vector<std::int32_t>& labels, int& pixels) {
  const core::PixelGroundTruth& gt = *frame.truth;
  int hit = 0;
  pixels = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (!frame.scan.valid[i] || gt.instance[i] != 1) continue;
    ++pixels;
    if (label_is_moving(labels[i])) ++hit;
  }
  return pixels == 0 ? kNaN : static_cast<double>(hit) / pixels;
}

// Smallest |true Doppler difference| between an actor pixel and a valid static 8-neighbour.
double silhouette_min_doppler(const core::Frame& frame) {
  const core::Scan& s = frame.scan;
  const core::PixelGroundTruth& gt = *frame.truth;
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < s.rows; ++r) {
    for (int c = 0; c < s.cols; ++c) {
      const std::size_t i = s.index(r, c);
      if (!s.valid[i] || gt.instance[i] != 1) continue;
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if ((dr == 0 && dc == 0) || rr < 0 || cc < 0 || rr >= s.rows || cc >= s.cols) continue;
          const std::size_t j = s.index(rr, cc);
          if (!s.valid[j] || gt.instance[j] != 0) continue;
          best = std::min(best, std::abs(static_cast<double>(gt.radial_velocity_mps[i]) - gt.radial_velocity_mps[j]));
        }
      }
    }
  }
  return best;
}

class SampleRunner {
 public:
  // Serial inside (one thread each): samples run in parallel instead, one runner per thread.
  SampleRunner(const BlindZoneSceneParams& scene, const BlindZoneStudyParams& params,
               const std::vector<std::string>& methods)
      : scene_(scene), params_(params) {
    scene_.num_threads = 1;
    for (const std::string& m : methods) {
      core::MotionPipelineParams p = core::MotionPipelineParams::preset(m);
      p.segmentation.velocity_threshold_mps = params.velocity_threshold_mps;
      p.num_threads = 1;
      pipelines_.emplace_back(p);
    }
  }

  BlindZoneSample run(std::uint64_t case_seed, double speed, double distance, double phi) {
    const std::uint64_t frame_index =
        core::mix_seed(case_seed, static_cast<std::uint64_t>(std::llround(phi * 1e6) + (1LL << 40)));
    if (!simulator_ || simulator_distance_ != distance) {
      simulator_ = std::make_unique<BlindZoneSimulator>(scene_, distance);
      simulator_distance_ = distance;
    }
    core::Frame frame = simulator_->simulate(speed, phi, frame_index);
    BlindZoneSample s;
    s.speed_mps = speed;
    s.distance_m = distance;
    s.phi_deg = phi;
    s.silhouette_min_doppler_mps = silhouette_min_doppler(frame);
    for (core::MotionPipeline& p : pipelines_) {
      s.recall.push_back(actor_recall(frame, p.process(frame.scan).labels, s.object_pixels));
    }
    if (params_.noise_free_too) {
      for (std::size_t i = 0; i < frame.scan.size(); ++i) {
        if (frame.scan.valid[i]) frame.scan.radial_velocity_mps[i] = frame.truth->radial_velocity_mps[i];
      }
      int pixels = 0;
      for (core::MotionPipeline& p : pipelines_) {
        s.recall_noise_free.push_back(actor_recall(frame, p.process(frame.scan).labels, pixels));
      }
    }
    if (s.object_pixels == 0) {
      throw std::runtime_error("blind zone: the actor at " + std::to_string(distance) + " m, phi " +
                               std::to_string(phi) + " deg has no valid pixel");
    }
    return s;
  }

 private:
  BlindZoneSceneParams scene_;
  std::unique_ptr<BlindZoneSimulator> simulator_;
  double simulator_distance_ = 0.0;
  const BlindZoneStudyParams& params_;
  std::vector<core::MotionPipeline> pipelines_;
};

// The curves whose edges are refined and reported: noisy and noise-free recall of the first
// method, and the silhouette prediction (1 = separable, 0 = blind).
std::vector<double> curve(const std::map<long long, BlindZoneSample>& samples, int which, std::size_t method,
                          double v_th) {
  std::vector<double> out;
  for (const auto& [key, s] : samples) {
    if (which == 0) out.push_back(s.recall[method]);
    if (which == 1) out.push_back(s.recall_noise_free[method]);
    if (which == 2) out.push_back(s.silhouette_min_doppler_mps >= v_th ? 1.0 : 0.0);
  }
  return out;
}

std::vector<double> angles(const std::map<long long, BlindZoneSample>& samples) {
  std::vector<double> out;
  for (const auto& [key, s] : samples) out.push_back(s.phi_deg);
  return out;
}
}  // namespace

void BlindZoneStudyParams::validate() const {
  FMCW_CHECK_ARG(!speeds_mps.empty() && !targets.empty(), "blind zone: need at least one speed and one target");
  for (const double v : speeds_mps) FMCW_CHECK_ARG(v > 0.0 && std::isfinite(v), "blind zone: speed ", v, " must be > 0");
  for (const BlindZoneTarget& t : targets) {
    FMCW_CHECK_ARG(!t.name.empty() && t.name.find_first_of(", \n\"") == std::string::npos,
                   "blind zone: target name '", t.name, "' must be a non-empty word");
    FMCW_CHECK_ARG(!t.distances_m.empty(), "blind zone: target '", t.name, "' has no distance");
    for (const double d : t.distances_m) {
      FMCW_CHECK_ARG(d >= 3.0 && d <= 140.0, "blind zone: distance ", d, " m must be in [3, 140] m (the head sees 150 m)");
    }
    BlindZoneSceneParams sc = scene;
    sc.box_size_m = t.box_size_m;
    sc.validate();
    FMCW_CHECK_FILE(t.mesh.empty() || std::filesystem::is_regular_file(t.mesh), "blind zone: mesh '", t.mesh,
                    "' does not exist");
  }
  FMCW_CHECK_ARG(phi_step_deg > 0.0 && phi_step_deg <= 1.0, "blind zone: phi_step_deg must be in (0, 1], got ", phi_step_deg);
  FMCW_CHECK_ARG(fine_step_deg > 0.0 && fine_step_deg <= phi_step_deg, "blind zone: fine_step_deg must be in (0, ",
                 "phi_step_deg], got ", fine_step_deg);
  FMCW_CHECK_ARG(phi_min_deg >= 0.0 && phi_max_deg <= 180.0 && phi_min_deg < phi_max_deg,
                 "blind zone: need 0 <= phi_min_deg < phi_max_deg <= 180");
  FMCW_CHECK_ARG(fine_margin_deg >= 0.0, "blind zone: fine_margin_deg must be >= 0");
  FMCW_CHECK_ARG(refine_iterations >= 0 && refine_iterations <= 20, "blind zone: refine_iterations must be in [0, 20]");
  FMCW_CHECK_ARG(recall_level > 0.0 && recall_level < 1.0, "blind zone: recall_level must be in (0, 1)");
  FMCW_CHECK_ARG(velocity_threshold_mps > 0.0, "blind zone: velocity_threshold_mps must be > 0");
  methods_with_baseline(methods);
}

namespace {
// Samples one (target, speed, distance): the coarse sweep, a fine grid over narrow theoretical
// bands, then bisection of each edge of each curve (the middle of the two samples around it).
// Each batch of angles runs in parallel, one runner per thread; a sample's noise depends only on
// (case_seed, phi), so the result does not depend on the thread count.
std::vector<BlindZoneSample> sweep(std::vector<std::unique_ptr<SampleRunner>>& runners,
                                   const BlindZoneStudyParams& params, const std::string& target,
                                   std::uint64_t case_seed, double speed, double distance) {
  const double v_th = params.velocity_threshold_mps;
  std::map<long long, BlindZoneSample> samples;  // keyed by phi in micro-degrees
  const auto run_batch = [&](const std::vector<double>& wanted) {
    std::vector<double> phis;
    for (const double w : wanted) {
      const double phi = std::round(w * 1e6) / 1e6;
      if (samples.count(std::llround(phi * 1e6)) == 0 && std::find(phis.begin(), phis.end(), phi) == phis.end()) {
        phis.push_back(phi);
      }
    }
    std::vector<BlindZoneSample> out(phis.size());
    const int n = static_cast<int>(phis.size());
    std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) num_threads(static_cast<int>(runners.size()))
    for (int k = 0; k < n; ++k) {
      try {
        out[static_cast<std::size_t>(k)] =
            runners[static_cast<std::size_t>(omp_get_thread_num())]->run(case_seed, speed, distance, phis[static_cast<std::size_t>(k)]);
      } catch (...) {
#pragma omp critical
        error = std::current_exception();
      }
    }
    if (error) std::rethrow_exception(error);
    for (std::size_t k = 0; k < phis.size(); ++k) {
      out[k].target = target;
      samples.emplace(std::llround(phis[k] * 1e6), std::move(out[k]));
    }
  };
  std::vector<double> grid;
  const int coarse = static_cast<int>(std::floor((params.phi_max_deg - params.phi_min_deg) / params.phi_step_deg + 1e-9));
  for (int k = 0; k <= coarse; ++k) grid.push_back(params.phi_min_deg + k * params.phi_step_deg);
  grid.push_back(params.phi_max_deg);
  const BandEdges theory = theoretical_blind_band(speed, v_th);
  if (theory.upper_deg - theory.lower_deg < 4.0 * params.phi_step_deg) {
    const double lo = std::max(params.phi_min_deg, theory.lower_deg - params.fine_margin_deg);
    const double hi = std::min(params.phi_max_deg, theory.upper_deg + params.fine_margin_deg);
    for (int k = static_cast<int>(std::ceil(lo / params.fine_step_deg)); k * params.fine_step_deg <= hi + 1e-9; ++k) {
      grid.push_back(k * params.fine_step_deg);
    }
  }
  run_batch(grid);
  // Curves: 0 noisy recall, 1 noise-free recall (of the first method), 2 silhouette prediction.
  std::vector<int> kinds = {0, 2};
  if (params.noise_free_too) kinds.insert(kinds.begin() + 1, 1);
  for (int it = 0; it < params.refine_iterations; ++it) {
    const std::vector<double> phi = angles(samples);
    std::vector<double> middles;
    for (const int kind : kinds) {
      const BandEdges e = find_blind_band(phi, curve(samples, kind, 0, v_th), params.recall_level);
      if (!e.found) continue;
      for (const double edge : {e.lower_deg, e.upper_deg}) {
        if (!std::isfinite(edge)) continue;
        const auto above = std::upper_bound(phi.begin(), phi.end(), edge);
        if (above == phi.begin() || above == phi.end()) continue;
        if (*above - *(above - 1) > 1e-3) middles.push_back(0.5 * (*above + *(above - 1)));
      }
    }
    if (middles.empty()) break;
    run_batch(middles);
  }
  std::vector<BlindZoneSample> out;
  for (auto& [key, s] : samples) out.push_back(std::move(s));
  return out;
}

std::vector<double> column(const std::vector<BlindZoneSample>& samples, int kind, std::size_t method, double v_th) {
  std::vector<double> out;
  for (const BlindZoneSample& s : samples) {
    if (kind == 0) out.push_back(s.recall[method]);
    if (kind == 1) out.push_back(s.recall_noise_free[method]);
    if (kind == 2) out.push_back(s.silhouette_min_doppler_mps >= v_th ? 1.0 : 0.0);
  }
  return out;
}
}  // namespace

BlindZoneStudyResult run_blind_zone_study(const BlindZoneStudyParams& params,
                                          const std::function<void(int, int)>& progress) {
  params.validate();
  const auto t0 = std::chrono::steady_clock::now();
  BlindZoneStudyResult result;
  result.params = params;
  result.methods = methods_with_baseline(params.methods);
  const double v_th = params.velocity_threshold_mps;
  int cases = 0, done = 0;
  for (const BlindZoneTarget& t : params.targets) cases += static_cast<int>(params.speeds_mps.size() * t.distances_m.size());
  for (std::size_t ti = 0; ti < params.targets.size(); ++ti) {
    const BlindZoneTarget& target = params.targets[ti];
    BlindZoneSceneParams scene = params.scene;
    scene.box_size_m = target.box_size_m;
    scene.actor_mesh = target.mesh;
    if (!target.mesh.empty()) {
      scene.actor_asset = std::make_shared<const sim::MeshAsset>(sim::load_mesh_asset(target.mesh, {}, 0.4f));
    }
    const int threads = params.scene.num_threads > 0 ? params.scene.num_threads : omp_get_max_threads();
    std::vector<std::unique_ptr<SampleRunner>> runners;
    for (int k = 0; k < threads; ++k) runners.push_back(std::make_unique<SampleRunner>(scene, result.params, result.methods));
    for (std::size_t si = 0; si < params.speeds_mps.size(); ++si) {
      for (std::size_t di = 0; di < target.distances_m.size(); ++di) {
        const double speed = params.speeds_mps[si], distance = target.distances_m[di];
        std::vector<BlindZoneSample> samples =
            sweep(runners, params, target.name, core::mix_seed(core::mix_seed(ti, si), di), speed, distance);
        std::vector<double> phi;
        for (const BlindZoneSample& s : samples) phi.push_back(s.phi_deg);
        for (std::size_t m = 0; m < result.methods.size(); ++m) {
          for (const bool noise : {true, false}) {
            if (!noise && !params.noise_free_too) continue;
            BlindZoneBand band;
            band.target = target.name;
            band.speed_mps = speed;
            band.distance_m = distance;
            band.method = result.methods[m];
            band.noise = noise;
            band.measured = find_blind_band(phi, column(samples, noise ? 0 : 1, m, v_th), params.recall_level);
            band.theory = theoretical_blind_band(speed, v_th);
            band.silhouette = find_blind_band(phi, column(samples, 2, m, v_th), 0.5);
            result.bands.push_back(band);
          }
        }
        for (BlindZoneSample& s : samples) result.samples.push_back(std::move(s));
        if (progress) progress(++done, cases);
      }
    }
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace fmcw::eval
