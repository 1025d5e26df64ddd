#pragma once
// The blind-zone scene: a static sensor head, a ground plane, a far wall, and one actor moving
// at speed v with heading phi relative to the beam towards its centre (paper Eq. 15).

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/head_model.hpp"
#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/measurement_model.hpp"
#include "fmcw/sim/mesh_asset.hpp"

namespace fmcw::eval {

struct BlindZoneSceneParams {
  /// Actor box: length along its velocity, width, height [m] (a car body by default).
  Eigen::Vector3d box_size_m = Eigen::Vector3d(4.5, 1.8, 1.5);
  double ground_clearance_m = 0.25;  ///< gap between the box and the ground [m]
  /// A mesh instead of the box (any format assimp reads; the body frame is x forward, z up, on
  /// the ground); empty = the box. Parts named wheel* spin as they roll.
  std::string actor_mesh;
  /// The mesh already loaded (takes precedence over actor_mesh; spares a load per sample).
  std::shared_ptr<const sim::MeshAsset> actor_asset;
  double wall_gap_m = 15.0;      ///< the far wall stands this far behind the actor's centre [m]
  double sensor_height_m = 1.6;  ///< the head's mount height [m]; the head looks along +x
  sim::MeasurementParams measurement;  ///< Table I noise by default
  std::uint64_t seed = 1;              ///< noise seed (mixed with each sample's frame index)
  int num_threads = 0;                 ///< ray-casting threads (0 = OpenMP default)

  void validate() const;
};

/// One head of the paper's rig (40 x 30 deg, 0.2 x 0.2 deg, 150 m) at (0, 0, sensor_height_m),
/// looking along +x.
core::RigModel blind_zone_rig(const BlindZoneSceneParams& params);

/// The scene of one actor distance, built once and re-posed for each (speed, heading): only the
/// actor's trajectory changes between samples, so the BVHs are built once.
class BlindZoneSimulator {
 public:
  BlindZoneSimulator(const BlindZoneSceneParams& params, double distance_m);
  ~BlindZoneSimulator();
  BlindZoneSimulator(const BlindZoneSimulator&) = delete;
  BlindZoneSimulator& operator=(const BlindZoneSimulator&) = delete;

  /// See simulate_blind_zone_sample.
  core::Frame simulate(double speed_mps, double phi_deg, std::uint64_t frame_index);

 private:
  class ActorMotion;
  std::shared_ptr<ActorMotion> motion_;
  std::unique_ptr<sim::LidarSimulator> simulator_;
  double distance_m_;
};

/// Builds the scene for one sample and simulates it at t = 0. The actor (instance 1) stands on
/// the ground at horizontal distance distance_m straight ahead of the head and moves at
/// speed_mps with heading phi_deg measured from the horizontal beam towards its centre
/// (0 = straight away, 90 = across to the left, 180 = straight towards the sensor); its long
/// axis is along its velocity. frame_index picks the noise draw.
core::Frame simulate_blind_zone_sample(const BlindZoneSceneParams& params, double speed_mps, double distance_m,
                                       double phi_deg, std::uint64_t frame_index);

/// A closed box [-h, h] as a one-part mesh asset with outward triangles.
std::shared_ptr<const sim::MeshAsset> box_mesh_asset(const Eigen::Vector3d& half_extent_m, float reflectivity);

}  // namespace fmcw::eval
