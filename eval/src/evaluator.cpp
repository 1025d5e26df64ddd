#include "fmcw/eval/evaluator.hpp"

#include <algorithm>
#include <set>
#include <tuple>
#include <stdexcept>

#include "fmcw/core/check.hpp"

namespace fmcw::eval {

std::vector<std::string> methods_with_baseline(const std::vector<std::string>& wanted_in) {
  const std::vector<std::string> wanted = wanted_in.empty() ? core::MotionPipelineParams::preset_names() : wanted_in;
  std::vector<std::string> out = {"paper"};
  for (const std::string& m : wanted) {
    core::MotionPipelineParams::preset(m);  // throws for an unknown name, listing the known
    if (std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
  }
  return out;
}

void EvaluationParams::validate() const {
  const std::vector<std::string> known = core::MotionPipelineParams::preset_names();
  methods_with_baseline(methods);
  FMCW_CHECK_ARG(std::find(known.begin(), known.end(), default_method) != known.end(), "evaluate: default method '",
                 default_method, "' is not a known method");
  FMCW_CHECK_ARG(num_threads >= 0, "evaluate: num_threads must be >= 0, got ", num_threads);
  FMCW_CHECK_ARG(blind_band_mps > 0.0, "evaluate: blind_band_mps must be > 0, got ", blind_band_mps);
  objects.validate();
  summary.validate();
}

std::vector<std::string> EvaluationParams::resolved_methods() const { return methods_with_baseline(methods); }

namespace {
// Ranks frames for the snapshot: more large moving actors first, then more evaluated actors,
// then more moving pixels.
std::tuple<int, int, std::uint64_t> snapshot_score(const FrameEvaluation& e, int large_pixels) {
  int evaluated = 0, large = 0;
  for (const ObjectMatch& m : e.objects) {
    evaluated += m.evaluated ? 1 : 0;
    large += m.moving_pixels >= large_pixels ? 1 : 0;
  }
  return {large, evaluated, e.motion.truth_moving()};
}
}  // namespace

EvaluationResult evaluate(FrameSource& source, const EvaluationParams& params, const ProgressFn& progress) {
  params.validate();
  EvaluationResult r;
  r.source = source.info();
  r.params = params;
  r.methods = params.resolved_methods();
  std::vector<core::MotionPipeline> pipelines;
  pipelines.reserve(r.methods.size());
  for (const std::string& m : r.methods) {
    core::MotionPipelineParams p = core::MotionPipelineParams::preset(m);
    p.seed = params.seed;
    p.num_threads = params.num_threads;
    pipelines.emplace_back(p);
  }
  r.frames.resize(r.methods.size());
  const std::size_t n = source.size();
  std::set<std::uint32_t> actors_seen;
  std::tuple<int, int, std::uint64_t> best_score{-1, -1, 0};
  double speed_sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    core::Frame frame = source.frame(k);
    if (!frame.truth || !frame.frame_truth) {
      throw core::FileError(source.describe(k) + ": frame carries no ground truth");
    }
    std::vector<core::MotionEstimate> estimates;
    try {
      for (std::size_t m = 0; m < r.methods.size(); ++m) {
        estimates.push_back(pipelines[m].process(frame.scan, k));
        r.frames[m].push_back(evaluate_frame(k, frame, *frame.frame_truth, estimates.back(), params.objects, params.blind_band_mps));
      }
    } catch (const std::invalid_argument&) {
      core::rethrow_as_file_error(source.describe(k) + ": ");  // the frame holds what the checks refuse
    }
    const FrameEvaluation& first = r.frames[0].back();
    r.dataset.valid_points += first.motion.total();
    r.dataset.motion_points += first.motion.truth_moving();
    for (const ObjectMatch& o : first.objects) actors_seen.insert(o.actor_id);
    const double speed = frame.frame_truth->ego.velocity_mps.norm();
    r.dataset.max_ego_speed_mps = std::max(r.dataset.max_ego_speed_mps, speed);
    speed_sum += speed;
    const auto score = snapshot_score(first, params.summary.large_object_pixels);
    if (score > best_score) {
      best_score = score;
      r.snapshot.frame_index = k;
      r.snapshot.frame = std::move(frame);
      r.snapshot.estimates = std::move(estimates);
    }
    if (progress) progress(k + 1, n);
  }
  r.dataset.frames = static_cast<int>(n);
  r.dataset.duration_s = static_cast<double>(n) / r.source.rate_hz;
  r.dataset.mean_ego_speed_mps = n == 0 ? 0.0 : speed_sum / static_cast<double>(n);
  r.dataset.ego_moving = r.dataset.max_ego_speed_mps > 0.1;
  r.dataset.actors_seen = static_cast<int>(actors_seen.size());
  for (std::size_t m = 0; m < r.methods.size(); ++m) {
    r.summaries.push_back(summarize(r.frames[m], params.summary));
    r.summaries.back().method = r.methods[m];
    r.checks.push_back(check_targets(r.summaries.back(), params.targets));
  }
  return r;
}

}  // namespace fmcw::eval
