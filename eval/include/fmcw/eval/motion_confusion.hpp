#pragma once
// Moving/static classification per pixel against the ground truth (Eq. 23-25, moving = positive).

#include <cstdint>
#include <vector>

namespace fmcw::eval {

/// A label counts as "moving" when it is a moving cluster (>= 1) or an unassigned region (-2,
/// below min_cluster_pixels: not claimed static); 0 is static; -1 (no return) is not counted.
constexpr bool label_is_moving(std::int32_t label) { return label >= 1 || label == -2; }

/// Pixel counts of one frame, or summed over frames (pooled).
struct MotionConfusion {
  std::uint64_t tp = 0;  ///< truly moving, labelled moving
  std::uint64_t fp = 0;  ///< static, labelled moving
  std::uint64_t tn = 0;  ///< static, labelled static
  std::uint64_t fn = 0;  ///< truly moving, labelled static

  std::uint64_t total() const { return tp + fp + tn + fn; }
  std::uint64_t truth_moving() const { return tp + fn; }
  std::uint64_t predicted_moving() const { return tp + fp; }
  double precision() const;  ///< Eq. 23: TP / (TP + FP); NaN when nothing is labelled moving
  double recall() const;     ///< Eq. 24: TP / (TP + FN); NaN when nothing truly moves
  double accuracy() const;   ///< Eq. 25: (TP + TN) / all; NaN without pixels

  MotionConfusion& operator+=(const MotionConfusion& other);
};

/// Counts over the pixels with valid[i] != 0. truth_moving is the ground truth `moving` field
/// (surface absolute speed above the simulator's threshold, 0.1 m/s by default). Throws
/// std::invalid_argument when the arrays differ in size, naming them.
MotionConfusion count_motion(const std::vector<std::int32_t>& labels, const std::vector<std::uint8_t>& truth_moving,
                             const std::vector<std::uint8_t>& valid);

}  // namespace fmcw::eval
