#include "fmcw/eval/object_points_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "fmcw/core/check.hpp"
#include "fmcw/eval/statistics.hpp"
#include "fmcw/eval/table_writer.hpp"
#include "fmcw/io/atomic_file.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

void ObjectPointsStudyParams::validate() const {
  FMCW_CHECK_ARG(!caps.empty(), "object-points study: no caps");
  for (const int c : caps) FMCW_CHECK_ARG(c == 0 || c >= 3, "object-points study: cap ", c, " must be 0 (all) or >= 3");
  FMCW_CHECK_ARG(!solvers.empty(), "object-points study: no solvers");
  for (const std::string& s : solvers) {
    FMCW_CHECK_ARG(s == "ceres" || s == "closed_form", "object-points study: unknown solver '", s,
                   "' (known: ceres, closed_form)");
  }
  FMCW_CHECK_ARG(stride >= 1, "object-points study: stride must be >= 1, got ", stride);
  FMCW_CHECK_ARG(num_threads >= 0, "object-points study: num_threads must be >= 0");
  objects.validate();
  summary.validate();
}

namespace {
// The paper's Algorithm 2 with num_th^m = cap; the ego stage is the same for every cap.
core::MotionPipelineParams pipeline_params(const ObjectPointsStudyParams& p, const std::string& solver, int cap) {
  core::MotionPipelineParams m = core::MotionPipelineParams::preset("paper");
  m.method = solver + "_" + std::to_string(cap);
  m.velocity.solver = solver == "ceres" ? core::VelocitySolver::kCeres : core::VelocitySolver::kClosedForm;
  m.velocity.object_max_points = cap;
  m.seed = p.seed;
  m.num_threads = p.num_threads;
  return m;
}

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
}  // namespace

ObjectPointsStudyResult run_object_points_study(FrameSource& source, const ObjectPointsStudyParams& params,
                                                const std::function<void(std::size_t, std::size_t)>& progress) {
  params.validate();
  const auto t0 = std::chrono::steady_clock::now();
  ObjectPointsStudyResult r;
  r.params = params;
  r.source = source.info();
  std::vector<int> caps = params.caps;
  if (std::find(caps.begin(), caps.end(), 0) == caps.end()) caps.push_back(0);
  std::vector<core::MotionPipeline> pipelines;
  std::vector<std::pair<std::string, int>> cases;
  std::vector<std::size_t> reference;  // case index of the same solver with every point
  for (const std::string& solver : params.solvers) {
    const std::size_t first = cases.size();
    for (const int cap : caps) {
      cases.emplace_back(solver, cap);
      pipelines.emplace_back(pipeline_params(params, solver, cap));
    }
    const std::size_t all = first + static_cast<std::size_t>(std::find(caps.begin(), caps.end(), 0) - caps.begin());
    reference.insert(reference.end(), caps.size(), all);
  }
  std::vector<std::vector<double>> subsample_errors(cases.size());
  std::vector<std::vector<FrameEvaluation>> frames(cases.size());
  const std::size_t n = source.size();
  for (std::size_t k = 0; k < n; k += static_cast<std::size_t>(params.stride)) {
    const core::Frame frame = source.frame(k);
    try {
      for (std::size_t c = 0; c < cases.size(); ++c) {
        frames[c].push_back(evaluate_frame(k, frame, *frame.frame_truth, pipelines[c].process(frame.scan, k), params.objects));
      }
      for (std::size_t c = 0; c < cases.size(); ++c) {
        const std::vector<ObjectMatch>& mine = frames[c].back().objects;
        const std::vector<ObjectMatch>& all = frames[reference[c]].back().objects;
        for (std::size_t o = 0; o < mine.size() && o < all.size(); ++o) {
          const ObjectMatch& a = mine[o];
          const ObjectMatch& b = all[o];
          if (a.actor_id != b.actor_id || !a.evaluated || !a.estimate_valid || !b.estimate_valid ||
              a.pixels < params.summary.large_object_pixels) {
            continue;
          }
          subsample_errors[c].push_back((a.estimate_mps - b.estimate_mps).norm());
        }
      }
    } catch (const std::invalid_argument&) {
      core::rethrow_as_file_error(source.describe(k) + ": ");  // the frame holds what the checks refuse
    }
    ++r.frames_used;
    if (progress) progress(std::min(k + 1, n), n);
  }
  for (std::size_t c = 0; c < cases.size(); ++c) {
    ObjectPointsPoint p;
    p.solver = cases[c].first;
    p.cap = cases[c].second;
    p.summary = summarize(frames[c], params.summary);
    p.median_subsample_error_mps_ge200 = median(subsample_errors[c]);
    double ms = 0.0, clusters = 0.0;
    for (const FrameEvaluation& f : frames[c]) {
      ms += f.timing.objects_ms;
      clusters += f.num_clusters;
    }
    p.mean_objects_ms = frames[c].empty() ? 0.0 : ms / static_cast<double>(frames[c].size());
    p.objects_ms_per_cluster = clusters > 0 ? ms / clusters : 0.0;
    r.points.push_back(p);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

void write_object_points_report(const std::string& dir, const ObjectPointsStudyResult& r,
                                const std::string& tool_version) {
  io::ensure_writable_directory(dir);
  CsvTable t({"solver", "cap", "objects_estimated", "objects_large", "median_error_mps", "median_error_mps_ge200",
              "p90_error_mps_ge200", "median_reference_error_mps_ge200", "median_subsample_error_mps_ge200",
              "mean_objects_ms", "objects_ms_per_cluster"});
  json points = json::array();
  for (const ObjectPointsPoint& p : r.points) {
    const MethodSummary& s = p.summary;
    t.add(p.solver).add(p.cap).add(s.objects_estimated).add(s.objects_large).add(s.median_error_mps);
    t.add(s.median_error_mps_ge200).add(s.p90_error_mps_ge200).add(s.median_reference_error_mps_ge200);
    t.add(p.median_subsample_error_mps_ge200);
    t.add(p.mean_objects_ms).add(p.objects_ms_per_cluster);
    t.end_row();
    points.push_back({{"solver", p.solver},
                      {"cap", p.cap},
                      {"objects_estimated", s.objects_estimated},
                      {"objects_large", s.objects_large},
                      {"median_error_mps", number(s.median_error_mps)},
                      {"median_error_mps_ge200", number(s.median_error_mps_ge200)},
                      {"p90_error_mps_ge200", number(s.p90_error_mps_ge200)},
                      {"median_subsample_error_mps_ge200", number(p.median_subsample_error_mps_ge200)},
                      {"mean_objects_ms", p.mean_objects_ms},
                      {"objects_ms_per_cluster", p.objects_ms_per_cluster}});
  }
  const fs::path d(dir);
  t.write((d / "object_points_sweep.csv").string());
  const json out = {{"kind", "object_points"},
                    {"format_version", 1},
                    {"tool_version", tool_version},
                    {"scenario", r.source.scenario},
                    {"source", r.source.path},
                    {"frames_used", r.frames_used},
                    {"stride", r.params.stride},
                    {"paper_cap", 200},
                    {"large_object_pixels", r.params.summary.large_object_pixels},
                    {"num_threads", r.params.num_threads},
                    {"seconds", r.seconds},
                    {"points", points},
                    {"files", {{"sweep", "object_points_sweep.csv"}}}};
  write_text_atomically((d / "metrics.json").string(), out.dump(2) + "\n");
}

}  // namespace fmcw::eval
