#include "fmcw/sim/animation_clip.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::sim {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// The segment [k, k + 1] holding t and the fraction s in [0, 1) along it; false when t is
// outside the keys (the curve holds its end value there), with k the end it holds.
bool find_segment(const std::vector<double>& times, double t, std::size_t& k, double& s) {
  if (times.size() < 2 || t < times.front()) {
    k = 0;
    return false;
  }
  if (t >= times.back()) {
    k = times.size() - 1;
    return false;
  }
  k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  s = (t - times[k]) / (times[k + 1] - times[k]);
  return true;
}

// The value of key k (for kCubicSpline, the middle of its three entries), width n.
template <int N>
Eigen::Matrix<double, N, 1> key_value(const KeyCurve& c, std::size_t k) {
  const std::size_t stride = c.interpolation == Interpolation::kCubicSpline ? 3 : 1;
  const std::size_t offset = c.interpolation == Interpolation::kCubicSpline ? N : 0;
  return Eigen::Map<const Eigen::Matrix<double, N, 1>>(&c.values[k * stride * N + offset]);
}

// Appendix C: p(s) = (2s^3 - 3s^2 + 1) v_k + d (s^3 - 2s^2 + s) b_k + (-2s^3 + 3s^2) v_k+1
// + d (s^3 - s^2) a_k+1, with d the segment duration, b_k the out-tangent of key k and a_k+1 the
// in-tangent of key k + 1; and its exact derivative with respect to time (ds/dt = 1/d).
template <int N>
void hermite(const KeyCurve& c, std::size_t k, double s, Eigen::Matrix<double, N, 1>& p,
             Eigen::Matrix<double, N, 1>& p_dot) {
  using Vec = Eigen::Matrix<double, N, 1>;
  const double d = c.times_s[k + 1] - c.times_s[k];
  const Vec v0 = Eigen::Map<const Vec>(&c.values[(3 * k + 1) * N]);
  const Vec b0 = Eigen::Map<const Vec>(&c.values[(3 * k + 2) * N]);
  const Vec a1 = Eigen::Map<const Vec>(&c.values[(3 * k + 3) * N]);
  const Vec v1 = Eigen::Map<const Vec>(&c.values[(3 * k + 4) * N]);
  const double s2 = s * s, s3 = s2 * s;
  p = (2 * s3 - 3 * s2 + 1) * v0 + d * (s3 - 2 * s2 + s) * b0 + (-2 * s3 + 3 * s2) * v1 + d * (s3 - s2) * a1;
  p_dot = ((6 * s2 - 6 * s) * v0 + d * (3 * s2 - 4 * s + 1) * b0 + (-6 * s2 + 6 * s) * v1 + d * (3 * s2 - 2 * s) * a1) / d;
}

Eigen::Quaterniond to_quaternion(const Eigen::Vector4d& xyzw) {
  return Eigen::Quaterniond(xyzw[3], xyzw[0], xyzw[1], xyzw[2]).normalized();
}

}  // namespace

const char* to_string(Interpolation interpolation) {
  switch (interpolation) {
    case Interpolation::kStep:
      return "STEP";
    case Interpolation::kLinear:
      return "LINEAR";
    case Interpolation::kCubicSpline:
      return "CUBICSPLINE";
  }
  return "?";
}

void KeyCurve::validate(const std::string& where) const {
  const auto fail = [&](const std::string& what) { throw core::FileError(where + ": " + what); };
  if (width != 3 && width != 4) fail("a curve has width 3 or 4, got " + std::to_string(width));
  if (times_s.empty()) fail("no key");
  const std::size_t per_key = static_cast<std::size_t>(width) * (interpolation == Interpolation::kCubicSpline ? 3 : 1);
  if (values.size() != times_s.size() * per_key) {
    fail(std::to_string(times_s.size()) + " key times but " + std::to_string(values.size() / static_cast<std::size_t>(width)) +
         " values of width " + std::to_string(width) + " (" + to_string(interpolation) + " needs " +
         std::to_string(per_key / static_cast<std::size_t>(width)) + " per key)");
  }
  for (std::size_t k = 0; k < times_s.size(); ++k) {
    if (!std::isfinite(times_s[k])) fail("key " + std::to_string(k) + " has a non-finite time");
    if (k > 0 && !(times_s[k] > times_s[k - 1])) {
      fail("key times must increase strictly, key " + std::to_string(k) + " at " + std::to_string(times_s[k]) +
           " s follows " + std::to_string(times_s[k - 1]) + " s");
    }
  }
  for (std::size_t v = 0; v < values.size(); ++v) {
    if (!std::isfinite(values[v])) fail("key " + std::to_string(v / per_key) + " has a non-finite value");
  }
  if (width == 4) {
    for (std::size_t k = 0; k < times_s.size(); ++k) {
      if (key_value<4>(*this, k).norm() < 1e-9) fail("key " + std::to_string(k) + " is a zero quaternion");
    }
  }
}

void KeyCurve::sample_vector(double t_s, Eigen::Vector3d& value, Eigen::Vector3d& rate) const {
  std::size_t k = 0;
  double s = 0.0;
  rate.setZero();
  if (!find_segment(times_s, t_s, k, s) || interpolation == Interpolation::kStep) {
    value = key_value<3>(*this, k);
    return;
  }
  if (interpolation == Interpolation::kCubicSpline) {
    hermite<3>(*this, k, s, value, rate);
    return;
  }
  const Eigen::Vector3d a = key_value<3>(*this, k), b = key_value<3>(*this, k + 1);
  value = (1.0 - s) * a + s * b;
  rate = (b - a) / (times_s[k + 1] - times_s[k]);
}

void KeyCurve::sample_rotation(double t_s, Eigen::Quaterniond& value, Eigen::Vector3d& omega) const {
  std::size_t k = 0;
  double s = 0.0;
  omega.setZero();
  if (!find_segment(times_s, t_s, k, s) || interpolation == Interpolation::kStep) {
    value = to_quaternion(key_value<4>(*this, k));
    return;
  }
  if (interpolation == Interpolation::kCubicSpline) {
    // q = p / |p|; dq/dt = (p' - q (q . p')) / |p|; omega = vector part of 2 dq/dt q*.
    Eigen::Vector4d p, p_dot;
    hermite<4>(*this, k, s, p, p_dot);
    const double n = p.norm();
    if (!(n > 1e-9)) {
      // The spline passes through (or next to) the zero quaternion, which is no rotation (e.g.
      // keys q and -q with zero tangents, at the middle): hold the nearer key there.
      value = to_quaternion(key_value<4>(*this, s < 0.5 ? k : k + 1));
      return;
    }
    const Eigen::Vector4d q = p / n;
    const Eigen::Vector4d q_dot = (p_dot - q * q.dot(p_dot)) / n;
    value = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
    const Eigen::Quaterniond w =
        Eigen::Quaterniond(q_dot[3], q_dot[0], q_dot[1], q_dot[2]) * value.conjugate();
    omega = 2.0 * w.vec();
    return;
  }
  // Slerp along the shorter arc: q(s) = q0 exp(s log(q0* q1)), a rotation about one fixed axis
  // at a constant rate: omega = R0 axis * angle / d in the parent frame.
  const Eigen::Quaterniond q0 = to_quaternion(key_value<4>(*this, k));
  Eigen::Quaterniond q1 = to_quaternion(key_value<4>(*this, k + 1));
  if (q0.dot(q1) < 0.0) q1.coeffs() = -q1.coeffs();
  const Eigen::Quaterniond delta = q0.conjugate() * q1;
  const double sin_half = delta.vec().norm();
  if (sin_half < 1e-15) {
    value = q0;
    return;
  }
  const double angle = 2.0 * std::atan2(sin_half, delta.w());
  const Eigen::Vector3d axis = delta.vec() / sin_half;
  value = q0 * Eigen::Quaterniond(Eigen::AngleAxisd(s * angle, axis));
  omega = q0 * axis * (angle / (times_s[k + 1] - times_s[k]));
}

void AnimationClip::local_transform(std::size_t track, const NodeTrs& rest, double t_s, Eigen::Matrix4d& L,
                                    Eigen::Matrix4d& L_dot) const {
  const NodeTrack& tr = tracks[track];
  Eigen::Vector3d t = rest.translation, t_dot = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = rest.rotation;
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  Eigen::Vector3d s = rest.scale, s_dot = Eigen::Vector3d::Zero();
  if (!tr.translation.empty()) tr.translation.sample_vector(t_s, t, t_dot);
  if (!tr.rotation.empty()) tr.rotation.sample_rotation(t_s, q, omega);
  if (!tr.scale.empty()) tr.scale.sample_vector(t_s, s, s_dot);
  const Eigen::Matrix3d R = q.toRotationMatrix();
  // L = [R S, t], dL/dt = [[omega]x R S + R dS/dt, dt/dt] (product rule).
  L.setIdentity();
  L.topLeftCorner<3, 3>() = R * s.asDiagonal();
  L.topRightCorner<3, 1>() = t;
  L_dot.setZero();
  L_dot.topLeftCorner<3, 3>() = skew(omega) * R * s.asDiagonal() + R * s_dot.asDiagonal();
  L_dot.topRightCorner<3, 1>() = t_dot;
}

void ClipPlayback::clip_time(double duration_s, double t_s, double distance_m, double speed_mps, double& tau,
                             double& tau_rate) const {
  if (clock == Clock::kDistance) {
    tau = offset_s + speed * distance_m / nominal_speed_mps;
    tau_rate = speed * speed_mps / nominal_speed_mps;
  } else if (t_s < start_s) {
    tau = offset_s;
    tau_rate = 0.0;
  } else {
    tau = offset_s + speed * (t_s - start_s);
    tau_rate = speed;
  }
  if (!(duration_s > 0.0)) {
    // A clip of single keys is one pose.
    tau = 0.0;
    tau_rate = 0.0;
  } else if (loop) {
    tau = std::fmod(tau, duration_s);
    if (tau < 0.0) tau += duration_s;
  } else if (tau < 0.0 || tau > duration_s) {
    tau = std::clamp(tau, 0.0, duration_s);
    tau_rate = 0.0;
  }
}

}  // namespace fmcw::sim
