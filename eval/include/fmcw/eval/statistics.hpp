#pragma once
// Small statistics used by the metrics: medians and per-axis error accumulators.

#include <Eigen/Core>
#include <vector>

namespace fmcw::eval {

/// Median of the finite values (NaN and Inf are skipped); NaN when there are none. An even
/// count gives the mean of the two middle values.
double median(std::vector<double> values);

/// Quantile q in [0, 1] of the finite values by linear interpolation between order statistics
/// (numpy's default); NaN when there are none. Throws std::invalid_argument for q outside [0, 1].
double quantile(std::vector<double> values, double q);

/// Per-axis error statistics over samples: RMSE and max |error|. Non-finite samples are
/// rejected by add() (std::invalid_argument): callers decide what a missing estimate means.
struct AxisErrorStats {
  Eigen::Vector3d sum_squares = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_abs = Eigen::Vector3d::Zero();
  int count = 0;

  void add(const Eigen::Vector3d& error);
  Eigen::Vector3d rmse() const;     ///< sqrt(mean(e^2)) per axis [same unit as the samples]; NaN when empty
  Eigen::Vector3d max_abs_or_nan() const;  ///< max |e| per axis; NaN when empty
};

}  // namespace fmcw::eval
