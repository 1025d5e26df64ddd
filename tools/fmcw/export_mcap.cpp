#include "export_mcap.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>

#include "fmcw/core/errors.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/dataset_files.hpp"
#include "fmcw/io/input_sequence.hpp"
#include "fmcw/io/mcap_export.hpp"
#include "fmcw/io/output_folder.hpp"
#include "fmcw/io/truth_tables.hpp"

namespace fmcw::cli {

namespace fs = std::filesystem;

namespace {
// What the export reads: the frames, and what a dataset or a process output adds to them.
struct McapSource {
  std::vector<std::string> files;       ///< PCD frames (empty for an MCAP input)
  std::unique_ptr<io::InputSequence> sequence;  ///< other formats
  std::vector<core::FrameTruth> truth;  ///< a dataset's ego.csv and objects.csv
  std::vector<std::vector<io::EstimatedObject>> estimated;  ///< a process output's results.json
  bool processed = false;
  std::size_t size() const { return sequence ? sequence->size() : files.size(); }
};

McapSource open_source(const InputFlags& flags, const io::InputOptions& input) {
  McapSource src;
  const fs::path dir(flags.path);
  std::error_code ec;
  const bool folder = fs::is_directory(dir, ec);
  src.processed = folder && fs::exists(dir / "results.json", ec) && fs::is_directory(dir / "labels", ec);
  if (src.processed) {
    // A `fmcw process` output: labelled clouds and the method's clusters.
    src.files = io::list_frame_files((dir / "labels").string(), ".pcd");
    src.estimated = io::read_estimated_objects((dir / "results.json").string());
    if (src.estimated.size() != src.files.size()) {
      throw core::FileError((dir / "results.json").string() + ": " + std::to_string(src.estimated.size()) +
                            " frames, but " + std::to_string(src.files.size()) + " clouds in labels/");
    }
    std::cerr << flags.path << ": a process output: labels in the clouds, clusters on /markers/estimated; no ego "
                               "pose, so no /tf\n";
    return src;
  }
  if (input.format == io::InputFormat::kPcd) {
    src.files = io::list_input_files(flags.path, input.format);
  } else {
    src.sequence = std::make_unique<io::InputSequence>(flags.path, input);
  }
  if (folder && fs::exists(dir / "ego.csv", ec) && fs::exists(dir / "objects.csv", ec)) {
    src.truth = io::read_truth_tables((dir / "ego.csv").string(), (dir / "objects.csv").string());
    if (src.truth.size() != src.size()) {
      throw core::FileError((dir / "ego.csv").string() + ": " + std::to_string(src.truth.size()) +
                            " frames in the tables, " + std::to_string(src.size()) + " frames");
    }
  }
  return src;
}
}  // namespace

int run_export_mcap(const InputFlags& flags, const std::string& output, const McapExportArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const io::InputOptions input = flags.resolve();
  io::McapExportOptions options;
  options.writer.compression = io::parse_mcap_compression(args.compression);
  options.points_topic = args.topic;
  if (fs::path(output).extension() != ".mcap") {
    std::cerr << "fmcw: note: " << output << ": --to mcap writes one file; its name does not end in .mcap\n";
  }
  io::refuse_output_over_inputs(output, {flags.path});
  McapSource src = open_source(flags, input);
  options.ego_poses = options.truth_markers = !src.truth.empty();
  options.estimated_markers = src.processed;
  std::uint64_t bytes = 0;
  io::write_file_atomically(output, [&](std::ostream& out) {
    io::McapSequenceWriter writer(out, options);
    io::PcdPackedData packed;
    for (std::size_t k = 0; k < src.size(); ++k) {
      const core::FrameTruth* truth = src.truth.empty() ? nullptr : &src.truth[k];
      const std::vector<io::EstimatedObject>* estimated = src.processed ? &src.estimated[k] : nullptr;
      std::string source;
      io::PcdCloud cloud;
      if (!src.sequence) {
        // A binary PCD's points go into the message as they lie in the file.
        source = src.files[k];
        if (io::read_pcd_packed(source, cloud, packed)) {
          writer.add_packed_frame(cloud, std::move(packed), source, truth, estimated);
          continue;
        }
      } else {
        source = src.sequence->source(k);
        if (src.sequence->is_mcap()) {
          cloud = src.sequence->mcap_cloud(k);
        } else {
          const io::InputFrame in = src.sequence->read(k);
          cloud = io::pcd_from_frame(in.frame, false);
          std::cerr << source << ": " << projection_summary(in) << "\n";
        }
      }
      writer.add_frame(cloud, source, truth, estimated);
    }
    writer.finish();
    bytes = writer.bytes_written();
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cerr << "wrote " << output << ": " << src.size() << " frames, " << bytes << " bytes (" << args.compression
            << "), " << seconds << " s\n";
  return 0;
}

}  // namespace fmcw::cli
