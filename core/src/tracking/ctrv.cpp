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

Mat5 transition_jacobian(const Vec5& x, double dt) {
  // By central differences: the model is smooth and five columns are cheap.
  Mat5 F;
  for (int k = 0; k < 5; ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(x(k)));
    Vec5 a = x;
    Vec5 b = x;
    a(k) += h;
    b(k) -= h;
    F.col(k) = (propagate(a, dt) - propagate(b, dt)) / (2.0 * h);
  }
  return F;
}

void predict(Track& t, double dt, const TrackerParams::Motion& p) {
  if (dt <= 0.0) return;
  const Mat5 F = transition_jacobian(t.x, dt);
  // Below 1 the scale is on both noises (a vehicle driving steadily); above 1 on the yaw
  // acceleration's alone (a turn sharper than its noise: Motion::max_noise_scale).
  const double q = std::min(1.0, t.noise_scale) * p.accel_sigma_mps2 * p.accel_sigma_mps2;
  Mat5 Q = Mat5::Zero();
  for (int k = 0; k < 2; ++k) {
    Q(k, k) = q * dt * dt * dt * dt / 4.0;
    Q(k, k + 2) = Q(k + 2, k) = q * dt * dt * dt / 2.0;
    Q(k + 2, k + 2) = q * dt * dt;
  }
  Q(4, 4) = t.noise_scale * p.yaw_accel_sigma_rps2 * p.yaw_accel_sigma_rps2 * dt * dt;
  t.x_before = t.x;
  t.P_before = t.P;
  t.Q_before = Q;
  t.dt_before = dt;
  t.x = propagate(t.x, dt);
  t.P = F * t.P * F.transpose() + Q;
  t.heading_rad += t.x(4) * dt;
  t.clock_s += dt;
  t.extents_heading_rad += t.x(4) * dt;
}

void adapt_noise(Track& t, double correction, double expected, const TrackerParams& p) {
  const TrackerParams::Motion& pm = p.motion;
  if ((pm.min_noise_scale >= 1.0 && pm.max_noise_scale <= 1.0) || !(expected > 1e-9) ||
      !std::isfinite(correction))
    return;
  // A gait, or walkers side by side, is no manoeuvre: the full noise is for what they do next.
  if (t.small(p) || t.velocity().norm() <= p.small.walker_max_speed_mps) {
    t.noise_scale = 1.0;
    return;
  }
  // A turning track's next motion is not what its past updates say: at least the full noise.
  const double lowest = t.unsteady(p) ? 1.0 : pm.min_noise_scale;
  const double r = correction / expected;
  const double gain = r > 1.0 ? pm.noise_gain_up : pm.noise_gain_down;
  t.noise_scale = std::clamp(t.noise_scale * (1.0 + gain * (r - 1.0)), lowest,
                             std::max(lowest, pm.max_noise_scale));
}

void follow_corrections(Track& t, double correction, double expected, const TrackerParams::Calibration& p) {
  if (!p.enabled) return;
  // dx^T P^-1 dx >= 0 but for rounding; a negative one, or one not finite, says nothing.
  if (!(correction >= 0.0) || !std::isfinite(correction) || !std::isfinite(expected) || !(expected > 0.0)) return;
  t.corrections = p.memory * t.corrections + correction;
  t.expected_corrections = p.memory * t.expected_corrections + expected;
}

void information_update(Track& t, const Mat5& info, const Vec5& grad, const TrackerParams& p) {
  const Mat5 P_inv = t.P.inverse();
  const Mat5 P_new = (P_inv + info).inverse();
  const Vec5 dx = P_new * grad;
  t.x += dx;
  t.x(4) = std::clamp(t.x(4), -p.motion.max_yaw_rate_rps, p.motion.max_yaw_rate_rps);
  // For a consistent filter E[dx^T P^-1 dx] = tr(P^-1 (P - P_new)) = 5 - tr(P^-1 P_new); each
  // of the two users below returns at once when it is off.
  const double correction = dx.dot(P_inv * dx);
  const double expected = 5.0 - (P_inv * P_new).trace();
  follow_corrections(t, correction, expected, p.calibration);
  adapt_noise(t, correction, expected, p);
  t.P = 0.5 * (P_new + P_new.transpose());
}

void fuse_motion_prior(Track& t, const Track& prior) {
  const Eigen::Matrix3d P_prior =
      0.5 * (prior.P.block<3, 3>(2, 2) + prior.P.block<3, 3>(2, 2).transpose());
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(P_prior);
  if (!lu.isInvertible() || !prior.x.allFinite()) return;
  Mat5 info = Mat5::Zero();
  info.block<3, 3>(2, 2) = lu.inverse();
  Vec5 grad = Vec5::Zero();
  grad.segment<3>(2) = info.block<3, 3>(2, 2) * (prior.x.segment<3>(2) - t.x.segment<3>(2));
  const Mat5 P_new = (t.P.inverse() + info).inverse();
  if (!P_new.allFinite()) return;
  t.x += P_new * grad;
  t.P = 0.5 * (P_new + P_new.transpose());
}

}  // namespace fmcw::core::tracking
