#include "fmcw/sim/lidar_simulator.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <thread>

#include "fmcw/core/check.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/sim/actor_boxes.hpp"
#include "fmcw/sim/actor_culling.hpp"
#include "fmcw/core/threads.hpp"
#include "beam_shading.hpp"

namespace fmcw::sim {

namespace {

constexpr int kBlockRows = 4;  // rows per scheduling block, cast together
constexpr int kTileCols = 4;   // columns per tile of a block
// Beam directions are single precision: a generous allowance when matching them to footprints.
constexpr double kCullMarginRad = 1e-5;

// The rig at one instant: each head's origin and its velocity V_ego + omega x r_mount.
struct RigPose {
  Eigen::Isometry3d T_world_rig;
  Eigen::Isometry3d T_rig_world;
  std::vector<Eigen::Vector3d> origin_world;
  std::vector<Eigen::Vector3d> origin_velocity_world;
};

RigPose rig_pose(const MotionState& ego, const core::RigModel& rig) {
  RigPose pose;
  pose.T_world_rig = ego.T_world_body;
  pose.T_rig_world = ego.T_world_body.inverse();
  const Eigen::Vector3d p_wr = ego.T_world_body.translation();
  for (const auto& head : rig.heads) {
    const Eigen::Vector3d o = ego.T_world_body * head.T_rig_head.translation();
    pose.origin_world.push_back(o);
    pose.origin_velocity_world.push_back(ego.twist.linear_mps + ego.twist.angular_rps.cross(o - p_wr));
  }
  return pose;
}

}  // namespace

void LidarSimulatorParams::validate() const {
  rig.validate();
  measurement.validate();
  FMCW_CHECK_ARG(min_range_m >= 0.0, "simulator: min_range_m must be >= 0, got ", min_range_m);
  FMCW_CHECK_ARG(moving_threshold_mps >= 0.0, "simulator: moving_threshold_mps must be >= 0, got ", moving_threshold_mps);
  FMCW_CHECK_LIMIT(num_threads >= 0 && num_threads <= core::kMaxThreads, "simulator: num_threads (--threads) must be in [0, ", core::kMaxThreads,
                   "] (0: all cores), got ", num_threads);
  FMCW_CHECK_ARG(time_slices >= 0, "simulator: time_slices must be >= 0, got ", time_slices);
  divergence.validate();
}

LidarSimulator::LidarSimulator(std::shared_ptr<Scene> scene, std::shared_ptr<const Trajectory> ego,
                               const LidarSimulatorParams& params)
    : scene_(std::move(scene)), ego_(std::move(ego)), params_(params), measurement_((params.validate(), params.measurement)) {
  FMCW_CHECK_ARG(scene_ != nullptr && ego_ != nullptr, "simulator: scene and ego trajectory are required");
  head_infos_ = params_.rig.head_infos();
  for (std::size_t a = 0; a < scene_->actors().size(); ++a) actor_ids_.emplace_back(scene_->actors()[a].actor_id, a);
  std::sort(actor_ids_.begin(), actor_ids_.end());
  directions_rig_ = params_.rig.directions_rig();
  directions_world_.resize(directions_rig_.size());
  pattern_ = make_sub_ray_pattern(params_.divergence.sub_rays);
  if (pattern_.offsets.size() > 1) {
    sub_directions_rig_.resize(directions_rig_.size() * pattern_.offsets.size());
    for (std::size_t i = 0; i < directions_rig_.size(); ++i) {
      sub_ray_directions(directions_rig_[i].cast<double>().normalized(), pattern_, params_.divergence.divergence_rad,
                         &sub_directions_rig_[i * pattern_.offsets.size()]);
    }
  }
}

int LidarSimulator::slice_count() const {
  if (!params_.motion_distortion) return 1;
  if (params_.time_slices > 0) return params_.time_slices;
  int widest = 0;
  for (const auto& info : head_infos_) widest = std::max(widest, info.cols());
  return widest;  // one slice per column: every beam at its own time
}

double LidarSimulator::beam_time_offset_s(std::size_t head, int local_col) const {
  if (!params_.motion_distortion) return 0.0;
  // Each head sweeps its columns left to right over one period; rows fire together.
  const double fraction = (local_col + 0.5) / head_infos_[head].cols();
  return fraction / params_.rig.heads[head].rate_hz;
}

void LidarSimulator::cast_static_block(int r0, int r1, const std::vector<std::pair<int, int>>& span,
                                       const std::vector<detail::HeadState>& heads, ThreadScratch& scratch) const {
  const int cols = params_.rig.cols();
  scratch.hits.resize(static_cast<std::size_t>(kBlockRows) * static_cast<std::size_t>(cols));
  const Eigen::Vector3f* directions = &directions_world_[static_cast<std::size_t>(r0) * static_cast<std::size_t>(cols)];
  scratch.tile_orders.resize(span.size());
  for (std::size_t h = 0; h < span.size(); ++h) {
    // Head by head, in tiles of kBlockRows x kTileCols beams: Embree traces consecutive rays
    // as one packet, and a square tile of beams stays together through the BVH better than a
    // strip of one row (about 15 % faster). The order is the same for every block as tall.
    TileOrder& tiles = scratch.tile_orders[h];
    if (tiles.rows != r1 - r0 || tiles.cols != span[h]) {
      tiles.rows = r1 - r0;
      tiles.cols = span[h];
      tiles.order.clear();
      for (int c0 = span[h].first; c0 < span[h].second; c0 += kTileCols) {
        for (int r = 0; r < tiles.rows; ++r) {
          for (int c = c0; c < std::min(span[h].second, c0 + kTileCols); ++c) {
            tiles.order.push_back(static_cast<std::uint32_t>(r * cols + c));
          }
        }
      }
    }
    const std::vector<std::uint32_t>& order = tiles.order;
    const Eigen::Vector3f origin = heads[h].origin_world.cast<float>();
    const auto near = static_cast<float>(params_.min_range_m);
    const auto far = static_cast<float>(params_.rig.heads[h].max_range_m);
    scene_->intersect(SceneLayer::kStatic, origin, directions, order.data(), order.size(), near, far,
                      scratch.hits.data());
  }
}

void LidarSimulator::cast_actor_block(int r0, int r1, const std::vector<std::pair<int, int>>& span,
                                      const std::vector<detail::HeadState>& heads,
                                      const std::vector<std::vector<ActorFootprint>>& footprints,
                                      ThreadScratch& scratch) const {
  const int cols = params_.rig.cols();
  const Eigen::Vector3f* directions = &directions_world_[static_cast<std::size_t>(r0) * static_cast<std::size_t>(cols)];
  for (std::size_t h = 0; h < span.size(); ++h) {
    const std::vector<std::uint32_t>& order = scratch.tile_orders[h].order;  // as cast_static_block left it
    // The actors only for tiles inside an actor's footprint, and not hidden behind static hits.
    scratch.actor_order.clear();
    for (std::size_t t = 0; t < order.size(); t += static_cast<std::size_t>((r1 - r0) * kTileCols)) {
      const int c0 = span[h].first + static_cast<int>(t) / (r1 - r0);
      const int c1 = std::min(span[h].second, c0 + kTileCols);
      const double nearest = nearest_actor_m(footprints[h], r0, r1, c0, c1);
      if (nearest == std::numeric_limits<double>::infinity()) continue;
      const std::size_t tile_end = std::min(order.size(), t + static_cast<std::size_t>((r1 - r0) * (c1 - c0)));
      float farthest = 0.0f;  // +inf where nothing static was hit
      for (std::size_t k = t; k < tile_end; ++k) farthest = std::max(farthest, scratch.hits[order[k]].distance_m);
      if (static_cast<double>(farthest) < nearest) continue;
      scratch.actor_order.insert(scratch.actor_order.end(), order.begin() + static_cast<std::ptrdiff_t>(t),
                                 order.begin() + static_cast<std::ptrdiff_t>(tile_end));
    }
    scene_->intersect(SceneLayer::kActors, heads[h].origin_world.cast<float>(), directions, scratch.actor_order.data(),
                      scratch.actor_order.size(), static_cast<float>(params_.min_range_m),
                      static_cast<float>(params_.rig.heads[h].max_range_m), scratch.hits.data());
  }
}

void LidarSimulator::cast_sub_rays(int r, const Eigen::Matrix3f& R_wr, const std::vector<std::pair<int, int>>& span,
                                   const std::vector<detail::HeadState>& heads,
                                   const std::vector<std::vector<ActorFootprint>>& footprints,
                                   ThreadScratch& scratch) const {
  // The sub-rays of one beam are neighbours already: a row at a time, in beam order.
  const std::size_t sub = pattern_.offsets.size();
  const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(params_.rig.cols());
  scratch.hits.resize(static_cast<std::size_t>(params_.rig.cols()) * sub);
  scratch.sub_dirs.resize(scratch.hits.size());
  for (std::size_t h = 0; h < span.size(); ++h) {
    const auto c0 = static_cast<std::size_t>(span[h].first);
    const auto count = static_cast<std::size_t>(span[h].second - span[h].first);
    for (std::size_t c = c0; c < c0 + count; ++c) {
      for (std::size_t j = 0; j < sub; ++j) scratch.sub_dirs[c * sub + j] = R_wr * sub_directions_rig_[(row + c) * sub + j];
    }
    const Eigen::Vector3f origin = heads[h].origin_world.cast<float>();
    const auto near = static_cast<float>(params_.min_range_m);
    const auto far = static_cast<float>(params_.rig.heads[h].max_range_m);
    scene_->intersect(SceneLayer::kStatic, origin, &scratch.sub_dirs[c0 * sub], nullptr, count * sub, near, far,
                      &scratch.hits[c0 * sub]);
    // The actors only for beams inside an actor's footprint (widened by the cone, see
    // simulate()) whose sub-rays are not all stopped nearer by the static world.
    scratch.actor_order.clear();
    for (std::size_t c = c0; c < c0 + count; ++c) {
      const double nearest = nearest_actor_m(footprints[h], r, r + 1, static_cast<int>(c), static_cast<int>(c) + 1);
      if (nearest == std::numeric_limits<double>::infinity()) continue;
      float farthest = 0.0f;  // +inf where nothing static was hit
      for (std::size_t j = 0; j < sub; ++j) farthest = std::max(farthest, scratch.hits[c * sub + j].distance_m);
      if (static_cast<double>(farthest) < nearest) continue;
      for (std::size_t j = 0; j < sub; ++j) scratch.actor_order.push_back(static_cast<std::uint32_t>(c * sub + j));
    }
    scene_->intersect(SceneLayer::kActors, origin, scratch.sub_dirs.data(), scratch.actor_order.data(),
                      scratch.actor_order.size(), near, far, scratch.hits.data());
  }
}

void LidarSimulator::prepare_rows(int r0, int r1, const std::vector<std::pair<int, int>>& span,
                                  const Eigen::Matrix3f* R_world_rig, core::Scan& scan) {
  if (R_world_rig == nullptr && !params_.motion_distortion) return;
  for (int r = r0; r < r1; ++r) {
    for (std::size_t h = 0; h < span.size(); ++h) {
      for (int c = span[h].first; c < span[h].second; ++c) {
        const std::size_t i = scan.index(r, c);
        if (R_world_rig != nullptr) {
          const float* m = R_world_rig->data();  // column-major
          const float x = directions_rig_[i].x(), y = directions_rig_[i].y(), z = directions_rig_[i].z();
          directions_world_[i] = Eigen::Vector3f(m[0] * x + m[3] * y + m[6] * z, m[1] * x + m[4] * y + m[7] * z,
                                                 m[2] * x + m[5] * y + m[8] * z);
        }
        if (params_.motion_distortion) {
          scan.time_offset_s[i] = static_cast<float>(beam_time_offset_s(h, c - head_infos_[h].col_begin));
        }
      }
    }
  }
}

core::Frame LidarSimulator::simulate(std::uint64_t frame_index, double t_s) {
  core::Frame frame;
  simulate(frame_index, t_s, frame);
  return frame;
}

void LidarSimulator::simulate(std::uint64_t frame_index, double t_s, core::Frame& frame) {
  const int rows = params_.rig.rows();
  const int cols = params_.rig.cols();
  const std::size_t n = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  if (frame.scan.rows != rows || frame.scan.cols != cols || frame.scan.size() != frame.scan.x_m.size()) {
    frame.scan = core::Scan::make_empty(rows, cols);
  }
  if (!frame.truth || frame.truth->range_m.size() != n) frame.truth = core::PixelGroundTruth::make_empty(n);
  frame.scan.heads = head_infos_;
  frame.scan.stamp_s = t_s;
  frame.scan.velocity_frame = params_.measurement.velocity_frame;
  if (params_.rig.scan_lines) {
    // Every head fires its rows together: a pixel's scan line is its row.
    frame.scan.line_index.resize(n);
    for (int r = 0; r < rows; ++r) {
      std::fill_n(frame.scan.line_index.begin() + static_cast<std::ptrdiff_t>(frame.scan.index(r, 0)), cols,
                  static_cast<std::uint16_t>(r));
    }
  } else {
    frame.scan.line_index.clear();
  }
  if (params_.motion_distortion) {
    frame.scan.time_offset_s.resize(n);
  } else {
    frame.scan.time_offset_s.clear();
  }
  core::Scan& scan = frame.scan;
  core::PixelGroundTruth& gt = *frame.truth;
  const std::uint64_t frame_seed = core::mix_seed(params_.seed, frame_index);
  const int threads = params_.num_threads > 0 ? params_.num_threads : omp_get_max_threads();
  const int slices = slice_count();
  const double moving_threshold_sq = params_.moving_threshold_mps * params_.moving_threshold_mps;
  // Per-thread scratch, kept between frames; pixel counts per actor restart at zero.
  if (scratch_.size() < static_cast<std::size_t>(threads)) scratch_.resize(static_cast<std::size_t>(threads));
  for (ThreadScratch& s : scratch_) s.pixels.assign(scene_->actors().size(), 0);
  const auto blocks = static_cast<std::size_t>((rows + kBlockRows - 1) / kBlockRows);
  if (block_order_.size() != blocks) {
    block_order_.resize(blocks);
    for (std::size_t b = 0; b < blocks; ++b) block_order_[b] = static_cast<int>(b);
    block_cost_.assign(blocks, 0.0);
  }

  for (int k = 0; k < slices; ++k) {
    // The columns of slice k in each head, and the instant they are cast at.
    std::vector<std::pair<int, int>> span(head_infos_.size());
    for (std::size_t h = 0; h < head_infos_.size(); ++h) {
      const int w = head_infos_[h].cols();
      span[h] = {head_infos_[h].col_begin + k * w / slices, head_infos_[h].col_begin + (k + 1) * w / slices};
    }
    const double t_slice = params_.motion_distortion
                               ? t_s + beam_time_offset_s(0, (k * head_infos_[0].cols() + head_infos_[0].cols() / 2) / slices)
                               : t_s;
    const RigPose pose = rig_pose(ego_->state(t_slice), params_.rig);
    const Eigen::Matrix3d R_wr = pose.T_world_rig.linear();
    const Eigen::Matrix3f R_wr_f = R_wr.cast<float>();
    // World beam directions: rotations keep unit vectors unit. A rig that did not turn since
    // the last frame keeps last frame's directions (all columns are one slice then).
    const bool rotate = slices > 1 || !(R_wr_f == last_rotation_);
    last_rotation_ = slices > 1 ? Eigen::Matrix3f::Constant(std::numeric_limits<float>::quiet_NaN()) : R_wr_f;
    std::vector<detail::HeadState> heads(span.size());
    for (std::size_t h = 0; h < span.size(); ++h) {
      heads[h] = {pose.origin_world[h], pose.origin_velocity_world[h], params_.rig.heads[h].T_rig_head.translation()};
    }
    const detail::ShadingContext shading{*scene_, measurement_, directions_world_.data(), directions_rig_.data(),
                                         R_wr, moving_threshold_sq, detail::PixelArrays(scan, gt)};
    std::vector<std::vector<ActorFootprint>> footprints(span.size());
    // The scene update: kMoving while the bodies move (one thread), kSkinning while any thread
    // that reaches it takes the next skin to deform and refit, kReady once the last skin's
    // thread has committed the scene and drawn the footprints.
    enum : int { kMoving, kSkinning, kReady, kFailed };
    std::atomic<int> scene_state{kMoving};
    std::atomic<std::size_t> next_skin{0}, skins_done{0};
    const std::size_t skins = scene_->skin_count();
    std::exception_ptr failure;
    const auto fail = [&] {
#pragma omp critical(fmcw_simulate_failure)
      if (!failure) failure = std::current_exception();
      scene_state.store(kFailed, std::memory_order_release);
    };
    const auto finish_update = [&] {
      scene_->end_time();
      for (std::size_t h = 0; h < span.size(); ++h) {
        // Sub-rays leave their beam's axis by up to half the cone: a generous margin.
        const double margin = kCullMarginRad + (pattern_.offsets.size() > 1 ? params_.divergence.divergence_rad : 0.0);
        actor_footprints(scene_->actor_bounds(), params_.rig.heads[h], head_infos_[h].col_begin,
                         pose.T_world_rig * params_.rig.heads[h].T_rig_head, margin, footprints[h]);
      }
      scene_state.store(kReady, std::memory_order_release);
    };
    // Deforms skins while there are any left; the thread that completes the last finishes the
    // update. Returns the state to wait on.
    const auto help_update = [&]() -> int {
      int state = scene_state.load(std::memory_order_acquire);
      while (state == kSkinning) {
        const std::size_t k = next_skin.fetch_add(1);
        if (k >= skins) break;
        try {
          scene_->update_skin(k);
          if (skins_done.fetch_add(1) + 1 == skins) finish_update();
        } catch (...) {
          fail();
        }
        state = scene_state.load(std::memory_order_acquire);
      }
      return state;
    };

#pragma omp parallel num_threads(threads)
    {
      // One thread moves the actors to the slice's instant while the others start on the static
      // world, which never moves: on two threads the update costs no time of its own. Skins are
      // shared out: each thread that reaches the actor layer first helps deform them.
#pragma omp single nowait
      {
        try {
          scene_->begin_time(t_slice);
          if (skins == 0) {
            finish_update();
          } else {
            scene_state.store(kSkinning, std::memory_order_release);
            help_update();
          }
        } catch (...) {
          fail();
        }
      }
      ThreadScratch& scratch = scratch_[static_cast<std::size_t>(omp_get_thread_num())];
      // Dynamic blocks of rows: sky rows cost little, rows near the horizon a lot. The costliest
      // blocks of the last frame go first, so that the last ones to finish are short. Each
      // (row, slice) draws from its own seed, so the result does not depend on which thread
      // takes it, nor on the order.
#pragma omp for schedule(dynamic, 1)
      for (std::size_t b = 0; b < block_order_.size(); ++b) {
        const auto started = std::chrono::steady_clock::now();
        const int r0 = block_order_[b] * kBlockRows;
        const int r1 = std::min(rows, r0 + kBlockRows);
        prepare_rows(r0, r1, span, rotate ? &R_wr_f : nullptr, scan);
        if (pattern_.offsets.size() == 1) cast_static_block(r0, r1, span, heads, scratch);
        int state = help_update();
        while (state == kMoving || state == kSkinning) {
          std::this_thread::yield();
          state = help_update();
        }
        if (state == kFailed) continue;
        if (pattern_.offsets.size() == 1) cast_actor_block(r0, r1, span, heads, footprints, scratch);
        for (int r = r0; r < r1; ++r) {
          core::Rng rng(core::mix_seed(frame_seed, static_cast<std::uint64_t>(r) * static_cast<std::uint64_t>(slices) +
                                                       static_cast<std::uint64_t>(k)));
          const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols);
          if (pattern_.offsets.size() == 1) {
            const RayHit* hits = scratch.hits.data() + static_cast<std::size_t>(r - r0) * static_cast<std::size_t>(cols);
            // The row's noise in one batch: two normals per return, in pixel order.
            std::size_t returns = 0;
            for (const auto& [c0, c1] : span) {
              for (int c = c0; c < c1; ++c) returns += std::isfinite(hits[c].distance_m) ? 1 : 0;
            }
            scratch.normals.resize(static_cast<std::size_t>(measurement_.normals_per_return()) * returns);
            rng.normals(scratch.normals.data(), scratch.normals.size());
            const double* normals = scratch.normals.data();
            for (std::size_t h = 0; h < span.size(); ++h) {
              normals = detail::shade_beams(shading, heads[h], row, span[h].first, span[h].second, hits, normals,
                                            scratch.pixels.data());
            }
            continue;
          }
          cast_sub_rays(r, R_wr_f, span, heads, footprints, scratch);
          const detail::SubRayShading sub_rays{pattern_, params_.divergence, scratch.sub_dirs.data(), actor_ids_};
          for (std::size_t h = 0; h < span.size(); ++h) {
            detail::shade_sub_ray_beams(shading, sub_rays, heads[h], row, span[h].first, span[h].second,
                                        scratch.hits.data(), rng, scratch.returns, scratch.pixels.data());
          }
        }
        block_cost_[static_cast<std::size_t>(block_order_[b])] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      }
    }
    if (failure) std::rethrow_exception(failure);
  }

  std::stable_sort(block_order_.begin(), block_order_.end(),
                   [this](int a, int b) { return block_cost_[static_cast<std::size_t>(a)] > block_cost_[static_cast<std::size_t>(b)]; });

  // Frame truth at the frame's stamp (with distortion, pixels carry their offsets from it).
  if (slices > 1) scene_->set_time(t_s);
  const MotionState ego = ego_->state(t_s);
  const Eigen::Matrix3d R_wr = ego.T_world_body.linear();
  const Eigen::Isometry3d T_rw = ego.T_world_body.inverse();
  core::FrameTruth truth;
  truth.stamp_s = t_s;
  truth.ego.T_world_rig = ego.T_world_body;
  truth.ego.velocity_mps = R_wr.transpose() * ego.twist.linear_mps;
  truth.ego.angular_velocity_rps = R_wr.transpose() * ego.twist.angular_rps;
  // Pixels per actor id (counted per actor by the threads; actors may share an id).
  const std::size_t actor_count = scene_->actors().size();
  std::vector<int> pixels(actor_count, 0);
  for (const ThreadScratch& s : scratch_) {
    for (std::size_t a = 0; a < actor_count; ++a) pixels[a] += s.pixels[a];
  }
  for (std::size_t a = 0; a < actor_count; ++a) {
    const SceneObject& actor = scene_->actors()[a];
    const MotionState& st = scene_->actor_state(a);
    core::ActorTruth at;
    at.id = actor.actor_id;
    at.class_name = actor.class_name;
    at.T_world_actor = st.T_world_body;
    at.position_rig_m = T_rw * st.T_world_body.translation();
    at.velocity_rig_mps = R_wr.transpose() * st.twist.linear_mps;
    at.angular_velocity_rig_rps = R_wr.transpose() * st.twist.angular_rps;
    at.pixels = 0;
    for (std::size_t b = 0; b < actor_count; ++b) {
      if (scene_->actors()[b].actor_id == actor.actor_id) at.pixels += pixels[b];
    }
    truth.actors.push_back(at);
  }
  // Boxes at the frame's instant, as the rig stands then.
  actor_boxes(*scene_, params_.rig, directions_rig_, ego.T_world_body, params_.min_range_m, threads, truth.actors);
  frame.frame_truth = std::move(truth);
}

}  // namespace fmcw::sim
