// Keyframe curves and clip playback against closed forms: a cubic Hermite spline reproduces a
// cubic exactly, slerp turns at a constant rate, every derivative matches the curve it belongs
// to (checked by finite differences here, never computed by them in the code).

#include <gtest/gtest.h>

#include <cmath>

#include "fmcw/sim/animation_clip.hpp"

namespace fmcw::sim {
namespace {

Eigen::Vector3d cubic(double t) { return {1 + 2 * t - t * t + 0.5 * t * t * t, -3 + 0.2 * t * t, 0.7 * t * t * t - t}; }
Eigen::Vector3d cubic_rate(double t) { return {2 - 2 * t + 1.5 * t * t, 0.4 * t, 2.1 * t * t - 1}; }

void push(std::vector<double>& v, const Eigen::Vector3d& x) { v.insert(v.end(), {x.x(), x.y(), x.z()}); }
void push(std::vector<double>& v, const Eigen::Quaterniond& q) { v.insert(v.end(), {q.x(), q.y(), q.z(), q.w()}); }

// Angular velocity from a finite difference of a rotation: [omega]x = dR/dt R^T.
Eigen::Vector3d omega_fd(const KeyCurve& c, double t, double h) {
  Eigen::Quaterniond qa, qb, q;
  Eigen::Vector3d unused;
  c.sample_rotation(t - h, qa, unused);
  c.sample_rotation(t + h, qb, unused);
  c.sample_rotation(t, q, unused);
  const Eigen::Matrix3d W = (qb.toRotationMatrix() - qa.toRotationMatrix()) / (2 * h) * q.toRotationMatrix().transpose();
  return {0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1))};
}

TEST(KeyCurve, CubicSplineReproducesACubicAndItsExactDerivative) {
  // Keys sampled from a cubic with its own derivative as both tangents: the Hermite spline of
  // glTF's Appendix C is then that cubic, value and derivative, at any time.
  KeyCurve c;
  c.interpolation = Interpolation::kCubicSpline;
  for (const double t : {0.0, 0.4, 1.1, 2.0}) {
    c.times_s.push_back(t);
    push(c.values, cubic_rate(t));  // in-tangent
    push(c.values, cubic(t));
    push(c.values, cubic_rate(t));  // out-tangent
  }
  c.validate("test");
  for (double t = 0.0; t < 2.0; t += 0.037) {
    Eigen::Vector3d v, r;
    c.sample_vector(t, v, r);
    ASSERT_LT((v - cubic(t)).norm(), 1e-12) << t;
    ASSERT_LT((r - cubic_rate(t)).norm(), 1e-12) << t;
  }
}

TEST(KeyCurve, CubicSplineUsesTheOutTangentOfAKeyAndTheInTangentOfTheNext) {
  KeyCurve c;
  c.interpolation = Interpolation::kCubicSpline;
  c.times_s = {0.0, 2.0};
  // key 0: in (9 9 9), value 0, out (1 0 0); key 1: in (0 -2 0), value (1 1 1), out (9 9 9).
  c.values = {9, 9, 9, 0, 0, 0, 1, 0, 0, 0, -2, 0, 1, 1, 1, 9, 9, 9};
  Eigen::Vector3d v, r;
  c.sample_vector(1e-9, v, r);
  EXPECT_LT((r - Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(0, 0, 0)).cwiseAbs().maxCoeff(), 2e-8);
  c.sample_vector(2.0 - 1e-9, v, r);
  EXPECT_LT((r - Eigen::Vector3d(0, -2, 0)).cwiseAbs().maxCoeff(), 2e-8);
  EXPECT_LT((v - Eigen::Vector3d(1, 1, 1)).norm(), 1e-8);
  // The analytic Hermite derivative inside: finite differences agree.
  for (double t = 0.1; t < 2.0; t += 0.3) {
    Eigen::Vector3d a, b, ra;
    c.sample_vector(t - 1e-6, a, ra);
    c.sample_vector(t + 1e-6, b, ra);
    c.sample_vector(t, v, r);
    EXPECT_LT((r - (b - a) / 2e-6).norm(), 1e-6) << t;
  }
}

TEST(KeyCurve, LinearIsPiecewiseLinearAndStepHoldsEachKey) {
  KeyCurve c;
  c.times_s = {0.0, 1.0, 3.0};
  c.values = {0, 0, 0, 2, 4, 6, 2, 0, 6};
  Eigen::Vector3d v, r;
  c.sample_vector(0.5, v, r);
  EXPECT_LT((v - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
  EXPECT_LT((r - Eigen::Vector3d(2, 4, 6)).norm(), 1e-12);
  c.sample_vector(2.0, v, r);
  EXPECT_LT((r - Eigen::Vector3d(0, -2, 0)).norm(), 1e-12);
  // Outside the keys: the end values, at rest.
  c.sample_vector(-1.0, v, r);
  EXPECT_EQ(v, Eigen::Vector3d::Zero());
  EXPECT_EQ(r, Eigen::Vector3d::Zero());
  c.sample_vector(5.0, v, r);
  EXPECT_EQ(v, Eigen::Vector3d(2, 0, 6));
  EXPECT_EQ(r, Eigen::Vector3d::Zero());
  c.interpolation = Interpolation::kStep;
  c.sample_vector(0.99, v, r);
  EXPECT_EQ(v, Eigen::Vector3d::Zero());
  EXPECT_EQ(r, Eigen::Vector3d::Zero());
  c.sample_vector(1.0, v, r);
  EXPECT_EQ(v, Eigen::Vector3d(2, 4, 6));
}

TEST(KeyCurve, LinearRotationIsSlerpAtAConstantRateAlongTheShorterArc) {
  // Two keys 1.2 rad apart about a tilted axis, 0.5 s apart: omega = R0 axis 1.2 / 0.5.
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 2).normalized();
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond q1 = q0 * Eigen::Quaterniond(Eigen::AngleAxisd(1.2, axis));
  KeyCurve c;
  c.width = 4;
  c.times_s = {1.0, 1.5};
  push(c.values, q0);
  push(c.values, q1);
  c.validate("test");
  const Eigen::Vector3d expected = q0 * axis * (1.2 / 0.5);
  for (const double t : {1.05, 1.2, 1.33, 1.49}) {
    Eigen::Quaterniond q;
    Eigen::Vector3d omega;
    c.sample_rotation(t, q, omega);
    EXPECT_LT((omega - expected).norm(), 1e-12) << t;
    EXPECT_LT((omega - omega_fd(c, t, 1e-6)).norm(), 1e-6) << t;
    const Eigen::Quaterniond exact = q0 * Eigen::Quaterniond(Eigen::AngleAxisd(1.2 * (t - 1.0) / 0.5, axis));
    EXPECT_NEAR(std::abs(q.dot(exact)), 1.0, 1e-12);
  }
  // The same rotation written with the opposite sign takes the same (short) way.
  KeyCurve flipped = c;
  for (std::size_t k = 4; k < 8; ++k) flipped.values[k] = -flipped.values[k];
  Eigen::Quaterniond q;
  Eigen::Vector3d omega;
  flipped.sample_rotation(1.2, q, omega);
  EXPECT_LT((omega - expected).norm(), 1e-12);
}

TEST(KeyCurve, CubicSplineRotationTurnsAtTheRateOfItsNormalisedCurve) {
  KeyCurve c;
  c.width = 4;
  c.interpolation = Interpolation::kCubicSpline;
  c.times_s = {0.0, 0.8, 2.0};
  const Eigen::Quaterniond keys[3] = {Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())),
                                      Eigen::Quaterniond(Eigen::AngleAxisd(0.9, Eigen::Vector3d(0, 1, 1).normalized())),
                                      Eigen::Quaterniond(Eigen::AngleAxisd(-0.5, Eigen::Vector3d::UnitY()))};
  const double tangents[3][4] = {{0.1, 0.0, 0.3, -0.1}, {-0.2, 0.4, 0.1, 0.0}, {0.0, 0.1, -0.3, 0.2}};
  for (int k = 0; k < 3; ++k) {
    c.values.insert(c.values.end(), tangents[k], tangents[k] + 4);
    push(c.values, keys[k]);
    c.values.insert(c.values.end(), tangents[k], tangents[k] + 4);
  }
  c.validate("test");
  for (double t = 0.05; t < 2.0; t += 0.11) {
    Eigen::Quaterniond q;
    Eigen::Vector3d omega;
    c.sample_rotation(t, q, omega);
    EXPECT_NEAR(q.norm(), 1.0, 1e-12);
    EXPECT_LT((omega - omega_fd(c, t, 1e-6)).norm(), 1e-6) << t;
  }
}

TEST(KeyCurve, ValidateNamesWhatIsWrong) {
  KeyCurve c;
  c.times_s = {0.0, 1.0, 2.0};
  c.values = {0, 0, 0, 1, 1, 1};
  EXPECT_THROW(
      try { c.validate("clip 'walk' channel 3"); } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "clip 'walk' channel 3: 3 key times but 2 values of width 3 (LINEAR needs 1 per key)");
        throw;
      },
      std::invalid_argument);
  c.values.insert(c.values.end(), {2, std::nan(""), 2});
  EXPECT_THROW(c.validate("x"), std::invalid_argument);
  c.values[7] = 2.0;
  c.times_s[2] = 1.0;
  EXPECT_THROW(c.validate("x"), std::invalid_argument);
  c.times_s[2] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(c.validate("x"), std::invalid_argument);
  KeyCurve r;
  r.width = 4;
  r.times_s = {0.0};
  r.values = {0, 0, 0, 0};
  EXPECT_THROW(r.validate("x"), std::invalid_argument);
  r.interpolation = Interpolation::kCubicSpline;
  r.values = {0, 0, 0, 1};  // CUBICSPLINE needs in-tangent, value, out-tangent
  EXPECT_THROW(r.validate("x"), std::invalid_argument);
}

TEST(ClipPlayback, TimeClockStartsLoopsAndHolds) {
  ClipPlayback p;
  p.speed = 2.0;
  p.start_s = 1.0;
  p.offset_s = 0.25;
  double tau = 0, rate = 0;
  p.clip_time(1.0, 0.5, 0.0, 0.0, tau, rate);  // before the start: the clip's start pose, at rest
  EXPECT_DOUBLE_EQ(tau, 0.25);
  EXPECT_EQ(rate, 0.0);
  p.clip_time(1.0, 1.5, 0.0, 0.0, tau, rate);  // 0.25 + 2 * 0.5 = 1.25 -> 0.25 looped
  EXPECT_NEAR(tau, 0.25, 1e-12);
  EXPECT_EQ(rate, 2.0);
  p.loop = false;
  p.clip_time(1.0, 1.5, 0.0, 0.0, tau, rate);  // held at the end
  EXPECT_EQ(tau, 1.0);
  EXPECT_EQ(rate, 0.0);
  p.speed = -1.0;  // backwards, looped
  p.loop = true;
  p.clip_time(1.0, 1.5, 0.0, 0.0, tau, rate);
  EXPECT_NEAR(tau, 0.75, 1e-12);
  EXPECT_EQ(rate, -1.0);
}

TEST(ClipPlayback, DistanceClockFollowsThePathAndRestsWithIt) {
  ClipPlayback p;
  p.clock = ClipPlayback::Clock::kDistance;
  p.nominal_speed_mps = 1.4;
  double tau = 0, rate = 0;
  p.clip_time(1.0, 123.0, 0.7, 2.8, tau, rate);  // 0.7 m at the 1.4 m/s clip: half a second
  EXPECT_NEAR(tau, 0.5, 1e-12);
  EXPECT_NEAR(rate, 2.0, 1e-12);  // twice the nominal speed: twice the cadence
  p.clip_time(1.0, 500.0, 0.7, 0.0, tau, rate);  // standing: the same pose, at rest
  EXPECT_NEAR(tau, 0.5, 1e-12);
  EXPECT_EQ(rate, 0.0);
}

}  // namespace
}  // namespace fmcw::sim
