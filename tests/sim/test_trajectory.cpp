#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fmcw/sim/trajectory.hpp"

namespace fmcw::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double deg(double rad) { return rad * 180.0 / kPi; }
double rad(double deg) { return deg * kPi / 180.0; }

Eigen::Isometry3d make_pose(const Eigen::Vector3d& position, double yaw, double pitch = 0.0,
                            double roll = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = position;
  return T;
}

double heading_of(const MotionState& state) {
  const Eigen::Vector3d forward = state.T_world_body.linear().col(0);
  return std::atan2(forward.y(), forward.x());
}

bool at_rest(const MotionState& state) {
  return state.twist.linear_mps.squaredNorm() == 0.0 &&
         state.twist.angular_rps.squaredNorm() == 0.0;
}

// Central differences of the pose over [t - h, t + h]: the position's derivative and the angular
// velocity from log(R(t + h) R(t - h)^T) / 2h, both in the world frame.
Twist finite_difference_twist(const Trajectory& trajectory, double t, double h) {
  const MotionState plus = trajectory.state(t + h);
  const MotionState minus = trajectory.state(t - h);
  Twist out;
  out.linear_mps = (plus.T_world_body.translation() - minus.T_world_body.translation()) / (2.0 * h);
  const Eigen::AngleAxisd delta(plus.T_world_body.linear() *
                                minus.T_world_body.linear().transpose());
  out.angular_rps = delta.axis() * delta.angle() / (2.0 * h);
  return out;
}

// Checks the twist against finite differences at `count` times spread over [t0, t1], and the
// Doppler use of it: a point fixed on the body moves at v + w x (p - origin). The step is small
// because a C2 spline's curvature has kinks at the waypoints, where a central difference errs by
// O(step) rather than O(step^2); rounding costs only ~1e-14 m / 2e-6 s here.
void expect_twist_consistent(const Trajectory& trajectory, double t0, double t1, int count,
                             double tolerance) {
  constexpr double kStep = 1e-6;
  const Eigen::Vector3d point_body(2.5, -1.0, 1.2);
  int checked = 0;
  for (int k = 0; k < count; ++k) {
    const double t = t0 + (t1 - t0) * (k + 0.5) / count;
    const MotionState state = trajectory.state(t);
    const Twist fd = finite_difference_twist(trajectory, t, kStep);
    const double scale = 1.0 + state.twist.linear_mps.norm();
    EXPECT_LT((fd.linear_mps - state.twist.linear_mps).norm(), tolerance * scale) << "t = " << t;
    EXPECT_LT((fd.angular_rps - state.twist.angular_rps).norm(), tolerance) << "t = " << t;

    const Eigen::Vector3d lever = state.T_world_body.linear() * point_body;
    const Eigen::Vector3d point_velocity =
        state.twist.linear_mps + state.twist.angular_rps.cross(lever);
    const Eigen::Vector3d fd_point_velocity =
        (trajectory.state(t + kStep).T_world_body * point_body -
         trajectory.state(t - kStep).T_world_body * point_body) /
        (2.0 * kStep);
    EXPECT_LT((fd_point_velocity - point_velocity).norm(), tolerance * (scale + 5.0))
        << "t = " << t;
    ++checked;
  }
  EXPECT_EQ(checked, count);
}

// Time at which the trajectory comes to rest for good, by bisection on "at rest", given a time
// `moving` at which it moves and a later time `resting` at which it rests.
double arrival_time(const Trajectory& trajectory, double moving, double resting) {
  EXPECT_FALSE(at_rest(trajectory.state(moving)));
  EXPECT_TRUE(at_rest(trajectory.state(resting)));
  for (int i = 0; i < 200 && resting - moving > 1e-13 * std::max(1.0, resting); ++i) {
    const double mid = 0.5 * (moving + resting);
    (at_rest(trajectory.state(mid)) ? resting : moving) = mid;
  }
  return resting;
}

// Time of closest approach to `target` within [t0, t1]: dense scan, then golden-section search.
double closest_approach_time(const Trajectory& trajectory, const Eigen::Vector3d& target, double t0,
                             double t1) {
  const auto distance = [&](double t) {
    return (trajectory.state(t).T_world_body.translation() - target).norm();
  };
  constexpr int kScan = 4000;
  int best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kScan; ++k) {
    const double d = distance(t0 + (t1 - t0) * k / kScan);
    if (d < best_distance) {
      best_distance = d;
      best = k;
    }
  }
  double lo = t0 + (t1 - t0) * std::max(best - 1, 0) / kScan;
  double hi = t0 + (t1 - t0) * std::min(best + 1, kScan) / kScan;
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int i = 0; i < 200 && hi - lo > 1e-13; ++i) {
    const double a = hi - ratio * (hi - lo);
    const double b = lo + ratio * (hi - lo);
    if (distance(a) < distance(b)) {
      hi = b;
    } else {
      lo = a;
    }
  }
  return 0.5 * (lo + hi);
}

template <typename Fn>
void expect_invalid_argument(Fn&& fn, const std::string& fragment) {
  try {
    fn();
    ADD_FAILURE() << "no exception; expected one mentioning '" << fragment << "'";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos)
        << "message '" << error.what() << "' lacks '" << fragment << "'";
  }
}

// ----------------------------------------------------------------------------------------------
// Static and constant velocity

TEST(StaticTrajectory, KeepsPoseWithZeroTwist) {
  const Eigen::Isometry3d T = make_pose({3.0, -2.0, 0.5}, 0.7, 0.1, -0.05);
  const auto trajectory = make_static_trajectory(T);
  for (double t : {-1e6, -3.0, 0.0, 0.25, 17.0, 1e6}) {
    const MotionState state = trajectory->state(t);
    EXPECT_EQ(state.T_world_body.matrix(), T.matrix());
    EXPECT_TRUE(at_rest(state));
  }
}

TEST(StaticTrajectory, RejectsBadPoseAndTime) {
  Eigen::Isometry3d scaled = make_pose({0.0, 0.0, 0.0}, 0.3);
  scaled.linear() *= 2.0;
  expect_invalid_argument([&] { make_static_trajectory(scaled); }, "not a proper rotation");
  Eigen::Isometry3d mirrored = Eigen::Isometry3d::Identity();
  mirrored.linear()(2, 2) = -1.0;
  expect_invalid_argument([&] { make_static_trajectory(mirrored); }, "not a proper rotation");
  Eigen::Isometry3d nan_pose = Eigen::Isometry3d::Identity();
  nan_pose.translation().x() = kNaN;
  expect_invalid_argument([&] { make_static_trajectory(nan_pose); }, "non-finite");
  const auto trajectory = make_static_trajectory(Eigen::Isometry3d::Identity());
  expect_invalid_argument([&] { trajectory->state(kNaN); }, "time must be finite");
}

TEST(ConstantVelocityTrajectory, MovesLinearlyWithFixedOrientation) {
  const Eigen::Isometry3d T0 = make_pose({1.0, 2.0, 3.0}, -0.4, 0.05, 0.02);
  const Eigen::Vector3d v(4.0, -1.5, 0.25);
  const auto trajectory = make_constant_velocity_trajectory(T0, v);
  for (double t : {-2.0, 0.0, 0.1, 3.7, 100.0}) {
    const MotionState state = trajectory->state(t);
    EXPECT_LT((state.T_world_body.translation() - (T0.translation() + v * t)).norm(), 1e-12);
    EXPECT_EQ(state.T_world_body.linear(), T0.linear());
    EXPECT_EQ(state.twist.linear_mps, v);
    EXPECT_EQ(state.twist.angular_rps, Eigen::Vector3d::Zero());
  }
  expect_twist_consistent(*trajectory, -5.0, 5.0, 50, 1e-6);
}

TEST(ConstantVelocityTrajectory, RejectsNonFiniteVelocity) {
  expect_invalid_argument(
      [] {
        make_constant_velocity_trajectory(Eigen::Isometry3d::Identity(), {1.0, kNaN, 0.0});
      },
      "velocity must be finite");
}

// ----------------------------------------------------------------------------------------------
// Constant turn rate

TEST(ConstantTurnRateTrajectory, ClosesACircleOfRadiusSpeedOverYawRate) {
  const double psi0 = rad(30.0);
  const double speed = 3.0;
  const double yaw_rate = 0.4;
  const Eigen::Isometry3d T0 = make_pose({1.0, 2.0, 0.5}, psi0);
  const auto trajectory = make_constant_turn_rate_trajectory(T0, speed, yaw_rate);
  const double radius = speed / yaw_rate;
  // Turning left (yaw rate > 0), the centre is one radius to the body's left at t = 0.
  const Eigen::Vector3d centre =
      T0.translation() + radius * Eigen::Vector3d(-std::sin(psi0), std::cos(psi0), 0.0);
  const double period = 2.0 * kPi / yaw_rate;
  for (int k = 0; k <= 100; ++k) {
    const double t = period * k / 100.0;
    const MotionState state = trajectory->state(t);
    const Eigen::Vector3d p = state.T_world_body.translation();
    EXPECT_NEAR((p - centre).norm(), radius, 1e-9) << "t = " << t;
    EXPECT_NEAR(p.z(), 0.5, 1e-12);
    // The brief's closed form.
    const double psi = psi0 + yaw_rate * t;
    EXPECT_NEAR(p.x(), 1.0 + radius * (std::sin(psi) - std::sin(psi0)), 1e-9);
    EXPECT_NEAR(p.y(), 2.0 - radius * (std::cos(psi) - std::cos(psi0)), 1e-9);
    EXPECT_NEAR(std::remainder(heading_of(state) - psi, 2.0 * kPi), 0.0, 1e-12);
  }
  const MotionState closed = trajectory->state(period);
  EXPECT_LT((closed.T_world_body.translation() - T0.translation()).norm(), 1e-9);
  EXPECT_TRUE(closed.T_world_body.linear().isApprox(T0.linear(), 1e-12));
  const MotionState half = trajectory->state(0.5 * period);
  EXPECT_NEAR((half.T_world_body.translation() - T0.translation()).norm(), 2.0 * radius, 1e-9);
}

TEST(ConstantTurnRateTrajectory, VelocityPointsAlongBodyX) {
  const auto trajectory =
      make_constant_turn_rate_trajectory(make_pose({-4.0, 7.0, 0.0}, 2.0), 8.0, -0.3);
  for (double t : {-3.0, 0.0, 1.0, 5.5, 12.0}) {
    const MotionState state = trajectory->state(t);
    const Eigen::Vector3d body_x = state.T_world_body.linear().col(0);
    EXPECT_LT((state.twist.linear_mps - 8.0 * body_x).norm(), 1e-12);
    EXPECT_EQ(state.twist.angular_rps, Eigen::Vector3d(0.0, 0.0, -0.3));
  }
}

TEST(ConstantTurnRateTrajectory, NegativeYawRateTurnsRightAndNegativeSpeedReverses) {
  const auto right = make_constant_turn_rate_trajectory(Eigen::Isometry3d::Identity(), 5.0, -0.5);
  EXPECT_LT(right->state(1.0).T_world_body.translation().y(), -0.1);
  EXPECT_LT(heading_of(right->state(1.0)), 0.0);
  const auto reverse = make_constant_turn_rate_trajectory(Eigen::Isometry3d::Identity(), -2.0, 0.0);
  EXPECT_LT(
      (reverse->state(3.0).T_world_body.translation() - Eigen::Vector3d(-6.0, 0.0, 0.0)).norm(),
      1e-12);
}

TEST(ConstantTurnRateTrajectory, ZeroAndTinyYawRatesStayAccurate) {
  const double psi0 = 1.1;
  const double speed = 10.0;
  const Eigen::Isometry3d T0 = make_pose({3.0, -1.0, 0.0}, psi0);
  const auto straight = make_constant_turn_rate_trajectory(T0, speed, 0.0);
  for (double t : {-2.0, 0.0, 7.0}) {
    const Eigen::Vector3d expected =
        T0.translation() + speed * t * Eigen::Vector3d(std::cos(psi0), std::sin(psi0), 0.0);
    EXPECT_LT((straight->state(t).T_world_body.translation() - expected).norm(), 1e-12);
    EXPECT_TRUE(std::isfinite(straight->state(t).T_world_body.translation().x()));
  }
  // yaw_rate * t runs across the series threshold (1e-4 rad) of the implementation; compare with
  // the closed form evaluated in long double, where its cancellation costs ~1e-13 m here.
  const double yaw_rate = 1e-5;
  const auto slow = make_constant_turn_rate_trajectory(T0, speed, yaw_rate);
  for (int k = 0; k <= 40; ++k) {
    const double t = -20.0 + k;
    const long double psi = psi0 + static_cast<long double>(yaw_rate) * t;
    const long double r = static_cast<long double>(speed) / yaw_rate;
    const double x =
        static_cast<double>(3.0L + r * (std::sin(psi) - std::sin(static_cast<long double>(psi0))));
    const double y =
        static_cast<double>(-1.0L - r * (std::cos(psi) - std::cos(static_cast<long double>(psi0))));
    const Eigen::Vector3d p = slow->state(t).T_world_body.translation();
    EXPECT_NEAR(p.x(), x, 1e-9) << "t = " << t;
    EXPECT_NEAR(p.y(), y, 1e-9) << "t = " << t;
  }
}

TEST(ConstantTurnRateTrajectory, PitchedStartClimbsAlongAHelix) {
  const double pitch = rad(-10.0);  // negative pitch about y raises the nose
  const double speed = 4.0;
  const double yaw_rate = 0.5;
  const Eigen::Isometry3d T0 = make_pose({0.0, 0.0, 1.0}, 0.0, pitch);
  const auto trajectory = make_constant_turn_rate_trajectory(T0, speed, yaw_rate);
  const double horizontal_radius = speed * std::cos(pitch) / yaw_rate;
  const Eigen::Vector3d centre(0.0, horizontal_radius, 0.0);
  for (double t : {0.5, 2.0, 6.0, 11.0}) {
    const Eigen::Vector3d p = trajectory->state(t).T_world_body.translation();
    EXPECT_NEAR((p - centre).head<2>().norm(), horizontal_radius, 1e-9);
    EXPECT_NEAR(p.z(), 1.0 + speed * std::sin(-pitch) * t, 1e-9);
  }
  expect_twist_consistent(*trajectory, -3.0, 15.0, 60, 1e-6);
}

TEST(ConstantTurnRateTrajectory, TwistMatchesFiniteDifferences) {
  const auto trajectory =
      make_constant_turn_rate_trajectory(make_pose({5.0, -3.0, 0.2}, -2.5), 12.0, 0.7);
  expect_twist_consistent(*trajectory, -10.0, 30.0, 200, 1e-6);
}

TEST(ConstantTurnRateTrajectory, RejectsNonFiniteInput) {
  expect_invalid_argument(
      [] { make_constant_turn_rate_trajectory(Eigen::Isometry3d::Identity(), kNaN, 0.1); },
      "speed must be finite");
  expect_invalid_argument(
      [] {
        make_constant_turn_rate_trajectory(Eigen::Isometry3d::Identity(), 1.0,
                                           std::numeric_limits<double>::infinity());
      },
      "yaw rate must be finite");
}

// ----------------------------------------------------------------------------------------------
// Waypoints

TEST(WaypointTrajectory, StraightLineAtConstantSpeedIsExact) {
  WaypointPath path;
  path.points_m = {{1.0, 2.0, 0.5}, {7.0, 10.0, 0.5}};  // 10 m long
  path.speeds_mps = {2.5};
  const auto trajectory = make_waypoint_trajectory(path);
  const Eigen::Vector3d direction(0.6, 0.8, 0.0);
  for (int k = 1; k < 40; ++k) {
    const double t = 4.0 * k / 40.0;
    const MotionState state = trajectory->state(t);
    EXPECT_LT((state.T_world_body.translation() - (path.points_m[0] + 2.5 * t * direction)).norm(),
              1e-9)
        << "t = " << t;
    EXPECT_LT((state.twist.linear_mps - 2.5 * direction).norm(), 1e-9);
    EXPECT_NEAR(heading_of(state), std::atan2(0.8, 0.6), 1e-12);
    EXPECT_NEAR(state.twist.angular_rps.norm(), 0.0, 1e-12);
    EXPECT_NEAR(state.T_world_body.linear()(2, 2), 1.0, 1e-15);
  }
  EXPECT_NEAR(arrival_time(*trajectory, 3.9, 4.1), 4.0, 1e-9);
}

TEST(WaypointTrajectory, SlopedLineKeepsTheBodyLevelAndClimbs) {
  WaypointPath path;
  path.points_m = {{0.0, 0.0, 0.0}, {4.0, 0.0, 3.0}, {8.0, 0.0, 6.0}};  // 10 m at 36.9 deg
  path.speeds_mps = {5.0};
  const auto trajectory = make_waypoint_trajectory(path);
  for (double t : {0.3, 1.0, 1.7}) {
    const MotionState state = trajectory->state(t);
    EXPECT_LT((state.twist.linear_mps - Eigen::Vector3d(4.0, 0.0, 3.0)).norm(), 1e-9);
    EXPECT_LT((state.T_world_body.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_LT((state.T_world_body.translation() - Eigen::Vector3d(4.0, 0.0, 3.0) * t).norm(), 1e-9);
  }
}

// Lead-in along +x, a quarter circle of radius 10 m around (10, 10) in 15 deg steps, lead-out
// along +y. Mirrored in y for a right turn.
WaypointPath quarter_turn(double speed, double mirror) {
  WaypointPath path;
  path.points_m = {{-10.0, 0.0, 0.0}, {-5.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}};
  for (int k = 0; k <= 6; ++k) {
    const double angle = rad(15.0 * k);
    path.points_m.emplace_back(10.0 + 10.0 * std::sin(angle),
                               mirror * (10.0 - 10.0 * std::cos(angle)), 0.0);
  }
  for (double y : {15.0, 20.0, 25.0, 30.0}) path.points_m.emplace_back(20.0, mirror * y, 0.0);
  path.speeds_mps = {speed};
  return path;
}

TEST(WaypointTrajectory, NinetyDegreeTurnHeadingAndYawRate) {
  const double speed = 5.0;
  const double radius = 10.0;
  for (double mirror : {1.0, -1.0}) {
    const WaypointPath path = quarter_turn(speed, mirror);
    const auto trajectory = make_waypoint_trajectory(path);
    const double end = arrival_time(*trajectory, 1.0, 100.0);

    EXPECT_NEAR(deg(heading_of(trajectory->state(-1.0))), 0.0, 0.5);
    EXPECT_NEAR(deg(heading_of(trajectory->state(end + 1.0))), mirror * 90.0, 0.5);

    const Eigen::Vector3d middle(10.0 + radius * std::sqrt(0.5),
                                 mirror * (10.0 - radius * std::sqrt(0.5)), 0.0);
    const double t_middle = closest_approach_time(*trajectory, middle, 0.0, end);
    const MotionState state = trajectory->state(t_middle);
    EXPECT_LT((state.T_world_body.translation() - middle).norm(), 1e-6);
    EXPECT_NEAR(deg(heading_of(state)), mirror * 45.0, 0.5);
    EXPECT_NEAR(state.twist.angular_rps.z(), mirror * speed / radius, 0.05 * speed / radius);

    // Along the arc the body turns one way only. A C2 interpolant cannot follow the curvature
    // jump where line meets arc, so around it the heading rings by about a degree, no more.
    const double t_arc_begin = closest_approach_time(*trajectory, path.points_m[4], 0.0, end);
    const double t_arc_end = closest_approach_time(*trajectory, path.points_m[10], 0.0, end);
    for (int k = 0; k <= 400; ++k) {
      const double t = end * k / 400.0;
      const MotionState at_t = trajectory->state(t);
      const double heading = mirror * deg(heading_of(at_t));
      EXPECT_GT(heading, -1.5) << "t = " << t;
      EXPECT_LT(heading, 91.5) << "t = " << t;
      if (t > t_arc_begin && t < t_arc_end) {
        EXPECT_GT(mirror * at_t.twist.angular_rps.z(), 0.2 * speed / radius) << "t = " << t;
      }
    }
  }
}

TEST(WaypointTrajectory, ConstantSpeedOnCurvedPathAndTravelTimeMatchesArcLength) {
  WaypointPath path;
  path.points_m = {
      {0.0, 0.0, 0.0}, {12.0, 3.0, 0.5}, {20.0, 15.0, 1.5}, {14.0, 26.0, 1.0}, {25.0, 35.0, 0.0}};
  const double speed = 7.0;
  path.speeds_mps = {speed};
  const auto trajectory = make_waypoint_trajectory(path);
  const double end = arrival_time(*trajectory, 1.0, 1000.0);

  constexpr int kSteps = 200000;
  double length = 0.0;
  Eigen::Vector3d previous = trajectory->state(0.0).T_world_body.translation();
  for (int k = 1; k <= kSteps; ++k) {
    const double t = end * k / kSteps;
    const Eigen::Vector3d p = trajectory->state(t).T_world_body.translation();
    length += (p - previous).norm();
    previous = p;
    if (k % 100 == 0 && k < kSteps) {
      EXPECT_NEAR(trajectory->state(t).twist.linear_mps.norm(), speed, 1e-6) << "t = " << t;
    }
  }
  // The chord sum underestimates by ~ kappa^2 ds^2 / 24 per unit length, ~1e-10 here.
  EXPECT_NEAR(end, length / speed, 1e-6 * end);
  EXPECT_LT((previous - path.points_m.back()).norm(), 1e-9);
}

TEST(WaypointTrajectory, PassesEveryWaypointAtItsSpeed) {
  WaypointPath path;
  path.points_m = {{0.0, 0.0, 0.0},   {10.0, 2.0, 0.3},  {18.0, 10.0, 1.0},
                   {15.0, 20.0, 1.2}, {25.0, 24.0, 0.8}, {35.0, 18.0, 0.0}};
  path.speeds_mps = {3.0, 5.0, 2.0, 0.0, 4.0, 1.0};
  path.start_time_s = 2.0;
  const auto trajectory = make_waypoint_trajectory(path);
  const double end = arrival_time(*trajectory, 3.0, 1000.0);
  double previous_time = path.start_time_s - 1e-9;
  for (std::size_t i = 1; i + 1 < path.points_m.size(); ++i) {
    const double t = closest_approach_time(*trajectory, path.points_m[i], previous_time, end);
    const MotionState state = trajectory->state(t);
    EXPECT_LT((state.T_world_body.translation() - path.points_m[i]).norm(), 1e-6)
        << "waypoint " << i;
    EXPECT_NEAR(state.twist.linear_mps.norm(), path.speeds_mps[i], 1e-5) << "waypoint " << i;
    EXPECT_GT(t, previous_time);
    previous_time = t;
  }
  // Speeds at the ends, just inside the motion.
  EXPECT_NEAR(trajectory->state(path.start_time_s + 1e-9).twist.linear_mps.norm(), 3.0, 1e-6);
  EXPECT_NEAR(trajectory->state(end - 1e-9).twist.linear_mps.norm(), 1.0, 1e-6);
}

// Collinear waypoints make the spline exactly the line, so arc length is the distance from the
// first point and the speed profile can be checked against its definition.
struct LinePath {
  WaypointPath path;
  std::vector<double> stations_m;
  Eigen::Vector3d direction;
};

LinePath uneven_line(const std::vector<double>& speeds) {
  LinePath line;
  line.direction = Eigen::Vector3d(3.0, 4.0, 0.0) / 5.0;
  line.stations_m = {0.0, 4.0, 10.0, 11.0, 20.0};
  for (double s : line.stations_m) {
    line.path.points_m.push_back(Eigen::Vector3d(2.0, -1.0, 0.0) + s * line.direction);
  }
  line.path.speeds_mps = speeds;
  return line;
}

double profile_speed(const LinePath& line, double s) {
  const std::vector<double>& st = line.stations_m;
  const std::size_t i =
      std::min<std::size_t>(
          static_cast<std::size_t>(std::upper_bound(st.begin(), st.end(), s) - st.begin()),
          st.size() - 1) -
      1;
  const double v0 = line.path.speeds_mps[i];
  const double v1 = line.path.speeds_mps[i + 1];
  const double x = (s - st[i]) / (st[i + 1] - st[i]);
  if (v0 > 0.0 && v1 > 0.0) return v0 + (v1 - v0) * x;
  // A span touching rest accelerates uniformly: v^2 linear in arc length.
  return std::sqrt(v0 * v0 + (v1 * v1 - v0 * v0) * x);
}

TEST(WaypointTrajectory, SpeedIsLinearInArcLengthBetweenWaypoints) {
  const LinePath line = uneven_line({1.0, 3.0, 3.0, 0.5, 2.0});
  const auto trajectory = make_waypoint_trajectory(line.path);
  const double end = arrival_time(*trajectory, 1.0, 1000.0);
  for (int k = 1; k < 500; ++k) {
    const double t = end * k / 500.0;
    const MotionState state = trajectory->state(t);
    const double s = (state.T_world_body.translation() - line.path.points_m[0]).dot(line.direction);
    EXPECT_NEAR(state.twist.linear_mps.norm(), profile_speed(line, s), 1e-9) << "s = " << s;
    EXPECT_LT((state.twist.linear_mps.normalized() - line.direction).norm(), 1e-9);
  }
}

TEST(WaypointTrajectory, TravelTimeIsTheIntegralOfInverseSpeed) {
  for (const std::vector<double>& speeds : {std::vector<double>{1.0, 3.0, 3.0, 0.5, 2.0},
                                            std::vector<double>{4.0, 4.0 + 1e-9, 2.0, 6.0, 6.0},
                                            std::vector<double>{0.0, 3.0, 0.0, 2.0, 0.0}}) {
    const LinePath line = uneven_line(speeds);
    // Composite Simpson per span; near a rest end 1 / v ~ 1 / sqrt(s) is integrable but not
    // smooth, so substitute s = L x^2 (from rest) or s = L (1 - x^2) (to rest) first.
    double expected = 0.0;
    for (std::size_t i = 0; i + 1 < line.stations_m.size(); ++i) {
      const double s0 = line.stations_m[i];
      const double length = line.stations_m[i + 1] - s0;
      const double v0 = speeds[i];
      const double v1 = speeds[i + 1];
      const auto integrand = [&](double x) {
        if (v0 == 0.0)
          return 2.0 * length * x / std::max(profile_speed(line, s0 + length * x * x), 1e-300);
        if (v1 == 0.0) {
          return 2.0 * length * x /
                 std::max(profile_speed(line, s0 + length * (1.0 - x * x)), 1e-300);
        }
        return length / profile_speed(line, s0 + length * x);
      };
      constexpr int kIntervals = 20000;
      double sum = 0.0;
      for (int k = 0; k <= kIntervals; ++k) {
        const double weight = (k == 0 || k == kIntervals) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
        // The substituted integrand's limit at the rest end is 2 L x / (v_other x) = 2 L / v_other.
        const double x = static_cast<double>(k) / kIntervals;
        const double value = (x == 0.0 && (v0 == 0.0 || v1 == 0.0))
                                 ? 2.0 * length / (v0 == 0.0 ? v1 : v0)
                                 : integrand(x);
        sum += weight * value;
      }
      expected += sum / (3.0 * kIntervals);
    }
    const auto trajectory = make_waypoint_trajectory(line.path);
    const double end = arrival_time(*trajectory, 0.01, 1000.0);
    EXPECT_NEAR(end, expected, 1e-8 * expected) << "first speed " << speeds[0];
  }
}

TEST(WaypointTrajectory, AcceleratingSpeedProfileMatchesClosedForm) {
  // v = 2 + 0.2 s on a 10 m line: ds/dt = 2 + 0.2 s gives s = 10 (e^{0.2 t} - 1), T = 5 ln 2.
  WaypointPath path;
  path.points_m = {{0.0, 0.0, 0.0}, {10.0, 0.0, 0.0}};
  path.speeds_mps = {2.0, 4.0};
  const auto trajectory = make_waypoint_trajectory(path);
  const double duration = 5.0 * std::log(2.0);
  for (int k = 1; k < 50; ++k) {
    const double t = duration * k / 50.0;
    const MotionState state = trajectory->state(t);
    EXPECT_NEAR(state.T_world_body.translation().x(), 10.0 * std::expm1(0.2 * t), 1e-9);
    EXPECT_NEAR(state.twist.linear_mps.x(), 2.0 * std::exp(0.2 * t), 1e-9);
  }
  EXPECT_NEAR(arrival_time(*trajectory, 1.0, 10.0), duration, 1e-9);
}

TEST(WaypointTrajectory, ZeroStartSpeedLeavesUniformlyAccelerating) {
  // From rest to 2 m/s over 4 m: a = v^2 / 2L = 0.5 m/s^2, reached after 4 s, then 2 m/s.
  WaypointPath path;
  path.points_m = {{0.0, 0.0, 0.0}, {4.0, 0.0, 0.0}, {10.0, 0.0, 0.0}};
  path.speeds_mps = {0.0, 2.0, 2.0};
  path.start_time_s = 1.0;
  const auto trajectory = make_waypoint_trajectory(path);
  for (double tau : {1e-6, 0.5, 1.0, 2.0, 3.9}) {
    const MotionState state = trajectory->state(1.0 + tau);
    EXPECT_NEAR(state.T_world_body.translation().x(), 0.25 * tau * tau, 1e-9);
    EXPECT_NEAR(state.twist.linear_mps.x(), 0.5 * tau, 1e-9);
  }
  EXPECT_NEAR(trajectory->state(1.0 + 6.0).T_world_body.translation().x(), 8.0, 1e-9);
  EXPECT_NEAR(arrival_time(*trajectory, 2.0, 100.0), 1.0 + 4.0 + 3.0, 1e-9);
}

TEST(WaypointTrajectory, StopsAtAZeroSpeedWaypointAndGoesOn) {
  WaypointPath path;
  path.points_m = {{0.0, 0.0, 0.0}, {5.0, 1.0, 0.0}, {10.0, 0.0, 0.0}};
  path.speeds_mps = {3.0, 0.0, 3.0};
  const auto trajectory = make_waypoint_trajectory(path);
  const double end = arrival_time(*trajectory, 0.5, 1000.0);
  const double t_stop = closest_approach_time(*trajectory, path.points_m[1], 0.0, end);
  EXPECT_NEAR(t_stop, 0.5 * end, 1e-3 * end);  // symmetric path and speeds
  EXPECT_LT(trajectory->state(t_stop).twist.linear_mps.norm(), 1e-6);
  EXPECT_GT(trajectory->state(t_stop + 0.1).twist.linear_mps.norm(), 0.01);
  EXPECT_LT((trajectory->state(end).T_world_body.translation() - path.points_m[2]).norm(), 1e-9);
}

TEST(WaypointTrajectory, WaitsBeforeStartAndRestsAfterEnd) {
  WaypointPath path = quarter_turn(6.0, 1.0);
  path.start_time_s = 3.0;
  const auto trajectory = make_waypoint_trajectory(path);
  const double initial_heading = heading_of(trajectory->state(3.0 + 1e-7));
  for (double t : {-100.0, 0.0, 2.999}) {
    const MotionState state = trajectory->state(t);
    EXPECT_EQ(state.T_world_body.translation(), path.points_m.front()) << "t = " << t;
    EXPECT_TRUE(at_rest(state));
    EXPECT_NEAR(heading_of(state), initial_heading, 1e-6);
    EXPECT_NEAR(state.T_world_body.linear()(2, 2), 1.0, 1e-15);
  }
  // At the start time itself the body is at the first point and already moving, so that a
  // path starting at t = 0 shows its speed in the first frame.
  const MotionState start = trajectory->state(3.0);
  EXPECT_LT((start.T_world_body.translation() - path.points_m.front()).norm(), 1e-12);
  EXPECT_FALSE(at_rest(start));
  EXPECT_FALSE(at_rest(trajectory->state(3.001)));

  const double end = arrival_time(*trajectory, 4.0, 1000.0);
  const double final_heading = heading_of(trajectory->state(end - 1e-7));
  for (double dt : {0.0, 1e-3, 1.0, 1e5}) {
    const MotionState state = trajectory->state(end + dt);
    EXPECT_EQ(state.T_world_body.translation(), path.points_m.back());
    EXPECT_TRUE(at_rest(state));
    EXPECT_NEAR(heading_of(state), final_heading, 1e-6);
  }
  EXPECT_LT(
      (trajectory->state(end - 1e-9).T_world_body.translation() - path.points_m.back()).norm(),
      1e-7);
}

TEST(WaypointTrajectory, TwistMatchesFiniteDifferences) {
  WaypointPath path;
  path.points_m = {{0.0, 0.0, 0.0},   {10.0, 2.0, 0.3},  {18.0, 10.0, 1.0}, {15.0, 20.0, 1.2},
                   {25.0, 24.0, 0.8}, {35.0, 18.0, 0.0}, {38.0, 5.0, -1.0}};
  path.speeds_mps = {0.0, 5.0, 2.0, 0.0, 14.0, 1.0, 3.0};
  path.start_time_s = -4.0;
  const auto trajectory = make_waypoint_trajectory(path);
  const double end = arrival_time(*trajectory, 0.0, 1000.0);
  // Avoid the jumps at start and end (the final speed is not 0).
  expect_twist_consistent(*trajectory, path.start_time_s + 1e-3, end - 1e-3, 997, 1e-6);
  // Also straddling waypoint passages, table nodes and the start, where speed starts at 0.
  expect_twist_consistent(*trajectory, path.start_time_s, path.start_time_s + 0.5, 50, 1e-6);

  const auto turn = make_waypoint_trajectory(quarter_turn(9.0, -1.0));
  expect_twist_consistent(*turn, 1e-3, arrival_time(*turn, 1.0, 100.0) - 1e-3, 500, 1e-6);
}

TEST(WaypointTrajectory, ClosedLoopMayRevisitTheFirstPoint) {
  WaypointPath path;
  path.points_m = {{0.0, 0.0, 0.0},  {20.0, 0.0, 0.0}, {25.0, 10.0, 0.0}, {10.0, 15.0, 0.0},
                   {-5.0, 8.0, 0.0}, {0.0, 0.0, 0.0},  {20.0, 0.0, 0.0}};
  path.speeds_mps = {8.0};
  const auto trajectory = make_waypoint_trajectory(path);
  const double end = arrival_time(*trajectory, 1.0, 1000.0);
  EXPECT_LT((trajectory->state(end).T_world_body.translation() - path.points_m.back()).norm(),
            1e-9);
  expect_twist_consistent(*trajectory, 1e-3, end - 1e-3, 200, 1e-6);
}

TEST(WaypointTrajectory, RejectsBadPaths) {
  const auto make = [](std::vector<Eigen::Vector3d> points, std::vector<double> speeds) {
    WaypointPath path;
    path.points_m = std::move(points);
    path.speeds_mps = std::move(speeds);
    return make_waypoint_trajectory(path);
  };
  expect_invalid_argument([&] { make({}, {1.0}); }, "at least 2 points, got 0");
  expect_invalid_argument([&] { make({{1.0, 2.0, 3.0}}, {1.0}); }, "at least 2 points, got 1");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}, {1.0, 2.0, 0.0}, {1.0, 2.0, 0.0}}, {1.0});
      },
      "points 2 and 3 coincide at (1, 2, 0)");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}, {9.0, 1.0, 0.0}}, {1.0, 2.0});
      },
      "2 speeds for 3 points");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}}, {});
      },
      "0 speeds for 2 points");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}}, {1.0, -0.5});
      },
      "speed 1 is -0.5 m/s");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}}, {kNaN});
      },
      "speed 0 is nan");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, kNaN, 0.0}}, {1.0});
      },
      "point 1 is not finite");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}}, {0.0});
      },
      "single speed is 0");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}, {9.0, 1.0, 0.0}}, {1.0, 0.0, 0.0});
      },
      "speeds at points 1 and 2 are both 0");
  expect_invalid_argument([&] { make({{0.0, 0.0, 0.0}, {0.0, 0.0, 5.0}}, {1.0}); }, "vertical");
  expect_invalid_argument(
      [&] {
        make({{0.0, 0.0, 0.0}, {10.0, 0.0, 0.0}, {0.0, 0.0, 0.0}}, {1.0});
      },
      "doubles back");

  WaypointPath late;
  late.points_m = {{0.0, 0.0, 0.0}, {5.0, 0.0, 0.0}};
  late.speeds_mps = {1.0};
  late.start_time_s = std::numeric_limits<double>::infinity();
  expect_invalid_argument([&] { make_waypoint_trajectory(late); }, "start time must be finite");
  late.start_time_s = 0.0;
  const auto trajectory = make_waypoint_trajectory(late);
  expect_invalid_argument([&] { trajectory->state(kNaN); }, "time must be finite");
}

// ----------------------------------------------------------------------------------------------
// Joints and gait

TEST(JointMotion, AngleAndRateFollowTheFormula) {
  JointMotion joint;
  joint.offset_rad = 0.2;
  joint.amplitude_rad = 0.5;
  joint.frequency_hz = 1.5;
  joint.phase_rad = 0.3;
  joint.spin_rate_rps = -0.7;
  for (double t : {-1.0, 0.0, 0.123, 2.5}) {
    const double arg = 2.0 * kPi * 1.5 * t + 0.3;
    EXPECT_NEAR(joint.angle_rad(t), 0.2 + 0.5 * std::sin(arg) - 0.7 * t, 1e-14);
    EXPECT_NEAR(joint.rate_rps(t), 0.5 * 2.0 * kPi * 1.5 * std::cos(arg) - 0.7, 1e-13);
    const double h = 1e-5;
    EXPECT_NEAR(joint.rate_rps(t), (joint.angle_rad(t + h) - joint.angle_rad(t - h)) / (2.0 * h),
                1e-8);
  }
  JointMotion wheel;
  wheel.spin_rate_rps = 31.25;  // 10 m/s on a 0.32 m wheel
  EXPECT_DOUBLE_EQ(wheel.angle_rad(2.0), 62.5);
  EXPECT_DOUBLE_EQ(wheel.rate_rps(-4.0), 31.25);
}

std::map<std::string, JointMotion> gait(double speed) {
  std::map<std::string, JointMotion> out;
  for (const auto& [name, motion] : pedestrian_gait(speed)) {
    EXPECT_TRUE(out.emplace(name, motion).second) << "duplicate node " << name;
  }
  return out;
}

TEST(PedestrianGait, DrivesTheEightLimbNodesAboutY) {
  const std::map<std::string, JointMotion> joints = gait(1.4);
  ASSERT_EQ(joints.size(), 8u);
  for (const char* name : {"upper_leg_l", "lower_leg_l", "upper_leg_r", "lower_leg_r",
                           "upper_arm_l", "lower_arm_l", "upper_arm_r", "lower_arm_r"}) {
    ASSERT_EQ(joints.count(name), 1u) << name;
    EXPECT_EQ(joints.at(name).axis, Eigen::Vector3d::UnitY()) << name;
    EXPECT_EQ(joints.at(name).spin_rate_rps, 0.0) << name;
  }
}

TEST(PedestrianGait, StandingStillHasNoMotion) {
  for (const auto& [name, joint] : pedestrian_gait(0.0)) {
    EXPECT_EQ(joint.amplitude_rad, 0.0) << name;
    for (double t : {0.0, 0.3, 1.7}) {
      EXPECT_EQ(joint.rate_rps(t), 0.0) << name;
      EXPECT_EQ(joint.angle_rad(t), joint.angle_rad(0.0)) << name;
    }
  }
  // Standing: legs straight, elbows only slightly bent.
  const auto joints = gait(0.0);
  EXPECT_EQ(joints.at("upper_leg_l").angle_rad(0.0), 0.0);
  EXPECT_EQ(joints.at("lower_leg_r").angle_rad(0.0), 0.0);
  EXPECT_LT(joints.at("lower_arm_l").angle_rad(0.0), 0.0);
  EXPECT_GT(joints.at("lower_arm_l").angle_rad(0.0), rad(-15.0));
}

TEST(PedestrianGait, NormalWalkingCadenceAndAmplitudes) {
  const auto joints = gait(1.4);
  const JointMotion& hip = joints.at("upper_leg_l");
  EXPECT_GE(hip.frequency_hz, 0.9);
  EXPECT_LE(hip.frequency_hz, 1.0);
  EXPECT_GE(deg(hip.amplitude_rad), 20.0);
  EXPECT_LE(deg(hip.amplitude_rad), 30.0);
  EXPECT_GE(deg(joints.at("upper_arm_l").amplitude_rad), 15.0);
  EXPECT_LE(deg(joints.at("upper_arm_l").amplitude_rad), 20.0);
  for (const auto& [name, joint] : joints) EXPECT_EQ(joint.frequency_hz, hip.frequency_hz) << name;
}

TEST(PedestrianGait, CadenceAndSwingGrowWithSpeed) {
  double previous_frequency = 0.0;
  double previous_amplitude = 0.0;
  for (double speed : {0.2, 0.6, 1.0, 1.4, 1.8, 2.2}) {
    const auto joints = gait(speed);
    EXPECT_GT(joints.at("upper_leg_r").frequency_hz, previous_frequency) << speed;
    EXPECT_GT(joints.at("upper_leg_r").amplitude_rad, previous_amplitude) << speed;
    previous_frequency = joints.at("upper_leg_r").frequency_hz;
    previous_amplitude = joints.at("upper_leg_r").amplitude_rad;
  }
  EXPECT_LE(gait(20.0).at("upper_leg_l").amplitude_rad, rad(40.0) + 1e-12);
}

// Samples two full cycles of the gait at `speed`.
std::vector<double> cycle_times(const std::map<std::string, JointMotion>& joints) {
  std::vector<double> times;
  const double period = 1.0 / joints.at("upper_leg_l").frequency_hz;
  for (int k = 0; k < 400; ++k) times.push_back(0.37 + 2.0 * period * k / 400.0);
  return times;
}

TEST(PedestrianGait, LegsInAntiphaseAndEachArmOppositeItsLeg) {
  const auto joints = gait(1.3);
  const double half_period = 0.5 / joints.at("upper_leg_l").frequency_hz;
  for (const auto& [left, right] :
       {std::pair{"upper_leg_l", "upper_leg_r"}, std::pair{"lower_leg_l", "lower_leg_r"},
        std::pair{"upper_arm_l", "upper_arm_r"}, std::pair{"lower_arm_l", "lower_arm_r"}}) {
    for (double t : cycle_times(joints)) {
      EXPECT_NEAR(joints.at(left).angle_rad(t), joints.at(right).angle_rad(t + half_period), 1e-12);
      EXPECT_NEAR(joints.at(left).angle_rad(t) - joints.at(left).offset_rad,
                  -(joints.at(right).angle_rad(t) - joints.at(right).offset_rad), 1e-12);
    }
  }
  // Correlation of the swings over whole cycles: -1 for an arm against its own leg.
  for (const auto& [arm, leg] :
       {std::pair{"upper_arm_l", "upper_leg_l"}, std::pair{"upper_arm_r", "upper_leg_r"}}) {
    double cross = 0.0, arm_sq = 0.0, leg_sq = 0.0;
    for (double t : cycle_times(joints)) {
      const double a = joints.at(arm).angle_rad(t) - joints.at(arm).offset_rad;
      const double l = joints.at(leg).angle_rad(t) - joints.at(leg).offset_rad;
      cross += a * l;
      arm_sq += a * a;
      leg_sq += l * l;
    }
    EXPECT_LT(cross / std::sqrt(arm_sq * leg_sq), -0.999) << arm;
  }
}

TEST(PedestrianGait, KneesFlexBackwardOnlyAndElbowsStayBent) {
  for (double speed : {0.5, 1.4, 2.2}) {
    const auto joints = gait(speed);
    for (const char* knee : {"lower_leg_l", "lower_leg_r"}) {
      double max_angle = 0.0;
      for (double t : cycle_times(joints)) {
        EXPECT_GE(joints.at(knee).angle_rad(t), -1e-12) << knee << " at " << speed << " m/s";
        max_angle = std::max(max_angle, joints.at(knee).angle_rad(t));
      }
      if (speed == 1.4) {
        EXPECT_GT(deg(max_angle), 45.0);
      }
    }
    for (const char* elbow : {"lower_arm_l", "lower_arm_r"}) {
      for (double t : cycle_times(joints)) {
        EXPECT_LT(joints.at(elbow).angle_rad(t), rad(-3.0)) << elbow << " at " << speed << " m/s";
        EXPECT_GT(joints.at(elbow).angle_rad(t), rad(-45.0));
      }
    }
    // Knee bends most while the thigh swings forward (hip angle falling): swing, not stance.
    const JointMotion& hip = joints.at("upper_leg_l");
    const JointMotion& knee = joints.at("lower_leg_l");
    double t_peak = 0.0;
    for (double t : cycle_times(joints)) {
      if (knee.angle_rad(t) > knee.angle_rad(t_peak)) t_peak = t;
    }
    EXPECT_LT(hip.rate_rps(t_peak), 0.0);
  }
}

TEST(PedestrianGait, RatesAreDerivativesOfAngles) {
  for (double speed : {0.3, 1.4, 2.5}) {
    for (const auto& [name, joint] : pedestrian_gait(speed)) {
      for (double t : {0.0, 0.11, 0.52, 1.37, 3.9}) {
        const double h = 1e-5;
        const double fd = (joint.angle_rad(t + h) - joint.angle_rad(t - h)) / (2.0 * h);
        EXPECT_NEAR(joint.rate_rps(t), fd, 1e-8) << name << " at " << speed << " m/s";
      }
    }
  }
}

// Sole position in the pelvis x-z plane for hip and knee angles: the asset's 0.43 m thigh and
// 0.47 m shank hang down and a positive angle about y moves the lower end towards -x.
Eigen::Vector2d foot(double hip, double knee) {
  return {-0.43 * std::sin(hip) - 0.47 * std::sin(hip + knee),
          -0.43 * std::cos(hip) - 0.47 * std::cos(hip + knee)};
}

TEST(PedestrianGait, FootMotionIsPlausibleAtWalkingSpeed) {
  const double speed = 1.4;
  const auto joints = gait(speed);
  const JointMotion& hip = joints.at("upper_leg_l");
  const JointMotion& knee = joints.at("lower_leg_l");
  double peak_speed = 0.0;
  for (double t : cycle_times(joints)) {
    // d/dt of foot(): chain rule with the joints' own rates.
    const double a = hip.angle_rad(t);
    const double b = a + knee.angle_rad(t);
    const double da = hip.rate_rps(t);
    const double db = da + knee.rate_rps(t);
    const Eigen::Vector2d velocity(-0.43 * std::cos(a) * da - 0.47 * std::cos(b) * db,
                                   0.43 * std::sin(a) * da + 0.47 * std::sin(b) * db);
    const double h = 1e-6;
    const Eigen::Vector2d fd = (foot(hip.angle_rad(t + h), knee.angle_rad(t + h)) -
                                foot(hip.angle_rad(t - h), knee.angle_rad(t - h))) /
                               (2.0 * h);
    EXPECT_LT((velocity - fd).norm(), 1e-6);
    peak_speed = std::max(peak_speed, velocity.norm());
  }
  EXPECT_GT(peak_speed, 1.0);
  EXPECT_LT(peak_speed, 6.0);

  // In stance (hip angle rising from its minimum to its maximum, half a cycle) the foot sweeps
  // backwards about as far as the body walks in that time, so it roughly stays on the ground.
  const double omega = 2.0 * kPi * hip.frequency_hz;
  const double t_heel_strike = (-0.5 * kPi - hip.phase_rad) / omega + 1.0 / hip.frequency_hz;
  const double t_toe_off = t_heel_strike + 0.5 / hip.frequency_hz;
  const double sweep = foot(hip.angle_rad(t_heel_strike), knee.angle_rad(t_heel_strike)).x() -
                       foot(hip.angle_rad(t_toe_off), knee.angle_rad(t_toe_off)).x();
  const double walked = speed * 0.5 / hip.frequency_hz;
  EXPECT_GT(sweep, 0.7 * walked);
  EXPECT_LT(sweep, 1.4 * walked);
}

TEST(PedestrianGait, RejectsNegativeOrNonFiniteSpeed) {
  expect_invalid_argument([] { pedestrian_gait(-0.1); }, "speed must be finite and >= 0");
  expect_invalid_argument([] { pedestrian_gait(kNaN); }, "speed must be finite and >= 0");
  expect_invalid_argument([] { pedestrian_gait(std::numeric_limits<double>::infinity()); },
                          "speed must be finite and >= 0");
}

}  // namespace
}  // namespace fmcw::sim
