#include "fmcw/eval/evaluation_report.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fmcw/eval/table_writer.hpp"
#include "fmcw/eval/tail_metrics.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "report_json.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;
using json = report_json::json;
using report_json::number;
using report_json::vec;

namespace {
json timing(const core::StageTiming& t) {
  return {{"clustering", number(t.clustering_ms)},
          {"ego", number(t.ego_ms)},
          {"objects", number(t.objects_ms)},
          {"total", number(t.total_ms)}};
}

json tracking_json(const MotReport& r) {
  json out = report_json::mot_json(r.all);
  json by_class = json::object();
  for (const auto& [k, m] : r.by_class) by_class[k] = report_json::mot_json(m);
  out["by_class"] = by_class;
  out["vehicles"] = report_json::mot_json(r.vehicles);
  return out;
}

json method_json(const MethodSummary& s, const std::vector<TargetCheck>& checks) {
  json targets = json::array();
  bool all_met = true;
  for (const TargetCheck& c : checks) {
    targets.push_back(
        {{"key", c.key}, {"relation", c.relation}, {"value", number(c.value)}, {"limit", c.limit}, {"met", c.met}});
    all_met = all_met && c.met;
  }
  return {
      {"frames", s.frames},
      {"frames_not_ok", s.frames_not_ok},
      {"motion", report_json::motion(s.motion)},
      {"ego_velocity",
       {{"rmse_mps", vec(s.ego_rmse_mps)},
        {"max_abs_mps", vec(s.ego_max_abs_mps)},
        {"rmse_at_heads_mps", vec(s.ego_rmse_at_heads_mps)},
        {"frames", s.ego_frames},
        {"yaw_rate_rmse_dps", number(s.yaw_rate_rmse_dps)},
        {"yaw_frames", s.yaw_frames}}},
      {"objects",
       {{"evaluated", s.objects_evaluated},
        {"detected", s.objects_detected},
        {"estimated", s.objects_estimated},
        {"large", s.objects_large},
        {"detected_fraction", number(s.detected_fraction)},
        {"median_error_mps", number(s.median_error_mps)},
        {"median_error_mps_ge200", number(s.median_error_mps_ge200)},
        {"p90_error_mps_ge200", number(s.p90_error_mps_ge200)},
        {"median_reference_error_mps", number(s.median_reference_error_mps)},
        {"median_reference_error_mps_ge200", number(s.median_reference_error_mps_ge200)},
        {"large_turning", s.objects_large_turning},
        {"median_reference_error_mps_ge200_turning", number(s.median_reference_error_mps_ge200_turning)},
        {"instance_precision", number(s.instance_precision)},
        {"instance_recall", number(s.instance_recall)},
        {"instance_clusters", s.instances.clusters},
        {"instance_actors", s.instances.actors},
        {"centre_error_median_mps_ge200", number(s.tails.ge200.median)},
        {"centre_error_p90_mps_ge200", number(s.tails.ge200.p90)},
        {"centre_error_p95_mps_ge200", number(s.tails.ge200.p95)},
        {"centre_error_max_mps_ge200", number(s.tails.ge200.max)},
        {"centre_error_share_over_0p5mps_ge200", number(s.tails.ge200.share_over_0p5mps)},
        {"centre_error_share_over_1mps_ge200", number(s.tails.ge200.share_over_1mps)},
        {"centre_error_count_ge200", s.tails.ge200.count},
        {"by_class", report_json::error_map_json(s.tails.by_class)},
        {"by_distance", report_json::error_map_json(s.tails.by_distance)},
        {"by_track_age", report_json::error_map_json(s.tails.by_age)},
        {"covariance_coverage_95", number(s.tails.calibration.coverage_95)},
        {"mean_nees", number(s.tails.calibration.mean_nees)},
        {"calibration",
         {{"estimates", s.tails.calibration.estimates},
          {"scored", s.tails.calibration.scored},
          {"without_covariance", s.tails.calibration.without_covariance},
          {"partly_unobservable", s.tails.calibration.partly_unobservable},
          {"fully_unobservable", s.tails.calibration.fully_unobservable},
          {"mean_dof", number(s.tails.calibration.mean_dof)}}},
        {"calibration_by_class", report_json::calibration_map_json(s.tails.calibration_by_class)},
        {"calibration_by_track_age", report_json::calibration_map_json(s.tails.calibration_by_age)}}},
      {"tracking", tracking_json(s.tracking)},
      {"blind_zone",
       {{"actor_frames", s.blind_actor_frames},
        {"band_pixels", s.blind_band_pixels},
        {"band_pixels_detected", s.blind_band_detected},
        {"recall_tracked", number(s.blind_recall_tracked)},
        {"part_pixels", s.blind_part_pixels},
        {"part_recall", number(s.blind_part_recall)}}},
      {"timing_ms", timing(s.mean_timing_ms)},
      {"timing_max_ms", timing(s.max_timing_ms)},
      {"targets", targets},
      {"targets_met", all_met},
  };
}

void write_frames(const std::string& path, const EvaluationResult& r) {
  CsvTable t({"frame", "method", "stamp_s", "status", "valid_pixels", "truth_moving", "predicted_moving", "tp", "fp",
              "tn", "fn", "precision", "recall", "accuracy", "clusters", "static_pixels", "ego_valid", "ego_vx_mps",
              "ego_vy_mps", "ego_vz_mps", "true_vx_mps", "true_vy_mps", "true_vz_mps", "err_x_mps", "err_y_mps",
              "err_z_mps", "err_heads_x_mps", "err_heads_y_mps", "err_heads_z_mps", "clustering_ms", "ego_ms",
              "objects_ms", "total_ms"});
  for (std::size_t k = 0; k < static_cast<std::size_t>(r.dataset.frames); ++k) {
    for (const auto& frames : r.frames) {
      const FrameEvaluation& f = frames[k];
      t.add(static_cast<std::uint64_t>(f.frame)).add(f.method).add(f.stamp_s).add(core::to_string(f.status));
      t.add(f.motion.total()).add(f.motion.truth_moving()).add(f.motion.predicted_moving());
      t.add(f.motion.tp).add(f.motion.fp).add(f.motion.tn).add(f.motion.fn);
      t.add(f.motion.precision()).add(f.motion.recall()).add(f.motion.accuracy());
      t.add(f.num_clusters).add(f.static_pixels).add(f.ego_valid);
      t.add(f.ego_estimate_mps).add(f.ego_truth_mps).add(f.ego_error_mps()).add(f.ego_error_at_heads_mps());
      t.add(f.timing.clustering_ms).add(f.timing.ego_ms).add(f.timing.objects_ms).add(f.timing.total_ms);
      t.end_row();
    }
  }
  t.write(path);
}

constexpr double kDegPerRad = 180.0 / M_PI;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void write_objects(const std::string& path, const EvaluationResult& r) {
  CsvTable t({"frame", "method", "actor", "class", "pixels", "moving_pixels", "distance_m", "evaluated", "detected",
              "estimate_valid", "cluster", "pixels_in_cluster", "cluster_pixels", "est_vx_mps", "est_vy_mps",
              "est_vz_mps", "true_vx_mps", "true_vy_mps", "true_vz_mps", "ref_vx_mps", "ref_vy_mps", "ref_vz_mps",
              "err_x_mps", "err_y_mps", "err_z_mps", "err_mps", "ref_err_mps", "true_x_m", "true_y_m",
              "est_centre_x_m", "est_centre_y_m", "true_yaw_rate_dps", "est_yaw_rate_dps", "track_id",
              "cov_xx_m2ps2", "cov_xy_m2ps2", "cov_yy_m2ps2", "nees", "nees_dof"});
  const double unobservable = r.params.summary.unobservable_sigma_mps;
  for (std::size_t k = 0; k < static_cast<std::size_t>(r.dataset.frames); ++k) {
    for (const auto& frames : r.frames) {
      const FrameEvaluation& f = frames[k];
      for (const ObjectMatch& m : f.objects) {
        t.add(static_cast<std::uint64_t>(f.frame)).add(f.method).add(m.actor_id).add(m.class_name);
        t.add(m.pixels).add(m.moving_pixels).add(m.distance_m).add(m.evaluated).add(m.detected).add(m.estimate_valid);
        t.add(m.cluster).add(m.pixels_in_cluster).add(m.cluster_pixels);
        t.add(m.estimate_mps).add(m.truth_mean_mps).add(m.reference_mps).add(m.error_mps());
        t.add(m.error_mps().norm()).add(m.reference_error_mps().norm());
        t.add(m.position_m.x()).add(m.position_m.y()).add(m.estimate_centre_m.x()).add(m.estimate_centre_m.y());
        t.add(m.yaw_rate_rps * kDegPerRad).add(m.estimate_yaw_rate_rps * kDegPerRad).add(m.estimate_track_id);
        // The calibration of this estimate as objects.covariance_coverage_95 scores it (NaN and 0
        // degrees of freedom where it is not scored).
        const Eigen::Matrix2d cov = m.estimate_covariance.topLeftCorner<2, 2>();
        const NeesScore n = m.estimate_valid ? score_nees(m.reference_error_mps().head<2>(), cov, unobservable) : NeesScore{};
        const bool scored = n.has_covariance && n.dof > 0;
        t.add(cov(0, 0)).add(cov(0, 1)).add(cov(1, 1)).add(scored ? n.nees : kNaN).add(scored ? n.dof : 0);
        t.end_row();
      }
    }
  }
  t.write(path);
}

// Every hypothesis of the tracking metrics and the object it overlaps most (by IoU).
void write_tracks(const std::string& path, const EvaluationResult& r) {
  CsvTable t({"frame", "method", "track", "pixels", "class", "actor", "iou", "centre_x_m", "centre_y_m"});
  for (std::size_t k = 0; k < static_cast<std::size_t>(r.dataset.frames); ++k) {
    for (const auto& frames : r.frames) {
      const FrameEvaluation& f = frames[k];
      const TrackingFrame& tf = f.tracking;
      for (std::size_t j = 0; j < tf.tracks.size(); ++j) {
        const TrackObservation& h = tf.tracks[j];
        std::uint32_t actor = 0;
        double best = 0.0;
        for (const PointOverlap& o : tf.overlaps) {
          if (o.track != static_cast<int>(j) || tf.iou(o) <= best) continue;
          best = tf.iou(o);
          actor = tf.truths[static_cast<std::size_t>(o.truth)].actor_id;
        }
        t.add(static_cast<std::uint64_t>(f.frame)).add(f.method).add(h.track).add(h.pixels);
        t.add(h.class_name).add(actor).add(best).add(h.centre_m.x()).add(h.centre_m.y());
        t.end_row();
      }
    }
  }
  t.write(path);
}

void write_snapshot(const std::string& dir, const EvaluationResult& r) {
  const Snapshot& s = r.snapshot;
  const core::Scan& scan = s.frame.scan;
  std::vector<std::string> columns = {"row", "col", "valid", "x_m", "y_m", "z_m", "v_mps", "gt_v_mps", "instance",
                                      "moving"};
  for (const std::string& m : r.methods) columns.push_back("label_" + m);
  CsvTable px(columns);
  if (s.frame.truth) {
    const core::PixelGroundTruth& gt = *s.frame.truth;
    for (int row = 0; row < scan.rows; ++row) {
      for (int col = 0; col < scan.cols; ++col) {
        const std::size_t i = scan.index(row, col);
        px.add(row).add(col).add(scan.valid[i] != 0);
        px.add(static_cast<double>(scan.x_m[i])).add(static_cast<double>(scan.y_m[i]));
        px.add(static_cast<double>(scan.z_m[i])).add(static_cast<double>(scan.radial_velocity_mps[i]));
        px.add(static_cast<double>(gt.radial_velocity_mps[i])).add(gt.instance[i]).add(gt.moving[i] != 0);
        for (const core::MotionEstimate& e : s.estimates) px.add(e.labels[i]);
        px.end_row();
      }
    }
  }
  px.write((fs::path(dir) / EvaluationFiles::kSnapshotPixels).string());

  CsvTable cl({"method", "cluster", "pixels", "centroid_x_m", "centroid_y_m", "centroid_z_m", "vx_mps", "vy_mps",
               "vz_mps", "valid"});
  for (const core::MotionEstimate& e : s.estimates) {
    for (const core::ClusterEstimate& c : e.clusters) {
      cl.add(e.method).add(c.id).add(c.num_pixels).add(c.centroid_m).add(c.velocity.velocity_mps).add(c.velocity.valid);
      cl.end_row();
    }
  }
  cl.write((fs::path(dir) / EvaluationFiles::kSnapshotClusters).string());

  CsvTable ac({"actor", "class", "x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps", "pixels", "box_x_m", "box_y_m",
               "box_z_m", "box_length_m", "box_width_m", "box_height_m", "box_yaw_rad"});
  if (s.frame.frame_truth) {
    for (const core::ActorTruth& a : s.frame.frame_truth->actors) {
      ac.add(a.id).add(a.class_name).add(a.position_rig_m).add(a.velocity_rig_mps).add(a.pixels);
      ac.add(a.box.center_m).add(a.box.size_m).add(a.box.yaw_rad);
      ac.end_row();
    }
  }
  ac.write((fs::path(dir) / EvaluationFiles::kSnapshotActors).string());
}
}  // namespace

std::string metrics_json(const EvaluationResult& r, const std::string& tool_version) {
  json methods = json::object();
  for (std::size_t m = 0; m < r.methods.size(); ++m) methods[r.methods[m]] = method_json(r.summaries[m], r.checks[m]);
  const DatasetStats& d = r.dataset;
  json out = {
      {"kind", "evaluation"},
      {"format_version", 1},
      {"tool_version", tool_version},
      {"scenario", r.source.scenario},
      {"frames", d.frames},
      {"default_method", r.params.default_method},
      {"method_order", r.methods},
      {"methods", methods},
      {"dataset",
       {{"path", r.source.path},
        {"scans", d.frames},
        {"valid_points", d.valid_points},
        {"motion_points", d.motion_points},
        {"duration_s", d.duration_s},
        {"rate_hz", r.source.rate_hz},
        {"ego_status", d.ego_moving ? "moving" : "stationary"},
        {"max_ego_speed_mps", d.max_ego_speed_mps},
        {"mean_ego_speed_mps", d.mean_ego_speed_mps},
        {"actors_seen", d.actors_seen},
        {"seed", r.source.seed}}},
      {"targets", report_json::held_targets(r.params)},
      {"snapshot_frame", r.snapshot.frame_index},
      {"config", {{"method_seed", r.params.seed}, {"num_threads", r.params.num_threads}, {"scenario_yaml", r.source.config_yaml}}},
      {"files",
       {{"frames", EvaluationFiles::kFrames},
        {"objects", EvaluationFiles::kObjects},
        {"tracks", EvaluationFiles::kTracks},
        {"snapshot_pixels", EvaluationFiles::kSnapshotPixels},
        {"snapshot_clusters", EvaluationFiles::kSnapshotClusters},
        {"snapshot_actors", EvaluationFiles::kSnapshotActors}}},
  };
  return out.dump(2) + "\n";
}

void write_evaluation_report(const std::string& dir, const EvaluationResult& r, const std::string& tool_version) {
  io::ensure_writable_directory(dir);
  const fs::path d(dir);
  write_frames((d / EvaluationFiles::kFrames).string(), r);
  write_objects((d / EvaluationFiles::kObjects).string(), r);
  write_tracks((d / EvaluationFiles::kTracks).string(), r);
  write_snapshot(dir, r);
  write_text_atomically((d / EvaluationFiles::kMetrics).string(), metrics_json(r, tool_version));
}

std::string summary_text(const EvaluationResult& r) {
  std::ostringstream out;
  out << std::fixed;
  out << r.source.scenario << ": " << r.dataset.frames << " frames, " << r.dataset.motion_points
      << " truly moving points, ego " << (r.dataset.ego_moving ? "moving" : "stationary") << "\n";
  for (std::size_t m = 0; m < r.methods.size(); ++m) {
    const MethodSummary& s = r.summaries[m];
    out << "  " << std::left << std::setw(6) << r.methods[m] << std::right << std::setprecision(4)
        << " accuracy " << s.motion.accuracy() << "  precision " << s.motion.precision() << "  recall "
        << s.motion.recall() << std::setprecision(4) << "  ego RMSE (" << s.ego_rmse_mps.x() << ", "
        << s.ego_rmse_mps.y() << ", " << s.ego_rmse_mps.z() << ") m/s  object median error >=200 px "
        << std::setprecision(3) << s.median_error_mps_ge200 << " m/s  (" << s.objects_large << " of "
        << s.objects_evaluated << ")  " << std::setprecision(2) << s.mean_timing_ms.total_ms << " ms/frame\n";
    std::string missed;
    for (const TargetCheck& c : r.checks[m]) {
      if (c.met) continue;
      std::ostringstream one;
      one << c.key << " " << std::setprecision(4) << c.value << " (target " << c.relation << " " << c.limit << ")";
      missed += (missed.empty() ? "" : "; ") + one.str();
    }
    out << "         targets: " << (missed.empty() ? "all met" : "missed " + missed) << "\n";
  }
  return out.str();
}

EvaluationResult evaluate_to_report(FrameSource& source, const EvaluationParams& params, const ReportOptions& options,
                                    const ProgressFn& progress, std::ostream* summary) {
  io::ensure_writable_directory(options.dir);
  EvaluationResult result = evaluate(source, params, progress);
  write_evaluation_report(options.dir, result, options.tool_version);
  if (summary != nullptr) *summary << summary_text(result) << std::flush;
  if (options.figures) run_report_script(options.script, options.dir);
  return result;
}

}  // namespace fmcw::eval
