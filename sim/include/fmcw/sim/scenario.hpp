#pragma once
// Scenarios: a YAML description of the rig, the measurement model, the static world, the ego
// trajectory and the actors, loaded strictly and built into a Scene and a LidarSimulator.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fmcw/core/semantic_classes.hpp"
#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/scene.hpp"
#include "fmcw/sim/trajectory.hpp"

namespace fmcw::sim {

struct TrajectorySpec {
  std::string type = "static";  ///< static | constant_velocity | constant_turn_rate | waypoints
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< start pose (not for waypoints)
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  ///< constant_velocity, world frame
  double speed_mps = 0.0;                                  ///< constant_turn_rate
  double yaw_rate_rps = 0.0;                               ///< constant_turn_rate
  WaypointPath path;                                       ///< waypoints

  std::unique_ptr<Trajectory> make() const;
  double nominal_speed_mps() const;  ///< for gait frequency: typical speed along the trajectory
};

/// An actor's `animation:` block: which clip of its mesh it plays and how.
struct AnimationSpec {
  bool given = false;  ///< written in the scenario (else, with animate on, the first clip loops)
  std::string clip;    ///< as written (a name or an index); after loading, the clip's name
  int clip_index = -1; ///< resolved at load; -1: the actor plays no clip
  ClipPlayback playback;
};

/// The classes of a mesh file's triangles (a class table's `meshes:` entry).
struct MeshClasses {
  std::string class_name;                     ///< of every triangle not in parts; empty: none given
  std::map<std::string, std::string> parts;   ///< node or material name -> class
};

struct ObjectSpec {
  std::string name;
  std::string class_name = "static";
  std::uint32_t id = 0;           ///< 0 for static objects
  std::string mesh;               ///< as written in the scenario
  std::string mesh_path;          ///< resolved against the scenario's folder
  Eigen::Affine3d T_body_asset = Eigen::Affine3d::Identity();  ///< mesh_transform
  TrajectorySpec trajectory;
  /// Static objects: the class of their triangles (the entry's `class:`, else the class table's
  /// for the mesh file, else other_structure); actors: class_name.
  std::string semantic_class;
  bool animate = true;  ///< play the mesh's clip; spin parts named wheel*, walk pedestrians
  AnimationSpec animation;
};

struct Scenario {
  std::string name;
  std::string source_file;
  int frames = 1;
  double rate_hz = 10.0;
  double start_time_s = 0.0;
  std::uint64_t seed = 0;
  core::RigModel rig = core::RigModel::paper_rig();
  std::string rig_source;  ///< the config file the rig came from, or "inline"
  MeasurementParams measurement;
  double moving_threshold_mps = 0.1;
  bool motion_distortion = false;  ///< simulation.motion_distortion
  int time_slices = 0;             ///< simulation.time_slices
  double min_range_m = 0.3;        ///< simulation.min_range_m
  BeamDivergenceParams divergence; ///< simulation.beam_divergence (off: sub_rays 1)
  std::string materials_file;
  ReflectivityTable materials;
  float default_reflectivity = 0.3f;
  std::string classes_file;  ///< the `classes:` table, resolved; empty: the built-in classes only
  core::ClassTable classes = core::ClassTable::builtin();
  std::map<std::string, MeshClasses> mesh_classes;  ///< by mesh file name (without its folder)
  std::string ground_class = "ground";
  bool ground = true;
  double ground_z_m = 0.0;
  double ground_half_size_m = 300.0;
  float ground_reflectivity = 0.1f;
  TrajectorySpec ego;
  std::vector<ObjectSpec> statics;
  std::vector<ObjectSpec> actors;

  double frame_time_s(std::uint64_t frame) const { return start_time_s + static_cast<double>(frame) / rate_hz; }
};

/// Loads and checks a scenario. Errors (core::FileError) name the file, the line and the
/// key path: malformed YAML, unknown keys, wrong types, out-of-range values, missing meshes or
/// configs, meshes assimp cannot read or without triangles, bad trajectories, heads without
/// pixels. Meshes are loaded here so that every such error shows before anything is written.
struct LoadedScenario {
  Scenario scenario;
  std::vector<std::shared_ptr<const MeshAsset>> static_meshes;  ///< one per static object
  std::vector<std::shared_ptr<const MeshAsset>> actor_meshes;   ///< one per actor
  /// What the scenario's files hold that the simulation does not use (clips of actors that do
  /// not animate, morph targets, ...): one line each, for the caller to say once.
  std::vector<std::string> notices;
};
/// max_memory_bytes: the memory the scenario may take by its estimate (rig pixels and placed
/// triangles, counted before they are allocated); 0 is half of this machine's memory. Over it,
/// core::LimitError names the file, line and key and the estimate (so does a head of more than
/// HeadModel::kMaxPixels pixels).
LoadedScenario load_scenario(const std::string& path, std::uint64_t max_memory_bytes = 0);

/// Loads a rig config (the `rig:` file of a scenario): heads with mount, fov_deg, resolution_deg,
/// max_range_m, rate_hz.
core::RigModel load_rig(const std::string& path);

/// The scenario as resolved (defaults filled in, paths resolved), as YAML text.
std::string scenario_to_yaml(const Scenario& scenario);

/// Builds the Embree scene and the simulator for a loaded scenario.
struct SimulationSetup {
  std::shared_ptr<Scene> scene;
  std::shared_ptr<const Trajectory> ego;
  LidarSimulatorParams params;
};
SimulationSetup build_simulation(const LoadedScenario& loaded, int num_threads = 0);

}  // namespace fmcw::sim
