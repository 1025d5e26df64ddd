// fmcw export INPUT -o DIR --to ply|kitti|pcd|openpcdet: frames in the formats other tools read;
// --to mcap -o FILE.mcap: one MCAP file (export_mcap.cpp).

#include <filesystem>
#include <iostream>
#include <map>

#include "commands.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/io/aeva.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/openpcdet.hpp"
#include "fmcw/io/output_folder.hpp"
#include "fmcw/io/ply.hpp"
#include "fmcw/io/semantic_kitti.hpp"
#include "fmcw/io/truth_tables.hpp"
#include "export_mcap.hpp"
#include "fmcw/io/tum_poses.hpp"
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
  McapExportArgs mcap;
};

using ActorClasses = std::map<std::uint32_t, std::string>;

// The ground-truth tables of a dataset folder (ego.csv and objects.csv beside frames/), one
// FrameTruth per frame file; nothing for any other input.
struct DatasetTables {
  bool boxes = false;  ///< objects.csv has the box columns (datasets written before boxes lack them)
  std::vector<core::FrameTruth> frames;
};

DatasetTables read_dataset_tables(const std::string& input, std::size_t frames) {
  DatasetTables tables;
  const fs::path dir(input);
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || !fs::exists(dir / "objects.csv", ec) || !fs::exists(dir / "ego.csv", ec)) {
    return tables;
  }
  tables.frames = io::read_truth_tables((dir / "ego.csv").string(), (dir / "objects.csv").string());
  tables.boxes = io::objects_csv_has_boxes((dir / "objects.csv").string());
  if (tables.frames.size() != frames) {
    throw core::FileError((dir / "ego.csv").string() + ": " + std::to_string(tables.frames.size()) +
                          " frames in the tables, " + std::to_string(frames) + " frame files");
  }
  return tables;
}

// Actor classes per frame, so that ground-truth labels of frames without the field `class` name
// cars, buses and pedestrians; empty maps for anything that is not a dataset folder.
std::vector<ActorClasses> actor_classes(const DatasetTables& tables, std::size_t frames) {
  std::vector<ActorClasses> classes(frames);
  for (std::size_t k = 0; k < tables.frames.size() && k < frames; ++k) {
    for (const auto& actor : tables.frames[k].actors) classes[k][actor.id] = actor.class_name;
  }
  return classes;
}

// --to openpcdet takes its boxes from a dataset's objects.csv: anything else is refused before
// a file is written, naming the input and what it lacks.
void require_dataset_with_boxes(const InputFlags& flags, const DatasetTables& tables) {
  const std::string& input = flags.path;
  const std::string needs =
      "--to openpcdet needs a dataset written by fmcw simulate (dataset.yaml, ego.csv and objects.csv with the box "
      "columns, beside frames/)";
  if (flags.format != "pcd") {
    throw core::InputError(input + ": --to openpcdet reads a dataset's own frames (--format pcd), not --format " +
                           flags.format);
  }
  const fs::path dir(input);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw core::FileError(input + ": not a dataset folder (no objects.csv, no boxes): " + needs);
  }
  for (const char* table : {"dataset.yaml", "ego.csv", "objects.csv"}) {
    if (!fs::exists(dir / table, ec)) {
      throw core::FileError((dir / table).string() + ": missing, so " + input + " is not a dataset: " + needs);
    }
  }
  if (!tables.boxes) {
    throw core::FileError((dir / "objects.csv").string() +
                          ": no box columns (box_x_m ... box_world_yaw_rad): the dataset was written before "
                          "boxes were; simulate it again to export it to OpenPCDet");
  }
}

// What an export writes, taken back unless it completes: a failed export (a frame that cannot be
// read or lacks a field, a full disk) leaves neither part of a set of files nor the folders it
// made for them. Files of an earlier export that this one did not write again stay.
class ExportOutput {
 public:
  ExportOutput() = default;
  ExportOutput(const ExportOutput&) = delete;
  ExportOutput& operator=(const ExportOutput&) = delete;
  ~ExportOutput() {
    if (complete_) return;
    if (!files_.empty()) {
      std::cerr << "fmcw: note: the export failed; removing the " << files_.size() << " files it wrote\n";
    }
    std::error_code ec;
    for (auto f = files_.rbegin(); f != files_.rend(); ++f) fs::remove(*f, ec);
    for (auto d = folders_.rbegin(); d != folders_.rend(); ++d) fs::remove(*d, ec);  // only when empty
  }

  /// Creates dir and its missing parents (remembered, to be removed again).
  void folder(const fs::path& dir) {
    std::vector<fs::path> missing;
    std::error_code ec;
    for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
      missing.push_back(p);
      if (p == p.parent_path()) break;
    }
    io::ensure_writable_directory(dir.string());
    folders_.insert(folders_.end(), missing.rbegin(), missing.rend());
  }
  /// A file written whole.
  void wrote(const fs::path& file) { files_.push_back(file); }
  void complete() { complete_ = true; }

 private:
  std::vector<fs::path> files_;
  std::vector<fs::path> folders_;  ///< outermost first
  bool complete_ = false;
};

// The cloud to export: a PCD as it is (every field, every type), other inputs as the organized
// scan the core would see.
io::PcdCloud read_cloud(const std::string& path, const io::InputOptions& input) {
  if (input.format == io::InputFormat::kPcd) return io::read_pcd(path);
  const io::InputFrame in = io::read_input_frame(path, input);
  std::cerr << path << ": " << projection_summary(in) << "\n";
  return io::pcd_from_frame(in.frame, false);
}

// --to tum: the dataset's ego poses (ego.csv) as DIR/poses.tum, what `fmcw process --poses`
// takes to undo an ego-compensated dataset's compensation.
int export_poses(const ExportOptions& opt, const DatasetTables& tables, const fs::path& out_dir, ExportOutput& output) {
  if (tables.frames.empty()) {
    throw core::InputError(opt.input.path + ": --to tum needs a dataset written by fmcw simulate (ego.csv beside frames/)");
  }
  core::PoseSeries poses;
  for (const core::FrameTruth& t : tables.frames) {
    poses.stamp_s.push_back(t.stamp_s);
    poses.position_m.push_back(t.ego.T_world_rig.translation());
    poses.orientation.emplace_back(t.ego.T_world_rig.linear());
  }
  const fs::path file = out_dir / "poses.tum";
  try {
    io::write_tum_poses(file.string(), poses);
  } catch (const std::invalid_argument& e) {
    throw core::FileError(opt.input.path + "/ego.csv: " + e.what());
  }
  output.wrote(file);
  output.complete();
  std::cerr << "wrote " << file.string() << " (" << poses.size() << " poses)\n";
  return 0;
}

int run_export(const ExportOptions& opt) {
  if (opt.to == "mcap") return run_export_mcap(opt.input, opt.output, opt.mcap);
  const io::InputOptions input = opt.input.resolve();
  const io::LabelSource label_source = io::parse_label_source(opt.labels);
  if (!(opt.doppler_scale_mps > 0.0)) throw core::InputError("--doppler-scale must be > 0 m/s");
  io::refuse_output_over_inputs(opt.output, {opt.input.path});
  const std::vector<std::string> files = io::list_input_files(opt.input.path, input.format);
  const DatasetTables tables = read_dataset_tables(opt.input.path, files.size());
  if (opt.to == "openpcdet") require_dataset_with_boxes(opt.input, tables);
  const std::vector<ActorClasses> classes = actor_classes(tables, files.size());
  const fs::path out_dir(opt.output);
  ExportOutput output;
  output.folder(out_dir);
  const io::FolderLock lock(opt.output);
  if (opt.to == "tum") return export_poses(opt, tables, out_dir, output);
  if (opt.to == "kitti") {
    output.folder(out_dir / "velodyne");
    output.folder(out_dir / "labels");
  } else if (opt.to == "openpcdet") {
    output.folder(out_dir / "points");
    output.folder(out_dir / "labels");
    output.folder(out_dir / "ImageSets");
  }
  std::vector<std::string> frame_ids;
  for (std::size_t k = 0; k < files.size(); ++k) {
    const std::string& file = files[k];
    const std::string stem = fs::path(file).stem().string();
    const io::PcdCloud cloud = read_cloud(file, input);
    std::string written;
    std::size_t points = 0;
    if (opt.to == "aeva") {
      const core::Frame frame = io::frame_from_pcd(cloud, file);
      io::AevaRecords records;
      try {
        records = io::aeva_records_from_scan(frame.scan);
      } catch (const std::invalid_argument& e) {
        throw core::InputError(file + ": --to aeva: " + e.what());
      }
      written = (out_dir / io::aeva_file_name(frame.scan.stamp_s)).string();
      io::write_aeva(written, records);
      output.wrote(written);
      points = records.size();
    } else if (opt.to == "ply") {
      std::vector<io::Rgb> colors;
      if (opt.color == "doppler") colors = io::doppler_colors(cloud, opt.doppler_scale_mps, file);
      if (opt.color == "label") colors = io::label_colors(io::point_labels(cloud, label_source, classes[k], file));
      if (opt.color == "class") colors = io::class_colors(cloud, file);
      written = (out_dir / (stem + ".ply")).string();
      points = io::write_ply(written, cloud, colors);
      output.wrote(written);
    } else if (opt.to == "kitti") {
      const io::PointLabels labels = io::point_labels(cloud, label_source, classes[k], file);
      written = (out_dir / "velodyne" / (stem + ".bin")).string();
      const std::string label_file = (out_dir / "labels" / (stem + ".label")).string();
      points = io::write_semantic_kitti(written, label_file, cloud, labels, file);
      output.wrote(written);
      output.wrote(label_file);
      written += " + .label";
    } else if (opt.to == "openpcdet") {
      written = (out_dir / "points" / (stem + ".npy")).string();
      const std::string label_file = (out_dir / "labels" / (stem + ".txt")).string();
      points = io::write_openpcdet_frame(written, label_file, cloud, tables.frames[k], file);
      output.wrote(written);
      output.wrote(label_file);
      frame_ids.push_back(stem);
      written += " + labels/" + stem + ".txt";
    } else {
      written = (out_dir / (stem + ".pcd")).string();
      io::write_pcd(written, cloud);
      output.wrote(written);
      points = cloud.points();
    }
    std::cerr << "[" << k + 1 << "/" << files.size() << "] " << file << " -> " << written << " (" << points
              << " points)\n";
  }
  if (opt.to == "openpcdet") {
    // The index last: a reader that finds it finds every frame it lists.
    const fs::path split = out_dir / "ImageSets" / "train.txt";
    io::write_openpcdet_split(split.string(), frame_ids);
    output.wrote(split);
    const fs::path meta = out_dir / "meta.json";
    io::write_openpcdet_meta(meta.string(), frame_ids, tables.frames, opt.input.path);
    output.wrote(meta);
    std::cerr << "wrote " << split.string() << " and " << meta.string() << " (" << frame_ids.size() << " frames)\n";
    std::size_t without_boxes = 0;
    for (const core::FrameTruth& t : tables.frames) without_boxes += io::openpcdet_boxes(t).empty() ? 1 : 0;
    if (without_boxes > 0) {
      std::cerr << "fmcw: note: " << without_boxes << " of " << frame_ids.size()
                << " frames have no box (an empty labels/ID.txt); OpenPCDet's stock custom dataset expects at least "
                   "one per frame (docs/FORMATS.md, OpenPCDet)\n";
    }
  }
  output.complete();
  return 0;
}
}  // namespace

Action add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand("export", "Write frames as PLY, SemanticKITTI .bin/.label, PCD, OpenPCDet's layout or MCAP");
  cmd->add_option("-o,--output", opt->output, "Output folder (--to mcap: output file)")->required();
  cmd->add_option("--to", opt->to,
                  "ply, kitti (velodyne/NAME.bin + labels/NAME.label), pcd, openpcdet (points/NAME.npy + "
                  "labels/NAME.txt + ImageSets/train.txt + meta.json; datasets only), aeva (STAMP_NS.bin, "
                  "Aeva Aeries II records in the head's frame; one-head rigs), tum (poses.tum: the dataset's ego "
                  "poses for --poses), or mcap (one file for Foxglove and ROS 2)")
      ->required()
      ->check(CLI::IsMember({"ply", "kitti", "pcd", "openpcdet", "aeva", "tum", "mcap"}));
  cmd->add_option("--compression", opt->mcap.compression, "mcap: chunk compression, zstd or none")
      ->check(CLI::IsMember({"zstd", "none"}));
  cmd->add_option("--points-topic", opt->mcap.topic, "mcap: the topic of the clouds");
  cmd->add_option("--color", opt->color, "ply: colour by doppler, label (instances), class (semantic classes), or none")
      ->check(CLI::IsMember({"doppler", "label", "class", "none"}));
  cmd->add_option("--labels", opt->labels, "Labels from: auto (estimate if the cloud has 'label', else truth), estimate, truth")
      ->check(CLI::IsMember({"auto", "estimate", "truth"}));
  cmd->add_option("--doppler-scale", opt->doppler_scale_mps, "ply: Doppler [m/s] shown fully red (+) or blue (-)");
  add_input_flags(cmd, opt->input);
  return [opt] { return run_export(*opt); };
}

}  // namespace fmcw::cli
