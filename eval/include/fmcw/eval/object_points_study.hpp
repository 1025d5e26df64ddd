#pragma once
// `fmcw study object-points`: num_th^m, the cap on points per cluster in Algorithm 2, swept:
// object velocity accuracy against object-estimation time. The paper chose 200.

#include <functional>
#include <string>
#include <vector>

#include "fmcw/eval/frame_source.hpp"
#include "fmcw/eval/run_summary.hpp"

namespace fmcw::eval {

struct ObjectPointsStudyParams {
  /// num_th^m; 0 = every point (always run: the subsampling error is measured against it).
  std::vector<int> caps = {10, 20, 50, 100, 200, 500, 1000, 2000, 0};
  /// "ceres" (the paper's Algorithm 2: the `paper` preset) and/or "closed_form" (the same capped
  /// subsets solved by the 3x3 normal equations).
  std::vector<std::string> solvers = {"ceres", "closed_form"};
  int stride = 1;  ///< use every stride-th frame of the source
  std::uint64_t seed = 0;
  int num_threads = 1;  ///< per-object threads; 1 keeps the timing per object clean
  ObjectMatchParams objects;
  SummaryParams summary;

  void validate() const;
};

struct ObjectPointsPoint {
  std::string solver;
  int cap = 0;
  MethodSummary summary;
  /// Median |V(cap) - V(all points)| over estimated objects with >= large_object_pixels pixels,
  /// same solver: the error the subsampling itself adds, apart from the model's own [m/s].
  double median_subsample_error_mps_ge200 = 0.0;
  double mean_objects_ms = 0.0;         ///< object stage per frame [ms]
  double objects_ms_per_cluster = 0.0;  ///< object stage time / clusters, over all frames [ms]
};

struct ObjectPointsStudyResult {
  ObjectPointsStudyParams params;
  SourceInfo source;
  int frames_used = 0;
  std::vector<ObjectPointsPoint> points;  ///< solver-major, caps in the given order
  double seconds = 0.0;
};

ObjectPointsStudyResult run_object_points_study(FrameSource& source, const ObjectPointsStudyParams& params,
                                                const std::function<void(std::size_t, std::size_t)>& progress = {});

/// object_points_sweep.csv, then metrics.json (kind "object_points").
void write_object_points_report(const std::string& dir, const ObjectPointsStudyResult& result,
                                const std::string& tool_version);

}  // namespace fmcw::eval
