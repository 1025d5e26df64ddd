#include "fmcw/sim/trajectory.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <tuple>
#include <utility>

#include "fmcw/core/check.hpp"

namespace fmcw::sim {

namespace {

// A pose read from a config may carry rounding; anything further off is a bug, not noise.
constexpr double kRotationTolerance = 1e-6;

// Consecutive waypoints closer than this [m] make the chord parameterisation degenerate.
constexpr double kMinPointSpacing_m = 1e-6;

// Horizontal tangent length per unit chord parameter below which the heading counts as
// undefined: the spline is nearly vertical there or almost stops to double back (a cusp).
constexpr double kMinHorizontalTangent = 0.05;

// Arc-length samples per spline span. The inverse u(s) is a quintic Hermite between samples, so
// the speed |dp/ds| it implies is off by O((1 / 64)^5): ~1e-8 relative on a 3 m radius hairpin
// between 10 m spaced waypoints, far less on ordinary bends.
constexpr int kSamplesPerSpan = 64;

// Below this |x| sinc(x) = 1 - x^2 / 6 is exact in double precision (next term x^4 / 120).
constexpr double kSincSeriesLimit = 1e-4;

double rad(double deg) { return deg * M_PI / 180.0; }

std::string to_text(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return out.str();
}

void check_time(double t_s) {
  FMCW_CHECK_ARG(std::isfinite(t_s), "trajectory: time must be finite, got ", t_s, " s");
}

void check_pose(const Eigen::Isometry3d& T, const char* what) {
  FMCW_CHECK_ARG(T.matrix().allFinite(), what, ": pose has non-finite entries");
  const Eigen::Matrix3d R = T.linear();
  const double error = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  const double det = R.determinant();
  FMCW_CHECK_ARG(error < kRotationTolerance && det > 0.0, what,
                 ": pose rotation is not a proper rotation (|R^T R - I| = ", error, ", det = ", det,
                 ")");
}

// sin(x) / x without the 0 / 0 at x = 0.
double sinc(double x) {
  return std::abs(x) < kSincSeriesLimit ? 1.0 - x * x / 6.0 : std::sin(x) / x;
}

Eigen::Matrix3d yaw_rotation(double cos_yaw, double sin_yaw) {
  Eigen::Matrix3d R;
  R << cos_yaw, -sin_yaw, 0.0, sin_yaw, cos_yaw, 0.0, 0.0, 0.0, 1.0;
  return R;
}

class StaticTrajectory final : public Trajectory {
 public:
  explicit StaticTrajectory(const Eigen::Isometry3d& T_world_body) {
    state_.T_world_body = T_world_body;
  }

  MotionState state(double t_s) const override {
    check_time(t_s);
    return state_;
  }

 private:
  MotionState state_;
};

class ConstantVelocityTrajectory final : public Trajectory {
 public:
  ConstantVelocityTrajectory(const Eigen::Isometry3d& T_world_body_at_0,
                             const Eigen::Vector3d& velocity_world_mps)
      : T_at_0_(T_world_body_at_0), velocity_mps_(velocity_world_mps) {}

  MotionState state(double t_s) const override {
    check_time(t_s);
    MotionState out;
    out.T_world_body = T_at_0_;
    out.T_world_body.translation() += velocity_mps_ * t_s;
    out.twist.linear_mps = velocity_mps_;
    out.distance_m = velocity_mps_.norm() * t_s;
    return out;
  }

 private:
  Eigen::Isometry3d T_at_0_;
  Eigen::Vector3d velocity_mps_;
};

class ConstantTurnRateTrajectory final : public Trajectory {
 public:
  ConstantTurnRateTrajectory(const Eigen::Isometry3d& T_world_body_at_0, double speed_mps,
                             double yaw_rate_rps)
      : T_at_0_(T_world_body_at_0),
        forward_at_0_(T_world_body_at_0.linear().col(0)),
        speed_mps_(speed_mps),
        yaw_rate_rps_(yaw_rate_rps) {}

  MotionState state(double t_s) const override {
    check_time(t_s);
    const double yaw = yaw_rate_rps_ * t_s;
    const double c = std::cos(yaw);
    const double s = std::sin(yaw);
    // Integrals over [0, t] of cos(w tau) and sin(w tau), in forms that stay finite as w -> 0:
    // sin(w t) / w = t sinc(w t) and (1 - cos(w t)) / w = t sin(w t / 2) sinc(w t / 2).
    const double int_cos = t_s * sinc(yaw);
    const double int_sin = t_s * std::sin(0.5 * yaw) * sinc(0.5 * yaw);
    const Eigen::Vector3d& f = forward_at_0_;
    const Eigen::Vector3d displacement(int_cos * f.x() - int_sin * f.y(),
                                       int_sin * f.x() + int_cos * f.y(), t_s * f.z());
    const Eigen::Matrix3d R_turn = yaw_rotation(c, s);

    MotionState out;
    out.T_world_body.linear() = R_turn * T_at_0_.linear();
    out.T_world_body.translation() = T_at_0_.translation() + speed_mps_ * displacement;
    out.twist.linear_mps = speed_mps_ * (R_turn * f);
    out.twist.angular_rps = Eigen::Vector3d(0.0, 0.0, yaw_rate_rps_);
    out.distance_m = std::abs(speed_mps_) * t_s;
    return out;
  }

 private:
  Eigen::Isometry3d T_at_0_;
  Eigen::Vector3d forward_at_0_;  // body x axis in the world at t = 0
  double speed_mps_;
  double yaw_rate_rps_;
};

// One span of the spline: p(d) = c0 + c1 d + c2 d^2 + c3 d^3 for d = u - u0 in [0, chord], where
// u is the cumulative chord length [m] of the waypoints (so |p'| is about 1).
struct SplineSpan {
  double u0 = 0.0;
  double chord = 0.0;
  Eigen::Vector3d c0, c1, c2, c3;

  Eigen::Vector3d position(double d) const { return c0 + d * (c1 + d * (c2 + d * c3)); }
  Eigen::Vector3d tangent(double d) const { return c1 + d * (2.0 * c2 + 3.0 * d * c3); }
  Eigen::Vector3d second(double d) const { return 2.0 * c2 + 6.0 * d * c3; }
};

// Natural cubic spline (zero second derivative at both ends) through the points over their
// cumulative chord length. Interior second derivatives come from the usual tridiagonal system,
// which is strictly diagonally dominant, so the Thomas algorithm needs no pivoting.
std::vector<SplineSpan> natural_spline(const std::vector<Eigen::Vector3d>& points) {
  const std::size_t n = points.size();
  const std::size_t spans = n - 1;
  std::vector<double> chord(spans);
  for (std::size_t i = 0; i < spans; ++i) chord[i] = (points[i + 1] - points[i]).norm();

  std::vector<Eigen::Vector3d> second(n, Eigen::Vector3d::Zero());
  if (n > 2) {
    const std::size_t m = n - 2;  // unknowns second[1] .. second[n - 2]
    std::vector<double> diag(m), upper(m);
    std::vector<Eigen::Vector3d> rhs(m);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = k + 1;
      diag[k] = 2.0 * (chord[i - 1] + chord[i]);
      upper[k] = chord[i];
      rhs[k] = 6.0 * ((points[i + 1] - points[i]) / chord[i] -
                      (points[i] - points[i - 1]) / chord[i - 1]);
    }
    for (std::size_t k = 1; k < m; ++k) {
      const double lower = chord[k];  // coefficient of second[k] in row k + 1 (point k + 1)
      const double factor = lower / diag[k - 1];
      diag[k] -= factor * upper[k - 1];
      rhs[k] -= factor * rhs[k - 1];
    }
    second[m] = rhs[m - 1] / diag[m - 1];
    for (std::size_t k = m - 1; k-- > 0;) {
      second[k + 1] = (rhs[k] - upper[k] * second[k + 2]) / diag[k];
    }
  }

  std::vector<SplineSpan> out(spans);
  double u = 0.0;
  for (std::size_t i = 0; i < spans; ++i) {
    const double h = chord[i];
    SplineSpan& span = out[i];
    span.u0 = u;
    span.chord = h;
    span.c0 = points[i];
    span.c1 = (points[i + 1] - points[i]) / h - h * (2.0 * second[i] + second[i + 1]) / 6.0;
    span.c2 = 0.5 * second[i];
    span.c3 = (second[i + 1] - second[i]) / (6.0 * h);
    u += h;
  }
  return out;
}

// How speed varies over one waypoint-to-waypoint span of the path (see WaypointPath).
enum class SpeedLaw { kConstant, kLinear, kFromRest, kToRest };

struct TimedSpan {
  SpeedLaw law = SpeedLaw::kConstant;
  double s_begin_m = 0.0;
  double length_m = 0.0;
  double v_begin_mps = 0.0;
  // kLinear: dv/ds [1/s]; kFromRest / kToRest: acceleration magnitude [m/s^2].
  double rate = 0.0;
  double duration_s = 0.0;
};

TimedSpan make_timed_span(double s_begin, double length, double v0, double v1) {
  TimedSpan span;
  span.s_begin_m = s_begin;
  span.length_m = length;
  span.v_begin_mps = v0;
  if (v0 == v1) {
    span.law = SpeedLaw::kConstant;
    span.duration_s = length / v0;
  } else if (v0 == 0.0) {
    span.law = SpeedLaw::kFromRest;
    span.rate = v1 * v1 / (2.0 * length);
    span.duration_s = 2.0 * length / v1;
  } else if (v1 == 0.0) {
    span.law = SpeedLaw::kToRest;
    span.rate = v0 * v0 / (2.0 * length);
    span.duration_s = 2.0 * length / v0;
  } else {
    // dt = ds / (v0 + a s) integrates to ln(v1 / v0) / a; log1p keeps it accurate for v1 ~ v0.
    span.law = SpeedLaw::kLinear;
    span.rate = (v1 - v0) / length;
    span.duration_s = std::log1p((v1 - v0) / v0) / span.rate;
  }
  return span;
}

// Arc length travelled into the span and speed, tau [s] after entering it.
std::pair<double, double> travel(const TimedSpan& span, double tau) {
  double s = 0.0;
  double v = 0.0;
  switch (span.law) {
    case SpeedLaw::kConstant:
      s = span.v_begin_mps * tau;
      v = span.v_begin_mps;
      break;
    case SpeedLaw::kLinear: {
      // ds/dt = v0 + a s  =>  s = v0 (e^{a t} - 1) / a, v = v0 e^{a t}.
      const double at = span.rate * tau;
      s = span.v_begin_mps * std::expm1(at) / span.rate;
      v = span.v_begin_mps * std::exp(at);
      break;
    }
    case SpeedLaw::kFromRest:
      s = 0.5 * span.rate * tau * tau;
      v = span.rate * tau;
      break;
    case SpeedLaw::kToRest:
      s = (span.v_begin_mps - 0.5 * span.rate * tau) * tau;
      v = span.v_begin_mps - span.rate * tau;
      break;
  }
  return {std::clamp(s, 0.0, span.length_m), std::max(v, 0.0)};
}

// One node of the arc-length table: the spline parameter u at arc length s and its first two
// derivatives there, from ds/du = |p'(u)|.
struct ArcSample {
  double u = 0.0;
  double du_ds = 0.0;
  double d2u_ds2 = 0.0;
};

ArcSample arc_sample(const SplineSpan& span, double d) {
  const Eigen::Vector3d tangent = span.tangent(d);
  const double speed_sq = tangent.squaredNorm();
  const double du_ds = 1.0 / std::sqrt(speed_sq);
  // d/ds |p'|^-1 = -(p' . p'') / |p'|^3 * du/ds.
  const double d2u_ds2 = -tangent.dot(span.second(d)) / (speed_sq * speed_sq);
  return {span.u0 + d, du_ds, d2u_ds2};
}

class WaypointTrajectory final : public Trajectory {
 public:
  explicit WaypointTrajectory(const WaypointPath& path)
      : start_time_s_(path.start_time_s + (path.waits_s.empty() ? 0.0 : path.waits_s.front())) {
    spans_ = natural_spline(path.points_m);
    build_arc_table();
    check_heading_defined();
    build_timing(path);
    rest_at_start_ = rest_state(path.points_m.front(), spans_.front().tangent(0.0));
    rest_at_end_ = rest_state(path.points_m.back(), spans_.back().tangent(spans_.back().chord));
    rest_at_end_.distance_m = sample_s_.back();
  }

  MotionState state(double t_s) const override {
    check_time(t_s);
    const double tau = t_s - start_time_s_;
    if (tau < 0.0) return rest_at_start_;  // at the start time itself the body already moves
    if (tau >= span_begin_s_.back()) return rest_at_end_;

    // span_begin_s_ holds the entry time of every span and, last, the arrival time.
    const auto after = std::upper_bound(span_begin_s_.begin() + 1, span_begin_s_.end() - 1, tau);
    const auto k = static_cast<std::size_t>(after - span_begin_s_.begin()) - 1;
    const TimedSpan& timed = timed_spans_[k];
    // Past the span's own duration the body waits at the span's end (a stop with wait_s), at rest.
    const auto [s_in_span, speed] = travel(timed, std::min(tau - span_begin_s_[k], timed.duration_s));
    const double s = timed.s_begin_m + s_in_span;

    const auto [sample, u, du_ds] = parameter_at(s);
    const SplineSpan& span = spans_[sample / kSamplesPerSpan];
    const double d = u - span.u0;
    const Eigen::Vector3d p = span.position(d);
    const Eigen::Vector3d dp_du = span.tangent(d);
    const Eigen::Vector3d d2p_du2 = span.second(d);
    const double du_dt = du_ds * speed;

    // Heading = atan2(p'_y, p'_x); its derivative is the planar cross product over |p'_xy|^2.
    const double horizontal_sq = dp_du.x() * dp_du.x() + dp_du.y() * dp_du.y();
    const double horizontal = std::sqrt(horizontal_sq);
    const double dyaw_du = (dp_du.x() * d2p_du2.y() - dp_du.y() * d2p_du2.x()) / horizontal_sq;

    MotionState out;
    out.T_world_body.linear() = yaw_rotation(dp_du.x() / horizontal, dp_du.y() / horizontal);
    out.T_world_body.translation() = p;
    out.twist.linear_mps = dp_du * du_dt;
    out.twist.angular_rps = Eigen::Vector3d(0.0, 0.0, dyaw_du * du_dt);
    out.distance_m = s;
    return out;
  }

 private:
  // Samples u evenly per span and accumulates the arc length with 5-point Gauss-Legendre, whose
  // error on the smooth |p'(u)| of one sub-interval is negligible.
  void build_arc_table() {
    static constexpr std::array<double, 5> kNodes = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                                     0.5384693101056831, 0.9061798459386640};
    static constexpr std::array<double, 5> kWeights = {0.2369268850561891, 0.4786286704993665,
                                                       0.5688888888888889, 0.4786286704993665,
                                                       0.2369268850561891};

    const std::size_t count = spans_.size() * kSamplesPerSpan + 1;
    sample_s_.reserve(count);
    samples_.reserve(count);
    double s = 0.0;
    for (const SplineSpan& span : spans_) {
      const double step = span.chord / kSamplesPerSpan;
      for (int j = 0; j < kSamplesPerSpan; ++j) {
        const double d = j * step;
        sample_s_.push_back(s);
        samples_.push_back(arc_sample(span, d));
        double length = 0.0;
        for (std::size_t q = 0; q < kNodes.size(); ++q) {
          length += kWeights[q] * span.tangent(d + 0.5 * step * (1.0 + kNodes[q])).norm();
        }
        s += 0.5 * step * length;
      }
    }
    const SplineSpan& last = spans_.back();
    sample_s_.push_back(s);
    samples_.push_back(arc_sample(last, last.chord));
  }

  void check_heading_defined() const {
    constexpr int kChecksPerSpan = 4 * kSamplesPerSpan;
    for (const SplineSpan& span : spans_) {
      for (int j = 0; j <= kChecksPerSpan; ++j) {
        const double d = span.chord * j / kChecksPerSpan;
        const Eigen::Vector3d tangent = span.tangent(d);
        FMCW_CHECK_ARG(tangent.head<2>().norm() >= kMinHorizontalTangent, "waypoint path: near ",
                       to_text(span.position(d)),
                       " the curve through the points is (nearly) vertical or doubles back on "
                       "itself, so the heading is undefined; add or move waypoints");
      }
    }
  }

  void build_timing(const WaypointPath& path) {
    const std::size_t n = path.points_m.size();
    const auto speed_at = [&](std::size_t i) {
      return path.speeds_mps.size() == 1 ? path.speeds_mps.front() : path.speeds_mps[i];
    };
    timed_spans_.reserve(n - 1);
    span_begin_s_.reserve(n);
    double t = 0.0;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double s0 = sample_s_[i * kSamplesPerSpan];
      const double s1 = sample_s_[(i + 1) * kSamplesPerSpan];
      timed_spans_.push_back(make_timed_span(s0, s1 - s0, speed_at(i), speed_at(i + 1)));
      span_begin_s_.push_back(t);
      t += timed_spans_.back().duration_s;
      if (!path.waits_s.empty() && i + 2 < n) t += path.waits_s[i + 1];  // the wait at point i + 1
    }
    span_begin_s_.push_back(t);
  }

  // Quintic Hermite interpolation of u(s) between table nodes (C2 across nodes), with the exact
  // derivative du/ds of the interpolant itself, so the returned velocity is the derivative of
  // the returned position. Returns the table interval too; interval k lies in spline span
  // k / kSamplesPerSpan.
  std::tuple<std::size_t, double, double> parameter_at(double s) const {
    const auto after = std::upper_bound(sample_s_.begin() + 1, sample_s_.end() - 1, s);
    const auto k = static_cast<std::size_t>(after - sample_s_.begin()) - 1;
    const double s0 = sample_s_[k];
    const double h = sample_s_[k + 1] - s0;
    const ArcSample& a = samples_[k];
    const ArcSample& b = samples_[k + 1];
    const double x = (s - s0) / h;
    const double x2 = x * x;
    const double x3 = x2 * x;
    const double x4 = x3 * x;
    const double x5 = x4 * x;
    // Basis for value, slope and curvature at x = 0, then the same at x = 1.
    const double h0 = 1.0 - 10.0 * x3 + 15.0 * x4 - 6.0 * x5;
    const double h1 = x - 6.0 * x3 + 8.0 * x4 - 3.0 * x5;
    const double h2 = 0.5 * (x2 - 3.0 * x3 + 3.0 * x4 - x5);
    const double h3 = 10.0 * x3 - 15.0 * x4 + 6.0 * x5;
    const double h4 = -4.0 * x3 + 7.0 * x4 - 3.0 * x5;
    const double h5 = 0.5 * (x3 - 2.0 * x4 + x5);
    const double g0 = -30.0 * x2 + 60.0 * x3 - 30.0 * x4;  // g_i = d h_i / dx
    const double g1 = 1.0 - 18.0 * x2 + 32.0 * x3 - 15.0 * x4;
    const double g2 = 0.5 * (2.0 * x - 9.0 * x2 + 12.0 * x3 - 5.0 * x4);
    const double g4 = -12.0 * x2 + 28.0 * x3 - 15.0 * x4;
    const double g5 = 0.5 * (3.0 * x2 - 8.0 * x3 + 5.0 * x4);
    const double hh = h * h;
    const double u = h0 * a.u + h1 * h * a.du_ds + h2 * hh * a.d2u_ds2 + h3 * b.u +
                     h4 * h * b.du_ds + h5 * hh * b.d2u_ds2;
    const double du_ds = g0 * (a.u - b.u) / h + g1 * a.du_ds + g2 * h * a.d2u_ds2 + g4 * b.du_ds +
                         g5 * h * b.d2u_ds2;
    return {k, u, du_ds};
  }

  static MotionState rest_state(const Eigen::Vector3d& p, const Eigen::Vector3d& tangent) {
    const double horizontal = tangent.head<2>().norm();
    MotionState out;
    out.T_world_body.linear() = yaw_rotation(tangent.x() / horizontal, tangent.y() / horizontal);
    out.T_world_body.translation() = p;
    return out;
  }

  double start_time_s_;
  std::vector<SplineSpan> spans_;
  std::vector<double> sample_s_;    // arc length [m] at each table node, increasing
  std::vector<ArcSample> samples_;  // parallel to sample_s_
  std::vector<TimedSpan> timed_spans_;
  std::vector<double> span_begin_s_;  // time since start_time_s_ of entering each span, then end
  MotionState rest_at_start_;
  MotionState rest_at_end_;
};

void check_waypoint_path(const WaypointPath& path) {
  const std::vector<Eigen::Vector3d>& points = path.points_m;
  const std::vector<double>& speeds = path.speeds_mps;
  FMCW_CHECK_ARG(points.size() >= 2, "waypoint path: need at least 2 points, got ", points.size());
  FMCW_CHECK_ARG(std::isfinite(path.start_time_s), "waypoint path: start time must be finite, got ",
                 path.start_time_s, " s");
  for (std::size_t i = 0; i < points.size(); ++i) {
    FMCW_CHECK_ARG(points[i].allFinite(), "waypoint path: point ", i,
                   " is not finite: ", to_text(points[i]));
  }
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    FMCW_CHECK_ARG((points[i + 1] - points[i]).norm() > kMinPointSpacing_m,
                   "waypoint path: points ", i, " and ", i + 1, " coincide at ",
                   to_text(points[i]));
  }
  FMCW_CHECK_ARG(speeds.size() == 1 || speeds.size() == points.size(),
                 "waypoint path: ", speeds.size(), " speeds for ", points.size(),
                 " points; give one speed per point or a single speed for all");
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    FMCW_CHECK_ARG(std::isfinite(speeds[i]) && speeds[i] >= 0.0, "waypoint path: speed ", i, " is ",
                   speeds[i], " m/s; speeds must be finite and >= 0");
  }
  if (speeds.size() == 1) {
    FMCW_CHECK_ARG(speeds.front() > 0.0,
                   "waypoint path: the single speed is 0 m/s, so the body could never move");
  }
  const std::vector<double>& waits = path.waits_s;
  FMCW_CHECK_ARG(waits.empty() || waits.size() == points.size(), "waypoint path: ", waits.size(),
                 " waits for ", points.size(), " points; give one wait per point or none");
  for (std::size_t i = 0; i < waits.size(); ++i) {
    FMCW_CHECK_ARG(std::isfinite(waits[i]) && waits[i] >= 0.0 && waits[i] <= 1e6, "waypoint path: wait ", i,
                   " is ", waits[i], " s; waits must be finite, >= 0 and at most 1e6 s");
    const double speed = speeds.size() == 1 ? speeds.front() : speeds[i];
    FMCW_CHECK_ARG(waits[i] == 0.0 || speed == 0.0, "waypoint path: wait ", i, " is ", waits[i],
                   " s at a point passed at ", speed, " m/s; the body can only wait where its speed is 0");
  }
  for (std::size_t i = 0; i + 1 < speeds.size(); ++i) {
    FMCW_CHECK_ARG(speeds[i] > 0.0 || speeds[i + 1] > 0.0, "waypoint path: speeds at points ", i,
                   " and ", i + 1,
                   " are both 0 m/s, so the body could never get from one to the other");
  }
}

// Gait constants. Cadence and amplitudes follow typical adult walking: ~112 steps/min and hip
// swing ~ +-25 deg at 1.4 m/s, knee flexion peaking near 60 deg early in swing, arm swing about
// 70% of the hip's and opposite to it.
constexpr double kGaitReferenceSpeed_mps = 1.4;
constexpr double kStrideFrequencyAtReference_hz = 0.93;  // one leg cycle = two steps
constexpr double kStrideFrequencyExponent = 0.35;        // slower walkers take shorter steps too
constexpr double kLegLength_m = 0.90;                    // asset: hip to sole 0.43 + 0.47
constexpr double kMaxHipAmplitude_rad = 40.0 * M_PI / 180.0;
constexpr double kHipForwardBias = 0.4;   // mean thigh angle forward, as a fraction of amplitude
constexpr double kKneeToHip = 1.2;        // knee amplitude / hip amplitude
constexpr double kKneeLagRad = M_PI / 4;  // knee peaks early in swing, 1/8 cycle after toe-off
constexpr double kArmToHip = 0.7;         // shoulder amplitude / hip amplitude
constexpr double kArmForwardBias = 0.2;   // mean arm angle forward, as a fraction of amplitude
constexpr double kElbowToArm = 0.4;       // elbow amplitude / shoulder amplitude
constexpr double kElbowFlexToArm = 0.6;   // extra mean elbow flexion / shoulder amplitude
constexpr double kElbowStandingFlexDeg = 5.0;

JointMotion about_y(double offset, double amplitude, double frequency, double phase) {
  JointMotion motion;
  motion.axis = Eigen::Vector3d::UnitY();
  motion.offset_rad = offset;
  motion.amplitude_rad = amplitude;
  motion.frequency_hz = frequency;
  motion.phase_rad = phase;
  return motion;
}

}  // namespace

std::unique_ptr<Trajectory> make_static_trajectory(const Eigen::Isometry3d& T_world_body) {
  check_pose(T_world_body, "static trajectory");
  return std::make_unique<StaticTrajectory>(T_world_body);
}

std::unique_ptr<Trajectory> make_constant_velocity_trajectory(
    const Eigen::Isometry3d& T_world_body_at_0, const Eigen::Vector3d& velocity_world_mps) {
  check_pose(T_world_body_at_0, "constant velocity trajectory");
  FMCW_CHECK_ARG(velocity_world_mps.allFinite(),
                 "constant velocity trajectory: velocity must be finite, got ",
                 to_text(velocity_world_mps), " m/s");
  return std::make_unique<ConstantVelocityTrajectory>(T_world_body_at_0, velocity_world_mps);
}

std::unique_ptr<Trajectory> make_constant_turn_rate_trajectory(
    const Eigen::Isometry3d& T_world_body_at_0, double speed_mps, double yaw_rate_rps) {
  check_pose(T_world_body_at_0, "constant turn rate trajectory");
  FMCW_CHECK_ARG(std::isfinite(speed_mps),
                 "constant turn rate trajectory: speed must be finite, got ", speed_mps, " m/s");
  FMCW_CHECK_ARG(std::isfinite(yaw_rate_rps),
                 "constant turn rate trajectory: yaw rate must be finite, got ", yaw_rate_rps,
                 " rad/s");
  return std::make_unique<ConstantTurnRateTrajectory>(T_world_body_at_0, speed_mps, yaw_rate_rps);
}

std::unique_ptr<Trajectory> make_waypoint_trajectory(const WaypointPath& path) {
  check_waypoint_path(path);
  return std::make_unique<WaypointTrajectory>(path);
}

double JointMotion::angle_rad(double t_s) const {
  return offset_rad + amplitude_rad * std::sin(2.0 * M_PI * frequency_hz * t_s + phase_rad) +
         spin_rate_rps * t_s;
}

double JointMotion::rate_rps(double t_s) const {
  const double omega = 2.0 * M_PI * frequency_hz;
  return amplitude_rad * omega * std::cos(omega * t_s + phase_rad) + spin_rate_rps;
}

std::vector<std::pair<std::string, JointMotion>> pedestrian_gait(double speed_mps) {
  FMCW_CHECK_ARG(std::isfinite(speed_mps) && speed_mps >= 0.0,
                 "pedestrian gait: speed must be finite and >= 0, got ", speed_mps, " m/s");

  double frequency = 0.0;
  double hip = 0.0;
  if (speed_mps > 0.0) {
    frequency = kStrideFrequencyAtReference_hz *
                std::pow(speed_mps / kGaitReferenceSpeed_mps, kStrideFrequencyExponent);
    // During stance the foot sweeps from +hip to -hip, 2 L sin(hip) along the ground, which
    // must match one step, half a stride.
    const double step_m = speed_mps / (2.0 * frequency);
    hip = std::asin(std::min(step_m / (2.0 * kLegLength_m), std::sin(kMaxHipAmplitude_rad)));
  }
  const double knee = kKneeToHip * hip;
  const double arm = kArmToHip * hip;
  const double elbow = kElbowToArm * arm;
  const double elbow_offset = -(rad(kElbowStandingFlexDeg) + kElbowFlexToArm * arm);

  // Per side, with x = 2 pi f t + phase: hip = -bias + A sin(x), so the foot moves back (angle
  // rising) in stance, x in (-pi/2, pi/2), and forward in swing. The knee (>= 0: lower end
  // backward) = K (1 + sin(x - pi/4)) is nearly straight at heel strike (x = -pi/2) and peaks
  // early in swing (x = 3 pi/4). The arm runs half a cycle from the same-side leg; the elbow bends
  // most (most negative) when the arm is most forward (most negative).
  std::vector<std::pair<std::string, JointMotion>> out;
  out.reserve(8);
  const std::array<std::pair<const char*, double>, 2> sides = {{{"l", 0.0}, {"r", M_PI}}};
  for (const auto& [side, phase] : sides) {
    out.emplace_back(std::string("upper_leg_") + side,
                     about_y(-kHipForwardBias * hip, hip, frequency, phase));
    out.emplace_back(std::string("lower_leg_") + side,
                     about_y(knee, knee, frequency, phase - kKneeLagRad));
  }
  for (const auto& [side, phase] : sides) {
    out.emplace_back(std::string("upper_arm_") + side,
                     about_y(-kArmForwardBias * arm, arm, frequency, phase + M_PI));
    out.emplace_back(std::string("lower_arm_") + side,
                     about_y(elbow_offset, elbow, frequency, phase + M_PI));
  }
  return out;
}

}  // namespace fmcw::sim
