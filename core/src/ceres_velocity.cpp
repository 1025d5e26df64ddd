#include "fmcw/core/ceres_velocity.hpp"

#include <ceres/ceres.h>

namespace fmcw::core {

namespace {
// Residual of one point: r_i = e_i . V - y_i, the negated term of Eq. 21 / Eq. 22.
struct DopplerResidual {
  DopplerResidual(const Eigen::Vector3d& e, double y) : e_(e), y_(y) {}
  template <typename T>
  bool operator()(const T* const v, T* residual) const {
    residual[0] = T(e_.x()) * v[0] + T(e_.y()) * v[1] + T(e_.z()) * v[2] - T(y_);
    return true;
  }
  Eigen::Vector3d e_;
  double y_;
};
}  // namespace

VelocityEstimate solve_velocity_ceres(const VelocityRows& rows, const CeresVelocityParams& params) {
  VelocityEstimate est;
  est.num_points = static_cast<int>(rows.size());
  if (rows.size() < 3) return est;
  double v[3] = {0.0, 0.0, 0.0};
  ceres::Problem problem;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<DopplerResidual, 1, 3>(
                                 new DopplerResidual(rows.directions[k], rows.targets_mps[k])),
                             nullptr, v);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = params.max_iterations;
  options.function_tolerance = params.function_tolerance;
  options.gradient_tolerance = params.gradient_tolerance;
  options.parameter_tolerance = params.parameter_tolerance;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  est.velocity_mps = Eigen::Vector3d(v[0], v[1], v[2]);
  est.iterations = static_cast<int>(summary.iterations.size());
  fill_statistics(NormalEquations::of(rows), est);
  est.valid = summary.IsSolutionUsable() && est.velocity_mps.allFinite() &&
              std::isfinite(est.condition_number);
  return est;
}

}  // namespace fmcw::core
