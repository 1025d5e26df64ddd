// Imported animation against known answers: a node turned by a LINEAR clip gives the Doppler of
// a rigid rotation, a bending two-bone strip moves as the analytic blend of its bones, a skinned
// character's surface velocity matches a finite difference of its deformed surface, keyframed
// wheels roll, and every bad clip or skin gets a message that names it.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/scenario.hpp"
#include "fmcw/sim/scene.hpp"
#include "support/sim_scenes.hpp"
#include "support/animated_scenes.hpp"
#include "support/gltf_builder.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::sim {
namespace {

using test::at;
using test::noise_free;

using test::GltfBuilder;
using test::box;
using test::one_head;
using test::scene_with;
using test::Strip;
using test::turn_keys;
using test::two_bone_strip;

const std::string kAssets = std::string(FMCW_SOURCE_DIR) + "/assets/";

class AnimatedMeshes : public test::TempDirTest {};

TEST_F(AnimatedMeshes, ALinearClipTurningANodeGivesTheDopplerOfItsRotation) {
  // A box beside a vertical axis on a node that a LINEAR clip turns at 1.2 rad/s about +z:
  // every hit point moves at omega x r, so its Doppler is e . (omega x (p - c)) exactly.
  GltfBuilder b;
  const int node = b.add_node("turntable");
  std::vector<Eigen::Vector3f> v;
  std::vector<std::uint32_t> idx;
  box({-0.6f, 0.4f, -0.5f}, {0.4f, 1.6f, 1.5f}, v, idx);
  b.add_mesh(node, v, idx);
  std::vector<float> times;
  const std::vector<float> values = turn_keys(1.2, 0.5, 3.0, times);
  b.add_channel(b.add_animation("spin"), node, "rotation", "LINEAR", times, values);
  b.write_gltf(path("spin.gltf"));
  auto asset = std::make_shared<const MeshAsset>(load_mesh_asset(path("spin.gltf"), {}, 0.3f));
  ASSERT_EQ(asset->clips.size(), 1u);
  EXPECT_NEAR(asset->clips[0].duration_s, 3.0, 1e-6);
  const Eigen::Vector3d c(10.0, -1.0, 0.0);
  auto scene = scene_with(asset, at(c.x(), c.y(), c.z()), 0);
  const core::RigModel rig = one_head();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(rig));
  int hits = 0;
  for (const double t : {0.7, 1.9}) {
    const core::Frame f = sim.simulate(0, t);
    const Eigen::Vector3d origin = rig.heads[0].T_rig_head.translation();
    for (std::size_t i = 0; i < f.scan.size(); ++i) {
      if (f.truth->instance[i] != 7) continue;
      const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
      const Eigen::Vector3d e = (p - origin).normalized();
      const double expected = e.dot(Eigen::Vector3d(0, 0, 1.2).cross(p - c));
      ASSERT_NEAR(f.truth->radial_velocity_mps[i], expected, 1e-4) << "pixel " << i << " at t " << t;
      ASSERT_NEAR(f.scan.radial_velocity_mps[i], expected, 1e-4);
      ++hits;
    }
  }
  EXPECT_GT(hits, 500);
  // Without the clip the same box stands still.
  auto still = scene_with(asset, at(c.x(), c.y(), c.z()), -1);
  LidarSimulator sim_still(still, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(rig));
  const core::Frame g = sim_still.simulate(0, 0.7);
  for (std::size_t i = 0; i < g.scan.size(); ++i) {
    if (g.truth->instance[i] == 7) {
      ASSERT_EQ(g.truth->radial_velocity_mps[i], 0.0f);
    }
  }
}

TEST_F(AnimatedMeshes, ABendingTwoBoneStripMovesAsTheAnalyticBlendOfItsBones) {
  const Strip strip = two_bone_strip();
  const double omega = 0.8;
  GltfBuilder b = test::bending_strip(strip, omega);
  b.write_glb(path("strip.glb"));
  auto asset = std::make_shared<const MeshAsset>(load_mesh_asset(path("strip.glb"), {}, 0.3f));
  const Eigen::Vector3d place(6.0, -1.0, 0.5);
  auto scene = scene_with(asset, at(place.x(), place.y(), place.z()), 0);
  const double t = 0.6;
  scene->set_time(t);
  const test::StripMotion analytic = test::strip_motion(strip, place, omega, t);
  const std::vector<Eigen::Vector3d>& p = analytic.p;
  const std::vector<Eigen::Vector3d>& p_dot = analytic.p_dot;
  const test::StripRays rays = test::cast_at_strip(*scene);
  const Eigen::Vector3f& origin = rays.origin;
  const std::vector<Eigen::Vector3f>& dirs = rays.dirs;
  const std::vector<RayHit>& hits = rays.hits;
  int checked = 0, bent = 0;
  for (std::size_t k = 0; k < hits.size(); ++k) {
    if (!std::isfinite(hits[k].distance_m)) continue;
    const Eigen::Vector3d x = origin.cast<double>() + hits[k].distance_m * dirs[k].cast<double>();
    const std::uint32_t* tri = &strip.indices[3 * hits[k].primitive];
    // Barycentric coordinates of the hit in the analytic triangle (least squares in its plane).
    Eigen::Matrix<double, 3, 2> E;
    E << p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]];
    const Eigen::Vector2d uv = E.colPivHouseholderQr().solve(x - p[tri[0]]);
    ASSERT_LT((p[tri[0]] + E * uv - x).norm(), 1e-4) << "the hit lies on the analytic surface";
    const Eigen::Vector3d expected = (1 - uv[0] - uv[1]) * p_dot[tri[0]] + uv[0] * p_dot[tri[1]] + uv[1] * p_dot[tri[2]];
    const SurfaceSample s = scene->resolve(hits[k], x);
    ASSERT_LT((s.velocity_world_mps - expected).norm(), 1e-4) << "ray " << k;
    EXPECT_EQ(s.actor_id, 7u);
    ++checked;
    bent += expected.norm() > 0.05 ? 1 : 0;
  }
  EXPECT_GT(checked, 300);
  EXPECT_GT(bent, 100);
}

TEST_F(AnimatedMeshes, ASkinnedCharactersSurfaceVelocityIsTheDerivativeOfItsSurface) {
  // The project's walker plays its walk clip while it walks a curve; a surface point followed
  // by its barycentric coordinates moves at (p(t+h) - p(t-h)) / 2h.
  auto asset = std::make_shared<const MeshAsset>(load_mesh_asset(kAssets + "walker_skinned.gltf", {}, 0.3f));
  ASSERT_EQ(asset->find_clip("walk"), 0);
  ASSERT_GE(asset->triangle_count(), 5000u);
  WaypointPath path_;
  path_.points_m = {{5, -3, 0}, {6, 0, 0}, {5, 3, 0}};
  path_.speeds_mps = {1.4};
  std::shared_ptr<const Trajectory> walk = make_waypoint_trajectory(path_);
  auto scene = scene_with(asset, Eigen::Isometry3d::Identity(), 0, walk);
  const Eigen::Vector3f origin(0, 0, 1.0);
  std::vector<Eigen::Vector3f> dirs;
  int checked = 0, moving = 0;
  double worst = 0.0;
  for (const double t : {0.9 + 1.0 / 60.0, 32.0 / 30.0 + 0.4 + 1.0 / 60.0}) {  // halfway between keys (1/30 s apart)
    scene->set_time(t);
    const Eigen::Vector3d centre = walk->state(t).T_world_body.translation();
    dirs.clear();
    for (int i = 0; i < 80; ++i) {
      for (int j = 0; j < 60; ++j) {
        const Eigen::Vector3d target = centre + Eigen::Vector3d(0, -0.6 + 0.015 * i, 0.05 + 0.028 * j);
        dirs.push_back((target.cast<float>() - origin).normalized());
      }
    }
    std::vector<RayHit> hits(dirs.size());
    scene->intersect(SceneLayer::kStatic, origin, dirs.data(), nullptr, dirs.size(), 0.1f, 100.0f, hits.data());
    scene->intersect(SceneLayer::kActors, origin, dirs.data(), nullptr, dirs.size(), 0.1f, 100.0f, hits.data());
    std::vector<SurfaceSample> samples(hits.size());
    for (std::size_t k = 0; k < hits.size(); ++k) {
      if (std::isfinite(hits[k].distance_m)) samples[k] = scene->resolve(hits[k], origin.cast<double>() + hits[k].distance_m * dirs[k].cast<double>());
    }
    const double h = 1e-3;
    scene->set_time(t - h);
    const std::vector<Eigen::Vector3f> before = scene->skinned_vertices(0);
    scene->set_time(t + h);
    const std::vector<Eigen::Vector3f> after = scene->skinned_vertices(0);
    for (std::size_t k = 0; k < hits.size(); ++k) {
      if (!std::isfinite(hits[k].distance_m)) continue;
      const std::uint32_t* tri = scene->slot(hits[k].slot).indices + 3 * hits[k].primitive;
      const double u = hits[k].u, v = hits[k].v;
      const auto point = [&](const std::vector<Eigen::Vector3f>& x) {
        return ((1 - u - v) * x[tri[0]].cast<double>() + u * x[tri[1]].cast<double>() + v * x[tri[2]].cast<double>()).eval();
      };
      const Eigen::Vector3d fd = (point(after) - point(before)) / (2 * h);
      const double err = (samples[k].velocity_world_mps - fd).norm();
      // Within 1 % of the speed; positions are single precision, hence the small floor.
      ASSERT_LE(err, 0.01 * fd.norm() + 2e-3) << "ray " << k << " at t " << t << ": " << samples[k].velocity_world_mps.transpose()
                                              << " vs " << fd.transpose();
      worst = std::max(worst, err / std::max(fd.norm(), 0.1));
      ++checked;
      moving += (samples[k].velocity_world_mps - walk->state(t).twist.linear_mps).norm() > 0.3 ? 1 : 0;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(moving, 200) << "limbs move relative to the body";
  RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST_F(AnimatedMeshes, KeyframedWheelsOnADistanceClockRollWithoutSlipping) {
  // The keyframed car's clip turns its wheels once a second at its nominal speed 2 pi r / 1 s;
  // on the distance clock at 10 m/s every wheel point turns about its contact line.
  auto asset = std::make_shared<const MeshAsset>(load_mesh_asset(kAssets + "car_keyframed.gltf", {}, 0.3f));
  const int clip = asset->find_clip("roll");
  ASSERT_EQ(clip, 0);
  const double nominal = asset->clips[0].nominal_speed_mps;
  auto scene = std::make_shared<Scene>();
  SceneObject car;
  car.actor_id = 1;
  car.class_name = "car";
  car.asset = asset;
  const Eigen::Isometry3d pose = at(8.0, 9.0, 0.0, -M_PI / 2);
  car.trajectory = make_constant_velocity_trajectory(pose, {0.0, -10.0, 0.0});
  car.clip = clip;
  car.playback.clock = ClipPlayback::Clock::kDistance;
  car.playback.nominal_speed_mps = nominal;
  // The procedural rule would spin the wheels too; the clip wins. Give it a wrong radius so a
  // procedural spin would show.
  double radius = 0.0;
  std::vector<Eigen::Vector3d> contacts;
  for (std::size_t p = 0; p < asset->parts.size(); ++p) {
    if (asset->parts[p].name.rfind("wheel", 0) != 0) continue;
    car.wheels.emplace_back(static_cast<int>(p), 0.1);
    radius = nominal / (2 * M_PI);
    contacts.push_back(pose * asset->rest_transforms()[p].translation() - Eigen::Vector3d(0, 0, radius));
  }
  ASSERT_EQ(contacts.size(), 4u);
  scene->add(std::move(car));
  scene->build();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(core::RigModel::paper_rig()));
  const core::Frame f = sim.simulate(0, 0.37);
  const Eigen::Isometry3d now = at(8.0, 9.0 - 3.7, 0.0, -M_PI / 2);
  for (auto& c : contacts) c.y() -= 3.7;
  int wheel_pixels = 0;
  double fastest = 0.0;
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    if (f.truth->instance[i] != 1) continue;
    const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
    const Eigen::Vector3d v(f.truth->vx_mps[i], f.truth->vy_mps[i], f.truth->vz_mps[i]);
    if ((v - Eigen::Vector3d(0, -10, 0)).norm() < 1e-6) continue;  // the body
    ++wheel_pixels;
    const double nearest = test::distance_to_contact_line(p, contacts, now.linear() * Eigen::Vector3d::UnitY());
    ASSERT_NEAR(v.norm(), 10.0 / radius * nearest, 2e-3) << "pixel " << i;
    fastest = std::max(fastest, v.norm());
  }
  EXPECT_GT(wheel_pixels, 30);
  EXPECT_GT(fastest, 15.0);
}

TEST_F(AnimatedMeshes, MotionDistortionTakesEachBeamsInstantForClipsAndSkins) {
  // A skinned slab whose only bone a LINEAR clip slides away at 10 m/s along +x; each column of
  // the head fires (c + 0.5) / cols of a 0.1 s period late, so it sees the slab 10 tau further.
  GltfBuilder b;
  const int bone = b.add_node("bone");
  const int mesh_node = b.add_node("slab");
  std::vector<Eigen::Vector3f> v;
  std::vector<std::uint32_t> idx;
  box({0.0f, -2.0f, -1.0f}, {0.5f, 2.0f, 1.0f}, v, idx);
  const int mesh = b.add_mesh(mesh_node, v, idx);
  b.set_skin_weights(mesh, std::vector<std::vector<std::pair<int, float>>>(v.size(), {{0, 1.0f}}));
  b.attach_skin(mesh_node, b.add_skin({bone}));
  b.add_channel(b.add_animation("slide"), bone, "translation", "LINEAR", {0.0f, 1.0f}, {0, 0, 0, 10, 0, 0});
  b.write_gltf(path("slide.gltf"));
  auto asset = std::make_shared<const MeshAsset>(load_mesh_asset(path("slide.gltf"), {}, 0.3f));
  auto scene = scene_with(asset, at(12.0, 0.0, 1.0), 0);
  core::RigModel rig = one_head();
  rig.heads[0].fov_vertical_rad = 4.0 * M_PI / 180.0;
  LidarSimulatorParams params = noise_free(rig);
  params.motion_distortion = true;
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), params);
  const core::Frame f = sim.simulate(0, 0.2);
  int n = 0;
  for (int r = 0; r < f.scan.rows; ++r) {
    for (int c = 0; c < f.scan.cols; ++c) {
      const std::size_t i = f.scan.index(r, c);
      if (f.truth->instance[i] != 7) continue;
      const double tau = (c + 0.5) / f.scan.cols / 10.0;
      ASSERT_NEAR(f.scan.x_m[i], 12.0 + 10.0 * (0.2 + tau), 1e-4) << "row " << r << " col " << c;
      ASSERT_NEAR(f.truth->vx_mps[i], 10.0, 1e-4);
      ++n;
    }
  }
  EXPECT_GT(n, 1000);
}

TEST_F(AnimatedMeshes, SameSeedGivesIdenticalFramesWithOneOrTwoThreads) {
  const std::string file = write("scene.yaml", R"(frames: 2
seed: 5
ego: {trajectory: {type: static, pose: {x: 0, y: 0}}}
actors:
  - {id: 1, class: pedestrian, mesh: )" + kAssets + R"(walker_skinned.gltf, trajectory: {type: waypoints, points: [[9, -3], [9, 3]], speed_mps: 1.4}}
  - {id: 2, class: car, mesh: )" + kAssets + R"(car_keyframed.gltf, animation: {clock: distance}, trajectory: {type: constant_velocity, pose: {x: 14, y: -6, yaw_deg: 90}, velocity_mps: [0, 3, 0]}}
)");
  const LoadedScenario loaded = load_scenario(file);
  std::vector<core::Frame> frames;
  for (const int threads : {1, 2}) {
    SimulationSetup setup = build_simulation(loaded, threads);
    LidarSimulator sim(setup.scene, setup.ego, setup.params);
    frames.push_back(sim.simulate(1, 0.1));
  }
  const core::Frame& a = frames[0];
  const core::Frame& b = frames[1];
  ASSERT_EQ(a.scan.size(), b.scan.size());
  EXPECT_EQ(0, std::memcmp(a.scan.radial_velocity_mps.data(), b.scan.radial_velocity_mps.data(), a.scan.size() * sizeof(float)));
  EXPECT_EQ(0, std::memcmp(a.scan.range_m.data(), b.scan.range_m.data(), a.scan.size() * sizeof(float)));
  EXPECT_EQ(a.truth->instance, b.truth->instance);
  int walker = 0;
  for (std::size_t i = 0; i < a.scan.size(); ++i) walker += a.truth->instance[i] == 1 && a.truth->moving[i] ? 1 : 0;
  EXPECT_GT(walker, 50);
}

// --- Scenarios: which clip plays, and what is said about the ones that do not ---------------

int moving_pixels(const LoadedScenario& loaded, std::uint32_t id, double t) {
  SimulationSetup setup = build_simulation(loaded, 1);
  setup.params.measurement.velocity_sigma_mps = 0.0;
  LidarSimulator sim(setup.scene, setup.ego, setup.params);
  const core::Frame f = sim.simulate(0, t);
  int n = 0;
  for (std::size_t i = 0; i < f.scan.size(); ++i) n += f.truth->instance[i] == id && f.truth->moving[i] ? 1 : 0;
  return n;
}

std::string standing_walker(const std::string& extra) {
  return "frames: 1\nego: {trajectory: {type: static, pose: {x: 0, y: 0}}}\nactors:\n"
         "  - {id: 3, class: pedestrian, mesh: " + kAssets + "walker_skinned.gltf, " + extra +
         "trajectory: {type: static, pose: {x: 8, y: 0.5}}}\n";
}

TEST_F(AnimatedMeshes, AnimateTruePlaysTheFirstClipLoopedAndAnimateFalseSaysSo) {
  const LoadedScenario on = load_scenario(write("on.yaml", standing_walker("")));
  ASSERT_EQ(on.scenario.actors[0].animation.clip_index, 0);
  EXPECT_EQ(on.scenario.actors[0].animation.clip, "walk");
  EXPECT_TRUE(on.scenario.actors[0].animation.playback.loop);
  EXPECT_TRUE(on.notices.empty());
  // On the time clock the walk plays in place, so its limbs move though the body stands; 4.3 s
  // is four loops on.
  EXPECT_GT(moving_pixels(on, 3, 0.3), 100);
  EXPECT_GT(moving_pixels(on, 3, 4.3), 100);
  // animate: false: a statue, and one notice for the mesh, however many actors use it.
  std::string two = standing_walker("animate: false, ");
  two += "  - {id: 4, class: pedestrian, mesh: " + kAssets + "walker_skinned.gltf, animate: false, trajectory: {type: static, pose: {x: 8, y: -2}}}\n";
  const LoadedScenario off = load_scenario(write("off.yaml", two));
  EXPECT_EQ(off.scenario.actors[0].animation.clip_index, -1);
  EXPECT_EQ(moving_pixels(off, 3, 0.3), 0);
  ASSERT_EQ(off.notices.size(), 1u);
  EXPECT_NE(off.notices[0].find("'walk', 'idle', not played: the actor has animate: false"), std::string::npos) << off.notices[0];
}

TEST_F(AnimatedMeshes, ADistanceClockRestsWhileTheActorWaits) {
  const std::string yaml = "frames: 1\nego: {trajectory: {type: static, pose: {x: 0, y: 0}}}\nactors:\n"
                           "  - {id: 3, class: pedestrian, mesh: " + kAssets + "walker_skinned.gltf, "
                           "animation: {clip: walk, clock: distance}, "
                           "trajectory: {type: waypoints, points: [[8, -1], [8, 4]], speed_mps: 1.4, start_time_s: 1.0}}\n";
  const LoadedScenario loaded = load_scenario(write("wait.yaml", yaml));
  EXPECT_NEAR(loaded.scenario.actors[0].animation.playback.nominal_speed_mps, 1.4, 1e-9) << "taken from the clip";
  EXPECT_EQ(moving_pixels(loaded, 3, 0.5), 0) << "waiting for its start: no limb moves";
  EXPECT_GT(moving_pixels(loaded, 3, 1.6), 100);
  // The resolved scenario records what plays, and loads again to the same.
  const std::string resolved = scenario_to_yaml(loaded.scenario);
  EXPECT_NE(resolved.find("animation: {clip: walk, speed: 1, loop: true, offset_s: 0, clock: distance, nominal_speed_mps: 1.4}"),
            std::string::npos)
      << resolved;
}

TEST_F(AnimatedMeshes, BadAnimationSettingsNameTheKey) {
  const auto message = [&](const std::string& extra) {
    try {
      load_scenario(write("bad.yaml", standing_walker(extra)));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("animation: {clip: run}, ").find("has no clip 'run'; its clips: 'walk', 'idle'"), std::string::npos);
  EXPECT_NE(message("animation: {clip: 5}, ").find("has no clip '5'"), std::string::npos);
  EXPECT_EQ(message("animation: {clip: 1}, "), "no error");  // by index: idle
  EXPECT_NE(message("animation: {clip: idle, clock: distance}, ").find("clip 'idle' gives none"), std::string::npos);
  EXPECT_NE(message("animation: {clock: sundial}, ").find("clock must be time or distance"), std::string::npos);
  EXPECT_NE(message("animation: {clock: distance, start_s: 2}, ").find("start_s is for clock: time"), std::string::npos);
  EXPECT_NE(message("animation: {speeed: 2}, ").find("speeed"), std::string::npos);
  EXPECT_NE(message("animate: false, animation: {clip: walk}, ").find("needs animate: true"), std::string::npos);
  EXPECT_NE(message("animation: {speed: .nan}, ").find("animation.speed: expected a finite number"), std::string::npos);
}

// --- Bad files: one clear error each, naming the file and what is wrong ---------------------

// A two-bone strip with a clip: each case corrupts one thing.
GltfBuilder strip_file(std::vector<std::vector<std::pair<int, float>>> influences = {}) {
  const Strip strip = two_bone_strip();
  GltfBuilder b;
  const int bone0 = b.add_node("bone0");
  const int bone1 = b.add_node("bone1", bone0, Eigen::Vector3d(0, 1, 0));
  const int mesh_node = b.add_node("strip");
  const int mesh = b.add_mesh(mesh_node, strip.vertices, strip.indices);
  if (influences.empty()) {
    for (const double w : strip.w1) influences.push_back({{0, static_cast<float>(1 - w)}, {1, static_cast<float>(w)}});
  }
  b.set_skin_weights(mesh, influences);
  b.attach_skin(mesh_node, b.add_skin({bone0, bone1}));
  std::vector<float> times;
  const std::vector<float> values = turn_keys(0.8, 0.5, 1.0, times);
  b.add_channel(b.add_animation("bend"), bone1, "rotation", "LINEAR", times, values);
  return b;
}

TEST_F(AnimatedMeshes, EachBadClipOrSkinGetsItsOwnMessage) {
  const auto error = [&](GltfBuilder& b, bool glb = false) {
    const std::string file = path(glb ? "bad.glb" : "bad.gltf");
    glb ? b.write_glb(file) : b.write_gltf(file);
    try {
      load_mesh_asset(file, {}, 0.3f);
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file), std::string::npos) << "the message names the file: " << m;
      return m;
    }
    return std::string("no error");
  };
  {
    GltfBuilder b = strip_file();
    EXPECT_EQ(error(b), "no error");
  }
  {  // key counts that disagree
    GltfBuilder b = strip_file();
    b.add_channel(0, 0, "translation", "LINEAR", {0.0f, 0.5f, 1.0f}, {0, 0, 0, 1, 1, 1});
    EXPECT_NE(error(b).find("clip 'bend' channel 1 (node 'bone0', translation): 3 key times but 2 values"), std::string::npos);
  }
  {  // CUBICSPLINE without its tangents
    GltfBuilder b = strip_file();
    b.add_channel(0, 0, "translation", "CUBICSPLINE", {0.0f, 1.0f}, {0, 0, 0, 1, 1, 1});
    EXPECT_NE(error(b).find("CUBICSPLINE needs 3 per key"), std::string::npos);
  }
  {  // a non-finite key
    GltfBuilder b = strip_file();
    b.add_channel(0, 0, "scale", "LINEAR", {0.0f, 1.0f}, {1, 1, 1, 1, std::nanf(""), 1});
    EXPECT_NE(error(b).find("channel 1 (node 'bone0', scale): key 1 has a non-finite value"), std::string::npos);
  }
  {  // times that go back
    GltfBuilder b = strip_file();
    b.add_channel(0, 0, "translation", "STEP", {0.0f, 1.0f, 0.5f}, {0, 0, 0, 1, 1, 1, 2, 2, 2});
    EXPECT_NE(error(b).find("key times must increase strictly, key 2"), std::string::npos);
  }
  {  // an unknown interpolation
    GltfBuilder b = strip_file();
    b.doc()["animations"][0]["samplers"][0]["interpolation"] = "SMOOTH";
    EXPECT_NE(error(b).find("has interpolation 'SMOOTH' (STEP, LINEAR or CUBICSPLINE)"), std::string::npos);
  }
  {  // a channel on a node with a matrix
    GltfBuilder b = strip_file();
    const int m = b.add_matrix_node("fixed", -1, Eigen::Matrix4d::Identity());
    b.add_channel(0, m, "rotation", "LINEAR", {0.0f}, {0, 0, 0, 1});
    EXPECT_NE(error(b).find("the node has a matrix"), std::string::npos);
  }
  {  // bone weights far from summing to 1
    std::vector<std::vector<std::pair<int, float>>> inf(34, {{0, 0.3f}, {1, 0.2f}});
    GltfBuilder b = strip_file(inf);
    EXPECT_NE(error(b).find("vertex 0: its bone weights sum to 0.5"), std::string::npos);
  }
  {  // a bone index out of range
    std::vector<std::vector<std::pair<int, float>>> inf(34, {{0, 1.0f}});
    inf[5] = {{0, 0.5f}, {5, 0.5f}};
    GltfBuilder b = strip_file(inf);
    EXPECT_NE(error(b).find("vertex 5 is bound to joint 5 but the skin has 2 joints"), std::string::npos);
  }
  {  // a negative weight
    std::vector<std::vector<std::pair<int, float>>> inf(34, {{0, 1.0f}});
    inf[2] = {{0, 1.5f}, {1, -0.5f}};
    GltfBuilder b = strip_file(inf);
    EXPECT_NE(error(b).find("vertex 2 has a weight -0.5"), std::string::npos);
  }
  {  // JOINTS_0 without WEIGHTS_0
    GltfBuilder b = strip_file();
    b.doc()["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
    EXPECT_NE(error(b).find("has only one of JOINTS_0 and WEIGHTS_0"), std::string::npos);
  }
  {  // a skinned node whose mesh has no joints at all
    GltfBuilder b = strip_file();
    auto& attributes = b.doc()["meshes"][0]["primitives"][0]["attributes"];
    attributes.erase("WEIGHTS_0");
    attributes.erase("JOINTS_0");
    EXPECT_NE(error(b).find("is skinned but has no JOINTS_0 and WEIGHTS_0"), std::string::npos);
  }
  {  // weights for fewer vertices than the mesh has
    GltfBuilder b = strip_file();
    b.doc()["accessors"][b.doc()["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"].get<int>()]["count"] = 10;
    EXPECT_NE(error(b).find("WEIGHTS_0 has 10 elements for 34 vertices"), std::string::npos);
  }
  {  // a skin without inverse bind matrices is valid glTF (identity): it loads
    GltfBuilder b = strip_file();
    b.doc()["skins"][0].erase("inverseBindMatrices");
    EXPECT_EQ(error(b), "no error");
  }
  {  // an accessor past the end of its buffer
    GltfBuilder b = strip_file();
    b.doc()["accessors"][0]["count"] = 40;
    EXPECT_NE(error(b).find("reaches past the end of its buffer view"), std::string::npos);
  }
  {  // a required extension the reader cannot honour
    GltfBuilder b = strip_file();
    b.doc()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    EXPECT_NE(error(b).find("requires the glTF extension 'KHR_draco_mesh_compression'"), std::string::npos);
  }
  {  // a node with two parents
    GltfBuilder b = strip_file();
    b.doc()["nodes"][2]["children"] = {1};
    EXPECT_NE(error(b).find("has two parents"), std::string::npos);
  }
  {  // a truncated GLB
    GltfBuilder b = strip_file();
    b.write_glb(path("whole.glb"));
    std::ifstream in(path("whole.glb"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(path("cut.glb"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    try {
      load_mesh_asset(path("cut.glb"), {}, 0.3f);
      ADD_FAILURE() << "a truncated file loaded";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("(truncated?)"), std::string::npos) << e.what();
    }
  }
  {  // malformed JSON
    std::ofstream(path("broken.gltf")) << "{\"asset\": {\"version\": \"2.0\"}, \"animations\": [";
    EXPECT_THROW(load_mesh_asset(path("broken.gltf"), {}, 0.3f), std::invalid_argument);
  }
}

TEST_F(AnimatedMeshes, MorphTargetsAreIgnoredWithANotice) {
  GltfBuilder b = strip_file();
  b.doc()["meshes"][0]["primitives"][0]["targets"] = nlohmann::json::array({{{"POSITION", 0}}});
  b.write_gltf(path("morph.gltf"));
  const MeshAsset asset = load_mesh_asset(path("morph.gltf"), {}, 0.3f);
  ASSERT_EQ(asset.notices.size(), 1u);
  EXPECT_NE(asset.notices[0].find("morph targets: the targets are ignored"), std::string::npos);
}

TEST_F(AnimatedMeshes, TheGltfReaderSeesTheSameTrianglesAsAssimp) {
  // The keyframed car read by the project's reader (it has a clip), and the same file without
  // its animations read by assimp: the same parts with the same triangles at rest.
  std::ifstream in(kAssets + "car_keyframed.gltf");
  nlohmann::json j = nlohmann::json::parse(in);
  j.erase("animations");
  std::ofstream(path("car_still.gltf")) << j.dump();
  const MeshAsset ours = load_mesh_asset(kAssets + "car_keyframed.gltf", {{"tire", 0.05f}}, 0.3f);
  const MeshAsset theirs = load_mesh_asset(path("car_still.gltf"), {{"tire", 0.05f}}, 0.3f);
  ASSERT_EQ(ours.clips.size(), 1u);
  ASSERT_TRUE(theirs.clips.empty());
  // assimp puts a scene of several roots under a root of its own, "ROOT".
  const std::size_t shift = theirs.parts[0].name == "ROOT" ? 1 : 0;
  ASSERT_EQ(ours.parts.size() + shift, theirs.parts.size());
  EXPECT_TRUE(ours.rest_bounds.isApprox(theirs.rest_bounds, 1e-6));
  const auto triangles = [](const MeshAsset& a, std::size_t p) {
    std::vector<std::array<float, 10>> out;
    const MeshPart& part = a.parts[p];
    for (std::size_t t = 0; t < part.triangle_count(); ++t) {
      std::array<float, 10> tri{};
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) tri[static_cast<std::size_t>(3 * c + k)] = part.vertices[part.indices[3 * t + static_cast<std::size_t>(c)]][k];
      }
      tri[9] = part.triangle_reflectivity[t];
      out.push_back(tri);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  for (std::size_t p = 0; p < ours.parts.size(); ++p) {
    const MeshPart& their = theirs.parts[p + shift];
    EXPECT_EQ(ours.parts[p].name, their.name);
    EXPECT_EQ(ours.parts[p].parent, their.parent < 0 || static_cast<std::size_t>(their.parent) < shift ? -1 : their.parent - static_cast<int>(shift));
    EXPECT_TRUE(ours.parts[p].T_parent_part.isApprox(their.T_parent_part, 1e-6));  // assimp keeps floats
    EXPECT_EQ(triangles(ours, p), triangles(theirs, p + shift)) << ours.parts[p].name;
  }
}

}  // namespace
}  // namespace fmcw::sim
