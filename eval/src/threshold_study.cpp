#include "fmcw/eval/threshold_study.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "fmcw/core/check.hpp"
#include "fmcw/core/doppler_segmentation.hpp"
#include "fmcw/eval/table_writer.hpp"
#include "fmcw/io/atomic_file.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

void ThresholdStudyParams::validate() const {
  FMCW_CHECK_ARG(!thresholds_mps.empty(), "threshold study: no thresholds");
  for (const double t : thresholds_mps) FMCW_CHECK_ARG(t > 0.0 && std::isfinite(t), "threshold study: v_th ", t, " must be > 0");
  core::MotionPipelineParams::preset(method);
  FMCW_CHECK_ARG(stride >= 1, "threshold study: stride must be >= 1, got ", stride);
  FMCW_CHECK_ARG(num_threads >= 0, "threshold study: num_threads must be >= 0");
  objects.validate();
  summary.validate();
}

ThresholdStudyResult run_threshold_study(FrameSource& source, const ThresholdStudyParams& params,
                                         const std::function<void(std::size_t, std::size_t)>& progress) {
  params.validate();
  const auto t0 = std::chrono::steady_clock::now();
  ThresholdStudyResult r;
  r.params = params;
  r.source = source.info();
  r.eq14_bound_mps = core::doppler_threshold_mps(0.2 * M_PI / 180.0, 25.0, 25.0);
  std::vector<core::MotionPipeline> pipelines;
  pipelines.reserve(params.thresholds_mps.size());
  for (const double t : params.thresholds_mps) {
    core::MotionPipelineParams p = core::MotionPipelineParams::preset(params.method);
    p.segmentation.velocity_threshold_mps = t;
    p.seed = params.seed;
    p.num_threads = params.num_threads;
    pipelines.emplace_back(p);
  }
  std::vector<std::vector<FrameEvaluation>> frames(params.thresholds_mps.size());
  const std::size_t n = source.size();
  for (std::size_t k = 0; k < n; k += static_cast<std::size_t>(params.stride)) {
    const core::Frame frame = source.frame(k);
    try {
      for (std::size_t t = 0; t < pipelines.size(); ++t) {
        frames[t].push_back(evaluate_frame(k, frame, *frame.frame_truth, pipelines[t].process(frame.scan, k), params.objects));
      }
    } catch (const std::invalid_argument&) {
      core::rethrow_as_file_error(source.describe(k) + ": ");  // the frame holds what the checks refuse
    }
    ++r.frames_used;
    if (progress) progress(std::min(k + 1, n), n);
  }
  for (std::size_t t = 0; t < frames.size(); ++t) {
    ThresholdPoint p;
    p.threshold_mps = params.thresholds_mps[t];
    p.summary = summarize(frames[t], params.summary);
    double clusters = 0.0;
    for (const FrameEvaluation& f : frames[t]) clusters += f.num_clusters;
    p.mean_clusters = frames[t].empty() ? 0.0 : clusters / static_cast<double>(frames[t].size());
    r.points.push_back(p);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

namespace {
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
}  // namespace

void write_threshold_report(const std::string& dir, const ThresholdStudyResult& r, const std::string& tool_version) {
  io::ensure_writable_directory(dir);
  CsvTable t({"threshold_mps", "precision", "recall", "accuracy", "tp", "fp", "tn", "fn", "mean_clusters",
              "ego_rmse_x_mps", "ego_rmse_y_mps", "ego_rmse_z_mps", "detected_fraction", "median_error_mps",
              "median_error_mps_ge200", "objects_large", "clustering_ms", "total_ms"});
  json points = json::array();
  for (const ThresholdPoint& p : r.points) {
    const MethodSummary& s = p.summary;
    t.add(p.threshold_mps).add(s.motion.precision()).add(s.motion.recall()).add(s.motion.accuracy());
    t.add(s.motion.tp).add(s.motion.fp).add(s.motion.tn).add(s.motion.fn).add(p.mean_clusters);
    t.add(s.ego_rmse_mps).add(s.detected_fraction).add(s.median_error_mps).add(s.median_error_mps_ge200);
    t.add(s.objects_large).add(s.mean_timing_ms.clustering_ms).add(s.mean_timing_ms.total_ms);
    t.end_row();
    points.push_back({{"threshold_mps", p.threshold_mps},
                      {"precision", number(s.motion.precision())},
                      {"recall", number(s.motion.recall())},
                      {"accuracy", number(s.motion.accuracy())},
                      {"mean_clusters", p.mean_clusters},
                      {"ego_rmse_mps", {number(s.ego_rmse_mps.x()), number(s.ego_rmse_mps.y()), number(s.ego_rmse_mps.z())}},
                      {"detected_fraction", number(s.detected_fraction)},
                      {"median_error_mps_ge200", number(s.median_error_mps_ge200)}});
  }
  const fs::path d(dir);
  t.write((d / "threshold_sweep.csv").string());
  const json out = {{"kind", "threshold"},
                    {"format_version", 1},
                    {"tool_version", tool_version},
                    {"scenario", r.source.scenario},
                    {"source", r.source.path},
                    {"method", r.params.method},
                    {"frames_used", r.frames_used},
                    {"stride", r.params.stride},
                    {"paper_threshold_mps", 0.17},
                    {"eq14_bound_mps", r.eq14_bound_mps},
                    {"seconds", r.seconds},
                    {"points", points},
                    {"files", {{"sweep", "threshold_sweep.csv"}}}};
  write_text_atomically((d / "metrics.json").string(), out.dump(2) + "\n");
}

}  // namespace fmcw::eval
