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

}  // namespace fmcw::test
