// The simulator on analytic scenes: exact ranges, exact Doppler, rigid-body surface velocities,
// beam origins, noise statistics, determinism across thread counts.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/scene.hpp"
#include "support/sim_scenes.hpp"

namespace fmcw::sim {
namespace {

using test::at;
using test::noise_free;

std::shared_ptr<const MeshAsset> box_asset(const Eigen::Vector3f& h, float reflectivity = 0.5f) {
  return std::make_shared<const MeshAsset>(box_mesh(h, reflectivity));
}

SceneObject wall_at_x(double x) {
  SceneObject wall;
  wall.name = "wall";
  wall.asset = box_asset({0.5f, 200.0f, 100.0f});
  wall.trajectory = make_static_trajectory(at(x + 0.5, 0, 0));
  return wall;
}

// One small head, 20 x 10 deg at 0.5 deg, mounted off the rig origin and yawed.
core::RigModel small_rig() {
  core::RigModel rig;
  core::HeadModel head;
  head.name = "h";
  head.fov_horizontal_rad = 20.0 * M_PI / 180.0;
  head.fov_vertical_rad = 10.0 * M_PI / 180.0;
  head.resolution_horizontal_rad = head.resolution_vertical_rad = 0.5 * M_PI / 180.0;
  head.T_rig_head = at(1.5, 0.3, 1.2, 5.0 * M_PI / 180.0);
  rig.heads.push_back(head);
  return rig;
}

TEST(LidarSimulator, PlaneAtKnownDistanceGivesExactRanges) {
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(20.0));
  scene->build();
  const core::RigModel rig = small_rig();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(rig));
  const core::Frame f = sim.simulate(0, 0.0);
  const auto dirs = rig.directions_rig();
  const Eigen::Vector3d o = rig.heads[0].T_rig_head.translation();
  ASSERT_EQ(f.scan.num_valid(), f.scan.size());
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    const Eigen::Vector3d d = dirs[i].cast<double>().normalized();
    const double expected = (20.0 - o.x()) / d.x();  // ray from the head's origin to x = 20
    ASSERT_NEAR(f.scan.range_m[i], expected, 1e-4) << "pixel " << i;
    ASSERT_NEAR(f.scan.x_m[i], 20.0, 1e-4);
  }
}

TEST(LidarSimulator, StaticWorldDopplerIsMinusEDotVOrigin) {
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(30.0));
  scene->add_ground_plane(0.0, 200.0, 0.1f);
  scene->build();
  core::RigModel rig = core::RigModel::paper_rig();
  // Ego turning: V_origin = V + omega x r_mount differs per head.
  const double speed = 8.0, yaw_rate = 0.3;
  auto ego = make_constant_turn_rate_trajectory(Eigen::Isometry3d::Identity(), speed, yaw_rate);
  LidarSimulator sim(scene, std::move(ego), noise_free(rig));
  const core::Frame f = sim.simulate(0, 0.0);
  const auto dirs = rig.directions_rig();
  std::size_t checked = 0;
  for (std::size_t h = 0; h < rig.heads.size(); ++h) {
    const Eigen::Vector3d r = rig.heads[h].T_rig_head.translation();
    const Eigen::Vector3d v_origin = Eigen::Vector3d(speed, 0, 0) + Eigen::Vector3d(0, 0, yaw_rate).cross(r);
    const auto& info = f.scan.heads[h];
    for (int row = 0; row < f.scan.rows; ++row) {
      for (int c = info.col_begin; c < info.col_end; ++c) {
        const std::size_t i = f.scan.index(row, c);
        if (!f.scan.valid[i]) continue;
        const double expected = -dirs[i].cast<double>().normalized().dot(v_origin);
        ASSERT_NEAR(f.scan.radial_velocity_mps[i], expected, 1e-5) << "head " << h << " pixel " << i;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 80000u);
  EXPECT_NEAR(f.frame_truth->ego.angular_velocity_rps.z(), yaw_rate, 1e-12);
}

TEST(LidarSimulator, RotatingActorSurfaceVelocityIsVPlusOmegaCrossR) {
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(40.0));
  SceneObject car;
  car.name = "spinner";
  car.class_name = "car";
  car.actor_id = 7;
  car.asset = box_asset({2.0f, 1.0f, 0.8f});
  // Constant turn rate: centre moves at 6 m/s along its heading, turning at 0.5 rad/s.
  car.trajectory = make_constant_turn_rate_trajectory(at(15.0, 1.0, 1.0, 0.7), 6.0, 0.5);
  scene->add(std::move(car));
  scene->build();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(core::RigModel::paper_rig()));
  const core::Frame f = sim.simulate(0, 0.4);
  ASSERT_EQ(f.frame_truth->actors.size(), 1u);
  const core::ActorTruth& a = f.frame_truth->actors[0];
  EXPECT_GT(a.pixels, 300);
  const Eigen::Vector3d c = a.position_rig_m;
  const Eigen::Vector3d w = a.angular_velocity_rig_rps;
  EXPECT_NEAR(w.z(), 0.5, 1e-12);
  EXPECT_NEAR(a.velocity_rig_mps.norm(), 6.0, 1e-9);
  int pixels = 0;
  double max_spread = 0.0;
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (f.truth->instance[i] != 7) continue;
    ++pixels;
    const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
    const Eigen::Vector3d expected = a.velocity_rig_mps + w.cross(p - c);
    const Eigen::Vector3d got(f.truth->vx_mps[i], f.truth->vy_mps[i], f.truth->vz_mps[i]);
    ASSERT_LT((got - expected).norm(), 1e-4) << "pixel " << i;
    max_spread = std::max(max_spread, (got - a.velocity_rig_mps).norm());
    EXPECT_EQ(f.truth->moving[i], 1);
  }
  EXPECT_EQ(pixels, a.pixels);
  EXPECT_GT(max_spread, 0.3) << "points of a turning car move at different velocities";
}

TEST(LidarSimulator, HeadsAtDifferentMountsHaveTheirOwnOrigins) {
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(25.0));
  scene->add_ground_plane(0.0, 200.0, 0.1f);
  scene->build();
  const core::RigModel rig = core::RigModel::paper_rig();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(rig));
  const core::Frame f = sim.simulate(0, 0.0);
  for (std::size_t h = 0; h < 3; ++h) {
    const Eigen::Vector3d o = rig.heads[h].T_rig_head.translation();
    EXPECT_EQ(f.scan.heads[h].origin_m(), o);
    int checked = 0;
    for (int c = f.scan.heads[h].col_begin; c < f.scan.heads[h].col_end; c += 7) {
      for (int r = 0; r < f.scan.rows; r += 5) {
        const std::size_t i = f.scan.index(r, c);
        if (!f.scan.valid[i]) continue;
        const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
        ASSERT_NEAR((p - o).norm(), f.scan.range_m[i], 1e-3);
        ++checked;
      }
    }
    EXPECT_GT(checked, 100);
  }
  EXPECT_GT((rig.heads[0].T_rig_head.translation() - rig.heads[1].T_rig_head.translation()).norm(), 0.1);
}

TEST(LidarSimulator, NoiseMatchesTableISigmasWithinFivePercent) {
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(30.0));
  scene->add_ground_plane(0.0, 200.0, 0.1f);
  scene->build();
  LidarSimulatorParams p;  // Table I defaults: 0.025 m, 0.031 m/s
  p.seed = 11;
  LidarSimulator sim(scene, make_constant_velocity_trajectory(Eigen::Isometry3d::Identity(), {5, 0, 0}), p);
  double sr = 0, sr2 = 0, sv = 0, sv2 = 0;
  std::size_t n = 0;
  for (std::uint64_t k = 0; k < 3; ++k) {
    const core::Frame f = sim.simulate(k, 0.1 * static_cast<double>(k));
    for (std::size_t i = 0; i < f.scan.size(); ++i) {
      if (!f.scan.valid[i]) continue;
      const double dr = f.scan.range_m[i] - f.truth->range_m[i];
      const double dv = f.scan.radial_velocity_mps[i] - f.truth->radial_velocity_mps[i];
      sr += dr;
      sr2 += dr * dr;
      sv += dv;
      sv2 += dv * dv;
      ++n;
    }
  }
  ASSERT_GT(n, 200000u);
  const double nd = static_cast<double>(n);
  EXPECT_NEAR(std::sqrt(sr2 / nd - (sr / nd) * (sr / nd)), 0.025, 0.05 * 0.025);
  EXPECT_NEAR(std::sqrt(sv2 / nd - (sv / nd) * (sv / nd)), 0.031, 0.05 * 0.031);
  EXPECT_NEAR(sr / nd, 0.0, 0.001);
  EXPECT_NEAR(sv / nd, 0.0, 0.001);
}

TEST(LidarSimulator, SameSeedGivesIdenticalFramesWithOneOrTwoThreads) {
  const auto make = [](int threads) {
    auto scene = std::make_shared<Scene>();
    scene->add(wall_at_x(35.0));
    scene->add_ground_plane(0.0, 200.0, 0.1f);
    SceneObject car;
    car.actor_id = 3;
    car.class_name = "car";
    car.asset = box_asset({2.2f, 0.9f, 0.75f});
    car.trajectory = make_constant_turn_rate_trajectory(at(18.0, -3.0, 0.75, 2.5), 7.0, 0.2);
    scene->add(std::move(car));
    scene->build();
    LidarSimulatorParams p;
    p.seed = 5;
    p.num_threads = threads;
    return LidarSimulator(scene, make_constant_velocity_trajectory(Eigen::Isometry3d::Identity(), {6, 0, 0}), p);
  };
  LidarSimulator one = make(1);
  LidarSimulator two = make(2);
  for (std::uint64_t k = 0; k < 2; ++k) {
    const core::Frame a = one.simulate(k, 0.1 * static_cast<double>(k));
    const core::Frame b = two.simulate(k, 0.1 * static_cast<double>(k));
    const auto same = [](const std::vector<float>& x, const std::vector<float>& y) {
      return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
    };
    EXPECT_TRUE(same(a.scan.x_m, b.scan.x_m));
    EXPECT_TRUE(same(a.scan.range_m, b.scan.range_m));
    EXPECT_TRUE(same(a.scan.radial_velocity_mps, b.scan.radial_velocity_mps));
    EXPECT_TRUE(same(a.scan.intensity, b.scan.intensity));
    EXPECT_TRUE(same(a.truth->vx_mps, b.truth->vx_mps));
    EXPECT_EQ(a.truth->instance, b.truth->instance);
  }
}

TEST(LidarSimulator, ReturnsBeyondMaxRangeAreDropped) {
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(60.0));
  scene->build();
  core::RigModel rig = small_rig();
  rig.heads[0].max_range_m = 50.0;
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(rig));
  EXPECT_EQ(sim.simulate(0, 0.0).scan.num_valid(), 0u);
  rig.heads[0].max_range_m = 80.0;
  LidarSimulator far(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(rig));
  EXPECT_EQ(far.simulate(0, 0.0).scan.num_valid(), static_cast<std::size_t>(rig.rows() * rig.cols()));
}

// A post with an arm hinged at (0, 0, 1.6) in the body frame (part 1), swinging about +y,
// actor 4. The arm reaches along the body's -x from its hinge.
SceneObject post_with_arm(const JointMotion& hinge) {
  MeshAsset asset = *box_asset({0.2f, 0.6f, 1.6f});
  asset.parts[0].name = "post";
  asset.parts[0].T_parent_part.translation() = Eigen::Vector3d(0, 0, 1.6);
  MeshPart arm = box_asset({0.8f, 0.5f, 0.15f})->parts[0];
  arm.name = "arm";
  arm.parent = 0;
  arm.T_parent_part = Eigen::Affine3d::Identity();
  for (auto& v : arm.vertices) v.x() -= 1.0f;
  asset.parts.push_back(arm);
  SceneObject body;
  body.actor_id = 4;
  body.class_name = "robot";
  body.asset = std::make_shared<const MeshAsset>(asset);
  body.joints.emplace_back(1, hinge);
  return body;
}

JointMotion swinging_hinge() {
  JointMotion hinge;
  hinge.axis = Eigen::Vector3d::UnitY();
  hinge.amplitude_rad = 0.4;
  hinge.frequency_hz = 0.5;
  return hinge;
}

TEST(LidarSimulator, ArticulatedPartMovesWithItsOwnJoint) {
  // A fixed post facing the sensor: the arm reaches towards it.
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(40.0));
  const JointMotion hinge = swinging_hinge();
  SceneObject body = post_with_arm(hinge);
  body.trajectory = make_static_trajectory(at(12.0, 0.0, 0.0));
  scene->add(std::move(body));
  scene->build();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(core::RigModel::paper_rig()));
  const double t = 0.3;
  const core::Frame f = sim.simulate(0, t);
  // Hinge in the world: body at (12, 0, 0), part 0 at +1.6 m up; the arm turns about +y at
  // rate amplitude * 2 pi f cos(2 pi f t).
  const Eigen::Vector3d hinge_world(12.0, 0.0, 1.6);
  const Eigen::Vector3d omega(0.0, hinge.rate_rps(t), 0.0);
  int arm_pixels = 0, post_pixels = 0;
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (f.truth->instance[i] != 4) continue;
    const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
    const Eigen::Vector3d v(f.truth->vx_mps[i], f.truth->vy_mps[i], f.truth->vz_mps[i]);
    if (v.norm() < 1e-9) {
      ++post_pixels;
      continue;
    }
    ++arm_pixels;
    ASSERT_LT((v - omega.cross(p - hinge_world)).norm(), 1e-4) << "pixel " << i;
  }
  EXPECT_GT(arm_pixels, 50);
  EXPECT_GT(post_pixels, 50);
}

TEST(LidarSimulator, AWalkersJointsRestWhileItStandsAndSwingWithItsPath) {
  // The post walks 4 m along -y at 2 m/s from t = 1 s, its joints on a gait clock of 1 m/s:
  // clock = distance / (1 m/s), running at 2 clock seconds per second while it walks.
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(40.0));
  const JointMotion hinge = swinging_hinge();
  SceneObject body = post_with_arm(hinge);
  WaypointPath path;
  path.points_m = {{12.0, 2.0, 0.0}, {12.0, -2.0, 0.0}};
  path.speeds_mps = {2.0};
  path.start_time_s = 1.0;
  std::shared_ptr<const Trajectory> walk = make_waypoint_trajectory(path);
  body.trajectory = walk;
  body.gait_speed_mps = 1.0;
  scene->add(std::move(body));
  scene->build();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(core::RigModel::paper_rig()));
  // Waiting at its first point, and standing at its last: nothing of it moves, though a clock
  // on time would swing the arm at up to 0.4 * pi rad/s (0.5 Hz, 0.4 rad).
  for (const double t : {0.3, 3.5}) {
    const core::Frame f = sim.simulate(0, t);
    int pixels = 0;
    for (std::size_t i = 0; i < f.scan.size(); ++i) {
      if (f.truth->instance[i] != 4) continue;
      ++pixels;
      ASSERT_EQ(f.truth->moving[i], 0) << "t " << t << " pixel " << i;
      ASSERT_EQ(Eigen::Vector3d(f.truth->vx_mps[i], f.truth->vy_mps[i], f.truth->vz_mps[i]).norm(), 0.0)
          << "t " << t << " pixel " << i;
    }
    EXPECT_GT(pixels, 100) << "t " << t;
  }
  // Walking: 1.2 m along its path at t = 1.6 s, so the clock reads 1.2 s; the arm turns about
  // the body's +y at 2 * rate(1.2 s) on top of the body's motion.
  const double t = 1.6;
  const MotionState state = walk->state(t);
  ASSERT_NEAR(state.distance_m, 1.2, 1e-6);
  const double rate = 2.0 * hinge.rate_rps(1.2);
  ASSERT_GT(std::abs(rate), 0.5);
  const Eigen::Vector3d omega = state.T_world_body.linear() * Eigen::Vector3d(0.0, rate, 0.0);
  const Eigen::Vector3d hinge_world = state.T_world_body * Eigen::Vector3d(0.0, 0.0, 1.6);
  const core::Frame f = sim.simulate(0, t);
  int arm_pixels = 0, post_pixels = 0;
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (f.truth->instance[i] != 4) continue;
    const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
    const Eigen::Vector3d v(f.truth->vx_mps[i], f.truth->vy_mps[i], f.truth->vz_mps[i]);
    const Eigen::Vector3d own = v - state.twist.linear_mps;
    if (own.norm() < 1e-9) {
      ++post_pixels;
      continue;
    }
    ++arm_pixels;
    ASSERT_LT((own - omega.cross(p - hinge_world)).norm(), 1e-3) << "pixel " << i;
  }
  EXPECT_GT(arm_pixels, 20);
  EXPECT_GT(post_pixels, 50);
}

TEST(LidarSimulator, RollingWheelsTurnAboutTheirContactPoint) {
  // The project's car at 10 m/s: a wheel spinning at v / r rolls without slipping, so its
  // points turn about the line where the wheel touches the ground: speed = (v / r) times the
  // distance to that line, from 0
  // at the ground to 2v at the top, while the body moves at v.
  const std::string assets = std::string(FMCW_SOURCE_DIR) + "/assets/";
  auto car_asset = std::make_shared<const MeshAsset>(load_mesh_asset(assets + "car.gltf", {}, 0.3f));
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(60.0));
  SceneObject car;
  car.actor_id = 1;
  car.class_name = "car";
  car.asset = car_asset;
  // Driving along -y on the rig's left, its right side (wheels) facing the sensor.
  const Eigen::Isometry3d pose = at(8.0, 9.0, 0.0, -M_PI / 2);
  car.trajectory = make_constant_velocity_trajectory(pose, {0.0, -10.0, 0.0});
  double radius = 0.0;
  std::vector<Eigen::Vector3d> contacts;
  for (std::size_t p = 0; p < car_asset->parts.size(); ++p) {
    const MeshPart& part = car_asset->parts[p];
    if (part.name.rfind("wheel", 0) != 0) continue;
    float zmin = 1e9f, zmax = -1e9f;
    for (const auto& v : part.vertices) {
      zmin = std::min(zmin, v.z());
      zmax = std::max(zmax, v.z());
    }
    radius = 0.5 * (zmax - zmin);
    car.wheels.emplace_back(static_cast<int>(p), radius);
    const Eigen::Vector3d axle = pose * part.T_parent_part.translation();
    contacts.push_back(axle - Eigen::Vector3d(0, 0, radius));
  }
  ASSERT_EQ(car.wheels.size(), 4u);
  scene->add(std::move(car));
  scene->build();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(core::RigModel::paper_rig()));
  const core::Frame f = sim.simulate(0, 0.0);
  int wheel_pixels = 0, body_pixels = 0;
  double fastest = 0.0;
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (f.truth->instance[i] != 1) continue;
    const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
    const Eigen::Vector3d v(f.truth->vx_mps[i], f.truth->vy_mps[i], f.truth->vz_mps[i]);
    if ((v - Eigen::Vector3d(0, -10, 0)).norm() < 1e-6) {
      ++body_pixels;
      continue;
    }
    ++wheel_pixels;
    // Distance to the instantaneous axis: the line through the contact point along the axle.
    const double nearest = test::distance_to_contact_line(p, contacts, pose.linear() * Eigen::Vector3d::UnitY());
    ASSERT_NEAR(v.norm(), 10.0 / radius * nearest, 1e-3) << "pixel " << i;
    fastest = std::max(fastest, v.norm());
  }
  EXPECT_GT(wheel_pixels, 30);
  EXPECT_GT(body_pixels, 300);
  EXPECT_GT(fastest, 15.0) << "the top of a wheel moves at nearly 2v";
}

TEST(LidarSimulator, MotionDistortionEvaluatesEgoAndActorsAtEachBeamsTime) {
  // One head at the rig origin; the ego drives at 20 m/s towards a wall at x = 30, and a box
  // 12 m ahead recedes at 10 m/s. Each column fires (c + 0.5) / 100 of a 0.1 s period late.
  core::RigModel rig;
  core::HeadModel head;
  head.fov_horizontal_rad = 20.0 * M_PI / 180.0;
  head.fov_vertical_rad = 4.0 * M_PI / 180.0;
  head.resolution_horizontal_rad = head.resolution_vertical_rad = 0.2 * M_PI / 180.0;
  head.T_rig_head = at(0, 0, 1.0);
  rig.heads.push_back(head);
  auto scene = std::make_shared<Scene>();
  scene->add(wall_at_x(30.0));
  SceneObject box;
  box.actor_id = 2;
  box.class_name = "box";
  box.asset = box_asset({0.5f, 0.6f, 0.5f});
  box.trajectory = make_constant_velocity_trajectory(at(12.5, 0.0, 1.0), {10.0, 0.0, 0.0});
  scene->add(std::move(box));
  scene->build();
  LidarSimulatorParams params = noise_free(rig);
  params.motion_distortion = true;
  LidarSimulator sim(scene, make_constant_velocity_trajectory(Eigen::Isometry3d::Identity(), {20.0, 0.0, 0.0}), params);
  const core::Frame f = sim.simulate(0, 0.0);
  ASSERT_EQ(f.scan.time_offset_s.size(), f.scan.size());
  int wall = 0, actor = 0;
  for (int r = 0; r < f.scan.rows; ++r) {
    for (int c = 0; c < f.scan.cols; ++c) {
      const std::size_t i = f.scan.index(r, c);
      const double tau = (c + 0.5) / f.scan.cols / 10.0;
      ASSERT_NEAR(f.scan.time_offset_s[i], tau, 1e-7);
      if (!f.scan.valid[i]) continue;
      // In the rig frame of the beam's instant: the wall is 20 tau closer, the box's front face
      // (x = 12 at t = 0) is 10 tau further and the rig 20 tau closer.
      const double expected = f.truth->instance[i] == 2 ? 12.0 + 10.0 * tau - 20.0 * tau : 30.0 - 20.0 * tau;
      ASSERT_NEAR(f.scan.x_m[i], expected, 1e-4) << "row " << r << " col " << c;
      (f.truth->instance[i] == 2 ? actor : wall)++;
    }
  }
  EXPECT_GT(actor, 100);
  EXPECT_GT(wall, 1000);
  // Without distortion every beam sees the frame's instant.
  params.motion_distortion = false;
  LidarSimulator still(scene, make_constant_velocity_trajectory(Eigen::Isometry3d::Identity(), {20.0, 0.0, 0.0}), params);
  const core::Frame g = still.simulate(0, 0.0);
  EXPECT_TRUE(g.scan.time_offset_s.empty());
  for (std::size_t i = 0; i < g.scan.size(); ++i) {
    if (g.scan.valid[i] && g.truth->instance[i] == 0) {
      ASSERT_NEAR(g.scan.x_m[i], 30.0, 1e-4);
    }
  }
}

}  // namespace
}  // namespace fmcw::sim
