// fmcw bench: time the whole motion pipeline per method on a 600 x 150 synthetic frame.

#include <algorithm>
#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <omp.h>

#include "commands.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/scenario.hpp"

namespace fmcw::cli {

namespace {
struct BenchOptions {
  bool json = false;
  int objects = 20;
  int repeats = 0;  // 0: per-method default
  int threads = 1;
  std::string scenario = FMCW_SOURCE_DIR "/scenarios/intersection.yaml";
  int sim_threads = 0;
  int sim_frames = 50;
  int sequence_frames = 40;
  int sequence_warmup = 5;
  int sequence_repeats = 3;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// The tracked method (and robust beside it) over a short simulated sequence of the scenario, in
// time order, each frame timed after the first sequence_warmup (tracks are then established);
// median over all timed frames of sequence_repeats passes, each with a fresh pipeline.
void bench_sequence(const BenchOptions& opt, const sim::LoadedScenario& loaded, nlohmann::json& out) {
  if (opt.sequence_frames <= opt.sequence_warmup) return;
  sim::SimulationSetup setup = sim::build_simulation(loaded, opt.sim_threads);
  sim::LidarSimulator simulator(setup.scene, setup.ego, setup.params);
  std::vector<core::Scan> scans(static_cast<std::size_t>(opt.sequence_frames));
  core::Frame f;
  for (int k = 0; k < opt.sequence_frames; ++k) {
    const auto frame = static_cast<std::uint64_t>(k);
    simulator.simulate(frame, loaded.scenario.frame_time_s(frame), f);
    scans[static_cast<std::size_t>(k)] = f.scan;
  }
  for (const std::string method : {"robust", "tracked"}) {
    core::MotionPipelineParams params = core::MotionPipelineParams::preset(method);
    params.num_threads = opt.threads;
    std::vector<double> total, clustering, ego, objects;
    for (int rep = 0; rep < opt.sequence_repeats; ++rep) {
      core::MotionPipeline pipeline(params);
      for (int k = 0; k < opt.sequence_frames; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        const core::MotionEstimate est = pipeline.process(scans[static_cast<std::size_t>(k)], static_cast<std::uint64_t>(k));
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (k < opt.sequence_warmup) continue;
        total.push_back(ms);
        clustering.push_back(est.timing.clustering_ms);
        ego.push_back(est.timing.ego_ms);
        objects.push_back(est.timing.objects_ms);
      }
    }
    const double ms = median(total);
    const std::size_t timed = total.size();
    out["sequence"][method] = {{"scenario", loaded.scenario.name}, {"ms_per_frame", ms},
                               {"clustering_ms", median(clustering)}, {"ego_ms", median(ego)},
                               {"objects_ms", median(objects)}, {"frames_timed", timed},
                               {"warmup_frames", opt.sequence_warmup}, {"passes", opt.sequence_repeats}};
    if (!opt.json) {
      std::cout << method << " on " << loaded.scenario.name << " (sequence): " << ms << " ms per frame (median of "
                << timed << " frames after " << opt.sequence_warmup << " warm-up, " << opt.sequence_repeats
                << " passes); clustering " << median(clustering) << " ms, ego " << median(ego) << " ms, objects "
                << median(objects) << " ms\n";
    }
  }
}

int run_bench(const BenchOptions& opt) {
  const core::SyntheticSceneParams scene = core::benchmark_scene(opt.objects, 1);
  const core::Frame frame = core::render_synthetic_scan(scene);
  const double pixels = static_cast<double>(frame.scan.size());
  nlohmann::json out;
  out["frame"] = {{"rows", frame.scan.rows}, {"cols", frame.scan.cols}, {"valid_points", frame.scan.num_valid()},
                  {"moving_objects", opt.objects}};
  out["threads"] = opt.threads;
  for (const std::string method : {"fast", "paper", "robust"}) {
    core::MotionPipelineParams params = core::MotionPipelineParams::preset(method);
    params.num_threads = opt.threads;
    core::MotionPipeline pipeline(params);
    const int repeats = opt.repeats > 0 ? opt.repeats : (method == "fast" ? 200 : 30);  // fast: cheap, many runs
    std::vector<double> total, clustering, ego, objects;
    std::size_t clusters = 0;
    for (int r = -3; r < repeats; ++r) {  // three warm-up runs
      const auto t0 = std::chrono::steady_clock::now();
      const core::MotionEstimate est = pipeline.process(frame.scan, static_cast<std::uint64_t>(r + 3));
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (r < 0) continue;
      total.push_back(ms);
      clustering.push_back(est.timing.clustering_ms);
      ego.push_back(est.timing.ego_ms);
      objects.push_back(est.timing.objects_ms);
      clusters = est.clusters.size();
    }
    const double ms = median(total);
    out[method] = {{"points_per_s", pixels / (ms * 1e-3)}, {"ms_per_frame", ms},
                   {"clustering_ms", median(clustering)}, {"ego_ms", median(ego)},
                   {"objects_ms", median(objects)},       {"clusters", clusters},
                   {"repeats", repeats}};
    if (!opt.json) {
      std::cout << method << ": " << ms << " ms per frame (median of " << repeats << "), "
                << pixels / (ms * 1e-3) / 1e6 << " M points/s; clustering " << median(clustering) << " ms, ego "
                << median(ego) << " ms, objects " << median(objects) << " ms, " << clusters << " clusters\n";
    }
  }
  const sim::LoadedScenario loaded = sim::load_scenario(opt.scenario);
  say_notices(loaded.notices);
  bench_sequence(opt, loaded, out);
  // Simulation of one frame of the scenario's rig, scene update included.
  {
    sim::SimulationSetup setup = sim::build_simulation(loaded, opt.sim_threads);
    sim::LidarSimulator simulator(setup.scene, setup.ego, setup.params);
    const double rays = static_cast<double>(setup.params.rig.rows()) * setup.params.rig.cols();
    std::vector<double> ms;
    core::Frame f;
    for (int k = -2; k < opt.sim_frames; ++k) {
      const auto frame = static_cast<std::uint64_t>(std::max(k, 0));
      const auto t0 = std::chrono::steady_clock::now();
      simulator.simulate(frame, loaded.scenario.frame_time_s(frame), f);
      const double dt = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (k >= 0) ms.push_back(dt);
    }
    const double m = median(ms);
    out["simulate"] = {{"scenario", loaded.scenario.name}, {"rays_per_frame", rays}, {"ms_per_frame", m},
                       {"rays_per_s", rays / (m * 1e-3)}, {"frames", opt.sim_frames},
                       {"threads", opt.sim_threads > 0 ? opt.sim_threads : omp_get_max_threads()}};
    if (!opt.json) {
      std::cout << "simulate " << loaded.scenario.name << ": " << m << " ms per frame (median of " << opt.sim_frames
                << "), " << rays / (m * 1e-3) / 1e6 << " M rays/s\n";
    }
  }
  if (opt.json) std::cout << out.dump(2) << std::endl;
  return 0;
}
}  // namespace

Action add_bench_command(CLI::App& app) {
  auto opt = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "Time the motion methods (fast, paper, robust on one frame; robust and tracked over a sequence) and the simulator");
  cmd->add_flag("--json", opt->json, "Print JSON");
  cmd->add_option("--objects", opt->objects, "Moving objects in the frame")->check(CLI::Range(0, 1000));
  cmd->add_option("--repeats", opt->repeats, "Timed runs per method (default 200 fast, 30 paper)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", opt->threads, "Threads for per-object estimation")->check(CLI::PositiveNumber);
  cmd->add_option("--scenario", opt->scenario, "Scenario whose first frames are simulated and timed");
  cmd->add_option("--sim-threads", opt->sim_threads, "Ray-casting threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--sim-frames", opt->sim_frames, "Simulated frames timed")->check(CLI::PositiveNumber);
  cmd->add_option("--sequence-frames", opt->sequence_frames,
                  "Frames of the scenario the tracked method runs through in order (0: no sequence benchmark)")
      ->check(CLI::Range(0, 10000));
  cmd->add_option("--sequence-warmup", opt->sequence_warmup, "Leading frames of the sequence not timed")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--sequence-repeats", opt->sequence_repeats, "Passes over the sequence")->check(CLI::Range(1, 1000));
  return [opt] { return run_bench(*opt); };
}

}  // namespace fmcw::cli
