#pragma once
// Evaluating many datasets: what is kept of each evaluation (a digest: the per-method summary,
// the targets, and the per-object centre-velocity errors needed for pooling, never the frames),
// the per-scenario metrics, and the metrics pooled over every scenario with their spread.

#include <cstdint>
#include <string>
#include <vector>

#include "fmcw/eval/evaluator.hpp"
#include "fmcw/eval/tail_metrics.hpp"

namespace fmcw::eval {

/// One method on one dataset.
struct MethodDigest {
  MethodSummary summary;
  std::vector<TargetCheck> checks;
  /// |estimate - reference| (the velocity at the actor's centre) of every estimated
  /// object-frame, and of those with >= large_object_pixels valid pixels [m/s].
  std::vector<double> centre_errors_mps;
  std::vector<double> centre_errors_large_mps;
};

/// What an aggregate evaluation keeps of one dataset's evaluation.
struct DatasetDigest {
  std::string folder;  ///< the dataset's folder name inside the evaluated folder
  SourceInfo source;   ///< config_yaml dropped
  DatasetStats dataset;
  std::vector<std::string> methods;
  std::vector<MethodDigest> per_method;  ///< [method], in methods order
};

DatasetDigest digest(const EvaluationResult& result, const std::string& folder);

/// A named number of a per-scenario row or of the pooled row. Counts are exact as doubles.
struct NamedValue {
  std::string key;
  double value = 0.0;
  bool integer = false;  ///< a count (written without decimals)
  bool spread = false;   ///< a rate or an error whose spread across scenarios is reported
};

/// The headline metrics of one method on one dataset (keys documented in docs/EVALUATION.md).
std::vector<NamedValue> scenario_metrics(const MethodDigest& method);

/// Quantiles of one per-scenario metric across the scenarios with a finite value.
struct Spread {
  std::string key;
  int scenarios = 0;  ///< scenarios with a finite value
  double median = 0.0, p10 = 0.0, p90 = 0.0, min = 0.0, max = 0.0;  ///< NaN when scenarios is 0
};

/// How often one target is met across the scenarios.
struct TargetShare {
  std::string key, relation;
  double limit = 0.0;
  int checked = 0;  ///< scenarios where the target was held (blind band: only with band pixels)
  int met = 0;
  double share = 0.0;  ///< met / checked (NaN when checked is 0)
};

/// One method over every scenario.
struct PooledMethod {
  std::string method;
  int scenarios = 0;
  MethodSummary pooled;  ///< counts summed; ratios from the sums; RMSEs from summed squares; medians unused
  ErrorStats centre, centre_large;  ///< of the pooled per-object samples
  std::vector<NamedValue> metrics;  ///< the pooled values under the per-scenario keys
  std::vector<Spread> spread;       ///< every per-scenario metric with spread = true
  std::vector<TargetShare> targets;
  int all_targets_met = 0;          ///< scenarios meeting every target held
};

/// Pools method `method` over the digests (all must list it). The per-object samples are
/// pooled, not the per-scenario medians; ego and yaw RMSEs pool the squared errors by frames.
PooledMethod pool(const std::vector<DatasetDigest>& digests, const std::string& method, const Targets& targets);

/// Every target key check_targets can return, in its order.
std::vector<TargetCheck> all_target_checks(const Targets& targets);

}  // namespace fmcw::eval
