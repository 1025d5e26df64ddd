// fmcw study blind-zone|threshold|object-points -o DIR: parameter studies, each with its own
// tables, metrics.json, figures and report.html.

#include <iostream>

#include "commands.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/eval/blind_zone_study.hpp"
#include "fmcw/eval/object_points_study.hpp"
#include "fmcw/eval/threshold_study.hpp"
#include "fmcw/eval/report_script.hpp"
#include "fmcw/eval/scenario_source.hpp"
#include "progress.hpp"

namespace fmcw::cli {

namespace {
struct StudyCommon {
  std::string output;
  bool no_figures = false;
  std::vector<std::string> methods;
  int threads = 0;
};

void add_common(CLI::App* cmd, StudyCommon& c) {
  cmd->add_option("-o,--output", c.output, "Report folder")->required();
  cmd->add_option("--methods", c.methods, "Methods, comma-separated (default: all; paper is always included)")
      ->delimiter(',')
      ->check(CLI::IsMember(core::MotionPipelineParams::preset_names()));
  cmd->add_option("--threads", c.threads, "Threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-figures", c.no_figures, "Write metrics.json and the tables only (no Python report)");
}

void finish_report(const StudyCommon& c) {
  if (!c.no_figures) {
    eval::run_report_script(eval::ReportScriptParams::from_environment(FMCW_REPORT_SCRIPT), c.output);
  }
  std::cerr << "report: " << c.output << "/" << (c.no_figures ? "metrics.json" : "report.html") << "\n";
}

struct BlindZoneOptions {
  StudyCommon common;
  eval::BlindZoneStudyParams params;
  std::vector<double> box = {4.5, 1.8, 1.5};
  std::vector<double> distances = {10.0, 20.0, 40.0};
  std::vector<double> small_box = {0.5, 0.5, 0.5};
  std::vector<double> small_distances = {40.0};
  bool no_small = false;
  std::string mesh;
  std::string measurement_model = "gaussian";
};

CLI::App* add_blind_zone(CLI::App* study, std::shared_ptr<BlindZoneOptions> opt) {
  CLI::App* cmd = study->add_subcommand("blind-zone", "Detection recall against heading (Eq. 15 Doppler blind band)");
  add_common(cmd, opt->common);
  eval::BlindZoneStudyParams& p = opt->params;
  cmd->add_option("--speeds", p.speeds_mps, "Actor speeds [m/s]")->delimiter(',')->capture_default_str();
  cmd->add_option("--distances", opt->distances, "Distances of the car-sized box [m]")->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--phi-step", p.phi_step_deg, "Coarse heading step [deg]")->capture_default_str();
  cmd->add_option("--fine-step", p.fine_step_deg, "Step near narrow theoretical bands [deg]")->capture_default_str();
  cmd->add_option("--refine", p.refine_iterations, "Bisection steps per band edge")->capture_default_str();
  cmd->add_option("--vth", p.velocity_threshold_mps, "Doppler threshold v_th [m/s]")->capture_default_str();
  cmd->add_option("--box", opt->box, "Car-sized box: length,width,height [m]")->delimiter(',')->expected(3)
      ->capture_default_str();
  cmd->add_option("--small-box", opt->small_box, "Small box (near-point target): length,width,height [m]")
      ->delimiter(',')->expected(3)->capture_default_str();
  cmd->add_option("--small-distances", opt->small_distances, "Distances of the small box [m]")->delimiter(',')
      ->capture_default_str();
  cmd->add_flag("--no-small", opt->no_small, "Sweep only the car-sized box (or the mesh)");
  cmd->add_option("--mesh", opt->mesh, "Mesh instead of the car-sized box (e.g. assets/car.gltf)");
  cmd->add_option("--clearance", p.scene.ground_clearance_m, "Box ground clearance [m]")->capture_default_str();
  cmd->add_option("--velocity-sigma", p.scene.measurement.velocity_sigma_mps, "Doppler noise [m/s] (Table I: 0.031)")
      ->capture_default_str();
  cmd->add_option("--range-sigma", p.scene.measurement.range_sigma_m, "Range noise [m] (Table I: 0.025)")
      ->capture_default_str();
  cmd->add_option("--seed", p.scene.seed, "Noise seed")->check(seed_validator())->capture_default_str();
  cmd->add_option("--measurement-model", opt->measurement_model,
                  "gaussian (Table I) or snr (noise and dropouts from reflectivity, incidence and range; "
                  "docs/SIMULATOR.md)")
      ->check(CLI::IsMember({"gaussian", "snr"}))
      ->capture_default_str();
  cmd->add_flag("!--no-noise-free", p.noise_free_too, "Skip the noise-free evaluation of each frame");
  return cmd;
}

int run_blind_zone(BlindZoneOptions& opt) {
  eval::BlindZoneStudyParams p = opt.params;
  p.scene.measurement.model = sim::measurement_model_from_string(opt.measurement_model);
  p.methods = opt.common.methods;
  p.scene.num_threads = opt.common.threads;
  p.targets = {{opt.mesh.empty() ? "car_box" : "mesh", Eigen::Vector3d(opt.box.at(0), opt.box.at(1), opt.box.at(2)),
                opt.distances, opt.mesh}};
  if (!opt.no_small) {
    p.targets.push_back({"small_box", Eigen::Vector3d(opt.small_box.at(0), opt.small_box.at(1), opt.small_box.at(2)),
                         opt.small_distances, ""});
  }
  p.validate();
  Progress progress("blind-zone study");
  const eval::BlindZoneStudyResult r = eval::run_blind_zone_study(p, [&](int done, int total) { progress.update(done, total); });
  eval::write_blind_zone_report(opt.common.output, r, FMCW_VERSION);
  std::cerr << "blind zone: " << r.samples.size() << " frames in " << r.seconds << " s\n";
  for (const eval::BlindZoneBand& b : r.bands) {
    if (b.method != r.methods.front()) continue;
    std::cerr << "  " << b.target << " v = " << b.speed_mps << " m/s, d = " << b.distance_m << " m, " << (b.noise ? "noise   " : "no noise")
              << ": measured " << (b.measured.found ? std::to_string(b.measured.lower_deg) + " .. " + std::to_string(b.measured.upper_deg) : std::string("none"))
              << "  theory " << b.theory.lower_deg << " .. " << b.theory.upper_deg << "\n";
  }
  finish_report(opt.common);
  return 0;
}
// Input of the dataset studies: a dataset folder or a scenario (simulated in memory).
struct SweepInput {
  std::string input = std::string(FMCW_SOURCE_DIR) + "/scenarios/intersection.yaml";
  int frames = 0;
  int stride = 1;
};

void add_input(CLI::App* cmd, SweepInput& in) {
  cmd->add_option("input", in.input, "Dataset folder or scenario YAML (simulated in memory)")->capture_default_str();
  cmd->add_option("--frames", in.frames, "Use only the first N frames")->check(CLI::PositiveNumber);
  cmd->add_option("--stride", in.stride, "Use every K-th frame")->check(CLI::PositiveNumber)->capture_default_str();
}

struct ThresholdOptions {
  StudyCommon common;
  SweepInput in;
  eval::ThresholdStudyParams params;
};

CLI::App* add_threshold(CLI::App* study, std::shared_ptr<ThresholdOptions> opt) {
  CLI::App* cmd = study->add_subcommand("threshold", "Sweep the Doppler threshold v_th: precision/recall trade-off");
  add_input(cmd, opt->in);
  cmd->add_option("-o,--output", opt->common.output, "Report folder")->required();
  cmd->add_option("--thresholds", opt->params.thresholds_mps, "v_th values [m/s]")->delimiter(',')->capture_default_str();
  cmd->add_option("--method", opt->params.method, "Method whose v_th is swept")
      ->check(CLI::IsMember(core::MotionPipelineParams::preset_names()))
      ->capture_default_str();
  cmd->add_option("--threads", opt->params.num_threads, "Threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-figures", opt->common.no_figures, "Write metrics.json and the tables only (no Python report)");
  return cmd;
}

int run_threshold(ThresholdOptions& opt) {
  eval::ThresholdStudyParams p = opt.params;
  p.stride = opt.in.stride;
  p.validate();
  const std::unique_ptr<eval::FrameSource> source = eval::open_frame_source(opt.in.input, opt.in.frames);
  say_notices(source->info().notices);
  Progress progress("threshold study");
  const eval::ThresholdStudyResult r = eval::run_threshold_study(
      *source, p, [&](std::size_t done, std::size_t total) { progress.update(static_cast<int>(done), static_cast<int>(total)); });
  eval::write_threshold_report(opt.common.output, r, FMCW_VERSION);
  std::cerr << "threshold study: " << r.frames_used << " frames x " << r.points.size() << " thresholds in " << r.seconds
            << " s\n";
  for (const eval::ThresholdPoint& pt : r.points) {
    std::cerr << "  v_th " << pt.threshold_mps << " m/s: precision " << pt.summary.motion.precision() << ", recall "
              << pt.summary.motion.recall() << ", accuracy " << pt.summary.motion.accuracy() << "\n";
  }
  finish_report(opt.common);
  return 0;
}

struct ObjectPointsOptions {
  StudyCommon common;
  SweepInput in;
  eval::ObjectPointsStudyParams params;
};

CLI::App* add_object_points(CLI::App* study, std::shared_ptr<ObjectPointsOptions> opt) {
  CLI::App* cmd = study->add_subcommand("object-points", "Sweep num_th^m (points per cluster): accuracy against time");
  add_input(cmd, opt->in);
  cmd->add_option("-o,--output", opt->common.output, "Report folder")->required();
  cmd->add_option("--caps", opt->params.caps, "num_th^m values (0 = all points)")->delimiter(',')->capture_default_str();
  cmd->add_option("--solvers", opt->params.solvers, "ceres and/or closed_form")->delimiter(',')
      ->check(CLI::IsMember({"ceres", "closed_form"}))
      ->capture_default_str();
  cmd->add_option("--threads", opt->params.num_threads, "Per-object threads (1 = serial timing)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("--no-figures", opt->common.no_figures, "Write metrics.json and the tables only (no Python report)");
  return cmd;
}

int run_object_points(ObjectPointsOptions& opt) {
  eval::ObjectPointsStudyParams p = opt.params;
  p.stride = opt.in.stride;
  p.validate();
  const std::unique_ptr<eval::FrameSource> source = eval::open_frame_source(opt.in.input, opt.in.frames);
  say_notices(source->info().notices);
  Progress progress("object-points study");
  const eval::ObjectPointsStudyResult r = eval::run_object_points_study(
      *source, p, [&](std::size_t done, std::size_t total) { progress.update(static_cast<int>(done), static_cast<int>(total)); });
  eval::write_object_points_report(opt.common.output, r, FMCW_VERSION);
  std::cerr << "object-points study: " << r.frames_used << " frames x " << r.points.size() << " settings in "
            << r.seconds << " s\n";
  for (const eval::ObjectPointsPoint& pt : r.points) {
    std::cerr << "  " << pt.solver << " cap " << pt.cap << ": median error >=200 px " << pt.summary.median_error_mps_ge200
              << " m/s, objects " << pt.mean_objects_ms << " ms/frame\n";
  }
  finish_report(opt.common);
  return 0;
}
}  // namespace

Action add_study_command(CLI::App& app) {
  CLI::App* study = app.add_subcommand("study", "Parameter studies: blind-zone, threshold, object-points");
  study->require_subcommand(1);
  auto blind = std::make_shared<BlindZoneOptions>();
  CLI::App* blind_cmd = add_blind_zone(study, blind);
  auto threshold = std::make_shared<ThresholdOptions>();
  CLI::App* threshold_cmd = add_threshold(study, threshold);
  auto points = std::make_shared<ObjectPointsOptions>();
  CLI::App* points_cmd = add_object_points(study, points);
  return [=]() -> int {
    if (blind_cmd->parsed()) return run_blind_zone(*blind);
    if (threshold_cmd->parsed()) return run_threshold(*threshold);
    if (points_cmd->parsed()) return run_object_points(*points);
    return 1;
  };
}

}  // namespace fmcw::cli
