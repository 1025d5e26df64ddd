#include "fmcw/eval/blind_zone_scene.hpp"

#include <cmath>

#include "fmcw/core/check.hpp"
#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/scene.hpp"
#include "fmcw/sim/trajectory.hpp"

namespace fmcw::eval {

namespace {
constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d pose(double x, double y, double z, double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

// Part index -> wheel radius for parts named wheel*, as the scenarios animate them.
std::vector<std::pair<int, double>> wheels_of(const sim::MeshAsset& asset) {
  std::vector<std::pair<int, double>> wheels;
  for (std::size_t p = 0; p < asset.parts.size(); ++p) {
    const sim::MeshPart& part = asset.parts[p];
    if (part.name.rfind("wheel", 0) != 0 || part.vertices.empty()) continue;
    float zmin = part.vertices[0].z(), zmax = zmin;
    for (const auto& v : part.vertices) {
      zmin = std::min(zmin, v.z());
      zmax = std::max(zmax, v.z());
    }
    wheels.emplace_back(static_cast<int>(p), 0.5 * static_cast<double>(zmax - zmin));
  }
  return wheels;
}
}  // namespace

void BlindZoneSceneParams::validate() const {
  FMCW_CHECK_ARG(box_size_m.minCoeff() > 0.0 && box_size_m.allFinite(), "blind zone: box size must be > 0, got (",
                 box_size_m.transpose(), ")");
  FMCW_CHECK_ARG(ground_clearance_m >= 0.0, "blind zone: ground_clearance_m must be >= 0, got ", ground_clearance_m);
  FMCW_CHECK_ARG(wall_gap_m > 0.5 * box_size_m.head<2>().norm(), "blind zone: wall_gap_m (", wall_gap_m,
                 ") must clear the actor");
  FMCW_CHECK_ARG(sensor_height_m > 0.0, "blind zone: sensor_height_m must be > 0, got ", sensor_height_m);
  FMCW_CHECK_ARG(num_threads >= 0, "blind zone: num_threads must be >= 0, got ", num_threads);
  measurement.validate();
}

core::RigModel blind_zone_rig(const BlindZoneSceneParams& params) {
  core::RigModel rig;
  core::HeadModel head;  // Table I defaults
  head.name = "front";
  head.T_rig_head = pose(0.0, 0.0, params.sensor_height_m, 0.0);
  rig.heads.push_back(head);
  return rig;
}

std::shared_ptr<const sim::MeshAsset> box_mesh_asset(const Eigen::Vector3d& half_extent_m, float reflectivity) {
  return std::make_shared<const sim::MeshAsset>(sim::box_mesh(half_extent_m.cast<float>(), reflectivity));
}

// The actor's motion: constant velocity at a heading the study sets between samples (never
// while the simulator runs, so the Trajectory contract, immutable during state() calls, holds).
class BlindZoneSimulator::ActorMotion : public sim::Trajectory {
 public:
  explicit ActorMotion(double distance_m) : distance_m_(distance_m) {}
  void set(double speed_mps, double heading_rad) {
    speed_mps_ = speed_mps;
    heading_rad_ = heading_rad;
  }
  sim::MotionState state(double t_s) const override {
    FMCW_CHECK_ARG(std::isfinite(t_s), "blind zone: time must be finite");
    const Eigen::Vector3d v(speed_mps_ * std::cos(heading_rad_), speed_mps_ * std::sin(heading_rad_), 0.0);
    sim::MotionState s;
    s.T_world_body = pose(distance_m_, 0.0, 0.0, heading_rad_);
    s.T_world_body.translation() += t_s * v;
    s.twist.linear_mps = v;
    return s;
  }

 private:
  double distance_m_;
  double speed_mps_ = 0.0;
  double heading_rad_ = 0.0;
};

BlindZoneSimulator::BlindZoneSimulator(const BlindZoneSceneParams& params, double distance_m)
    : motion_(std::make_shared<ActorMotion>(distance_m)), distance_m_(distance_m) {
  params.validate();
  FMCW_CHECK_ARG(std::isfinite(distance_m) && distance_m > 0.0, "blind zone: distance must be > 0, got ", distance_m);
  auto scene = std::make_shared<sim::Scene>();
  scene->add_ground_plane(0.0, distance_m + params.wall_gap_m + 100.0, 0.12f);

  sim::SceneObject wall;
  wall.name = "wall";
  wall.asset = box_mesh_asset(Eigen::Vector3d(0.5, 300.0, 30.0), 0.3f);
  wall.trajectory = sim::make_static_trajectory(pose(distance_m + params.wall_gap_m + 0.5, 0.0, 0.0, 0.0));
  scene->add(std::move(wall));

  sim::SceneObject actor;
  actor.name = "target";
  actor.class_name = "car";
  actor.actor_id = 1;
  if (params.actor_asset) {
    actor.asset = params.actor_asset;
    actor.wheels = wheels_of(*actor.asset);
  } else if (params.actor_mesh.empty()) {
    actor.asset = box_mesh_asset(0.5 * params.box_size_m, 0.4f);
    actor.T_body_asset.translation() = Eigen::Vector3d(0.0, 0.0, params.ground_clearance_m + 0.5 * params.box_size_m.z());
  } else {
    actor.asset = std::make_shared<const sim::MeshAsset>(sim::load_mesh_asset(params.actor_mesh, {}, 0.4f));
    actor.wheels = wheels_of(*actor.asset);
  }
  actor.trajectory = motion_;
  scene->add(std::move(actor));
  scene->build();

  sim::LidarSimulatorParams sp;
  sp.rig = blind_zone_rig(params);
  sp.measurement = params.measurement;
  sp.seed = params.seed;
  sp.num_threads = params.num_threads;
  simulator_ = std::make_unique<sim::LidarSimulator>(scene, sim::make_static_trajectory(Eigen::Isometry3d::Identity()), sp);
}

BlindZoneSimulator::~BlindZoneSimulator() = default;

core::Frame BlindZoneSimulator::simulate(double speed_mps, double phi_deg, std::uint64_t frame_index) {
  FMCW_CHECK_ARG(std::isfinite(speed_mps) && speed_mps >= 0.0, "blind zone: speed must be >= 0, got ", speed_mps);
  FMCW_CHECK_ARG(std::isfinite(phi_deg), "blind zone: phi must be finite");
  // The beam towards the actor's centre is horizontal +x (the actor stands straight ahead), so
  // phi is the actor's heading in the sensor's frame; its long axis is along its velocity.
  motion_->set(speed_mps, phi_deg * kDeg);
  return simulator_->simulate(frame_index, 0.0);
}

core::Frame simulate_blind_zone_sample(const BlindZoneSceneParams& params, double speed_mps, double distance_m,
                                       double phi_deg, std::uint64_t frame_index) {
  BlindZoneSimulator simulator(params, distance_m);
  return simulator.simulate(speed_mps, phi_deg, frame_index);
}

}  // namespace fmcw::eval
