// Dataset labels against what they describe: every actor's box holds its pixels and is no looser
// than the tightest box around its surface at that instant, the box centre moves at the box
// velocity, every pixel carries a class (its actor's for actor pixels), and a bad class table is
// an error naming the file and key.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <set>

#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/scenario.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::sim {
namespace {

const std::string kSource = FMCW_SOURCE_DIR;

// Frames of a committed scenario, simulated with its Table I noise.
std::vector<core::Frame> frames_of(const std::string& scenario, std::initializer_list<int> frames,
                                   std::shared_ptr<Scene>* scene_out = nullptr) {
  const LoadedScenario loaded = load_scenario(kSource + "/scenarios/" + scenario + ".yaml");
  SimulationSetup setup = build_simulation(loaded, 2);
  LidarSimulator sim(setup.scene, setup.ego, setup.params);
  std::vector<core::Frame> out;
  for (const int k : frames) out.push_back(sim.simulate(static_cast<std::uint64_t>(k), loaded.scenario.frame_time_s(static_cast<std::uint64_t>(k))));
  if (scene_out) *scene_out = setup.scene;
  return out;
}

// A point in a box's own frame (the rig is level in these scenarios: the box turns about z).
Eigen::Vector3d in_box(const core::BoxTruth& b, const Eigen::Vector3d& p_rig) {
  return Eigen::AngleAxisd(-b.yaw_rad, Eigen::Vector3d::UnitZ()) * (p_rig - b.center_m);
}

// Every class of actor the project has, in front of a standing rig: vehicles crossing, turning
// and coming, walkers (procedural and skinned mid-stride), a cyclist.
std::string mixed_traffic() {
  const std::string a = kSource + "/assets/";
  return "frames: 40\nseed: 4\nmaterials: " + a + "materials.yaml\nego: {trajectory: {type: static, pose: {x: 0, y: 0}}}\nactors:\n"
         "  - {id: 1, class: car, mesh: " + a + "car.gltf, trajectory: {type: waypoints, points: [[12, 30], [12, -30]], speed_mps: 9}}\n"
         "  - {id: 2, class: bus, mesh: " + a + "bus.gltf, trajectory: {type: waypoints, points: [[26, -40], [26, 40]], speed_mps: 7}}\n"
         "  - {id: 3, class: truck, mesh: " + a + "truck.gltf, trajectory: {type: waypoints, points: [[60, 1.75], [30, 1.75], [20, -12]], speed_mps: 6}}\n"
         "  - {id: 4, class: van, mesh: " + a + "van.gltf, trajectory: {type: constant_turn_rate, pose: {x: 35, y: -10, yaw_deg: 60}, speed_mps: 5, yaw_rate_dps: 12}}\n"
         "  - {id: 5, class: cyclist, mesh: " + a + "cyclist.gltf, trajectory: {type: waypoints, points: [[16, -12], [16, 12]], speed_mps: 5}}\n"
         "  - {id: 6, class: pedestrian, mesh: " + a + "pedestrian.gltf, trajectory: {type: waypoints, points: [[8, 4], [8, -4]], speed_mps: 1.4}}\n"
         "  - {id: 7, class: pedestrian, mesh: " + a + "walker_skinned.gltf, animation: {clock: distance}, trajectory: {type: waypoints, points: [[9.5, -4], [9.5, 4]], speed_mps: 1.6}}\n"
         "  - {id: 8, class: pedestrian, mesh: " + a + "walker_skinned.gltf, trajectory: {type: waypoints, points: [[14, 2], [24, 2]], speed_mps: 1.2}}\n"
         "  - {id: 9, class: car, mesh: " + a + "car_keyframed.gltf, animation: {clock: distance}, trajectory: {type: waypoints, points: [[70, -1.75], [5, -1.75]], speed_mps: 10}}\n";
}

class Labels : public test::TempDirTest {};

TEST_F(Labels, EveryActorsBoxHoldsItsPixels) {
  // A pixel is inside when within 3 sigma of the range noise (0.025 m) of its box.
  const double grow = 3 * 0.025;
  const LoadedScenario loaded = load_scenario(write("mixed.yaml", mixed_traffic()));
  SimulationSetup setup = build_simulation(loaded, 2);
  LidarSimulator sim(setup.scene, setup.ego, setup.params);
  std::map<std::string, std::pair<long, long>> by_class;  // inside, all
  double worst = 1.0;
  for (std::uint64_t k = 0; k < 40; k += 3) {
    const core::Frame f = sim.simulate(k, loaded.scenario.frame_time_s(k));
    for (const core::ActorTruth& a : f.frame_truth->actors) {
      if (a.pixels == 0) continue;
      long inside = 0, all = 0;
      for (std::size_t i = 0; i < f.scan.size(); ++i) {
        if (f.truth->instance[i] != a.id) continue;
        const Eigen::Vector3d q = in_box(a.box, {f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]});
        inside += (q.cwiseAbs() - 0.5 * a.box.size_m).maxCoeff() <= grow ? 1 : 0;
        ++all;
      }
      ASSERT_EQ(all, a.pixels) << "frame " << k << " actor " << a.id;
      EXPECT_GE(inside, 0.995 * static_cast<double>(all)) << "frame " << k << " actor " << a.id << " (" << a.class_name << ")";
      worst = std::min(worst, static_cast<double>(inside) / static_cast<double>(all));
      by_class[a.class_name].first += inside;
      by_class[a.class_name].second += all;
    }
  }
  for (const char* c : {"car", "bus", "truck", "van", "cyclist", "pedestrian"}) {
    EXPECT_GT(by_class[c].second, 200) << c << " seen";
  }
  RecordProperty("worst_actor_frame_share_inside", std::to_string(worst));
}

TEST_F(Labels, BoxesAreTightAtTheirHeadingAndNoLooserThanTheTightestBox) {
  // The surface as the scene holds it at the frame's instant (skins deformed, wheels and limbs
  // where they are): in the box's own frame its extent is the box, to 0.1 mm, and the box is no
  // more than 10 % larger than the tightest box at any heading (a search in 0.25 deg steps) for
  // vehicles. A walker's box keeps the body's heading, so its swinging limbs may leave a box at
  // another heading tighter: 25 % is allowed there, and the worst is recorded.
  const LoadedScenario loaded = load_scenario(write("mixed.yaml", mixed_traffic()));
  SimulationSetup setup = build_simulation(loaded, 1);
  LidarSimulator sim(setup.scene, setup.ego, setup.params);
  double worst_vehicle = 0.0, worst_walker = 0.0;
  int checked = 0;
  for (const std::uint64_t k : {5u, 20u, 35u}) {
    const core::FrameTruth truth = *sim.simulate(k, loaded.scenario.frame_time_s(k)).frame_truth;
    const Eigen::Isometry3d T_rig_world = truth.ego.T_world_rig.inverse();
    for (std::size_t a = 0; a < setup.scene->actors().size(); ++a) {
      const core::BoxTruth& box = truth.actors[a].box;
      std::vector<Eigen::Vector3d> points;
      for (const auto& v : setup.scene->actor_surface(a)) points.push_back(T_rig_world * v);
      Eigen::AlignedBox3d own;
      for (const auto& p : points) own.extend(in_box(box, p));
      EXPECT_LT((own.center()).norm(), 1e-4) << "actor " << truth.actors[a].id;
      EXPECT_LT((own.sizes() - box.size_m).cwiseAbs().maxCoeff(), 1e-4) << "actor " << truth.actors[a].id;
      double tightest = std::numeric_limits<double>::infinity();
      for (double yaw = 0.0; yaw < M_PI; yaw += 0.25 * M_PI / 180.0) {
        Eigen::AlignedBox3d b;
        for (const auto& p : points) b.extend(Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()) * p);
        tightest = std::min(tightest, b.volume());
      }
      const double ratio = box.size_m.prod() / tightest;
      const bool walker = truth.actors[a].class_name == "pedestrian" || truth.actors[a].class_name == "cyclist";
      EXPECT_LE(ratio, walker ? 1.25 : 1.10) << "actor " << truth.actors[a].id << " (" << truth.actors[a].class_name << ")";
      (walker ? worst_walker : worst_vehicle) = std::max(walker ? worst_walker : worst_vehicle, ratio);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 27);
  RecordProperty("worst_vehicle_ratio", std::to_string(worst_vehicle));
  RecordProperty("worst_walker_ratio", std::to_string(worst_walker));
  std::cout << "box volume / tightest box volume, worst: vehicles " << worst_vehicle << ", walkers and cyclists " << worst_walker
            << "\n";
}

TEST_F(Labels, TheBoxCentreMovesAtTheBoxVelocity) {
  // A rigid box whose mesh sits off the body origin, turning at 0.4 rad/s: its box centre is not
  // its origin, so (c(t + h) - c(t - h)) / 2h = v + omega x (c - o) tells the two apart.
  auto scene = std::make_shared<Scene>();
  SceneObject o;
  o.name = "crate";
  o.class_name = "other_object";
  o.actor_id = 1;
  o.asset = std::make_shared<const MeshAsset>(box_mesh({2.0f, 1.0f, 0.75f}, 0.5f));
  o.T_body_asset.translation() = Eigen::Vector3d(1.5, 0.5, 0.75);
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.translation() = Eigen::Vector3d(15, -4, 0);
  o.trajectory = make_constant_turn_rate_trajectory(start, 8.0, 0.4);
  scene->add(std::move(o));
  scene->build();
  LidarSimulatorParams params;
  params.rig = core::RigModel::paper_rig();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), params);
  const double h = 1e-4;
  for (const double t : {0.3, 1.1}) {
    const core::BoxTruth a = sim.simulate(0, t - h).frame_truth->actors[0].box;
    const core::BoxTruth b = sim.simulate(0, t + h).frame_truth->actors[0].box;
    const core::BoxTruth c = sim.simulate(0, t).frame_truth->actors[0].box;
    const Eigen::Vector3d fd = (b.center_world_m - a.center_world_m) / (2 * h);
    EXPECT_LT((fd - c.velocity_mps).norm(), 1e-4) << "t " << t;
    EXPECT_GT((c.velocity_mps - Eigen::Vector3d(8.0 * std::cos(0.4 * t), 8.0 * std::sin(0.4 * t), 0)).norm(), 0.1)
        << "the centre's velocity differs from the origin's";
    EXPECT_NEAR(c.size_m.x(), 4.0, 1e-5);
    EXPECT_NEAR(c.size_m.y(), 2.0, 1e-5);
    EXPECT_NEAR(c.size_m.z(), 1.5, 1e-5);
    EXPECT_NEAR(c.yaw_world_rad, 0.4 * t, 1e-9);
  }
}

TEST_F(Labels, EveryPixelHasAClassAndActorPixelsTheirActors) {
  std::shared_ptr<Scene> scene;
  const std::vector<core::Frame> frames = frames_of("intersection", {20, 60, 110}, &scene);
  const core::ClassTable table = core::ClassTable::builtin();
  std::set<std::string> present;
  for (const core::Frame& f : frames) {
    ASSERT_EQ(f.truth->semantic_class.size(), f.scan.size());
    std::map<std::uint32_t, std::uint16_t> actor_class;
    for (const auto& a : f.frame_truth->actors) actor_class[a.id] = *table.find(a.class_name);
    for (std::size_t i = 0; i < f.scan.size(); ++i) {
      const std::uint16_t c = f.truth->semantic_class[i];
      if (!f.scan.valid[i]) {
        ASSERT_EQ(c, core::kUnlabeledClass);
        continue;
      }
      ASSERT_NE(table.get(c), nullptr) << "pixel " << i << " class " << c;
      ASSERT_NE(c, core::kUnlabeledClass) << "pixel " << i << " has a return but no class";
      present.insert(table.get(c)->name);
      if (f.truth->instance[i] != 0) {
        ASSERT_EQ(c, actor_class.at(f.truth->instance[i])) << "pixel " << i;
      }
    }
  }
  EXPECT_TRUE(present.count("road") || present.count("ground"));
  for (const char* c : {"building", "vegetation", "pole", "sidewalk", "trunk", "traffic_sign", "lane_marking"}) {
    EXPECT_TRUE(present.count(c)) << c;
  }
  EXPECT_TRUE(present.count("car") || present.count("truck") || present.count("bus") || present.count("van"));
}

class ClassTables : public test::TempDirTest {
 protected:
  std::string error(const std::string& scenario) {
    try {
      load_scenario(write("s.yaml", scenario));
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  }
};

TEST_F(ClassTables, UnknownClassesAndClashingIdsNameTheFileAndKey) {
  const std::string tree = kSource + "/assets/tree.gltf";
  write("classes.yaml", "classes: {forklift: 120}\nmeshes:\n  tree.gltf: {class: vegetation, parts: {bark: trunk}}\n");
  EXPECT_EQ(error("classes: classes.yaml\nstatic:\n  - {mesh: " + tree + "}\nactors:\n  - {id: 1, class: forklift, mesh: " + tree +
                  ", trajectory: {type: static}}\n"),
            "no error");
  EXPECT_NE(error("static:\n  - {mesh: " + tree + ", class: shrubbery}\n").find("s.yaml:2: static[0]: class: unknown class 'shrubbery'"),
            std::string::npos);
  EXPECT_NE(error("actors:\n  - {id: 1, class: robot, mesh: " + tree + ", trajectory: {type: static}}\n")
                .find("s.yaml:2: actors[0]: class: unknown class 'robot'"),
            std::string::npos);
  EXPECT_NE(error("ground: {class: lava}\n").find("s.yaml:1: ground.class: unknown class 'lava'"), std::string::npos);
  write("clash.yaml", "classes: {forklift: 10}\n");
  EXPECT_NE(error("classes: clash.yaml\n").find("clash.yaml:1: classes.forklift: class 'forklift': id 10 is taken by class 'car'"),
            std::string::npos);
  write("twice.yaml", "classes: {road: 120}\n");
  EXPECT_NE(error("classes: twice.yaml\n").find("twice.yaml:1: classes.road: class 'road' is defined already (id 40)"),
            std::string::npos);
  write("badpart.yaml", "meshes:\n  tree.gltf: {parts: {bark: wood}}\n");
  EXPECT_NE(error("classes: badpart.yaml\n").find("badpart.yaml:2: meshes.tree.gltf.parts.bark: unknown class 'wood'"),
            std::string::npos);
  // A part that names nothing in the mesh is said once, not dropped silently.
  write("leaves.yaml", "meshes:\n  tree.gltf: {class: vegetation, parts: {bark: trunk, leaves: vegetation}}\n");
  const LoadedScenario trees = load_scenario(write("t.yaml", "classes: leaves.yaml\nstatic:\n  - {mesh: " + tree +
                                                                   "}\n  - {mesh: " + tree + ", pose: {x: 5}}\n"));
  ASSERT_EQ(trees.notices.size(), 1u);
  EXPECT_NE(trees.notices[0].find("meshes.tree.gltf.parts: 'leaves' name no node or material of mesh"), std::string::npos)
      << trees.notices[0];
  write("typo.yaml", "mesh:\n  tree.gltf: {class: vegetation}\n");
  EXPECT_NE(error("classes: typo.yaml\n").find("unknown key 'mesh'"), std::string::npos);
  EXPECT_NE(error("classes: none.yaml\n").find("class table"), std::string::npos);
}

}  // namespace
}  // namespace fmcw::sim
