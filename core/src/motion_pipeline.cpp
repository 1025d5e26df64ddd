#include "fmcw/core/motion_pipeline.hpp"

#include "fmcw/core/check.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/core/threads.hpp"
#include "pipeline_internal.hpp"
#include "pipeline_workspace.hpp"

namespace fmcw::core {

void VelocityParams::validate() const {
  FMCW_CHECK_ARG(ego_max_points == 0 || ego_max_points >= 3,
                 "velocity: ego_max_points must be 0 (all) or >= 3, got ", ego_max_points);
  FMCW_CHECK_ARG(object_max_points == 0 || object_max_points >= 3,
                 "velocity: object_max_points must be 0 (all) or >= 3, got ", object_max_points);
  FMCW_CHECK_ARG(qr_condition_threshold >= 1.0, "velocity: qr_condition_threshold must be >= 1, got ",
                 qr_condition_threshold);
  FMCW_CHECK_ARG(ceres.max_iterations >= 1, "velocity: ceres.max_iterations must be >= 1");
}

void MotionPipelineParams::validate() const {
  segmentation.validate();
  velocity.validate();
  ego.validate();
  ego_prior.validate();
  instances.validate();
  FMCW_CHECK_ARG(moving_sigma > 0.0, "pipeline: moving_sigma must be > 0, got ", moving_sigma);
  FMCW_CHECK_ARG(range_noise_band_m >= 0.0, "pipeline: range_noise_band_m must be >= 0, got ",
                 range_noise_band_m);
  FMCW_CHECK_ARG(range_noise_bands >= 1, "pipeline: range_noise_bands must be >= 1, got ",
                 range_noise_bands);
  FMCW_CHECK_ARG(range_noise_min_pixels >= 1, "pipeline: range_noise_min_pixels must be >= 1, got ",
                 range_noise_min_pixels);
  FMCW_CHECK_ARG(range_noise_margin >= 1.0, "pipeline: range_noise_margin must be >= 1, got ",
                 range_noise_margin);
  FMCW_CHECK_ARG(min_static_fraction >= 0.0 && min_static_fraction <= 1.0, "pipeline: min_static_fraction must be in [0, 1], got ",
                 min_static_fraction);
  FMCW_CHECK_LIMIT(num_threads >= 0 && num_threads <= kMaxThreads, "pipeline: num_threads (--threads) must be in [0, ", kMaxThreads,
                 "] (0: all cores), got ", num_threads);
  FMCW_CHECK_ARG(max_weak_sigma_mps > 0.0, "pipeline: max_weak_sigma_mps must be > 0, got ", max_weak_sigma_mps);
  FMCW_CHECK_ARG(max_valid_sigma_mps > 0.0, "pipeline: max_valid_sigma_mps must be > 0, got ", max_valid_sigma_mps);
  FMCW_CHECK_ARG(!track_objects || approach == MotionApproach::kRobustEgo,
                 "pipeline: track_objects needs the robust-ego approach");
  tracking.validate();
}

MotionPipelineParams MotionPipelineParams::preset(const std::string& method) {
  MotionPipelineParams p;
  p.method = method;
  if (method == "paper") {
    p.segmentation.algorithm = RegionAlgorithm::kRegionGrowing;
    p.velocity.solver = VelocitySolver::kCeres;
    p.velocity.ego_max_points = 1000;
    p.velocity.object_max_points = 200;
  } else if (method == "robust") {
    p.approach = MotionApproach::kRobustEgo;
  } else if (method == "tracked") {
    p.approach = MotionApproach::kRobustEgo;
    p.track_objects = true;
    p.ego.lateral_velocity_sigma_mps = 0.1;  // a vehicle rig, its origin under the rear axle
  } else if (method == "fast") {
    p.velocity.solver = VelocitySolver::kClosedForm;
    p.velocity.ego_max_points = 0;
    p.velocity.object_max_points = 0;
  } else {
    std::string known;
    for (const auto& name : preset_names()) known += (known.empty() ? "" : ", ") + name;
    throw InputError(concat("unknown method '", method, "' (known: ", known, ")"));
  }
  return p;
}

std::vector<std::string> MotionPipelineParams::preset_names() { return {"paper", "fast", "robust", "tracked"}; }

std::string MotionPipelineParams::default_method() { return "tracked"; }

std::string to_string(MotionStatus status) {
  switch (status) {
    case MotionStatus::kOk: return "ok";
    case MotionStatus::kNoValidPoints: return "no_valid_points";
    case MotionStatus::kTooFewStaticPoints: return "too_few_static_points";
  }
  return "unknown";
}

PipelineBuffers::PipelineBuffers() : p_(std::make_unique<PipelineWorkspace>()) {}
PipelineBuffers::PipelineBuffers(const PipelineBuffers&) : PipelineBuffers() {}
PipelineBuffers& PipelineBuffers::operator=(const PipelineBuffers&) { return *this; }
PipelineBuffers::PipelineBuffers(PipelineBuffers&&) noexcept = default;
PipelineBuffers& PipelineBuffers::operator=(PipelineBuffers&&) noexcept = default;
PipelineBuffers::~PipelineBuffers() = default;

MotionPipeline::MotionPipeline(const MotionPipelineParams& params)
    : params_(params), segmenter_((params.validate(), params.segmentation)), tracker_(params.tracking) {}

MotionEstimate MotionPipeline::process(const Scan& scan, std::uint64_t frame_index) {
  MotionEstimate out = process_in_scan_frame(scan, frame_index);
  if (scan.velocity_frame == VelocityFrame::kEgoCompensated) {
    // The static world reads about 0: what the methods find is the residual of the
    // compensation, not the rig's motion. Object velocities are absolute already (their rows
    // are e . V_point); the ego velocity is not measurable from this scan and is not guessed.
    out.ego = VelocityEstimate{};
    out.ego_angular_velocity_rps = Eigen::Vector3d::Constant(VelocityEstimate::kNaN);
    out.ego_yaw_rate_estimated = false;
    out.ego_measurable = false;
  }
  return out;
}

MotionEstimate MotionPipeline::process_in_scan_frame(const Scan& scan, std::uint64_t frame_index) {
  if (params_.approach == MotionApproach::kRobustEgo) {
    MotionEstimate out = process_robust(scan, frame_index);
    if (params_.track_objects && scan.velocity_frame == VelocityFrame::kEgoCompensated) {
      // The ego motion that carries tracks from one scan to the next is not in such a scan (its
      // static world reads about 0 whatever the rig does): tracked against a rig taken to
      // stand, every object would seem to move by the ego's own motion. Objects are estimated
      // scan by scan instead; undo the compensation with known ego motion to track them.
      tracker_.reset();
    } else if (params_.track_objects) {
      const auto t0 = Clock::now();
      tracker_.update(scan, buffers_.get().beams, out);
      const double ms = ms_since(t0);
      out.timing.objects_ms += ms;
      out.timing.total_ms += ms;
    }
    // What one scan reports for an object without a track: a direction its fit hardly
    // observes zeroed. The tracker takes the fits as they are and caps their weak direction
    // itself; a track reports its own estimate.
    if (params_.planar_objects) {
      for (ClusterEstimate& ce : out.clusters) {
        if (ce.track_id == 0) zero_unobserved_direction(ce.velocity, params_.ego.noise_sigma_mps, params_.max_weak_sigma_mps);
      }
    }
    return out;
  }
  return process_regions(scan, frame_index);
}

}  // namespace fmcw::core
