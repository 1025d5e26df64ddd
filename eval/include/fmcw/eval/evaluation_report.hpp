#pragma once
// The tables and metrics.json of an evaluation: what the report script draws from.

#include <ostream>
#include <string>

#include "fmcw/eval/evaluator.hpp"
#include "fmcw/eval/report_script.hpp"

namespace fmcw::eval {

/// Files written into the report folder (names relative to it).
struct EvaluationFiles {
  static constexpr const char* kMetrics = "metrics.json";
  static constexpr const char* kFrames = "frames.csv";    ///< per frame and method
  static constexpr const char* kObjects = "objects.csv";  ///< per frame, actor and method
  static constexpr const char* kTracks = "tracks.csv";    ///< per frame, method and moving cluster
  static constexpr const char* kSnapshotPixels = "snapshot_pixels.csv";      ///< every pixel of the snapshot frame
  static constexpr const char* kSnapshotClusters = "snapshot_clusters.csv";  ///< its clusters per method
  static constexpr const char* kSnapshotActors = "snapshot_actors.csv";      ///< its actors' truth
};

/// metrics.json as text (keys documented in docs/EVALUATION.md).
std::string metrics_json(const EvaluationResult& result, const std::string& tool_version);

/// Writes every table, then metrics.json last, each atomically, into dir (created if missing).
/// std::runtime_error naming the file when one cannot be written.
void write_evaluation_report(const std::string& dir, const EvaluationResult& result, const std::string& tool_version);

/// A few lines per method for the console: accuracy, ego RMSE, object errors, time, and the
/// targets missed.
std::string summary_text(const EvaluationResult& result);

struct ReportOptions {
  std::string dir;                    ///< report folder
  std::string tool_version = "unknown";
  bool figures = true;                ///< run the report script (PNG figures and report.html)
  ReportScriptParams script;
};

/// evaluate(), write_evaluation_report(), summary_text() to summary (when given), then the
/// report script. Nothing is written when evaluation fails (a bad frame is found before any file
/// is written).
EvaluationResult evaluate_to_report(FrameSource& source, const EvaluationParams& params, const ReportOptions& options,
                                    const ProgressFn& progress = {}, std::ostream* summary = nullptr);

}  // namespace fmcw::eval
