#include "fmcw/eval/aggregate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/eval/statistics.hpp"

namespace fmcw::eval {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ratio(double a, double b) { return b > 0.0 ? a / b : kNaN; }

// The metrics of a row from a summary and its error samples' statistics: one list for the
// per-scenario rows and the pooled row, so that both carry the same keys.
std::vector<NamedValue> metrics_of(const MethodSummary& s, const ErrorStats& all, const ErrorStats& large) {
  const auto count = [](const char* key, double v) { return NamedValue{key, v, true, false}; };
  const auto rate = [](const char* key, double v) { return NamedValue{key, v, false, true}; };
  return {
      count("frames_not_ok", s.frames_not_ok),
      rate("accuracy", s.motion.accuracy()),
      rate("precision", s.motion.precision()),
      rate("recall", s.motion.recall()),
      count("tp", static_cast<double>(s.motion.tp)),
      count("fp", static_cast<double>(s.motion.fp)),
      count("tn", static_cast<double>(s.motion.tn)),
      count("fn", static_cast<double>(s.motion.fn)),
      count("ego_frames", s.ego_frames),
      rate("ego_rmse_x_mps", s.ego_rmse_mps.x()),
      rate("ego_rmse_y_mps", s.ego_rmse_mps.y()),
      rate("ego_rmse_z_mps", s.ego_rmse_mps.z()),
      rate("yaw_rate_rmse_dps", s.yaw_rate_rmse_dps),
      count("objects_evaluated", s.objects_evaluated),
      count("objects_detected", s.objects_detected),
      count("objects_estimated", s.objects_estimated),
      count("objects_large", s.objects_large),
      rate("detected_fraction", s.detected_fraction),
      rate("centre_err_median_mps", all.median),
      rate("centre_err_p90_mps", all.p90),
      rate("centre_err_p95_mps", all.p95),
      rate("centre_err_max_mps", all.max),
      rate("share_over_1mps", all.share_over_1mps),
      rate("centre_err_median_ge200_mps", large.median),
      rate("centre_err_p90_ge200_mps", large.p90),
      rate("centre_err_p95_ge200_mps", large.p95),
      rate("centre_err_max_ge200_mps", large.max),
      rate("share_over_1mps_ge200", large.share_over_1mps),
      rate("covariance_coverage_95", s.tails.calibration.coverage_95),
      rate("mean_nees", s.tails.calibration.mean_nees),
      rate("mota", s.tracking.all.mota),
      rate("idf1", s.tracking.all.idf1),
      rate("hota", s.tracking.all.hota),
      count("id_switches", s.tracking.all.id_switches),
      rate("instance_precision", s.instance_precision),
      rate("instance_recall", s.instance_recall),
      count("band_pixels", static_cast<double>(s.blind_band_pixels)),
      rate("band_recall", s.blind_recall_tracked),
  };
}

// Pooled calibration: the counts summed back from each run's shares (coverage x scored,
// mean NEES x scored).
void add_counts(CalibrationStats& sum, const CalibrationStats& x) {
  sum.estimates += x.estimates;
  sum.without_covariance += x.without_covariance;
  sum.partly_unobservable += x.partly_unobservable;
  sum.fully_unobservable += x.fully_unobservable;
  if (x.scored == 0) return;
  sum.coverage_95 += x.coverage_95 * x.scored;
  sum.mean_nees += x.mean_nees * x.scored;
  sum.mean_dof += x.mean_dof * x.scored;
  sum.scored += x.scored;
}
void finish(CalibrationStats& c) {
  c.coverage_95 = ratio(c.coverage_95, c.scored);
  c.mean_nees = ratio(c.mean_nees, c.scored);
  c.mean_dof = ratio(c.mean_dof, c.scored);
}
void add_counts(MotMetrics& sum, const MotMetrics& x) { add_mot_counts(sum, x); }
void finish(MotMetrics& m) { complete_mot(m); }

// Pools an RMSE over runs: the squared errors summed back from RMSE^2 * n.
struct RmsePool {
  double sum_sq = 0.0;
  int n = 0;
  void add(double rmse, int frames) {
    if (frames <= 0 || !std::isfinite(rmse)) return;
    sum_sq += rmse * rmse * frames;
    n += frames;
  }
  double value() const { return n == 0 ? kNaN : std::sqrt(sum_sq / n); }
};
}  // namespace

DatasetDigest digest(const EvaluationResult& r, const std::string& folder) {
  DatasetDigest d;
  d.folder = folder;
  d.source = r.source;
  d.source.config_yaml.clear();
  d.dataset = r.dataset;
  d.methods = r.methods;
  const int large_pixels = r.params.summary.large_object_pixels;
  for (std::size_t m = 0; m < r.methods.size(); ++m) {
    MethodDigest md;
    md.summary = r.summaries[m];
    md.checks = r.checks[m];
    // The same object-frames summarize() takes its reference-error medians over.
    for (const FrameEvaluation& f : r.frames[m]) {
      for (const ObjectMatch& o : f.objects) {
        if (!o.evaluated || !o.estimate_valid) continue;
        const double err = o.reference_error_mps().norm();
        md.centre_errors_mps.push_back(err);
        if (o.pixels >= large_pixels) md.centre_errors_large_mps.push_back(err);
      }
    }
    d.per_method.push_back(std::move(md));
  }
  return d;
}

std::vector<NamedValue> scenario_metrics(const MethodDigest& m) {
  return metrics_of(m.summary, error_stats(m.centre_errors_mps), error_stats(m.centre_errors_large_mps));
}

std::vector<TargetCheck> all_target_checks(const Targets& targets) {
  MethodSummary with_band;
  with_band.blind_band_pixels = 1;  // the blind-band target is held only where there is a band
  with_band.tracking.vehicles.objects = 1;  // the vehicles' targets only where there are vehicles
  return check_targets(with_band, targets);
}

PooledMethod pool(const std::vector<DatasetDigest>& digests, const std::string& method, const Targets& targets) {
  PooledMethod p;
  p.method = method;
  MethodSummary& s = p.pooled;
  s.method = method;
  RmsePool ego[3], yaw;
  std::vector<double> all, large;
  std::vector<std::vector<NamedValue>> rows;
  for (const TargetCheck& c : all_target_checks(targets)) p.targets.push_back({c.key, c.relation, c.limit, 0, 0, kNaN});
  double total_ms = 0.0;
  for (const DatasetDigest& d : digests) {
    const auto it = std::find(d.methods.begin(), d.methods.end(), method);
    if (it == d.methods.end()) {
      throw core::InputError("pool: dataset '" + d.folder + "' was not evaluated with method '" + method + "'");
    }
    const MethodDigest& md = d.per_method[static_cast<std::size_t>(it - d.methods.begin())];
    const MethodSummary& x = md.summary;
    ++p.scenarios;
    s.frames += x.frames;
    s.frames_not_ok += x.frames_not_ok;
    s.motion += x.motion;
    s.ego_frames += x.ego_frames;
    for (int k = 0; k < 3; ++k) ego[k].add(x.ego_rmse_mps[k], x.ego_frames);
    s.ego_max_abs_mps = s.ego_max_abs_mps.cwiseMax(x.ego_max_abs_mps.unaryExpr([](double v) {
      return std::isfinite(v) ? v : 0.0;
    }));
    s.yaw_frames += x.yaw_frames;
    yaw.add(x.yaw_rate_rmse_dps, x.yaw_frames);
    s.objects_evaluated += x.objects_evaluated;
    s.objects_detected += x.objects_detected;
    s.objects_estimated += x.objects_estimated;
    s.objects_large += x.objects_large;
    s.objects_large_turning += x.objects_large_turning;
    s.instances += x.instances;
    s.blind_actor_frames += x.blind_actor_frames;
    s.blind_band_pixels += x.blind_band_pixels;
    s.blind_band_detected += x.blind_band_detected;
    s.blind_part_pixels += x.blind_part_pixels;
    s.blind_part_detected += x.blind_part_detected;
    add_counts(s.tails.calibration, x.tails.calibration);
    add_counts(s.tracking.all, x.tracking.all);
    add_counts(s.tracking.vehicles, x.tracking.vehicles);
    if (std::isfinite(x.mean_timing_ms.total_ms)) total_ms += x.mean_timing_ms.total_ms * x.frames;
    s.max_timing_ms.total_ms = std::max(s.max_timing_ms.total_ms, x.max_timing_ms.total_ms);
    all.insert(all.end(), md.centre_errors_mps.begin(), md.centre_errors_mps.end());
    large.insert(large.end(), md.centre_errors_large_mps.begin(), md.centre_errors_large_mps.end());
    rows.push_back(scenario_metrics(md));
    bool every = true;
    for (TargetShare& t : p.targets) {
      const auto c = std::find_if(md.checks.begin(), md.checks.end(), [&](const TargetCheck& k) { return k.key == t.key; });
      if (c == md.checks.end()) continue;  // not held on this scenario
      ++t.checked;
      t.met += c->met ? 1 : 0;
      every = every && c->met;
    }
    p.all_targets_met += every ? 1 : 0;
  }
  s.ego_rmse_mps = {ego[0].value(), ego[1].value(), ego[2].value()};
  s.yaw_rate_rmse_dps = yaw.value();
  s.detected_fraction = ratio(s.objects_detected, s.objects_evaluated);
  s.instance_precision = ratio(s.instances.clusters_matched, s.instances.clusters);
  s.instance_recall = ratio(s.instances.actors_matched, s.instances.actors);
  s.blind_recall_tracked = ratio(static_cast<double>(s.blind_band_detected), static_cast<double>(s.blind_band_pixels));
  s.blind_part_recall = ratio(static_cast<double>(s.blind_part_detected), static_cast<double>(s.blind_part_pixels));
  s.mean_timing_ms.total_ms = ratio(total_ms, s.frames);
  finish(s.tails.calibration);
  finish(s.tracking.all);
  finish(s.tracking.vehicles);
  p.centre = error_stats(all);
  p.centre_large = error_stats(large);
  s.median_reference_error_mps = p.centre.median;
  s.median_reference_error_mps_ge200 = p.centre_large.median;
  s.median_error_mps = s.median_error_mps_ge200 = s.p90_error_mps_ge200 = kNaN;  // not pooled (no samples kept)
  s.median_reference_error_mps_ge200_turning = kNaN;
  p.metrics = metrics_of(s, p.centre, p.centre_large);
  for (TargetShare& t : p.targets) t.share = ratio(t.met, t.checked);
  if (!rows.empty()) {
    for (std::size_t k = 0; k < rows.front().size(); ++k) {
      if (!rows.front()[k].spread) continue;
      std::vector<double> v;
      for (const auto& row : rows) {
        if (std::isfinite(row[k].value)) v.push_back(row[k].value);
      }
      p.spread.push_back({rows.front()[k].key, static_cast<int>(v.size()), quantile(v, 0.5), quantile(v, 0.1),
                          quantile(v, 0.9), quantile(v, 0.0), quantile(v, 1.0)});
    }
  }
  return p;
}

}  // namespace fmcw::eval
