// The scenario generator: footprint clearance (with controls that break it), determinism, every
// layout, generated files that load and keep their clearance, config errors, waits at stop lines.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include "fmcw/sim/scenario.hpp"
#include "fmcw/sim/scenario_generator.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace fmcw::sim;

const std::string kConfigs = std::string(FMCW_SOURCE_DIR) + "/configs/";
const std::string kAssets = std::string(FMCW_SOURCE_DIR) + "/assets/";

std::array<Eigen::Vector2d, 4> rect(double x0, double y0, double x1, double y1) {
  return {Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y0), Eigen::Vector2d(x1, y1), Eigen::Vector2d(x0, y1)};
}

TEST(Clearance, RectangleGapKnownAnswers) {
  EXPECT_DOUBLE_EQ(rectangle_gap(rect(0, 0, 1, 1), rect(3, 0, 4, 1)), 2.0);           // side by side
  EXPECT_NEAR(rectangle_gap(rect(0, 0, 1, 1), rect(4, 5, 5, 6)), 5.0, 1e-12);          // corner to corner: 3-4-5
  EXPECT_EQ(rectangle_gap(rect(0, 0, 2, 2), rect(1, 1, 3, 3)), 0.0);                   // overlapping
  EXPECT_EQ(rectangle_gap(rect(0, 0, 4, 4), rect(1, 1, 2, 2)), 0.0);                   // one inside the other
  EXPECT_EQ(rectangle_gap(rect(0, -1, 4, 1), rect(1, -3, 2, 3)), 0.0);                 // a cross: no corner inside
  // A diamond (a square turned 45 degrees) with its corner 0.5 m from a side.
  const double h = std::sqrt(0.5);
  const std::array<Eigen::Vector2d, 4> diamond = {Eigen::Vector2d(1.5, 0.5), Eigen::Vector2d(1.5 + h, 0.5 + h),
                                                  Eigen::Vector2d(1.5 + 2 * h, 0.5), Eigen::Vector2d(1.5 + h, 0.5 - h)};
  EXPECT_NEAR(rectangle_gap(rect(0, 0, 1, 1), diamond), 0.5, 1e-12);
}

Footprint box_body(const std::string& what, std::shared_ptr<const Trajectory> motion, double half_length, double half_width) {
  Footprint f;
  f.what = what;
  f.motion = std::move(motion);
  f.box = Eigen::AlignedBox2d(Eigen::Vector2d(-half_length, -half_width), Eigen::Vector2d(half_length, half_width));
  return f;
}

// Two cars 4 x 2 m on crossing straight paths at 10 m/s: one along x through the origin, the
// other along y. With equal starts they meet at the origin at t = 5 s; with the second delayed,
// the gap at the frame times is known in closed form.
TEST(Clearance, CrossingPathsControl) {
  WaypointPath a;
  a.points_m = {Eigen::Vector3d(-50, 0, 0), Eigen::Vector3d(50, 0, 0)};
  a.speeds_mps = {10.0};
  std::vector<double> times;
  for (int k = 0; k <= 100; ++k) times.push_back(0.1 * k);
  const auto run = [&](double start_b) {
    WaypointPath b;
    b.points_m = {Eigen::Vector3d(0, -50, 0), Eigen::Vector3d(0, 50, 0)};
    b.speeds_mps = {10.0};
    b.start_time_s = start_b;
    return check_clearance({box_body("a", make_waypoint_trajectory(a), 2, 1), box_body("b", make_waypoint_trajectory(b), 2, 1)},
                           {}, times);
  };
  const ClearanceResult same = run(0.0);
  EXPECT_EQ(same.min_clearance_m, 0.0);  // the control: they collide
  EXPECT_FALSE(same.ok(0.5));
  EXPECT_EQ(same.first, "b");
  EXPECT_EQ(same.second, "a");
  // b 1 s later: when a's rear (x = 50 t - 52) has passed b's side (x = 1) b is still 8 m away;
  // the closest frame is where a's rear leaves x = 1, at t = 1.06 s... between frames. Check the
  // value against a brute force over the same frame times instead of a formula.
  const ClearanceResult late = run(1.0);
  double brute = 1e300;
  for (double t : times) {
    const double ax = -50 + 10 * t, by = t < 1.0 ? -50 : -50 + 10 * (t - 1.0);
    const double dx = std::max(0.0, std::abs(ax) - 2.0 - 1.0), dy = std::max(0.0, std::abs(by) - 1.0 - 2.0);
    brute = std::min(brute, std::hypot(dx, dy));
  }
  EXPECT_NEAR(late.min_clearance_m, brute, 1e-9);
  EXPECT_GT(late.min_clearance_m, 0.5);
  // A fixed pole 0.3 m beside a's path breaks it too.
  Footprint pole = box_body("pole", nullptr, 0.2, 0.2);
  pole.T_world_body.translation() = Eigen::Vector3d(10, 1.5, 0);
  const ClearanceResult near_pole = check_clearance({box_body("a", make_waypoint_trajectory(a), 2, 1)}, {pole}, times);
  EXPECT_NEAR(near_pole.min_clearance_m, 0.3, 1e-9);
  EXPECT_EQ(near_pole.second, "pole");
}

class Generator : public fmcw::test::TempDirTest {
 protected:
  static void SetUpTestSuite() {
    config_ = std::make_unique<GeneratorConfig>(GeneratorConfig::load(kConfigs + "generator.yaml"));
    assets_ = load_generator_assets(*config_);
  }
  static std::unique_ptr<GeneratorConfig> config_;
  static std::shared_ptr<const GeneratorAssets> assets_;
};
std::unique_ptr<GeneratorConfig> Generator::config_;
std::shared_ptr<const GeneratorAssets> Generator::assets_;

TEST_F(Generator, SameSeedSameFilesAndScenarioIndependentOfCount) {
  for (int k = 0; k < 6; ++k) {
    const GeneratedScenario a = generate_scenario(*config_, *assets_, 7, k);
    const GeneratedScenario b = generate_scenario(*config_, *assets_, 7, k);
    EXPECT_EQ(a.yaml, b.yaml);
    EXPECT_EQ(manifest_line(a.row), manifest_line(b.row));
    EXPECT_NE(a.yaml, generate_scenario(*config_, *assets_, 8, k).yaml);
  }
}

TEST_F(Generator, EveryLayoutAppearsAndEveryScenarioKeepsItsClearance) {
  std::set<std::string> layouts;
  for (int k = 0; k < 40; ++k) {
    const GeneratedScenario g = generate_scenario(*config_, *assets_, 1, k);
    layouts.insert(g.row.layout);
    EXPECT_TRUE(g.row.clearance_ok) << g.row.name;
    EXPECT_GE(g.row.min_clearance_m, 0.5) << g.row.name;
    EXPECT_GT(g.row.cars + g.row.vans + g.row.trucks + g.row.buses, 0) << g.row.name;
    EXPECT_GT(g.row.static_objects, 0) << g.row.name;
  }
  EXPECT_EQ(layouts, (std::set<std::string>{"straight_road", "junction", "t_junction", "roundabout", "highway"}));
}

// The written files, read back by the scenario loader, keep the clearance: checked from the
// loaded trajectories and the meshes' own footprints, not from the generator's numbers.
TEST_F(Generator, WrittenScenariosLoadAndKeepTheClearance) {
  int pedestrians = 0, cyclists = 0, parked = 0, stops = 0;
  for (int k = 0; k < 10; ++k) {
    const GeneratedScenario g = generate_scenario(*config_, *assets_, 3, k);
    const std::string file = write(g.row.name + ".yaml", g.yaml);
    const LoadedScenario loaded = load_scenario(file);
    EXPECT_EQ(loaded.scenario.name, g.row.name);
    EXPECT_EQ(static_cast<int>(loaded.scenario.statics.size()), g.row.static_objects);
    EXPECT_EQ(static_cast<int>(loaded.scenario.actors.size()),
              g.row.cars + g.row.vans + g.row.trucks + g.row.buses + g.row.cyclists + g.row.pedestrians + g.row.parked);
    const ScenarioFootprints f = scenario_footprints(loaded);
    std::vector<double> times;
    for (int i = 0; i < loaded.scenario.frames; ++i) times.push_back(loaded.scenario.frame_time_s(static_cast<std::uint64_t>(i)));
    const ClearanceResult r = check_clearance(f.moving, f.fixed, times);
    EXPECT_GE(r.min_clearance_m, 0.5) << g.row.name << ": " << r.first << " and " << r.second << " at " << r.time_s;
    EXPECT_NEAR(r.min_clearance_m, g.row.min_clearance_m, 2e-3) << g.row.name;
    pedestrians += g.row.pedestrians;
    cyclists += g.row.cyclists;
    parked += g.row.parked;
    stops += g.row.vehicles_stopping;
  }
  EXPECT_GT(pedestrians, 0);
  EXPECT_GT(cyclists, 0);
  EXPECT_GT(parked, 0);
  EXPECT_GT(stops, 0);
}

// The ground of a written scenario, read back, lies under every body at every frame with room
// to spare: 50 m at least between anything and its edge. (Once, a half size of 270 m was
// written as "27": the trailing zeros of a number without decimals were trimmed.)
TEST_F(Generator, TheGroundReachesFarBeyondEveryBodyOfTheScenario) {
  std::set<std::string> layouts;
  for (int k = 0; k < 12; ++k) {
    const GeneratedScenario g = generate_scenario(*config_, *assets_, 1, k);
    layouts.insert(g.row.layout);
    const LoadedScenario loaded = load_scenario(write(g.row.name + ".yaml", g.yaml));
    ASSERT_TRUE(loaded.scenario.ground) << g.row.name;
    const double half = loaded.scenario.ground_half_size_m;
    const ScenarioFootprints f = scenario_footprints(loaded);
    double farthest = 0.0;
    std::string what;
    const auto reach = [&](const Eigen::Vector3d& p, const std::string& name) {
      const double d = std::max(std::abs(p.x()), std::abs(p.y()));
      if (d > farthest) std::tie(farthest, what) = std::make_pair(d, name);
    };
    for (const Footprint& m : f.moving) {
      for (int i = 0; i < loaded.scenario.frames; ++i) {
        reach(m.motion->state(loaded.scenario.frame_time_s(static_cast<std::uint64_t>(i)))
                  .T_world_body.translation(),
              m.what);
      }
    }
    for (const Footprint& s : f.fixed) reach(s.T_world_body.translation(), s.what);
    EXPECT_GE(half, farthest + 50.0)
        << g.row.name << " (" << g.row.layout << "): ground half size " << half << " m, " << what
        << " " << farthest << " m from the origin";
    EXPECT_GT(farthest, 100.0) << g.row.name
                               << ": the scenario spans more than the ground of the error did";
  }
  EXPECT_EQ(layouts.count("highway"), 1u) << "a highway among the twelve";
}

// A scenario written by hand that breaks the clearance: the loader-based check finds it.
TEST_F(Generator, LoadedScenarioCheckFindsACollision) {
  const std::string file = write("bad.yaml",
                                 "name: bad\nframes: 30\nrate_hz: 10\nground: {enabled: false}\n"
                                 "ego:\n  trajectory: {type: static, pose: {x: -40, y: 0}}\n"
                                 "static:\n  - {mesh: " + kAssets + "pole.gltf, pose: {x: 10, y: -1.6}}\n"
                                 "actors:\n"
                                 "  - {id: 1, class: car, mesh: " + kAssets + "car.gltf, trajectory: {type: waypoints, points: [[0, 0], [60, 0]], speed_mps: 10}}\n");
  const LoadedScenario loaded = load_scenario(file);
  const ScenarioFootprints f = scenario_footprints(loaded);
  std::vector<double> times;
  for (int i = 0; i < 30; ++i) times.push_back(0.1 * i);
  const ClearanceResult r = check_clearance(f.moving, f.fixed, times);
  // The car is 1.84 m wide (0.92 either side of its path), the pole's post 0.44 m wide (0.22
  // either side of y = -1.6): a gap of 1.6 - 0.22 - 0.92 = 0.46 m as the car passes it.
  EXPECT_NEAR(r.min_clearance_m, 0.46, 1e-3);
  EXPECT_FALSE(r.ok(0.5));
  EXPECT_EQ(r.first, "actor 1 (car)");
  EXPECT_EQ(r.second, "static 0 (" + kAssets + "pole.gltf)");
}

TEST_F(Generator, MalformedConfigNamesFileLineAndKey) {
  const auto error_of = [&](const std::string& text) {
    const std::string file = write("gen.yaml", text);
    try {
      GeneratorConfig::load(file);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string base = "rigs: {" + kConfigs + "paper_rig.yaml: 1}\nassets: " + kAssets +
                           "\nmaterials: " + kAssets + "materials.yaml\nclasses: " + kConfigs + "classes.yaml\n";
  std::string e = error_of(base + "traffic:\n  vehicles_per_100m: [5, 1]\n");
  EXPECT_NE(e.find("gen.yaml:6"), std::string::npos) << e;
  EXPECT_NE(e.find("traffic.vehicles_per_100m"), std::string::npos) << e;
  e = error_of(base + "trafic: {}\n");
  EXPECT_NE(e.find("trafic"), std::string::npos) << e;
  e = error_of(base + "layouts: {junction: 1, motorway: 2}\n");
  EXPECT_NE(e.find("gen.yaml:5"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown name 'motorway'"), std::string::npos) << e;
  e = error_of(base + "frames: many\n");
  EXPECT_NE(e.find("gen.yaml:5"), std::string::npos) << e;
  EXPECT_NE(e.find("frames"), std::string::npos) << e;
  e = error_of("assets: " + kAssets + "\nmaterials: " + kAssets + "materials.yaml\nclasses: " + kConfigs + "classes.yaml\n");
  EXPECT_NE(e.find("rigs"), std::string::npos) << e;
  e = error_of(base + "ego: {stop_probability: 1.5}\n");
  EXPECT_NE(e.find("ego.stop_probability"), std::string::npos) << e;
  e = error_of("rigs: {no_such_rig.yaml: 1}\nassets: " + kAssets + "\nmaterials: " + kAssets +
               "materials.yaml\nclasses: " + kConfigs + "classes.yaml\n");
  EXPECT_NE(e.find("gen.yaml:1"), std::string::npos) << e;
  EXPECT_NE(e.find("no rig config"), std::string::npos) << e;
  const std::string bad_rig = write("bad_rig.yaml", "heads: [1, 2]\n");
  e = error_of("rigs: {" + bad_rig + ": 1}\nassets: " + kAssets + "\nmaterials: " + kAssets +
               "materials.yaml\nclasses: " + kConfigs + "classes.yaml\n");
  EXPECT_NE(e.find("gen.yaml:1"), std::string::npos) << e;
  EXPECT_NE(e.find("the rig config does not load"), std::string::npos) << e;
  EXPECT_NE(e.find("bad_rig.yaml"), std::string::npos) << e;
  e = error_of(base + "traffic: {vehicles_per_100m: [1, 2, 3]}\n");
  EXPECT_NE(e.find("traffic.vehicles_per_100m"), std::string::npos) << e;
}

TEST(WaypointWait, StandsStillAtTheStopForItsWaitThenGoesOn) {
  // 0 -> 20 m at 10 m/s braking uniformly to rest at x = 20 (4 s), a 3 s wait, then from rest
  // to 10 m/s over 20 m (4 s).
  WaypointPath p;
  p.points_m = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(20, 0, 0), Eigen::Vector3d(40, 0, 0)};
  p.speeds_mps = {10.0, 0.0, 10.0};
  p.waits_s = {0.0, 3.0, 0.0};
  const auto t = make_waypoint_trajectory(p);
  EXPECT_NEAR(t->state(4.0).T_world_body.translation().x(), 20.0, 1e-6);
  for (double at : {4.0, 5.5, 7.0}) {
    const MotionState s = t->state(at);
    EXPECT_NEAR(s.T_world_body.translation().x(), 20.0, 1e-6) << at;
    EXPECT_NEAR(s.twist.linear_mps.norm(), 0.0, 1e-6) << at;
  }
  // After the wait: uniform acceleration a = 100 / 40 = 2.5 m/s^2 from rest at t = 7 s.
  const MotionState s = t->state(9.0);
  EXPECT_NEAR(s.T_world_body.translation().x(), 20.0 + 0.5 * 2.5 * 4.0, 1e-6);
  EXPECT_NEAR(s.twist.linear_mps.x(), 2.5 * 2.0, 1e-6);
  EXPECT_NEAR(t->state(11.0).T_world_body.translation().x(), 40.0, 1e-6);
  // Finite-difference cross-check of the velocity during the wait and after it.
  for (double at : {6.0, 8.3}) {
    const double h = 1e-5;
    const double fd = (t->state(at + h).T_world_body.translation().x() - t->state(at - h).T_world_body.translation().x()) / (2 * h);
    EXPECT_NEAR(t->state(at).twist.linear_mps.x(), fd, 1e-5) << at;
  }
  // A wait where the body does not stop is refused, naming it.
  WaypointPath bad = p;
  bad.speeds_mps = {10.0, 5.0, 10.0};
  try {
    make_waypoint_trajectory(bad);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("wait 1"), std::string::npos) << e.what();
  }
}

}  // namespace

namespace {

class SetManifest : public fmcw::test::TempDirTest {
 protected:
  std::string error_of(const std::string& text) {
    const std::string file = write("manifest.csv", text);
    try {
      read_set_manifest(file);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  }
};

TEST_F(SetManifest, ReadsNamesAndFilesAndRefusesWhatCouldEscapeTheSet) {
  const std::string file = write("manifest.csv", "name,file,layout\na_1,scenarios/a_1.yaml,junction\nb-2,b.yaml,highway\n");
  const std::vector<SetEntry> rows = read_set_manifest(file);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].name, "b-2");
  EXPECT_EQ(rows[1].file, "b.yaml");
  std::string e = error_of("name,file\n../x,x.yaml\n");
  EXPECT_NE(e.find("manifest.csv:2: name must be"), std::string::npos) << e;
  e = error_of("name,file\nx,../../etc/passwd\n");
  EXPECT_NE(e.find("manifest.csv:2: file '../../etc/passwd' must be a path inside the set folder"), std::string::npos) << e;
  e = error_of("name,file\nx,/etc/passwd\n");
  EXPECT_NE(e.find("must be a path inside"), std::string::npos) << e;
  e = error_of("name,file\nx,a.yaml\nx,b.yaml\n");
  EXPECT_NE(e.find("manifest.csv:3: name 'x' repeats"), std::string::npos) << e;
  e = error_of("name,layout\nx,junction\n");
  EXPECT_NE(e.find("manifest.csv:1: no column 'file'"), std::string::npos) << e;
  e = error_of("name,file\nx,a.yaml,extra\n");
  EXPECT_NE(e.find("manifest.csv:2: 3 columns, expected 2"), std::string::npos) << e;
  e = error_of("name,file\n");
  EXPECT_NE(e.find("no scenario rows"), std::string::npos) << e;
  e = error_of("");
  EXPECT_NE(e.find("empty"), std::string::npos) << e;
}

}  // namespace
