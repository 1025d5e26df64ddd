#pragma once
// `fmcw evaluate FOLDER` where FOLDER holds datasets in its subfolders: every dataset evaluated
// one after another (each evaluation is multi-threaded itself), digested, and written as one
// aggregate report: a row per scenario and method, the metrics pooled over the scenarios with
// their spread, the share of scenarios meeting each target, figures against layout, speed and
// density (manifest.csv of a generated set, else what the datasets give).

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "fmcw/eval/aggregate.hpp"
#include "fmcw/eval/evaluation_report.hpp"
#include "fmcw/eval/scenario_manifest.hpp"

namespace fmcw::eval {

/// Files of an aggregate report (names relative to its folder).
struct AggregateFiles {
  static constexpr const char* kMetrics = "metrics.json";
  static constexpr const char* kScenarios = "scenarios.csv";  ///< per dataset and method
  static constexpr const char* kPooled = "pooled.csv";        ///< per method
  static constexpr const char* kSpread = "spread.csv";        ///< per method and metric
  static constexpr const char* kTargets = "targets.csv";      ///< per method and target
  static constexpr const char* kDatasets = "datasets";        ///< datasets/<folder>/metrics.json
  static constexpr const char* kManifest = "manifest.csv";    ///< read from the evaluated folder
};

/// A dataset inside the evaluated folder.
struct DatasetFolder {
  std::string name;  ///< the subfolder's name
  std::string path;
};

/// True when dir holds a dataset.yaml: one dataset, not a folder of them.
bool is_dataset_folder(const std::string& dir);

/// The subfolders of folder that hold a dataset.yaml, sorted by name (byte order). Hidden
/// subfolders are skipped; other subfolders are said in notes. std::invalid_argument when
/// folder is not a folder or holds no dataset.
std::vector<DatasetFolder> find_datasets(const std::string& folder, std::vector<std::string>* notes);

struct FailedDataset {
  std::string folder;  ///< subfolder name
  std::string error;   ///< what went wrong (names the file)
};

struct AggregateResult {
  std::string folder;
  int max_frames = 0;  ///< 0 = every frame
  EvaluationParams params;
  std::vector<std::string> methods;     ///< run order, paper first
  std::vector<DatasetDigest> digests;   ///< evaluated datasets, by folder name
  std::vector<FailedDataset> failures;  ///< datasets whose evaluation failed part-way
  std::optional<ScenarioManifest> manifest;
  std::vector<std::string> notes;       ///< said once each: ignored subfolders, manifest mismatches
  std::vector<PooledMethod> pooled;     ///< [method]
};

struct AggregateCallbacks {
  /// Once, after the datasets and the manifest are checked and before any is evaluated: the
  /// notes (AggregateResult::notes) for the caller to say.
  std::function<void(const std::vector<std::string>&)> notes;
  /// Before dataset index (0-based) of count is evaluated.
  std::function<void(std::size_t index, std::size_t count, const std::string& folder)> dataset_started;
  ProgressFn frame_progress;  ///< per frame of the current dataset
  /// After a dataset is evaluated, with its whole result (freed right after).
  std::function<void(const EvaluationResult&, const std::string& folder)> dataset_done;
};

/// Finds the datasets, checks each (dataset.yaml complete, frames, truth tables) and reads
/// manifest.csv before evaluating any: a dataset that fails these checks, a malformed manifest
/// or a folder without datasets throws std::invalid_argument naming the file. A dataset whose
/// evaluation fails later (a bad frame) is recorded in failures and the others go on.
AggregateResult evaluate_folder(const std::string& folder, int max_frames, const EvaluationParams& params,
                                const AggregateCallbacks& callbacks = {});

/// metrics.json of an aggregate report (keys documented in docs/EVALUATION.md).
std::string aggregate_metrics_json(const AggregateResult& result, const std::string& tool_version);

/// Writes the tables, then metrics.json, each atomically, into dir.
void write_aggregate_report(const std::string& dir, const AggregateResult& result, const std::string& tool_version);

/// Pooled figures per method and the target shares, for the console.
std::string aggregate_summary_text(const AggregateResult& result);

/// evaluate_folder(), each dataset's metrics.json into dir/datasets/<folder>/, the aggregate
/// tables and metrics.json, the console summary, the report script. When some datasets failed
/// the report (listing them) is still written, then std::runtime_error names every failed
/// dataset; when every dataset failed no report is written, only that error.
AggregateResult evaluate_folder_to_report(const std::string& folder, int max_frames, const EvaluationParams& params,
                                          const ReportOptions& options, const AggregateCallbacks& callbacks = {},
                                          std::ostream* summary = nullptr);

}  // namespace fmcw::eval
