// fmcw evaluate DATASET -o DIR: every motion method on every frame of a simulated dataset,
// compared with the ground truth; metrics.json, tables, figures and report.html.
// fmcw evaluate FOLDER -o DIR, FOLDER holding datasets in its subfolders: each evaluated in
// turn, one aggregate report (eval/aggregate_report.hpp).

#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "fmcw/eval/aevascenes_source.hpp"
#include "fmcw/eval/aggregate_report.hpp"
#include "fmcw/eval/evaluation_report.hpp"
#include "progress.hpp"

namespace fmcw::cli {

namespace {
struct EvaluateOptions {
  std::string dataset;
  std::string output;
  std::vector<std::string> methods;
  std::uint64_t seed = 0;
  int threads = 0;
  int frames = 0;
  double mot_iou = 0.5;
  bool no_figures = false;
};

// Runs `write`, which writes a report into `output`. If it fails and `output` did not exist
// before, the folder goes again when nothing is in it: an evaluation that stops on a bad frame
// leaves no empty report folder behind (one that was there before stays, as it was).
template <class Write>
int into_report_folder(const std::string& output, Write&& write) {
  std::error_code ec;
  const bool made = !std::filesystem::exists(output, ec);
  try {
    return write();
  } catch (...) {
    if (made && std::filesystem::is_empty(output, ec)) std::filesystem::remove(output, ec);
    throw;
  }
}

int write_evaluation_report(eval::FrameSource& source, const eval::EvaluationParams& params,
                            const std::string& output, bool no_figures) {
  eval::ReportOptions report;
  report.dir = output;
  report.tool_version = FMCW_VERSION;
  report.figures = !no_figures;
  report.script = eval::ReportScriptParams::from_environment(FMCW_REPORT_SCRIPT);
  Progress progress("evaluate " + source.info().scenario);
  eval::evaluate_to_report(
      source, params, report, [&](std::size_t done, std::size_t total) {
        progress.update(static_cast<int>(done), static_cast<int>(total));
      }, &std::cerr);
  std::cerr << "report: " << output << "/" << (no_figures ? "metrics.json" : "report.html") << "\n";
  return 0;
}
}  // namespace

int evaluate_and_report(eval::FrameSource& source, const eval::EvaluationParams& params,
                        const std::string& output, bool no_figures) {
  return into_report_folder(
      output, [&] { return write_evaluation_report(source, params, output, no_figures); });
}

namespace {
int write_folder_report(const std::string& folder, int frames, const eval::EvaluationParams& params,
                        const std::string& output, bool no_figures) {
  eval::ReportOptions report;
  report.dir = output;
  report.tool_version = FMCW_VERSION;
  report.figures = !no_figures;
  report.script = eval::ReportScriptParams::from_environment(FMCW_REPORT_SCRIPT);
  std::unique_ptr<Progress> progress;
  eval::AggregateCallbacks callbacks;
  callbacks.dataset_started = [&](std::size_t k, std::size_t n, const std::string& name) {
    progress = std::make_unique<Progress>("evaluate [" + std::to_string(k + 1) + "/" + std::to_string(n) + "] " + name);
  };
  callbacks.frame_progress = [&](std::size_t done, std::size_t total) {
    progress->update(static_cast<int>(done), static_cast<int>(total));
  };
  callbacks.notes = say_notices;
  eval::evaluate_folder_to_report(folder, frames, params, report, callbacks, &std::cerr);
  std::cerr << "report: " << output << "/" << (no_figures ? "metrics.json" : "report.html") << "\n";
  return 0;
}

int evaluate_folder_and_report(const std::string& folder, int frames,
                               const eval::EvaluationParams& params, const std::string& output,
                               bool no_figures) {
  return into_report_folder(
      output, [&] { return write_folder_report(folder, frames, params, output, no_figures); });
}
}  // namespace

Action add_evaluate_command(CLI::App& app) {
  auto opt = std::make_shared<EvaluateOptions>();
  CLI::App* cmd = app.add_subcommand("evaluate", "Evaluate the motion methods on a simulated dataset against its ground truth");
  cmd->add_option("dataset", opt->dataset,
                  "Dataset folder written by `fmcw simulate`, a folder of such datasets (one aggregate report), or "
                  "an AevaScenes sequence folder (SEQ/sequence.json)")
      ->required();
  cmd->add_option("-o,--output", opt->output, "Report folder")->required();
  cmd->add_option("--methods", opt->methods, "Methods to run, comma-separated (default: all; paper is always included)")
      ->delimiter(',')
      ->check(CLI::IsMember(core::MotionPipelineParams::preset_names()));
  cmd->add_option("--seed", opt->seed, "Seed of the methods' random subsampling")->check(seed_validator());
  cmd->add_option("--threads", opt->threads, "Threads for per-object estimation (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--frames", opt->frames, "Evaluate only the first N frames")->check(CLI::PositiveNumber);
  cmd->add_option("--mot-iou", opt->mot_iou,
                  "Point IoU at which a track may match an object in the tracking metrics (default 0.5)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_flag("--no-figures", opt->no_figures, "Write metrics.json and the tables only (no Python report)");
  return [opt] {
    eval::EvaluationParams params;
    params.methods = opt->methods;
    params.seed = opt->seed;
    params.num_threads = opt->threads;
    params.summary.mot_iou_threshold = opt->mot_iou;
    params.validate();
    std::error_code ec;
    if (eval::is_aevascenes_sequence(opt->dataset)) {
      eval::AevaScenesSource source(opt->dataset, opt->frames);
      say_notices(source.info().notices);
      return evaluate_and_report(source, params, opt->output, opt->no_figures);
    }
    if (std::filesystem::is_directory(opt->dataset, ec) && !eval::is_dataset_folder(opt->dataset)) {
      return evaluate_folder_and_report(opt->dataset, opt->frames, params, opt->output, opt->no_figures);
    }
    eval::DatasetSource source(opt->dataset, opt->frames);
    return evaluate_and_report(source, params, opt->output, opt->no_figures);
  };
}

}  // namespace fmcw::cli
