#pragma once
// Procedural scenarios: road layouts with traffic, written as ordinary scenario files.
//
// A generator config (configs/generator.yaml documents every key) sets the layouts and their
// weights, the rigs, the measurement model and ranges for traffic density, speeds and class
// mix. Each generated scenario is drawn from its own seed (mix of the set's seed and the
// scenario's index), so scenario i is the same whatever the count, and the same seed gives the
// same files. Every actor's footprint keeps a clearance of at least `clearance_m` to every other
// actor's (the ego included) and to every static object's at every frame time: candidates that
// would come closer are drawn again or left out, and the clearance is measured again on the
// finished scenario and written to the manifest.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fmcw/sim/trajectory.hpp"

namespace fmcw::sim {

struct LoadedScenario;

struct ValueRange {
  double lo = 0.0;
  double hi = 0.0;
};

/// A choice among names with relative weights (> 0 for at least one; order as written).
struct WeightedNames {
  std::vector<std::string> names;
  std::vector<double> weights;
};

struct GeneratorConfig {
  std::string source_file;  ///< the config file ("" for built-in defaults)
  int frames = 100;
  double rate_hz = 10.0;
  WeightedNames layouts;  ///< straight_road, junction, t_junction, roundabout, highway
  WeightedNames rigs;     ///< rig config files, resolved to absolute paths
  std::string measurement_model = "gaussian";
  ValueRange range_sigma_m{0.02, 0.03};
  ValueRange velocity_sigma_mps{0.025, 0.04};
  std::string assets_dir;    ///< resolved folder of the project's meshes
  std::string materials;     ///< resolved materials table
  std::string classes;       ///< resolved class table
  double highway_barriers = 0.7;  ///< chance that a highway has barrier rows (median and edges)

  // Traffic. Densities are per 100 m of lane (vehicles, cyclists) or of sidewalk (pedestrians).
  ValueRange vehicles_per_100m{1.0, 4.0};
  ValueRange cyclists_per_100m{0.0, 0.6};
  ValueRange pedestrians_per_100m{2.0, 8.0};
  ValueRange parked_share{0.1, 0.5};  ///< share of parking slots taken
  WeightedNames vehicle_mix;          ///< car, van, truck, bus
  ValueRange urban_speed_mps{6.0, 14.0};
  ValueRange highway_speed_mps{20.0, 32.0};
  ValueRange pedestrian_speed_mps{0.8, 1.8};
  ValueRange cyclist_speed_mps{3.0, 7.0};
  double turn_probability = 0.5;         ///< a vehicle at a junction or roundabout turns
  double stop_probability = 0.4;         ///< a vehicle stops at the stop line before going on
  ValueRange stop_wait_s{0.5, 4.0};
  double lane_change_probability = 0.25; ///< on roads of two or more lanes per direction
  WeightedNames pedestrian_behaviour;    ///< walk, cross, wait, stand
  WeightedNames straight_road_lanes;     ///< lanes per direction "1", "2", "3"

  // The ego vehicle.
  ValueRange ego_speed_mps{5.0, 13.0};
  ValueRange ego_highway_speed_mps{20.0, 30.0};
  double ego_turn_probability = 0.5;
  double ego_stop_probability = 0.4;
  double ego_static_probability = 0.1;  ///< the ego waits at the stop line the whole time

  double clearance_m = 0.5;

  /// Reads a config; every key optional (defaults above), unknown keys, wrong types and
  /// out-of-range values are errors naming the file, line and key. Paths are relative to it.
  static GeneratorConfig load(const std::string& path);
};

/// One row of the manifest.
struct ManifestRow {
  std::string name;
  std::string file;  ///< relative to the set folder: scenarios/NAME.yaml
  std::string layout;
  std::uint64_t seed = 0;
  int frames = 0;
  double rate_hz = 0.0;
  std::string rig;  ///< file name of the rig config
  double range_sigma_m = 0.0;
  double velocity_sigma_mps = 0.0;
  int lanes_per_direction = 0;
  double lane_length_m = 0.0;      ///< driving lanes, both directions
  double sidewalk_length_m = 0.0;
  std::string ego_route;           ///< straight, left, right, lane_change, exit_1..3, static
  bool ego_stops = false;
  double ego_max_speed_mps = 0.0;
  int cars = 0, vans = 0, trucks = 0, buses = 0, cyclists = 0, pedestrians = 0, parked = 0;
  int static_objects = 0;
  int barriers = 0;  ///< barrier segments (10 m each), of static_objects
  int vehicles_stopping = 0, vehicles_turning = 0, lane_changes = 0;
  int pedestrians_crossing = 0, pedestrians_waiting = 0, pedestrians_standing = 0;
  double min_speed_mps = 0.0;   ///< cruise speeds of the moving actors
  double max_speed_mps = 0.0;
  double mean_speed_mps = 0.0;
  double actors_per_100m = 0.0;  ///< moving road users per 100 m of lane
  int rejected_candidates = 0;   ///< draws left out for coming closer than the clearance
  double min_clearance_m = 0.0;  ///< over every pair and every frame (the ego included)
  bool clearance_ok = false;
};

struct GeneratedScenario {
  ManifestRow row;
  std::string yaml;  ///< the scenario file's text
};

/// Footprints and meshes the generator places, read once from the config's assets folder.
class GeneratorAssets;
std::shared_ptr<const GeneratorAssets> load_generator_assets(const GeneratorConfig& config);

/// Scenario `index` of the set with seed `seed`, named `gen_<index, 5 digits>`.
GeneratedScenario generate_scenario(const GeneratorConfig& config, const GeneratorAssets& assets,
                                    std::uint64_t seed, int index);

/// The manifest's CSV header line and one row (no newline).
std::string manifest_header();
std::string manifest_line(const ManifestRow& row);

/// A scenario of a generated set, as its manifest lists it.
struct SetEntry {
  std::string name;  ///< letters, digits, '_', '-', '.'; the dataset folder's name
  std::string file;  ///< relative to the set folder, inside it
};
/// Reads a set's manifest.csv (the columns name and file; others are for people and reports).
/// std::invalid_argument naming the file and line: a missing file or column, a row of another
/// width, an unsafe name, a file outside the set, a repeated name, no rows.
std::vector<SetEntry> read_set_manifest(const std::string& path);

// ---- Clearance between moving footprints ---------------------------------------------------

/// A body's footprint: a rectangle in its own frame (x forward, y left), moved by a trajectory
/// (null: fixed at T_world_body).
struct Footprint {
  std::string what;  ///< for messages: "actor 3 (car)", "ego", "static 12 (tree.gltf)"
  std::shared_ptr<const Trajectory> motion;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::AlignedBox2d box;  ///< body frame [m]
};

struct ClearanceResult {
  double min_clearance_m = 1e300;  ///< smallest gap (0: touching or overlapping) over all pairs
  std::string first;               ///< the pair and time of the smallest gap
  std::string second;
  double time_s = 0.0;
  bool ok(double required_m) const { return min_clearance_m >= required_m; }
};

/// Gap between two rectangles in the plane (0 if they touch or overlap), each given by its
/// four corners in order.
double rectangle_gap(const std::array<Eigen::Vector2d, 4>& a, const std::array<Eigen::Vector2d, 4>& b);

/// The smallest gap over every pair of moving bodies and every moving body against every fixed
/// one, at each of the given times. Pairs of two fixed bodies are not checked.
ClearanceResult check_clearance(const std::vector<Footprint>& moving, const std::vector<Footprint>& fixed,
                                const std::vector<double>& times_s);

/// The footprints of a loaded scenario: every actor (its mesh's rest bounds), the ego (a car of
/// kEgoFootprint), and every static object's part below 4 m (what a vehicle or a walker could
/// touch: a pole's arm or a tree's crown above does not count).
struct ScenarioFootprints {
  std::vector<Footprint> moving;
  std::vector<Footprint> fixed;
};
ScenarioFootprints scenario_footprints(const LoadedScenario& loaded);
/// The ego's footprint [m] for clearance: a 4.6 x 1.9 m car centred on its origin.
inline constexpr double kEgoLength_m = 4.6;
inline constexpr double kEgoWidth_m = 1.9;
/// Static mesh parts at or above this height do not count for clearance [m].
inline constexpr double kFootprintHeight_m = 4.0;

}  // namespace fmcw::sim
