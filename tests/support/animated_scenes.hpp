#pragma once
// Scenes the animation tests share: a small head, a closed box mesh, constant-rate turn keys, a
// one-actor scene, and a strip along two bones whose blend is known in closed form. The glTF and
// FBX tests build the same scenes from them.

#include <Eigen/Geometry>
#include <algorithm>
#include <memory>
#include <vector>

#include "fmcw/core/head_model.hpp"
#include "fmcw/sim/scene.hpp"
#include "support/gltf_builder.hpp"
#include "support/sim_scenes.hpp"

namespace fmcw::test {

// One head at the rig origin looking along +x, 30 x 20 deg at 0.25 deg.
inline core::RigModel one_head(double z = 1.0) {
  core::RigModel rig;
  core::HeadModel head;
  head.name = "h";
  head.fov_horizontal_rad = 30.0 * M_PI / 180.0;
  head.fov_vertical_rad = 20.0 * M_PI / 180.0;
  head.resolution_horizontal_rad = head.resolution_vertical_rad = 0.25 * M_PI / 180.0;
  head.T_rig_head = at(0, 0, z);
  rig.heads.push_back(head);
  return rig;
}

// A closed box [lo, hi] as 8 vertices and 12 outward triangles.
inline void box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, std::vector<Eigen::Vector3f>& v, std::vector<std::uint32_t>& i) {
  const auto base = static_cast<std::uint32_t>(v.size());
  for (int k = 0; k < 8; ++k) v.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const std::uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                      {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) i.insert(i.end(), {base + f[0], base + f[1], base + f[2]});
}

// Rotation keys about +z at a constant rate, every `step` seconds over [0, duration].
inline std::vector<float> turn_keys(double rate_rps, double step, double duration, std::vector<float>& times) {
  std::vector<float> values;
  for (double t = 0.0; t <= duration + 1e-9; t += step) {
    times.push_back(static_cast<float>(t));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(rate_rps * t, Eigen::Vector3d::UnitZ()));
    values.insert(values.end(), {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()),
                                 static_cast<float>(q.w())});
  }
  return values;
}

inline std::shared_ptr<sim::Scene> scene_with(std::shared_ptr<const sim::MeshAsset> asset, const Eigen::Isometry3d& pose, int clip,
                                  std::shared_ptr<const sim::Trajectory> trajectory = nullptr) {
  auto scene = std::make_shared<sim::Scene>();
  sim::SceneObject o;
  o.name = "actor";
  o.class_name = "thing";
  o.actor_id = 7;
  o.asset = std::move(asset);
  o.trajectory = trajectory ? std::move(trajectory) : std::shared_ptr<const sim::Trajectory>(sim::make_static_trajectory(pose));
  o.clip = clip;
  scene->add(std::move(o));
  scene->build();
  return scene;
}

// A strip in the y-z plane (facing -x) along two bones: bone 0 at the origin, bone 1 at y = 1.
// Vertices blend from bone 0 (y <= 0.5) to bone 1 (y >= 1.5); bone 1 turns about +z.
struct Strip {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<double> w1;  // weight of bone 1 per vertex
};
inline Strip two_bone_strip() {
  Strip s;
  const int n = 16;
  for (int k = 0; k <= n; ++k) {
    const float y = 2.0f * static_cast<float>(k) / n;
    for (const float z : {-0.5f, 0.5f}) s.vertices.emplace_back(0.0f, y, z);
    const double w = std::clamp((y - 0.5) / 1.0, 0.0, 1.0);
    s.w1.insert(s.w1.end(), {w, w});
  }
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t a = 2 * k, b = a + 1, c = a + 2, d = a + 3;
    s.indices.insert(s.indices.end(), {a, c, b, b, c, d});
  }
  return s;
}

// The strip's vertices and their velocities in closed form, placed at `place`, bone 1 turned by
// omega t about +z: p = w0 v + w1 (c + R (v - c)), dp/dt = w1 omega z x R (v - c), c = (0, 1, 0).
struct StripMotion {
  std::vector<Eigen::Vector3d> p, p_dot;
};
inline StripMotion strip_motion(const Strip& strip, const Eigen::Vector3d& place, double omega, double t) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(omega * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d c(0, 1, 0);
  StripMotion m;
  for (std::size_t k = 0; k < strip.vertices.size(); ++k) {
    const Eigen::Vector3d v = strip.vertices[k].cast<double>();
    m.p.push_back(place + (1.0 - strip.w1[k]) * v + strip.w1[k] * (c + R * (v - c)));
    m.p_dot.push_back(strip.w1[k] * Eigen::Vector3d(0, 0, omega).cross(R * (v - c)));
  }
  return m;
}

// A grid of rays from (0, 0, 0.5) over a strip placed at (6, -1, 0.5), and where they hit.
struct StripRays {
  Eigen::Vector3f origin{0.0f, 0.0f, 0.5f};
  std::vector<Eigen::Vector3f> dirs;
  std::vector<sim::RayHit> hits;
};
inline StripRays cast_at_strip(const sim::Scene& scene) {
  StripRays r;
  for (int i = 0; i < 60; ++i) {
    for (int j = 0; j < 12; ++j) r.dirs.push_back((Eigen::Vector3f(6.0f, -1.1f + 0.04f * i, 0.1f + 0.07f * j) - r.origin).normalized());
  }
  r.hits.resize(r.dirs.size());
  scene.intersect(sim::SceneLayer::kStatic, r.origin, r.dirs.data(), nullptr, r.dirs.size(), 0.1f, 100.0f, r.hits.data());
  scene.intersect(sim::SceneLayer::kActors, r.origin, r.dirs.data(), nullptr, r.dirs.size(), 0.1f, 100.0f, r.hits.data());
  return r;
}

// The strip as a glTF: root "rig" holding bone0 (bone1 at y = 1 under it) and the skinned node
// "strip", bound at the rest pose; a LINEAR clip "bend" turns bone1 about +z at omega [rad/s],
// keyed every 0.25 s over [0, 2] s.
inline GltfBuilder bending_strip(const Strip& strip, double omega) {
  GltfBuilder b;
  const int root = b.add_node("rig");
  const int bone0 = b.add_node("bone0", root);
  const int bone1 = b.add_node("bone1", bone0, Eigen::Vector3d(0, 1, 0));
  const int mesh_node = b.add_node("strip", root);
  const int mesh = b.add_mesh(mesh_node, strip.vertices, strip.indices);
  std::vector<std::vector<std::pair<int, float>>> influences;
  for (const double w : strip.w1) influences.push_back({{0, static_cast<float>(1.0 - w)}, {1, static_cast<float>(w)}});
  b.set_skin_weights(mesh, influences);
  b.attach_skin(mesh_node, b.add_skin({bone0, bone1}));
  std::vector<float> times;
  const std::vector<float> values = turn_keys(omega, 0.25, 2.0, times);
  b.add_channel(b.add_animation("bend"), bone1, "rotation", "LINEAR", times, values);
  return b;
}

}  // namespace fmcw::test
