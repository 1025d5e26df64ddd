// Scenario loading: the shipped scenarios load, and bad input names file, line and key.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

#include "fmcw/core/errors.hpp"
#include "fmcw/sim/scenario.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::sim {
namespace {

namespace fs = std::filesystem;
const std::string kSource = FMCW_SOURCE_DIR;

class ScenarioFiles : public fmcw::test::TempDirTest {
 protected:
  // The scenario text must fail to load with an Error (the file's fault, unless said otherwise)
  // whose message holds every fragment.
  template <typename Error = core::FileError>
  void expect_error(const std::string& text, const std::vector<std::string>& fragments) {
    const std::string path = write("s.yaml", text);
    try {
      load_scenario(path);
      FAIL() << "expected an error for:\n" << text;
    } catch (const Error& e) {
      for (const auto& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
  std::string asset(const std::string& name) const { return kSource + "/assets/" + name; }
};

TEST_F(ScenarioFiles, ShippedIntersectionLoadsWithItsActorsAndRig) {
  const LoadedScenario s = load_scenario(kSource + "/scenarios/intersection.yaml");
  EXPECT_EQ(s.scenario.frames, 135);
  EXPECT_EQ(s.scenario.rig.cols(), 600);
  EXPECT_EQ(s.scenario.rig.rows(), 150);
  EXPECT_GE(s.scenario.actors.size(), 10u);
  EXPECT_EQ(s.scenario.ego.type, "static");
  const std::string yaml = scenario_to_yaml(s.scenario);
  EXPECT_NE(yaml.find("velocity_sigma_mps: 0.031"), std::string::npos) << yaml.substr(0, 2000);
}

TEST_F(ScenarioFiles, ThePapersFourScenariosLoadAndSimulate) {
  const std::pair<const char*, int> expected[] = {
      {"intersection", 135}, {"t_intersection", 98}, {"straight_road", 91}, {"turn_and_straight_road", 151}};
  for (const auto& [name, frames] : expected) {
    const LoadedScenario s = load_scenario(kSource + "/scenarios/" + name + ".yaml");
    EXPECT_EQ(s.scenario.frames, frames) << name;
    SimulationSetup setup = build_simulation(s, 0);
    LidarSimulator sim(setup.scene, setup.ego, setup.params);
    // Early, middle and late in the sequence.
    for (const int k : {5, frames / 2, frames - 5}) {
    const auto frame = static_cast<std::uint64_t>(k);
    const core::Frame f = sim.simulate(frame, s.scenario.frame_time_s(frame));
    EXPECT_GT(f.scan.num_valid(), f.scan.size() / 3) << name;
    int moving = 0, visible_actors = 0;
    for (std::size_t i = 0; i < f.scan.size(); ++i) moving += f.truth->moving[i];
    for (const auto& a : f.frame_truth->actors) visible_actors += a.pixels > 0;
    // Early in t_intersection its cars are still 60 m and more away (its walkers wait, still).
    EXPECT_GT(moving, k == 5 ? 20 : 200) << name << " frame " << k;
    EXPECT_GE(visible_actors, 2) << name << " frame " << k;
    }
  }
}

TEST_F(ScenarioFiles, EveryCommittedScenarioLoadsAndShowsItsActorsMoving) {
  // Every file of scenarios/ (one added later is covered as it lands): it loads, and its middle
  // frame shows the scene (a third of the beams hit something) and at least one actor in view
  // moving faster than 0.5 m/s, with pixels the truth labels moving.
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kSource + "/scenarios")) {
    if (e.path().extension() == ".yaml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 13u);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    const LoadedScenario s = load_scenario(file.string());
    ASSERT_GE(s.scenario.frames, 1);
    SimulationSetup setup = build_simulation(s, 0);
    LidarSimulator sim(setup.scene, setup.ego, setup.params);
    const auto k = static_cast<std::uint64_t>(s.scenario.frames / 2);
    const core::Frame f = sim.simulate(k, s.scenario.frame_time_s(k));
    EXPECT_GT(f.scan.num_valid(), f.scan.size() / 3);
    int moving = 0, moving_in_view = 0;
    for (std::size_t i = 0; i < f.scan.size(); ++i) moving += f.truth->moving[i];
    for (const auto& a : f.frame_truth->actors)
      moving_in_view += a.pixels > 0 && a.velocity_rig_mps.norm() > 0.5;
    EXPECT_GT(moving, 50);
    EXPECT_GE(moving_in_view, 1);
  }
}

TEST_F(ScenarioFiles, AssetsLoadWithTheirParts) {
  const ReflectivityTable table = {{"car_paint", 0.3f}, {"tire", 0.05f}};
  const MeshAsset car = load_mesh_asset(asset("car.gltf"), table, 0.2f);
  EXPECT_GE(car.find_part("wheel_fl"), 0);
  EXPECT_GE(car.find_part("body"), 0);
  EXPECT_NEAR(car.rest_bounds.sizes().x(), 4.5, 0.1);
  const MeshAsset ped = load_mesh_asset(asset("pedestrian.gltf"), table, 0.2f);
  const int thigh = ped.find_part("upper_leg_l");
  ASSERT_GE(thigh, 0);
  EXPECT_EQ(ped.parts[static_cast<std::size_t>(ped.find_part("lower_leg_l"))].parent, thigh);
}

TEST_F(ScenarioFiles, MalformedYamlNamesFileAndLine) {
  expect_error("name: x\nframes: [1, 2\n", {"s.yaml:", "malformed YAML"});
}

TEST_F(ScenarioFiles, UnknownKeyIsNamedWithItsPlace) {
  expect_error("name: x\nframs: 3\n", {"s.yaml:2: unknown key 'frams' in the top level", "accepted:", "frames"});
  expect_error("rig:\n  heads:\n    - {name: a, [2, 2]}\n", {"s.yaml:3: rig.heads[0]: a key must be a plain word, got a list"});
  expect_error("ego:\n  trajectory: {type: static, pose: {x: 1, yaww_deg: 3}}\n",
               {"unknown key 'yaww_deg' in ego.trajectory.pose"});
}

TEST_F(ScenarioFiles, WrongTypesAndOutOfRangeValuesAreRejected) {
  expect_error("frames: many\n", {"s.yaml:1: frames: expected a finite number, got 'many'"});
  expect_error("frames: 0\n", {"frames must be >= 1"});
  expect_error("frames: 2.5\n", {"s.yaml:1: frames: expected an integer, got '2.5'"});
  expect_error("seed: -3\n", {"s.yaml:1: seed: expected a non-negative integer, got '-3'"});
  expect_error("ground: 4\n", {"s.yaml:1: ground: expected a map of keys"});
  expect_error("static: {mesh: a.obj}\n", {"s.yaml:1: static: expected a list"});
  expect_error("rate_hz: -10\n", {"rate_hz must be in [0.001, 1e6] Hz"});
  expect_error("measurement: {range_sigma_m: -1}\n", {"measurement", "range_sigma_m must be in [0, 10] m, got -1"});
}

TEST_F(ScenarioFiles, RigErrorsNameTheHead) {
  expect_error("rig:\n  heads:\n    - {name: a, rate_hz: -10}\n", {"rig.heads[0]", "head 'a': rate must be > 0 Hz, got -10"});
  expect_error("rig:\n  heads:\n    - {name: a, resolution_deg: [0, 0.2]}\n", {"head 'a': angular resolution must be > 0"});
  expect_error("rig:\n  heads:\n    - {name: a, fov_deg: [400, 30]}\n", {"horizontal field of view must be in (0, 360]"});
  expect_error("rig:\n  heads:\n    - {name: a, fov_deg: [0.01, 30]}\n", {"gives no pixels"});
  expect_error("rig:\n  heads:\n    - {name: a, max_range_m: 0}\n", {"max range must be > 0"});
  // A resolution in the wrong unit: 6e12 pixels refused before anything is allocated.
  expect_error<core::LimitError>("rig:\n  heads:\n    - {name: a, fov_deg: [360, 170], resolution_deg: [0.0001, 0.0001]}\n",
                                 {"s.yaml:3: rig.heads[0]", "head 'a'", "pixels, more than the 16777216 a head may have"});
  expect_error("rig: nowhere.yaml\n", {"rig config", "nowhere.yaml' does not exist"});
  // A name the system rejects (longer than PATH_MAX) is reported like a missing file.
  expect_error("rig: " + std::string(5000, 'r') + "\n", {"s.yaml:1: rig", "does not exist"});
}

// The three kinds of error a scenario can end in: a parameter out of range in the file and a
// missing file are the file's fault (core::FileError), a scenario over the memory budget is a
// resource limit (core::LimitError, not a std::invalid_argument).
TEST_F(ScenarioFiles, ErrorsAreTypedByWhoseFaultTheyAre) {
  expect_error("rig:\n  heads:\n    - {name: a, max_range_m: 0}\n", {"s.yaml:3: rig.heads[0]", "max range must be > 0"});
  EXPECT_THROW(load_scenario(path("missing.yaml")), core::FileError);
  try {
    load_scenario(kSource + "/scenarios/straight_road.yaml", std::uint64_t{1} << 20);
    FAIL() << "expected the memory budget to refuse the scenario";
  } catch (const core::LimitError& e) {
    EXPECT_NE(std::string(e.what()).find("over the memory budget of 1 MB"), std::string::npos) << e.what();
    EXPECT_EQ(dynamic_cast<const std::invalid_argument*>(&e), nullptr);
  }
}

TEST_F(ScenarioFiles, MeshProblemsAreNamed) {
  expect_error("static:\n  - {mesh: missing.obj}\n", {"static[0].mesh", "missing.obj' does not exist"});
  write("garbage.obj", "this is not a mesh\n\x01\x02\x03");
  write("garbage.gltf", "{ not json");
  expect_error("static:\n  - {mesh: garbage.gltf}\n", {"s.yaml:2: static[0]", "garbage.gltf' cannot be read"});
  expect_error("static:\n  - {mesh: garbage.obj}\n", {"s.yaml:2: static[0]", "garbage.obj' cannot be read"});
  // No triangles: no faces at all (assimp refuses it), or only lines.
  write("empty.obj", "# no faces\nv 0 0 0\nv 1 0 0\n");
  expect_error("static:\n  - {mesh: empty.obj}\n", {"s.yaml:2: static[0]", "empty.obj' cannot be read", "no faces"});
  write("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  expect_error("static:\n  - {mesh: lines.obj}\n", {"s.yaml:2: static[0]", "lines.obj' holds no triangles"});
  // An asset missing from an actor, and a materials table that is not there.
  expect_error("actors:\n  - {id: 1, class: car, mesh: nocar.gltf, trajectory: {type: static}}\n",
               {"s.yaml:2: actors[0].mesh", "nocar.gltf' does not exist"});
  expect_error("materials: nomaterials.yaml\n", {"s.yaml:1: materials", "nomaterials.yaml"});
}

TEST_F(ScenarioFiles, TrajectoryProblemsAreNamed) {
  const std::string car = asset("car.gltf");
  expect_error("actors:\n  - {id: 1, class: car, mesh: " + car +
                   ", trajectory: {type: waypoints, points: [[0, 0]], speed_mps: 3}}\n",
               {"s.yaml:2: actors[0].trajectory", "need at least 2 points, got 1"});
  // Waypoint times follow from the path and its speeds: time stands still where two points
  // coincide or a segment has zero speed at both ends, and both are rejected.
  expect_error("actors:\n  - {id: 1, class: car, mesh: " + car +
                   ", trajectory: {type: waypoints, points: [[0, 0], [5, 0], [5, 0]], speed_mps: 3}}\n",
               {"s.yaml:2: actors[0].trajectory", "points 1 and 2 coincide"});
  expect_error("actors:\n  - {id: 1, class: car, mesh: " + car +
                   ", trajectory: {type: waypoints, points: [[0, 0], [5, 0], [9, 0]], speed_mps: [2, 0, 0]}}\n",
               {"s.yaml:2: actors[0].trajectory", "speeds at points 1"});
  expect_error("actors:\n  - {id: 1, class: car, mesh: " + car +
                   ", trajectory: {type: waypoints, points: [[0, 0], [5, 0]], speed_mps: -1}}\n",
               {"speeds must be finite and >= 0"});
  expect_error("ego:\n  trajectory: {type: waypoints, points: [[0, 0], [5, 0]], speed_mps: 2, start_time_s: .nan}\n",
               {"s.yaml:2: ego.trajectory"});
  expect_error("actors:\n  - {id: 1, class: car, mesh: " + car + ", trajectory: {type: teleport}}\n",
               {"unknown trajectory type 'teleport'"});
  expect_error("actors:\n  - {id: 0, class: car, mesh: " + car + ", trajectory: {type: static}}\n",
               {"actor id must be in [1, 4294967294]"});
  expect_error("actors:\n  - {id: 2, class: car, mesh: " + car + ", trajectory: {type: static}}\n  - {id: 2, class: car, mesh: " +
                   car + ", trajectory: {type: static}}\n",
               {"actor id 2 is already used by actors[0]"});
}

TEST_F(ScenarioFiles, ObjMeshesFromUsersLoad) {
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string path = write("s.yaml", "static:\n  - {mesh: tri.obj, pose: {x: 5}}\n");
  const LoadedScenario s = load_scenario(path);
  ASSERT_EQ(s.static_meshes.size(), 1u);
  EXPECT_EQ(s.static_meshes[0]->triangle_count(), 1u);
}

}  // namespace
}  // namespace fmcw::sim
