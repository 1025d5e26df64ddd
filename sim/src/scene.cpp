#include "fmcw/sim/scene.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "fmcw/core/errors.hpp"

namespace fmcw::sim {

namespace {

void embree_error(void* user, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(user);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// World transform of a part and its time derivative, as 4x4 matrices (last row 0 0 0 1 / 0).
struct PartMotion {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d M_dot = Eigen::Matrix4d::Zero();
};

// Joint rotation about a unit axis and its derivative with respect to time.
// The joint at clock t, the clock running at clock_rate clock seconds per second.
void joint_matrices(const JointMotion& joint, double t, double clock_rate, Eigen::Matrix4d& J, Eigen::Matrix4d& J_dot) {
  const double angle = joint.angle_rad(t);
  const double rate = joint.rate_rps(t) * clock_rate;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, joint.axis.normalized()).toRotationMatrix();
  J.setIdentity();
  J.topLeftCorner<3, 3>() = R;
  J_dot.setZero();
  J_dot.topLeftCorner<3, 3>() = rate * skew(joint.axis.normalized()) * R;
}

}  // namespace

struct Scene::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  RTCScene static_scene = nullptr;
  bool packets16 = false;  // the device traces packets of 16 rays natively
  std::string last_error;
  // Static world: triangles in world coordinates, merged.
  std::vector<float> static_vertices;
  std::vector<std::uint32_t> static_indices;
  // One Embree scene per asset part with triangles, shared between actors of the same asset.
  std::map<std::pair<const MeshAsset*, int>, RTCScene> part_scenes;
  // Instance slots: 0 = static world, then one per (actor, part with triangles).
  struct Slot {
    int actor = -1;
    int part = -1;
    RTCGeometry instance = nullptr;
    Eigen::AlignedBox3d bounds_part;  // of the part's vertices, part frame
    int skinned = -1;                 // index into skinned, for a skinned part
  };
  std::vector<Slot> slots;
  // A skinned actor part: its own triangle geometry in the world frame, its vertices deformed and
  // its BVH refit every set_time. The triangles are the asset's (shared between actors); the
  // vertices and their velocities are the actor's own.
  struct Skinned {
    std::size_t actor = 0;
    std::size_t part = 0;
    RTCScene scene = nullptr;
    RTCGeometry geometry = nullptr;
    float* vertices = nullptr;  // Embree's vertex buffer
    std::vector<Eigen::Vector3d> velocity;
    Eigen::AlignedBox3d box;  // of the deformed vertices, world, at the current time
    JointMatrices joints;     // scratch
  };
  std::vector<Skinned> skinned;
  // Per actor and part: the track of the actor's clip that animates the part, -1 for none.
  std::vector<std::vector<int>> clip_track;
  // Per actor: per-part motion at the current time, and each part's slot (0: no triangles).
  std::vector<std::vector<PartMotion>> part_motion;
  std::vector<std::vector<std::uint32_t>> part_slot;
  std::vector<Eigen::AlignedBox3d> actor_box;  // per actor, world, at the current time

  void check(const char* what) const {
    if (!last_error.empty()) throw std::runtime_error(std::string(what) + ": " + last_error);
  }
};

Scene::Scene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("threads=1");
  if (impl_->device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  rtcSetDeviceErrorFunction(impl_->device, embree_error, &impl_->last_error);
  impl_->packets16 = rtcGetDeviceProperty(impl_->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) == 1;
}

Scene::~Scene() {
  for (auto& slot : impl_->slots) {
    if (slot.instance) rtcReleaseGeometry(slot.instance);
  }
  for (auto& [key, scene] : impl_->part_scenes) rtcReleaseScene(scene);
  for (auto& skinned : impl_->skinned) {
    if (skinned.geometry) rtcReleaseGeometry(skinned.geometry);
    if (skinned.scene) rtcReleaseScene(skinned.scene);
  }
  if (impl_->static_scene) rtcReleaseScene(impl_->static_scene);
  if (impl_->top) rtcReleaseScene(impl_->top);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

void Scene::add_ground_plane(double z_m, double half_size_m, float reflectivity, std::uint16_t class_id) {
  const auto base = static_cast<std::uint32_t>(impl_->static_vertices.size() / 3);
  const double h = half_size_m;
  const double corners[4][2] = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
  for (const auto& c : corners) {
    impl_->static_vertices.insert(impl_->static_vertices.end(),
                                  {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(z_m)});
  }
  for (const std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) impl_->static_indices.push_back(base + i);
  static_reflectivity_.insert(static_reflectivity_.end(), 2, reflectivity);
  static_class_.insert(static_class_.end(), 2, class_id);
}

void Scene::add(SceneObject object) {
  if (!object.asset) throw core::InputError("scene object '" + object.name + "' has no mesh");
  if (!object.trajectory) throw core::InputError("scene object '" + object.name + "' has no trajectory");
  if (object.actor_id != 0) {
    if (object.clip >= static_cast<int>(object.asset->clips.size())) {
      throw core::InputError("scene object '" + object.name + "' plays clip " + std::to_string(object.clip) +
                             " of a mesh with " + std::to_string(object.asset->clips.size()));
    }
    actors_.push_back(std::move(object));
    return;
  }
  // Bake the static object's parts at their rest pose.
  const MeshAsset& asset = *object.asset;
  const Eigen::Affine3d T_world_asset =
      Eigen::Affine3d(object.trajectory->state(0.0).T_world_body.matrix()) * object.T_body_asset;
  std::vector<Eigen::Affine3d> T_world_part(asset.parts.size());
  for (std::size_t k = 0; k < asset.parts.size(); ++k) {
    const MeshPart& part = asset.parts[k];
    const Eigen::Affine3d parent = part.parent < 0 ? T_world_asset : T_world_part[static_cast<std::size_t>(part.parent)];
    T_world_part[k] = parent * part.T_parent_part;
  }
  for (std::size_t k = 0; k < asset.parts.size(); ++k) {
    const MeshPart& part = asset.parts[k];
    const auto base = static_cast<std::uint32_t>(impl_->static_vertices.size() / 3);
    // A skinned part at its rest pose: skinned by the joints' rest transforms (world).
    std::vector<Eigen::Vector3f> skinned;
    if (part.skin) skinned = asset.rest_vertices(k, T_world_part);
    for (std::size_t i = 0; i < part.vertices.size(); ++i) {
      const Eigen::Vector3d w = part.skin ? skinned[i].cast<double>() : T_world_part[k] * part.vertices[i].cast<double>();
      impl_->static_vertices.insert(impl_->static_vertices.end(),
                                    {static_cast<float>(w.x()), static_cast<float>(w.y()), static_cast<float>(w.z())});
    }
    for (const auto i : part.indices) impl_->static_indices.push_back(base + i);
    static_reflectivity_.insert(static_reflectivity_.end(), part.triangle_reflectivity.begin(),
                                part.triangle_reflectivity.end());
    // The part's class by its node name, else each triangle's by its material's name.
    const auto by_node = object.part_classes.find(part.name);
    for (std::size_t t = 0; t < part.triangle_count(); ++t) {
      std::uint16_t c = object.class_id;
      if (by_node != object.part_classes.end()) {
        c = by_node->second;
      } else if (t < part.triangle_material.size() && part.triangle_material[t] < asset.materials.size()) {
        const auto by_material = object.part_classes.find(asset.materials[part.triangle_material[t]]);
        if (by_material != object.part_classes.end()) c = by_material->second;
      }
      static_class_.push_back(c);
    }
  }
}

void Scene::build() {
  Impl& im = *impl_;
  im.top = rtcNewScene(im.device);
  // The top level holds one instance per actor part (about a hundred): rebuilding it at
  // medium quality every frame costs little and makes every ray's traversal cheaper.
  rtcSetSceneBuildQuality(im.top, RTC_BUILD_QUALITY_MEDIUM);

  // Slot 0: the static world, one high-quality BVH that is never rebuilt. Rays traverse it
  // directly, not through an instance (see intersect()).
  im.static_scene = rtcNewScene(im.device);
  rtcSetSceneBuildQuality(im.static_scene, RTC_BUILD_QUALITY_HIGH);
  for (std::size_t t = 0; t + 2 < im.static_indices.size(); t += 3) {
    const auto vertex = [&](std::size_t k) {
      const std::size_t v = im.static_indices[t + k];
      return Eigen::Vector3f(im.static_vertices[3 * v], im.static_vertices[3 * v + 1], im.static_vertices[3 * v + 2]);
    };
    const Eigen::Vector3f n = (vertex(1) - vertex(0)).cross(vertex(2) - vertex(0));
    static_normals_.push_back(n.norm() > 0.0f ? n.normalized() : Eigen::Vector3f::UnitZ());
  }
  if (!im.static_indices.empty()) {
    RTCGeometry geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), im.static_vertices.size() / 3));
    auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                    3 * sizeof(std::uint32_t), im.static_indices.size() / 3));
    im.check("static world buffers");
    std::copy(im.static_vertices.begin(), im.static_vertices.end(), vb);
    std::copy(im.static_indices.begin(), im.static_indices.end(), ib);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(im.static_scene, geom, 0);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(im.static_scene);
  im.check("static world BVH");
  im.slots.push_back({});
  slots_.assign(1, SlotMotion{});

  // Actors: one BVH per asset part, one instance per actor part.
  im.part_motion.resize(actors_.size());
  im.part_slot.resize(actors_.size());
  im.clip_track.resize(actors_.size());
  actor_states_.resize(actors_.size());
  for (std::size_t a = 0; a < actors_.size(); ++a) {
    const MeshAsset& asset = *actors_[a].asset;
    im.part_motion[a].resize(asset.parts.size());
    im.part_slot[a].assign(asset.parts.size(), 0);
    im.clip_track[a].assign(asset.parts.size(), -1);
    if (actors_[a].clip >= 0) {
      const AnimationClip& clip = asset.clips[static_cast<std::size_t>(actors_[a].clip)];
      for (std::size_t t = 0; t < clip.tracks.size(); ++t) im.clip_track[a][static_cast<std::size_t>(clip.tracks[t].part)] = static_cast<int>(t);
    }
    for (std::size_t k = 0; k < asset.parts.size(); ++k) {
      const MeshPart& part = asset.parts[k];
      if (part.triangle_count() == 0) continue;
      if (part.skin) {
        add_skinned_slot(a, k);
        continue;
      }
      const auto key = std::make_pair(&asset, static_cast<int>(k));
      auto it = im.part_scenes.find(key);
      if (it == im.part_scenes.end()) {
        RTCScene scene = rtcNewScene(im.device);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                3 * sizeof(float), part.vertices.size()));
        auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), part.triangle_count()));
        im.check("actor mesh buffers");
        for (std::size_t v = 0; v < part.vertices.size(); ++v) {
          vb[3 * v] = part.vertices[v].x();
          vb[3 * v + 1] = part.vertices[v].y();
          vb[3 * v + 2] = part.vertices[v].z();
        }
        std::copy(part.indices.begin(), part.indices.end(), ib);
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(scene, geom, 0);
        rtcReleaseGeometry(geom);
        rtcCommitScene(scene);
        im.check(("mesh '" + asset.path + "' part '" + part.name + "'").c_str());
        it = im.part_scenes.emplace(key, scene).first;
      }
      RTCGeometry inst = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(inst, it->second);
      const auto slot = static_cast<unsigned>(im.slots.size());
      rtcAttachGeometryByID(im.top, inst, slot);
      Eigen::AlignedBox3d box;
      for (const auto& v : part.vertices) box.extend(v.cast<double>());
      im.slots.push_back({static_cast<int>(a), static_cast<int>(k), inst, box});
      im.part_slot[a][k] = slot;
      SlotMotion motion;
      motion.reflectivity = part.triangle_reflectivity.data();
      motion.actor_id = actors_[a].actor_id;
      motion.class_id = actors_[a].class_id;
      motion.actor_index = static_cast<std::uint32_t>(a);
      slots_.push_back(motion);
    }
  }
  // Pointers into the skins last, when the vector of skins has stopped growing.
  for (std::size_t s = 1; s < im.slots.size(); ++s) {
    if (im.slots[s].skinned >= 0) slots_[s].vertex_velocity = im.skinned[static_cast<std::size_t>(im.slots[s].skinned)].velocity.data();
  }
  im.check("scene build");
  set_time(0.0);
}

void Scene::add_skinned_slot(std::size_t a, std::size_t k) {
  Impl& im = *impl_;
  const MeshPart& part = actors_[a].asset->parts[k];
  Impl::Skinned sk;
  sk.actor = a;
  sk.part = k;
  sk.velocity.resize(part.vertices.size());
  // Refit, not rebuild: the topology never changes, only the vertices move. Compact leaves hold
  // vertex indices, not copies, so a refit only recomputes bounds (update 5.0 -> 2.2 ms for 30
  // walkers, docs/PERFORMANCE.md).
  sk.scene = rtcNewScene(im.device);
  rtcSetSceneFlags(sk.scene, RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_COMPACT);
  rtcSetSceneBuildQuality(sk.scene, RTC_BUILD_QUALITY_LOW);
  sk.geometry = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(sk.geometry, RTC_BUILD_QUALITY_REFIT);
  sk.vertices = static_cast<float*>(rtcSetNewGeometryBuffer(sk.geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                             3 * sizeof(float), part.vertices.size()));
  rtcSetSharedGeometryBuffer(sk.geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, part.indices.data(), 0,
                             3 * sizeof(std::uint32_t), part.triangle_count());
  im.check(("skinned mesh '" + actors_[a].asset->path + "' part '" + part.name + "'").c_str());
  rtcAttachGeometryByID(sk.scene, sk.geometry, 0);
  // Instanced with the identity: the deformed vertices are in the world frame already.
  RTCGeometry inst = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(inst, sk.scene);
  const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
  rtcCommitGeometry(inst);
  const auto slot = static_cast<unsigned>(im.slots.size());
  rtcAttachGeometryByID(im.top, inst, slot);
  im.slots.push_back({static_cast<int>(a), static_cast<int>(k), inst, Eigen::AlignedBox3d(), static_cast<int>(im.skinned.size())});
  im.part_slot[a][k] = slot;
  SlotMotion motion;  // vertex_velocity: set once every skin is in place (see build)
  motion.reflectivity = part.triangle_reflectivity.data();
  motion.indices = part.indices.data();
  motion.actor_id = actors_[a].actor_id;
  motion.class_id = actors_[a].class_id;
  motion.actor_index = static_cast<std::uint32_t>(a);
  slots_.push_back(motion);
  im.skinned.push_back(std::move(sk));
}

void Scene::for_each_surface_point(std::size_t k, const std::function<void(const Eigen::Vector3d&)>& visit) const {
  const Impl& im = *impl_;
  const MeshAsset& asset = *actors_[k].asset;
  for (std::size_t p = 0; p < asset.parts.size(); ++p) {
    const std::uint32_t slot = im.part_slot[k][p];
    if (slot == 0) continue;
    if (im.slots[slot].skinned >= 0) {
      const Impl::Skinned& sk = im.skinned[static_cast<std::size_t>(im.slots[slot].skinned)];
      for (std::size_t v = 0; v < sk.velocity.size(); ++v) visit(Eigen::Vector3d(sk.vertices[3 * v], sk.vertices[3 * v + 1], sk.vertices[3 * v + 2]));
      continue;
    }
    const Eigen::Matrix4d& M = im.part_motion[k][p].M;
    for (const auto& v : asset.parts[p].vertices) visit(M.topLeftCorner<3, 3>() * v.cast<double>() + M.topRightCorner<3, 1>());
  }
}

std::vector<Eigen::Vector3d> Scene::actor_surface(std::size_t k) const {
  std::vector<Eigen::Vector3d> out;
  for_each_surface_point(k, [&](const Eigen::Vector3d& p) { out.push_back(p); });
  return out;
}

Eigen::AlignedBox3d Scene::actor_extent(std::size_t k, const Eigen::Isometry3d& T_frame_world) const {
  Eigen::AlignedBox3d box;
  for_each_surface_point(k, [&](const Eigen::Vector3d& p) { box.extend(T_frame_world * p); });
  return box;
}

std::vector<Eigen::Vector3f> Scene::skinned_vertices(std::size_t k) const {
  std::vector<Eigen::Vector3f> out;
  for (const Impl::Skinned& sk : impl_->skinned) {
    if (sk.actor != k) continue;
    for (std::size_t v = 0; v < sk.velocity.size(); ++v) out.emplace_back(sk.vertices[3 * v], sk.vertices[3 * v + 1], sk.vertices[3 * v + 2]);
  }
  return out;
}

void Scene::set_time(double t_s) {
  begin_time(t_s);
  for (std::size_t k = 0; k < skin_count(); ++k) update_skin(k);
  end_time();
}

std::size_t Scene::skin_count() const { return impl_->skinned.size(); }

void Scene::begin_time(double t_s) {
  Impl& im = *impl_;
  time_s_ = t_s;
  for (std::size_t a = 0; a < actors_.size(); ++a) {
    const SceneObject& actor = actors_[a];
    const MeshAsset& asset = *actor.asset;
    const MotionState state = actor.trajectory->state(t_s);
    actor_states_[a] = state;
    // Body: rigid motion, M = [R p], M_dot = [[w]x R, v].
    Eigen::Matrix4d M_body = state.T_world_body.matrix();
    Eigen::Matrix4d M_body_dot = Eigen::Matrix4d::Zero();
    M_body_dot.topLeftCorner<3, 3>() = skew(state.twist.angular_rps) * state.T_world_body.linear();
    M_body_dot.topRightCorner<3, 1>() = state.twist.linear_mps;
    const Eigen::Matrix4d M_asset = M_body * actor.T_body_asset.matrix();
    const Eigen::Matrix4d M_asset_dot = M_body_dot * actor.T_body_asset.matrix();
    // Forward speed, for the wheels.
    const double forward_mps = (state.T_world_body.linear().transpose() * state.twist.linear_mps).x();
    // The gait clock of a walker, else time.
    const bool gait = actor.gait_speed_mps > 0.0;
    const double clock = gait ? state.distance_m / actor.gait_speed_mps : t_s;
    const double clock_rate = gait ? state.twist.linear_mps.norm() / actor.gait_speed_mps : 1.0;
    // The clip's time and its rate.
    const AnimationClip* clip = actor.clip >= 0 ? &asset.clips[static_cast<std::size_t>(actor.clip)] : nullptr;
    double tau = 0.0, tau_rate = 0.0;
    if (clip) actor.playback.clip_time(clip->duration_s, t_s, state.distance_m, state.twist.linear_mps.norm(), tau, tau_rate);
    std::vector<PartMotion>& motion = im.part_motion[a];
    for (std::size_t k = 0; k < asset.parts.size(); ++k) {
      const MeshPart& part = asset.parts[k];
      Eigen::Matrix4d L = part.T_parent_part.matrix();
      Eigen::Matrix4d L_dot = Eigen::Matrix4d::Zero();
      const int track = im.clip_track[a][k];
      if (track >= 0) {
        // The clip drives this node (it wins over any procedural rule): dL/dt = dL/dtau dtau/dt.
        clip->local_transform(static_cast<std::size_t>(track), part.rest_trs, tau, L, L_dot);
        L_dot *= tau_rate;
      }
      const JointMotion* joint = nullptr;
      JointMotion wheel;
      bool on_clock = false;
      for (const auto& [index, j] : actor.joints) {
        if (index == static_cast<int>(k)) {
          joint = &j;
          on_clock = true;
        }
      }
      for (const auto& [index, radius] : actor.wheels) {
        if (index == static_cast<int>(k)) {
          wheel.axis = Eigen::Vector3d::UnitY();
          wheel.spin_rate_rps = forward_mps / radius;
          joint = &wheel;
          on_clock = false;
        }
      }
      if (joint != nullptr && track < 0) {
        Eigen::Matrix4d J, J_dot;
        joint_matrices(*joint, on_clock ? clock : t_s, on_clock ? clock_rate : 1.0, J, J_dot);
        L_dot = L * J_dot;
        L = L * J;
      }
      const Eigen::Matrix4d& P = part.parent < 0 ? M_asset : motion[static_cast<std::size_t>(part.parent)].M;
      const Eigen::Matrix4d& P_dot = part.parent < 0 ? M_asset_dot : motion[static_cast<std::size_t>(part.parent)].M_dot;
      motion[k].M = P * L;
      motion[k].M_dot = P_dot * L + P * L_dot;  // product rule
      const std::uint32_t slot = im.part_slot[a][k];
      // No triangles: nothing to resolve (its children use motion[k]); skinned: see below.
      if (slot == 0 || im.slots[slot].skinned >= 0) continue;
      // Velocity field of the part's points: v(p) = M_dot M^-1 p.
      const Eigen::Matrix4d M_inv = motion[k].M.inverse();
      slots_[slot].velocity_field = (motion[k].M_dot * M_inv).topRows<3>();
      slots_[slot].normal_matrix = M_inv.topLeftCorner<3, 3>().transpose();
    }
  }
}

void Scene::update_skin(std::size_t k) {
  // Every vertex moved by its joints (M_j B_j), with its exact velocity; then a refit.
  Impl& im = *impl_;
  Impl::Skinned& sk = im.skinned[k];
  const MeshPart& part = actors_[sk.actor].asset->parts[sk.part];
  const SkinBinding& skin = *part.skin;
  const std::vector<PartMotion>& motion = im.part_motion[sk.actor];
  sk.joints.M.resize(skin.joint_parts.size());
  sk.joints.M_dot.resize(skin.joint_parts.size());
  for (std::size_t j = 0; j < skin.joint_parts.size(); ++j) {
    const PartMotion& m = motion[static_cast<std::size_t>(skin.joint_parts[j])];
    sk.joints.M[j] = (m.M * skin.inverse_bind[j]).topRows<3>();
    sk.joints.M_dot[j] = (m.M_dot * skin.inverse_bind[j]).topRows<3>();
  }
  skin_vertices(skin, sk.joints, part.vertices, sk.vertices, sk.velocity.data());
  sk.box.setEmpty();
  for (std::size_t v = 0; v < part.vertices.size(); ++v) {
    sk.box.extend(Eigen::Vector3d(sk.vertices[3 * v], sk.vertices[3 * v + 1], sk.vertices[3 * v + 2]));
  }
  rtcUpdateGeometryBuffer(sk.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(sk.geometry);
  rtcCommitScene(sk.scene);
  // The instance is unchanged, but the top level must take its new bounds.
  rtcCommitGeometry(im.slots[im.part_slot[sk.actor][sk.part]].instance);
}

void Scene::end_time() {
  Impl& im = *impl_;
  std::vector<Eigen::AlignedBox3d>& actor_box = im.actor_box;
  actor_box.resize(actors_.size());
  for (auto& box : actor_box) box.setEmpty();
  for (const Impl::Skinned& sk : im.skinned) actor_box[sk.actor].extend(sk.box);
  for (std::size_t s = 1; s < im.slots.size(); ++s) {
    const Impl::Slot& slot = im.slots[s];
    if (slot.skinned >= 0) continue;
    const Eigen::Matrix4d& M = im.part_motion[static_cast<std::size_t>(slot.actor)][static_cast<std::size_t>(slot.part)].M;
    // The part lies inside the image of its box's corners (the transform is affine).
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d p = slot.bounds_part.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
      actor_box[static_cast<std::size_t>(slot.actor)].extend(M.topLeftCorner<3, 3>() * p + M.topRightCorner<3, 1>());
    }
    float xfm[12];
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 3; ++r) xfm[3 * c + r] = static_cast<float>(M(r, c));
    }
    rtcSetGeometryTransform(slot.instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(slot.instance);
  }
  rtcCommitScene(im.top);
  im.check("scene update");
  actor_bounds_.assign(actors_.size(), BoundingSphere{});
  for (std::size_t a = 0; a < actors_.size(); ++a) {
    if (actor_box[a].isEmpty()) continue;
    // Padded for Embree's single-precision transforms and hit tests.
    actor_bounds_[a].center = actor_box[a].center();
    actor_bounds_[a].radius_m = 0.5 * actor_box[a].diagonal().norm() * (1.0 + 1e-4) + 1e-3;
  }
}

namespace {

// One layer's query: rays from one origin, in a given order, as in Scene::intersect.
struct RayQuery {
  RTCScene scene;
  bool actors;
  const Eigen::Vector3f& origin;
  const Eigen::Vector3f* directions;
  const std::uint32_t* order;
  std::size_t count;
  float near_m, far_m;
  RayHit* hits;

  std::size_t index(std::size_t k) const { return order ? order[k] : k; }
  // Actors: only what is nearer than the hit so far (+inf: none).
  float tfar(std::size_t i) const { return actors ? std::min(far_m, hits[i].distance_m) : far_m; }
  void store(std::size_t i, unsigned geom, unsigned inst, float t, unsigned prim, float u, float v, float nx, float ny,
             float nz) const {
    RayHit& out = hits[i];
    if (geom == RTC_INVALID_GEOMETRY_ID) {
      if (!actors) out.distance_m = std::numeric_limits<float>::infinity();
      return;
    }
    out.distance_m = t;
    out.slot = actors ? inst : 0;
    out.primitive = prim;
    out.u = u;
    out.v = v;
    out.normal_object = Eigen::Vector3f(nx, ny, nz);
  }
};

// Packets of 16 consecutive rays, for a device that traces them natively (AVX-512): about 5 %
// faster than streams here, which convert to the same packets.
void intersect_packets(const RayQuery& q, RTCIntersectContext& context) {
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  // What every ray of the call shares; Embree writes only tfar and the hit.
  for (int k = 0; k < 16; ++k) {
    rh.ray.org_x[k] = q.origin.x();
    rh.ray.org_y[k] = q.origin.y();
    rh.ray.org_z[k] = q.origin.z();
    rh.ray.tnear[k] = q.near_m;
    rh.ray.time[k] = 0.0f;
    rh.ray.mask[k] = 0xFFFFFFFFu;
    rh.ray.id[k] = static_cast<unsigned>(k);
    rh.ray.flags[k] = 0;
  }
  for (std::size_t begin = 0; begin < q.count; begin += 16) {
    const std::size_t n = std::min<std::size_t>(16, q.count - begin);
    for (std::size_t k = 0; k < 16; ++k) {
      valid[k] = k < n ? -1 : 0;
      const std::size_t i = q.index(begin + std::min(k, n - 1));  // idle lanes repeat the last ray
      rh.ray.dir_x[k] = q.directions[i].x();
      rh.ray.dir_y[k] = q.directions[i].y();
      rh.ray.dir_z[k] = q.directions[i].z();
      rh.ray.tfar[k] = q.tfar(i);
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, q.scene, &context, &rh);
    for (std::size_t k = 0; k < n; ++k) {
      q.store(q.index(begin + k), rh.hit.geomID[k], rh.hit.instID[0][k], rh.ray.tfar[k], rh.hit.primID[k], rh.hit.u[k],
              rh.hit.v[k], rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]);
    }
  }
}

// Coherent ray streams: Embree cuts them into packets of the CPU's width.
void intersect_stream(const RayQuery& q, RTCIntersectContext& context) {
  constexpr std::size_t kChunk = 256;
  RTCRayHit rays[kChunk];
  for (std::size_t k = 0; k < std::min(kChunk, q.count); ++k) {
    RTCRay& ray = rays[k].ray;
    ray.org_x = q.origin.x();
    ray.org_y = q.origin.y();
    ray.org_z = q.origin.z();
    ray.tnear = q.near_m;
    ray.time = 0.0f;
    ray.mask = 0xFFFFFFFFu;
    ray.id = static_cast<unsigned>(k);
    ray.flags = 0;
  }
  for (std::size_t begin = 0; begin < q.count; begin += kChunk) {
    const std::size_t n = std::min(kChunk, q.count - begin);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = q.index(begin + k);
      RTCRayHit& rh = rays[k];
      rh.ray.dir_x = q.directions[i].x();
      rh.ray.dir_y = q.directions[i].y();
      rh.ray.dir_z = q.directions[i].z();
      rh.ray.tfar = q.tfar(i);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect1M(q.scene, &context, rays, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (std::size_t k = 0; k < n; ++k) {
      const RTCRayHit& rh = rays[k];
      q.store(q.index(begin + k), rh.hit.geomID, rh.hit.instID[0], rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v,
              rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    }
  }
}

}  // namespace

void Scene::intersect(SceneLayer layer, const Eigen::Vector3f& origin, const Eigen::Vector3f* directions,
                      const std::uint32_t* order, std::size_t count, float near_m, float far_m, RayHit* hits) const {
  const bool actors = layer == SceneLayer::kActors;
  if (count == 0 || (actors && actors_.empty())) return;
  // The static world is traced straight (no instance level, and its BVH is never rebuilt); the
  // actors through their top level, rebuilt each frame.
  const RayQuery query{actors ? impl_->top : impl_->static_scene, actors, origin, directions, order, count, near_m,
                       far_m, hits};
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  if (impl_->packets16) {
    intersect_packets(query, context);
  } else {
    intersect_stream(query, context);
  }
}

}  // namespace fmcw::sim
