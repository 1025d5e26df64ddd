#include "fmcw/eval/motion_confusion.hpp"

#include <limits>

#include "fmcw/core/check.hpp"

namespace fmcw::eval {

namespace {
double ratio(std::uint64_t num, std::uint64_t den) {
  return den == 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(num) / static_cast<double>(den);
}
}  // namespace

double MotionConfusion::precision() const { return ratio(tp, tp + fp); }
double MotionConfusion::recall() const { return ratio(tp, tp + fn); }
double MotionConfusion::accuracy() const { return ratio(tp + tn, total()); }

MotionConfusion& MotionConfusion::operator+=(const MotionConfusion& other) {
  tp += other.tp;
  fp += other.fp;
  tn += other.tn;
  fn += other.fn;
  return *this;
}

MotionConfusion count_motion(const std::vector<std::int32_t>& labels, const std::vector<std::uint8_t>& truth_moving,
                             const std::vector<std::uint8_t>& valid) {
  FMCW_CHECK_ARG(labels.size() == truth_moving.size() && labels.size() == valid.size(),
                 "count_motion: labels (", labels.size(), "), truth moving (", truth_moving.size(), ") and valid (",
                 valid.size(), ") must have one value per pixel");
  MotionConfusion c;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (!valid[i]) continue;
    const bool predicted = label_is_moving(labels[i]);
    if (truth_moving[i]) {
      ++(predicted ? c.tp : c.fn);
    } else {
      ++(predicted ? c.fp : c.tn);
    }
  }
  return c;
}

}  // namespace fmcw::eval
