// fmcw export INPUT -o DIR --to ply|kitti|pcd: frames in the formats other tools read.

#include <filesystem>
#include <iostream>
#include <map>

#include "commands.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/ply.hpp"
#include "fmcw/io/semantic_kitti.hpp"
#include "fmcw/io/truth_tables.hpp"
#include "input_flags.hpp"

namespace fmcw::cli {

namespace fs = std::filesystem;

namespace {
struct ExportOptions {
  std::string output;
  std::string to;
  std::string color = "doppler";
  std::string labels = "auto";
  double doppler_scale_mps = 10.0;
  InputFlags input;
};

using ActorClasses = std::map<std::uint32_t, std::string>;

// Actor classes per frame from a dataset's objects.csv, so that ground-truth labels name cars,
// buses and pedestrians; empty maps for anything that is not a dataset folder.
std::vector<ActorClasses> dataset_actor_classes(const std::string& input, std::size_t frames) {
  std::vector<ActorClasses> classes(frames);
  const fs::path dir(input);
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || !fs::exists(dir / "objects.csv", ec) || !fs::exists(dir / "ego.csv", ec)) {
    return classes;
  }
  const auto truth = io::read_truth_tables((dir / "ego.csv").string(), (dir / "objects.csv").string());
  if (truth.size() != frames) {
    throw std::invalid_argument((dir / "ego.csv").string() + ": " + std::to_string(truth.size()) +
                                " frames in the tables, " + std::to_string(frames) + " frame files");
  }
  for (std::size_t k = 0; k < frames; ++k) {
    for (const auto& actor : truth[k].actors) classes[k][actor.id] = actor.class_name;
  }
  return classes;
}

// The cloud to export: a PCD as it is (every field, every type), other inputs as the organized
// scan the core would see.
io::PcdCloud read_cloud(const std::string& path, const io::InputOptions& input) {
  if (input.format == io::InputFormat::kPcd) return io::read_pcd(path);
  const io::InputFrame in = io::read_input_frame(path, input);
  std::cerr << path << ": " << projection_summary(in) << "\n";
  return io::pcd_from_frame(in.frame, false);
}

int run_export(const ExportOptions& opt) {
  const io::InputOptions input = opt.input.resolve();
  const io::LabelSource label_source = io::parse_label_source(opt.labels);
  if (!(opt.doppler_scale_mps > 0.0)) throw std::invalid_argument("--doppler-scale must be > 0 m/s");
  const std::vector<std::string> files = io::list_input_files(opt.input.path, input.format);
  const std::vector<ActorClasses> classes = dataset_actor_classes(opt.input.path, files.size());
  const fs::path out_dir(opt.output);
  io::ensure_writable_directory(opt.output);
  if (opt.to == "kitti") {
    io::ensure_writable_directory((out_dir / "velodyne").string());
    io::ensure_writable_directory((out_dir / "labels").string());
  }
  for (std::size_t k = 0; k < files.size(); ++k) {
    const std::string& file = files[k];
    const std::string stem = fs::path(file).stem().string();
    const io::PcdCloud cloud = read_cloud(file, input);
    std::string written;
    std::size_t points = 0;
    if (opt.to == "ply") {
      std::vector<io::Rgb> colors;
      if (opt.color == "doppler") colors = io::doppler_colors(cloud, opt.doppler_scale_mps, file);
      if (opt.color == "label") colors = io::label_colors(io::point_labels(cloud, label_source, classes[k], file));
      written = (out_dir / (stem + ".ply")).string();
      points = io::write_ply(written, cloud, colors);
    } else if (opt.to == "kitti") {
      const io::PointLabels labels = io::point_labels(cloud, label_source, classes[k], file);
      written = (out_dir / "velodyne" / (stem + ".bin")).string();
      points = io::write_semantic_kitti(written, (out_dir / "labels" / (stem + ".label")).string(), cloud, labels, file);
      written += " + .label";
    } else {
      written = (out_dir / (stem + ".pcd")).string();
      io::write_pcd(written, cloud);
      points = cloud.points();
    }
    std::cerr << "[" << k + 1 << "/" << files.size() << "] " << file << " -> " << written << " (" << points
              << " points)\n";
  }
  return 0;
}
}  // namespace

Action add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand("export", "Write frames as PLY, SemanticKITTI .bin/.label or PCD");
  cmd->add_option("-o,--output", opt->output, "Output folder")->required();
  cmd->add_option("--to", opt->to, "ply, kitti (velodyne/NAME.bin + labels/NAME.label) or pcd")
      ->required()
      ->check(CLI::IsMember({"ply", "kitti", "pcd"}));
  cmd->add_option("--color", opt->color, "ply: colour by doppler, label, or none")
      ->check(CLI::IsMember({"doppler", "label", "none"}));
  cmd->add_option("--labels", opt->labels, "Labels from: auto (estimate if the cloud has 'label', else truth), estimate, truth")
      ->check(CLI::IsMember({"auto", "estimate", "truth"}));
  cmd->add_option("--doppler-scale", opt->doppler_scale_mps, "ply: Doppler [m/s] shown fully red (+) or blue (-)");
  add_input_flags(cmd, opt->input);
  return [opt] { return run_export(*opt); };
}

}  // namespace fmcw::cli
