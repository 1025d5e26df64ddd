#pragma once
// Animated mesh scene on Embree: static world baked into one BVH, actors as instances of
// per-part BVHs, so a new time only re-commits instance transforms.

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <map>
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
  /// > 0: the joints run on a gait clock, the distance the body has travelled divided by this
  /// speed, not on time: a walker's limbs swing as it walks, at the cadence of its speed, and
  /// rest when it stands (before its path starts, after it ends) [m/s]. 0: they run on time.
  double gait_speed_mps = 0.0;
  /// Part index -> wheel radius [m]: the part spins about its local +y at forward speed / radius.
  std::vector<std::pair<int, double>> wheels;
  /// Index into asset->clips of the clip the actor plays (-1: none), and how it plays it. A
  /// part the clip animates follows the clip, not a procedural joint or wheel rule.
  int clip = -1;
  ClipPlayback playback;
  /// Semantic class of its triangles (semantic_classes.hpp); for the static world, parts whose
  /// node name, else material name, is in part_classes take that class instead.
  std::uint16_t class_id = 0;
  std::map<std::string, std::uint16_t> part_classes;
};

/// Where a ray hit, before the hit is resolved into a surface sample.
struct RayHit {
  float distance_m = 0.0f;  ///< +inf when nothing was hit within range
  std::uint32_t slot = 0;   ///< instance slot (0: static world)
  std::uint32_t primitive = 0;
  float u = 0.0f, v = 0.0f;  ///< barycentric: the hit is (1 - u - v) v0 + u v1 + v v2 of the triangle
  Eigen::Vector3f normal_object = Eigen::Vector3f::UnitZ();  ///< unnormalised, object space
};

/// An actor part's motion at the current time, flat for the per-pixel loop: what resolving a
/// hit on its instance slot needs.
struct SlotMotion {
  Eigen::Matrix<double, 3, 4> velocity_field = Eigen::Matrix<double, 3, 4>::Zero();  ///< v(p) = K [p; 1], world
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Identity();  ///< inverse transpose of the part's 3x3
  const float* reflectivity = nullptr;                          ///< per triangle of the part
  /// A skinned part (vertices in the world frame, deformed each set_time): each vertex's exact
  /// velocity (world) and the part's triangles. Null for rigid parts.
  const Eigen::Vector3d* vertex_velocity = nullptr;
  const std::uint32_t* indices = nullptr;
  std::uint32_t actor_id = 0;
  std::uint16_t class_id = 0;
  std::uint32_t actor_index = 0;  ///< into actors()

  /// Velocity (world) of the surface point hit at p (world): the rigid field of the part, or for
  /// a skinned part the material point's velocity, its vertices' velocities blended by the hit's
  /// barycentric coordinates (exact for the deforming flat triangle).
  Eigen::Vector3d velocity(const RayHit& hit, const Eigen::Vector3d& p) const {
    if (vertex_velocity == nullptr) return velocity_field.leftCols<3>() * p + velocity_field.col(3);
    const std::uint32_t* t = indices + 3 * static_cast<std::size_t>(hit.primitive);
    const double u = hit.u, v = hit.v;
    return (1.0 - u - v) * vertex_velocity[t[0]] + u * vertex_velocity[t[1]] + v * vertex_velocity[t[2]];
  }
};

/// The two layers of a scene, traced separately (see Scene::intersect).
enum class SceneLayer { kStatic, kActors };

struct BoundingSphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
};

/// What the sensor needs to know about a surface point.
struct SurfaceSample {
  Eigen::Vector3d velocity_world_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_world = Eigen::Vector3d::UnitZ();  ///< unit
  float reflectivity = 0.0f;
  std::uint32_t actor_id = 0;
  std::uint16_t semantic_class = 0;
};

class Scene {
 public:
  Scene();
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  /// A horizontal square of the static world, half_size_m around the origin, at height z_m.
  void add_ground_plane(double z_m, double half_size_m, float reflectivity, std::uint16_t class_id = 0);
  /// Static objects (actor_id 0) are baked at the pose of their trajectory at t = 0.
  void add(SceneObject object);
  /// Builds every BVH. Throws std::runtime_error on an Embree error.
  void build();

  /// Moves every actor to time t (pose, clips, joints, wheels, skins: each skinned part's
  /// vertices are deformed and its BVH refit) and re-commits the top-level scene:
  /// begin_time(t), update_skin(k) for every k, end_time().
  void set_time(double t_s);
  /// set_time in three steps, so that several threads can share the skins. begin_time moves the
  /// bodies and rigid parts (one thread); then update_skin(k) for each k < skin_count(), each
  /// once, from any threads at once (each writes only its own skin); then end_time, once all
  /// are done (one thread): instance transforms, bounds, the top-level commit.
  void begin_time(double t_s);
  std::size_t skin_count() const;
  void update_skin(std::size_t k);
  void end_time();
  double time() const { return time_s_; }

  /// Closest hits in one layer of rays from one origin along unit directions, within
  /// [near, far]. Ray k goes along directions[order[k]] and its hit is hits[order[k]]
  /// (order == nullptr: k itself). kStatic sets every hit (+inf distance: none); kActors
  /// looks only nearer than the hit a ray has and replaces it when an actor is nearer, so
  /// kStatic on all rays and then kActors on any subset that contains every ray that can reach
  /// an actor gives the closest hits in the whole scene. Rays are traced in packets of
  /// consecutive k: an order that keeps neighbouring directions together is faster.
  /// Thread-safe between set_time() calls.
  void intersect(SceneLayer layer, const Eigen::Vector3f& origin, const Eigen::Vector3f* directions,
                 const std::uint32_t* order, std::size_t count, float near_m, float far_m, RayHit* hits) const;
  /// Velocity, normal and reflectivity at a hit point (world frame) at the current time.
  SurfaceSample resolve(const RayHit& hit, const Eigen::Vector3d& point_world) const {
    SurfaceSample s;
    if (hit.slot == 0) {
      s.normal_world = static_normals_[hit.primitive].cast<double>();
      s.reflectivity = static_reflectivity_[hit.primitive];
      s.semantic_class = static_class_[hit.primitive];
      return s;
    }
    const SlotMotion& m = slots_[hit.slot];
    s.velocity_world_mps = m.velocity(hit, point_world);
    // Normals transform with the inverse transpose (parts may be scaled).
    s.normal_world = (m.normal_matrix * hit.normal_object.cast<double>()).normalized();
    s.reflectivity = m.reflectivity[hit.primitive];
    s.actor_id = m.actor_id;
    s.semantic_class = m.class_id;
    return s;
  }
  /// Unit normal and reflectivity of static triangle k (hits on slot 0).
  const Eigen::Vector3f& static_normal(std::uint32_t k) const { return static_normals_[k]; }
  float static_reflectivity(std::uint32_t k) const { return static_reflectivity_[k]; }
  std::uint16_t static_class(std::uint32_t k) const { return static_class_[k]; }
  /// Motion of instance slot s >= 1 at the current time.
  const SlotMotion& slot(std::uint32_t s) const { return slots_[s]; }

  const std::vector<SceneObject>& actors() const { return actors_; }
  /// A sphere around each actor at the current time (world), padded for single-precision hit
  /// tests: no ray that misses it hits the actor. Radius 0 for an actor without triangles.
  const std::vector<BoundingSphere>& actor_bounds() const { return actor_bounds_; }
  /// Body state of actor k at the current time.
  const MotionState& actor_state(std::size_t k) const { return actor_states_[k]; }
  std::size_t static_triangle_count() const { return static_reflectivity_.size(); }
  /// Calls visit(p) for every vertex p of actor k's parts at the current time (skins deformed),
  /// world frame.
  void for_each_surface_point(std::size_t k, const std::function<void(const Eigen::Vector3d&)>& visit) const;
  /// Every vertex of actor k's parts at the current time, world frame.
  std::vector<Eigen::Vector3d> actor_surface(std::size_t k) const;
  /// The box of actor_surface(k) in the frame T_frame_world takes the world to.
  Eigen::AlignedBox3d actor_extent(std::size_t k, const Eigen::Isometry3d& T_frame_world) const;
  /// Vertices of actor k's skinned parts, deformed at the current time (world frame): what the
  /// rays see. Empty for an actor without skins.
  std::vector<Eigen::Vector3f> skinned_vertices(std::size_t k) const;

 private:
  void add_skinned_slot(std::size_t actor, std::size_t part);
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<SceneObject> actors_;
  std::vector<MotionState> actor_states_;
  std::vector<float> static_reflectivity_;
  std::vector<std::uint16_t> static_class_;      // per static triangle
  std::vector<Eigen::Vector3f> static_normals_;  // unit, per static triangle
  std::vector<SlotMotion> slots_;                // 0: the static world (unused), then actor parts
  std::vector<BoundingSphere> actor_bounds_;
  double time_s_ = 0.0;
};

}  // namespace fmcw::sim
