#pragma once
// The tails of the object-velocity errors and the calibration of the reported covariances:
// what a median hides.

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "fmcw/eval/frame_evaluation.hpp"

namespace fmcw::eval {

/// Statistics of a list of error magnitudes [m/s]. Non-finite samples are skipped.
struct ErrorStats {
  int count = 0;
  double median = 0.0, p90 = 0.0, p95 = 0.0, max = 0.0;  ///< NaN when count is 0
  double share_over_0p5mps = 0.0;  ///< share of the errors above 0.5 m/s (NaN when count is 0)
  double share_over_1mps = 0.0;    ///< share of the errors above 1 m/s (NaN when count is 0)
};
ErrorStats error_stats(const std::vector<double>& errors_mps);

/// The normalised estimation error squared of one estimate in the ground plane (x, y):
/// e^T Sigma^-1 e over the directions the estimate observes. A direction whose reported
/// standard deviation is infinite, NaN or above `unobservable_sigma_mps` is one the estimate
/// says it does not observe: it is left out and `dof` drops by one.
struct NeesScore {
  bool has_covariance = false;  ///< a finite, positive semi-definite covariance was reported
  int dof = 0;                  ///< observed directions (0, 1 or 2)
  double nees = 0.0;            ///< e^T Sigma^-1 e over those directions
  bool inside_95 = false;       ///< nees below the chi-square 95 % quantile for dof
};
NeesScore score_nees(const Eigen::Vector2d& error_mps, const Eigen::Matrix2d& covariance, double unobservable_sigma_mps);

/// Chi-square 95 % quantile for 1 or 2 degrees of freedom (3.841, 5.991).
double chi2_95(int dof);

struct CalibrationStats {
  int estimates = 0;           ///< estimated object-frames
  int without_covariance = 0;  ///< of which report no usable covariance (not scored)
  int scored = 0;              ///< scored on at least one direction
  int partly_unobservable = 0; ///< of the scored, those reporting one direction unobservable
  int fully_unobservable = 0;  ///< report both directions unobservable (not scored)
  double coverage_95 = 0.0;    ///< share of the scored whose error is inside their 95 % ellipse (NaN when none)
  double mean_nees = 0.0;      ///< mean NEES over the scored (NaN when none)
  double mean_dof = 0.0;       ///< mean observed directions over the scored (the mean NEES's expectation)
};

struct TailParams {
  int large_object_pixels = 200;         ///< the objects the tails are taken over [valid pixels]
  double unobservable_sigma_mps = 1e3;   ///< see NeesScore
  int young_updates = 5;                 ///< "young": the first this many frames an actor is evaluated
};

/// Centre-velocity errors (|estimate - ActorTruth velocity|, the velocity at the actor's origin)
/// of estimated object-frames with >= large_object_pixels valid pixels, and broken down.
struct ObjectTails {
  ErrorStats ge200;
  std::map<std::string, ErrorStats> by_class;
  /// "0-20", "20-40", "40-80", "80+": the actor's distance from the rig origin [m].
  std::map<std::string, ErrorStats> by_distance;
  /// "first_5" (with young_updates = 5: the first young_updates frames in which the actor is evaluated, counting
  /// from its first) and "later".
  std::map<std::string, ErrorStats> by_age;
  /// Over every estimated object-frame (all sizes): are the reported covariances honest?
  CalibrationStats calibration;
  /// The same by the actor's class and by track age (keys as by_class and by_age): a coverage
  /// near 0.95 over all can hide one class overconfident and another overcautious.
  std::map<std::string, CalibrationStats> calibration_by_class;
  std::map<std::string, CalibrationStats> calibration_by_age;
};

/// The distance band name of a distance [m].
std::string distance_band(double distance_m);

/// Frames must be one method's, in frame order.
ObjectTails object_tails(const std::vector<FrameEvaluation>& frames, const TailParams& params = {});

}  // namespace fmcw::eval
