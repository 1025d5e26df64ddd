#pragma once
// Casts every beam of a rig through an animated scene and makes an FMCW frame with ground truth.

#include <cstdint>
#include <memory>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/head_model.hpp"
#include "fmcw/sim/measurement_model.hpp"
#include "fmcw/sim/scene.hpp"

namespace fmcw::sim {

struct LidarSimulatorParams {
  core::RigModel rig = core::RigModel::paper_rig();
  MeasurementParams measurement;
  double min_range_m = 0.3;             ///< returns closer than this are not reported [m]
  double moving_threshold_mps = 0.1;    ///< ground truth "moving" above this absolute speed [m/s]
  std::uint64_t seed = 0;               ///< noise seed; frame f, row r draws from mix(seed, f, r)
  int num_threads = 0;                  ///< 0: OpenMP default

  void validate() const;
};

/// For each frame: moves the scene to the frame's time, casts all beams (Embree ray streams,
/// rows in parallel), and computes per hit the Doppler of Eq. 6 from the beam's own origin,
/// v = e . (V_point - V_origin), where V_origin = V_ego + omega_ego x r_mount and V_point is the
/// exact velocity of the surface hit (rigid parts: v + omega x r). The result is identical for
/// any thread count.
class LidarSimulator {
 public:
  LidarSimulator(std::shared_ptr<Scene> scene, std::shared_ptr<const Trajectory> ego, const LidarSimulatorParams& params);

  core::Frame simulate(std::uint64_t frame_index, double t_s);
  /// The same into an existing frame, reusing its buffers (every pixel is overwritten).
  void simulate(std::uint64_t frame_index, double t_s, core::Frame& frame);
  const LidarSimulatorParams& params() const { return params_; }

 private:
  std::shared_ptr<Scene> scene_;
  std::shared_ptr<const Trajectory> ego_;
  LidarSimulatorParams params_;
  MeasurementModel measurement_;
  std::vector<core::HeadInfo> head_infos_;
  std::vector<Eigen::Vector3f> directions_rig_;
  std::vector<Eigen::Vector3f> directions_world_;  // per frame
  std::vector<std::size_t> col_head_;              // image column -> head index
};

}  // namespace fmcw::sim
