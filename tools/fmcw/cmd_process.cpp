// fmcw process INPUT -o DIR: run a motion method on one frame file or every frame of a folder
// (a dataset, or a folder of Aeva scans).

#include <filesystem>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "fmcw/core/ego_motion.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/frame_layout.hpp"
#include "fmcw/io/input_sequence.hpp"
#include "fmcw/io/output_folder.hpp"
#include "fmcw/io/results_writer.hpp"
#include "fmcw/io/tum_poses.hpp"
#include "input_flags.hpp"

namespace fmcw::cli {

namespace fs = std::filesystem;

namespace {
struct ProcessOptions {
  std::string output;
  std::string method = core::MotionPipelineParams::default_method();
  std::uint64_t seed = 0;
  int threads = 0;
  bool no_clouds = false;
  std::string poses;  ///< TUM trajectory to undo the ego compensation with
  InputFlags input;
};

// Brings an ego-compensated scan back to the sensor frame with the poses' motion at its stamp,
// so that the ego velocity is measured; says once on stderr what was done or left undone.
void apply_poses(io::InputFrame& in, const std::optional<core::PoseSeries>& poses,
                 const std::string& file, bool first, bool tracks) {
  core::Scan& scan = in.frame.scan;
  if (scan.velocity_frame == core::VelocityFrame::kSensor) {
    if (poses && first) std::cerr << "--poses ignored: the frames hold raw (sensor-frame) velocities\n";
    return;
  }
  if (!poses) {
    if (first) {
      std::cerr << "ego-compensated frames without --poses: the ego velocity is not measurable and "
                   "is reported as nan; objects and labels are estimated directly"
                << (tracks ? ", scan by scan: no tracks without the ego motion that carries them"
                           : "")
                << "\n";
    }
    return;
  }
  try {
    core::uncompensate_ego_velocity(scan, poses->ego_motion_at(scan.stamp_s));
  } catch (const std::invalid_argument& e) {
    throw core::InputError(file + ": --poses: " + e.what());
  }
}

// Runs the pipeline on every file, writing each frame's labelled cloud (recorded in `written`)
// and, once all are done, the tables.
void process_frames(const ProcessOptions& opt, io::InputSequence& files, core::MotionPipeline& pipeline,
                    const fs::path& label_dir, std::vector<fs::path>& written) {
  const std::optional<core::PoseSeries> poses =
      opt.poses.empty() ? std::nullopt : std::optional<core::PoseSeries>(io::read_tum_poses(opt.poses));
  io::ResultsWriter writer(opt.output);
  io::FrameLayoutCheck layout;
  for (std::size_t k = 0; k < files.size(); ++k) {
    io::InputFrame in = files.read(k);
    const std::string file = files.source(k);
    if (k == 0) {
      const std::string note = velocity_frame_note(in, opt.input);
      if (!note.empty()) std::cerr << note << "\n";
    }
    apply_poses(in, poses, file, k == 0, pipeline.params().track_objects);
    const core::Frame& frame = in.frame;
    // Organized frames bring their own shape and heads; a projected frame's come from the grid
    // options (and, for Aeva scans without --aeva-lines, rows from each scan's line indices).
    if (!in.projected) layout.check(frame.scan, file);
    if (in.projected) std::cerr << file << ": " << projection_summary(in) << "\n";
    const core::MotionEstimate est = pipeline.process(frame.scan, k);
    if (!est.ok()) throw std::runtime_error(file + ": " + est.message);
    writer.add(k, file, est);
    if (!opt.no_clouds) {
      // Labelled clouds are PCD whatever the input: an Aeva scan's labels go to NAME.pcd.
      const fs::path name = label_dir / (files.stem(k) + ".pcd");
      written.push_back(name);
      io::write_labelled_pcd(name.string(), frame.scan, est);
    }
    const Eigen::Vector3d& v = est.ego.velocity_mps;
    std::cerr << "[" << k + 1 << "/" << files.size() << "] " << file << ": " << est.clusters.size()
              << " moving clusters, ego (" << v.x() << ", " << v.y() << ", " << v.z() << ") m/s, "
              << est.timing.total_ms << " ms\n";
  }
  writer.finish();
}

int run_process(const ProcessOptions& opt) {
  const io::InputOptions input = opt.input.resolve();
  io::InputSequence files(opt.input.path, input);
  core::MotionPipelineParams params = core::MotionPipelineParams::preset(opt.method);
  params.seed = opt.seed;
  params.num_threads = opt.threads;
  core::MotionPipeline pipeline(params);
  const fs::path out_dir(opt.output);
  const fs::path label_dir = out_dir / "labels";
  io::refuse_output_over_inputs(opt.output, {opt.input.path});
  std::error_code ec;
  const bool made_out = !fs::exists(out_dir, ec);
  const bool made_labels = !opt.no_clouds && !fs::exists(label_dir, ec);
  std::optional<io::FolderLock> lock(std::in_place, opt.output);
  if (!opt.no_clouds) io::ensure_writable_directory(label_dir.string());
  // A frame that fails stops the run with its error; the labelled clouds written before it go
  // too (and the folders this run made, if nothing else is in them): no half-written output.
  std::vector<fs::path> written;
  try {
    process_frames(opt, files, pipeline, label_dir, written);
  } catch (...) {
    for (const fs::path& f : written) fs::remove(f, ec);
    lock.reset();
    if (made_labels && fs::is_empty(label_dir, ec)) fs::remove(label_dir, ec);
    if (made_out && fs::is_empty(out_dir, ec)) fs::remove(out_dir, ec);
    throw;
  }
  std::cerr << "wrote " << opt.output << "/{ego.csv,objects.csv,timing.csv,results.json}"
            << (opt.no_clouds ? "" : " and labels/*.pcd") << "\n";
  return 0;
}

}  // namespace

Action add_process_command(CLI::App& app) {
  auto opt = std::make_shared<ProcessOptions>();
  CLI::App* cmd = app.add_subcommand("process", "Run a motion method on a PCD file, a dataset folder, Aeva scans or an MCAP file");
  cmd->add_option("-o,--output", opt->output, "Output folder")->required();
  cmd->add_option("--method", opt->method, "Motion method")->check(CLI::IsMember(core::MotionPipelineParams::preset_names()));
  cmd->add_option("--seed", opt->seed, "Seed of the random subsampling")->check(seed_validator());
  cmd->add_option("--threads", opt->threads, "Threads for per-object estimation (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-clouds", opt->no_clouds, "Do not write labelled clouds");
  cmd->add_option("--poses", opt->poses,
                  "Ego poses (TUM: t x y z qx qy qz qw, rig in the world) to undo the ego compensation of "
                  "compensated frames, so that the ego velocity is measured");
  add_input_flags(cmd, opt->input);
  return [opt] { return run_process(*opt); };
}

}  // namespace fmcw::cli
