#include "fmcw/eval/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fmcw/core/check.hpp"

namespace fmcw::eval {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<double> finite_sorted(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  std::sort(values.begin(), values.end());
  return values;
}
}  // namespace

double median(std::vector<double> values) { return quantile(std::move(values), 0.5); }

double quantile(std::vector<double> values, double q) {
  FMCW_CHECK_ARG(q >= 0.0 && q <= 1.0, "quantile: q must be in [0, 1], got ", q);
  const std::vector<double> v = finite_sorted(std::move(values));
  if (v.empty()) return kNaN;
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  return v[lo] + frac * (v[hi] - v[lo]);
}

void AxisErrorStats::add(const Eigen::Vector3d& error) {
  FMCW_CHECK_ARG(error.allFinite(), "AxisErrorStats: error (", error.transpose(), ") must be finite");
  sum_squares += error.cwiseAbs2();
  max_abs = max_abs.cwiseMax(error.cwiseAbs());
  ++count;
}

Eigen::Vector3d AxisErrorStats::rmse() const {
  if (count == 0) return Eigen::Vector3d::Constant(kNaN);
  return (sum_squares / static_cast<double>(count)).cwiseSqrt();
}

Eigen::Vector3d AxisErrorStats::max_abs_or_nan() const {
  return count == 0 ? Eigen::Vector3d::Constant(kNaN) : max_abs;
}

}  // namespace fmcw::eval
