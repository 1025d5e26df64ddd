#pragma once
// Animated mesh scene on Embree: static world baked into one BVH, actors as instances of
// per-part BVHs, so a new time only re-commits instance transforms.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/trajectory.hpp"

namespace fmcw::sim {

/// An asset placed in the scene.
struct SceneObject {
  std::string name;
  std::string class_name;  ///< "static" for the world; car, van, truck, bus, cyclist, pedestrian, ...
  std::uint32_t actor_id = 0;  ///< 0: part of the static world; else the ground-truth instance id
  std::shared_ptr<const MeshAsset> asset;
  Eigen::Affine3d T_body_asset = Eigen::Affine3d::Identity();  ///< mesh placement in the body frame
  std::shared_ptr<const Trajectory> trajectory;                ///< world pose of the body over time
  std::vector<std::pair<int, JointMotion>> joints;             ///< part index -> joint motion
  /// Part index -> wheel radius [m]: the part spins about its local +y at forward speed / radius.
  std::vector<std::pair<int, double>> wheels;
};

/// Where a ray hit, before the hit is resolved into a surface sample.
struct RayHit {
  float distance_m = 0.0f;  ///< +inf when nothing was hit within range
  std::uint32_t slot = 0;   ///< instance slot (0: static world)
  std::uint32_t primitive = 0;
  Eigen::Vector3f normal_object = Eigen::Vector3f::UnitZ();  ///< unnormalised, object space
};

/// What the sensor needs to know about a surface point.
struct SurfaceSample {
  Eigen::Vector3d velocity_world_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_world = Eigen::Vector3d::UnitZ();  ///< unit
  float reflectivity = 0.0f;
  std::uint32_t actor_id = 0;
};

class Scene {
 public:
  Scene();
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  /// A horizontal square of the static world, half_size_m around the origin, at height z_m.
  void add_ground_plane(double z_m, double half_size_m, float reflectivity);
  /// Static objects (actor_id 0) are baked at the pose of their trajectory at t = 0.
  void add(SceneObject object);
  /// Builds every BVH. Throws std::runtime_error on an Embree error.
  void build();

  /// Moves every actor to time t (pose, joints, wheels) and re-commits the top-level scene.
  void set_time(double t_s);
  double time() const { return time_s_; }

  /// Closest hits of rays from one origin along unit directions, within [near, far].
  /// Thread-safe between set_time() calls.
  void intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f* directions, std::size_t count, float near_m,
                 float far_m, RayHit* hits) const;
  /// Velocity, normal and reflectivity at a hit point (world frame) at the current time.
  SurfaceSample resolve(const RayHit& hit, const Eigen::Vector3d& point_world) const;

  const std::vector<SceneObject>& actors() const { return actors_; }
  /// Body state of actor k at the current time.
  const MotionState& actor_state(std::size_t k) const { return actor_states_[k]; }
  std::size_t static_triangle_count() const { return static_reflectivity_.size(); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<SceneObject> actors_;
  std::vector<MotionState> actor_states_;
  std::vector<float> static_reflectivity_;
  double time_s_ = 0.0;
};

}  // namespace fmcw::sim
