#include "ctrv.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace fmcw::core::tracking {

Vec5 propagate(const Vec5& x, double dt) {
  Vec5 out = x;
  const double w = x(4);
  const double a = w * dt;
  const double s = std::sin(a);
  const double c = std::cos(a);
  const double vx = x(2);
  const double vy = x(3);
  if (std::abs(w) < 1e-9) {
    out(0) += vx * dt;
    out(1) += vy * dt;
  } else {
    out(0) += (s * vx - (1.0 - c) * vy) / w;
    out(1) += ((1.0 - c) * vx + s * vy) / w;
  }
  out(2) = c * vx - s * vy;
  out(3) = s * vx + c * vy;
  return out;
}

void predict(Track& t, double dt, const TrackerParams::Motion& p) {
  if (dt <= 0.0) return;
  // Jacobian by central differences: the model is smooth and five columns are cheap.
  Mat5 F;
  for (int k = 0; k < 5; ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(t.x(k)));
    Vec5 a = t.x;
    Vec5 b = t.x;
    a(k) += h;
    b(k) -= h;
    F.col(k) = (propagate(a, dt) - propagate(b, dt)) / (2.0 * h);
  }
  const double q = p.accel_sigma_mps2 * p.accel_sigma_mps2;
  Mat5 Q = Mat5::Zero();
  for (int k = 0; k < 2; ++k) {
    Q(k, k) = q * dt * dt * dt * dt / 4.0;
    Q(k, k + 2) = Q(k + 2, k) = q * dt * dt * dt / 2.0;
    Q(k + 2, k + 2) = q * dt * dt;
  }
  Q(4, 4) = p.yaw_accel_sigma_rps2 * p.yaw_accel_sigma_rps2 * dt * dt;
  t.x = propagate(t.x, dt);
  t.P = F * t.P * F.transpose() + Q;
  t.heading_rad += t.x(4) * dt;
  t.extents_heading_rad += t.x(4) * dt;
}

void information_update(Track& t, const Mat5& info, const Vec5& grad, const TrackerParams::Motion& p) {
  const Mat5 P_inv = t.P.inverse();
  const Mat5 P_new = (P_inv + info).inverse();
  t.x += P_new * grad;
  t.x(4) = std::clamp(t.x(4), -p.max_yaw_rate_rps, p.max_yaw_rate_rps);
  t.P = 0.5 * (P_new + P_new.transpose());
}

}  // namespace fmcw::core::tracking
