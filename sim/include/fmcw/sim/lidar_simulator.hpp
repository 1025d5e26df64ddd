#pragma once
// Casts every beam of a rig through an animated scene and makes an FMCW frame with ground truth.

#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/head_model.hpp"
#include "fmcw/sim/beam_divergence.hpp"
#include "fmcw/sim/measurement_model.hpp"
#include "fmcw/sim/scene.hpp"

namespace fmcw::sim {

struct ActorFootprint;
namespace detail {
struct HeadState;
}

struct LidarSimulatorParams {
  core::RigModel rig = core::RigModel::paper_rig();
  MeasurementParams measurement;
  double min_range_m = 0.3;             ///< returns closer than this are not reported [m]
  double moving_threshold_mps = 0.1;    ///< ground truth "moving" above this absolute speed [m/s]
  std::uint64_t seed = 0;               ///< noise seed; frame f, row r draws from mix(seed, f, r)
  int num_threads = 0;                  ///< 0: OpenMP default
  /// Off (as in the paper): every beam at the frame's instant. On: each head sweeps its columns
  /// left to right over one period (1 / rate_hz), rows firing together; the scene (ego and
  /// every actor) is evaluated at each beam's own time, points are reported in the rig frame of
  /// that time, and Scan::time_offset_s holds each pixel's offset from the frame stamp.
  bool motion_distortion = false;
  /// With motion_distortion: instants per frame; 0 = one per column (exact), fewer trades
  /// accuracy for speed (beams of a slice share its middle instant).
  int time_slices = 0;
  /// Sub-rays per beam and how their returns merge (off by default: one ray per beam).
  BeamDivergenceParams divergence;

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
  /// Offset of a beam from the frame stamp [s] (0 without motion distortion).
  double beam_time_offset_s(std::size_t head, int local_col) const;
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
  Eigen::Matrix3f last_rotation_ = Eigen::Matrix3f::Constant(std::numeric_limits<float>::quiet_NaN());
  SubRayPattern pattern_;
  std::vector<Eigen::Vector3f> sub_directions_rig_;  // sub-rays of pixel i at [i * sub, (i + 1) * sub)
  std::vector<std::pair<std::uint32_t, std::size_t>> actor_ids_;  // (actor id, index into actors()), sorted
  // The order a block's beams in one head's columns are cast in, as indices into the block.
  struct TileOrder {
    int rows = 0;
    std::pair<int, int> cols{0, 0};
    std::vector<std::uint32_t> order;
  };
  // What each thread reuses from frame to frame.
  struct ThreadScratch {
    std::vector<RayHit> hits;
    std::vector<TileOrder> tile_orders;      // per head
    std::vector<std::uint32_t> actor_order;  // the beams traced against the actors
    std::vector<double> normals;  // a row's measurement noise
    std::vector<Eigen::Vector3f> sub_dirs;
    std::vector<SubReturn> returns;
    std::vector<int> pixels;  // per actor index
  };
  std::vector<ThreadScratch> scratch_;
  std::vector<int> block_order_;    // blocks of kBlockRows rows, costliest in the last frame first
  std::vector<double> block_cost_;  // per block, seconds in the last frame

  int slice_count() const;
  // Rows [r0, r1) of slice columns span: world directions (when R_world_rig is given) and beam
  // time offsets (with motion distortion).
  void prepare_rows(int r0, int r1, const std::vector<std::pair<int, int>>& span, const Eigen::Matrix3f* R_world_rig,
                    core::Scan& scan);
  // Casts rows [r0, r1) (at most kBlockRows) into scratch.hits, row-major by block row: the
  // static world, then the actors (after the scene has moved).
  void cast_static_block(int r0, int r1, const std::vector<std::pair<int, int>>& span,
                         const std::vector<detail::HeadState>& heads, ThreadScratch& scratch) const;
  void cast_actor_block(int r0, int r1, const std::vector<std::pair<int, int>>& span,
                        const std::vector<detail::HeadState>& heads,
                        const std::vector<std::vector<ActorFootprint>>& footprints, ThreadScratch& scratch) const;
  // Casts the sub-rays of row r into scratch.hits, along scratch.sub_dirs (world).
  void cast_sub_rays(int r, const Eigen::Matrix3f& R_wr, const std::vector<std::pair<int, int>>& span,
                     const std::vector<detail::HeadState>& heads,
                     const std::vector<std::vector<ActorFootprint>>& footprints, ThreadScratch& scratch) const;
};

}  // namespace fmcw::sim
