#pragma once
// Velocity from Doppler by linear least squares (Eq. 16-22), solved in closed form.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

/// One least-squares velocity estimate with what a user needs to judge it.
struct VelocityEstimate {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Constant(kNaN);  ///< rig frame [m/s]
  /// sigma^2 (A^T A)^-1 with sigma^2 from the residuals (RSS / (n - 3)) [m^2/s^2]; NaN when
  /// n <= 3. A large diagonal entry says that axis is not observable from these beams.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Constant(kNaN);
  /// Eigenvalues of A^T A, ascending: the information along the weakest to strongest direction.
  Eigen::Vector3d information_eigenvalues = Eigen::Vector3d::Zero();
  double condition_number = std::numeric_limits<double>::infinity();  ///< of A^T A
  double residual_rms_mps = kNaN;  ///< RMS of e_i . V - y_i [m/s], from the normal-equation sums
                                   ///< (floor about 1e-7 m/s from cancellation)
  int num_points = 0;              ///< rows used
  int iterations = 0;              ///< solver iterations (0 for the closed form)
  bool used_qr = false;            ///< closed form fell back to QR on A
  bool valid = false;              ///< n >= 3, full rank, solver converged

  /// Per-axis standard deviation [m/s]: sqrt of the covariance diagonal.
  Eigen::Vector3d axis_std_mps() const { return covariance.diagonal().cwiseSqrt(); }
};

/// Rows e_i . V = y_i of a velocity problem, with e_i the unit beam direction from the beam's
/// origin to the point (Eq. 9, 16; generalised to heads not at the rig origin).
struct VelocityRows {
  std::vector<Eigen::Vector3d> directions;
  std::vector<double> targets_mps;

  std::size_t size() const { return targets_mps.size(); }
  void clear() {
    directions.clear();
    targets_mps.clear();
  }
};

/// Sums over the rows of a velocity problem: A^T A, A^T y, y^T y and n. Everything the closed
/// form and the statistics need, so rows need not be kept.
struct NormalEquations {
  Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
  Eigen::Vector3d Aty = Eigen::Vector3d::Zero();
  double yty = 0.0;
  int n = 0;

  void add(const Eigen::Vector3d& e, double y) {
    AtA.noalias() += e * e.transpose();
    Aty += y * e;
    yty += y * y;
    ++n;
  }
  static NormalEquations of(const VelocityRows& rows);
};

/// Mount point of each image column's head, for fast per-pixel origin lookup.
std::vector<Eigen::Vector3d> column_origins(const Scan& scan);

/// Eq. 20: a static point sees v_i = -e_i . V_self, so rows are e_i . V_self = -v_i.
void build_ego_rows(const Scan& scan, const std::vector<Eigen::Vector3d>& col_origin,
                    const std::vector<std::uint32_t>& pixels, VelocityRows& rows);

/// Eq. 22: a point of a moving object sees v_i = e_i . (V_model - V_self), so rows are
/// e_i . V_model = v_i + e_i . V_self.
void build_object_rows(const Scan& scan, const std::vector<Eigen::Vector3d>& col_origin,
                       const std::vector<std::uint32_t>& pixels, const Eigen::Vector3d& ego_velocity_mps,
                       VelocityRows& rows);

/// Fills covariance, conditioning and residual fields of an estimate whose velocity is set.
/// RSS = y^T y - 2 V^T A^T y + V^T A^T A V.
void fill_statistics(const NormalEquations& ne, VelocityEstimate& estimate);

/// Closed form: solves the 3x3 normal equations (LDLT). When the condition number of A^T A
/// exceeds qr_condition_threshold (the normal equations square it), solves by column-pivoting
/// QR on A instead, with the rows that rows_for_qr returns.
VelocityEstimate solve_normal_equations(const NormalEquations& ne, double qr_condition_threshold,
                                        const std::function<VelocityRows()>& rows_for_qr);

/// Velocity constrained to the horizontal plane (v_z = 0), for road users: only the x and y
/// columns are solved (2x2 normal equations). Covariance and conditioning are those of the 2x2
/// problem (the z row and column of the covariance are 0).
VelocityEstimate solve_velocity_planar(const VelocityRows& rows);

/// solve_velocity_planar made robust to parts that do not move with the body (limbs, wheels):
/// iteratively reweighted least squares with Tukey's biweight, scale from the median absolute
/// residual (at least noise_sigma_mps), starting from the plain least-squares solution.
VelocityEstimate solve_velocity_planar_robust(const VelocityRows& rows, double noise_sigma_mps, int iterations = 8);

/// A planar estimate's horizontal direction known to worse than max_weak_sigma_mps is
/// unobserved: beams that hardly fan out (a far cluster a few pixels wide), or a walker whose
/// swinging limbs vary the Doppler across the few degrees it spans, fit it to tens or thousands
/// of m/s. Known to: the larger of the covariance's larger eigenvalue and noise_sigma_mps^2 over
/// the smaller information eigenvalue (a three-point fit has next to no residual). Its velocity
/// along it is set to zero and its variance to at least unobserved_speed_sigma_mps squared: zero
/// is a guess, not a measurement. Invalid or non-finite estimates are left alone.
void zero_unobserved_direction(VelocityEstimate& estimate, double noise_sigma_mps, double max_weak_sigma_mps,
                               double unobserved_speed_sigma_mps = 10.0);

/// solve_normal_equations on explicit rows.
VelocityEstimate solve_velocity_closed_form(const VelocityRows& rows, double qr_condition_threshold = 1e8);

/// Flags an estimate not valid when its velocity says nothing: no finite covariance (3 rows or
/// fewer), a direction with a standard deviation above max_sigma_mps, or a speed above
/// kMaxPlausibleSpeedMps. The velocity and covariance are kept as they are.
inline constexpr double kMaxPlausibleSpeedMps = 1e3;
void flag_meaningless(VelocityEstimate& estimate, double max_sigma_mps);

}  // namespace fmcw::core
