#pragma once
// The paper's solver: the same least-squares problem handed to Ceres, one residual per point.

#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core {

struct CeresVelocityParams {
  int max_iterations = 50;
  // Tight enough to agree with the closed form to well under 1e-6 m/s, loose enough to stop by
  // convergence before rounding noise makes Levenberg-Marquardt steps invalid (a FAILURE).
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-12;
};

/// Minimises sum_i (e_i . V - y_i)^2 (Eq. 21 for the ego, Eq. 22 for an object) with Ceres'
/// Levenberg-Marquardt and dense QR, starting from V = 0.
VelocityEstimate solve_velocity_ceres(const VelocityRows& rows, const CeresVelocityParams& params = {});

}  // namespace fmcw::core
