#include "fmcw/sim/dataset_merge.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

#include "fmcw/core/errors.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/output_folder.hpp"
#include "fmcw/io/truth_tables.hpp"
#include "fmcw/io/dataset_header.hpp"

namespace fmcw::sim {

namespace fs = std::filesystem;

namespace {

struct Shard {
  fs::path dir;
  io::DatasetHeader header;
};

// A truth table's rows without its header line.
std::string table_rows(const fs::path& file, const char* header) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw core::FileError(file.string() + ": missing truth table");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  if (text.rfind(header, 0) != 0) throw core::FileError(file.string() + ": does not start with the expected header");
  return text.substr(std::strlen(header));
}

// Puts one frame file into the merged dataset under a temporary name, then renames it, so that
// a stopped merge leaves no partial frame.
bool place_frame(const fs::path& from, const fs::path& to) {
  const fs::path tmp = to.parent_path() / (".tmp." + to.filename().string() + "." + std::to_string(::getpid()));
  std::error_code ec;
  fs::remove(tmp, ec);
  fs::create_hard_link(from, tmp, ec);
  const bool linked = !ec;
  if (!linked) {
    fs::copy_file(from, tmp, fs::copy_options::overwrite_existing, ec);
    if (ec) {
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write '" + to.string() + "': " + ec.message());
    }
  }
  fs::rename(tmp, to, ec);
  if (ec) throw std::runtime_error("cannot write '" + to.string() + "': rename failed: " + ec.message());
  return linked;
}

}  // namespace

MergeSummary merge_shards(const std::vector<std::string>& shard_dirs, const std::string& output_dir, bool overwrite) {
  if (shard_dirs.empty()) throw core::InputError("merge: no shard folders given");
  // Before anything is read or written: the merged dataset never goes over one of its shards.
  io::refuse_output_over_inputs(output_dir, shard_dirs);
  std::vector<Shard> shards;
  for (const std::string& d : shard_dirs) {
    const fs::path yaml = fs::path(d) / "dataset.yaml";
    std::error_code ec;
    if (!fs::is_regular_file(yaml, ec)) throw core::FileError(yaml.string() + ": missing (not a shard written by fmcw simulate --shard)");
    Shard s{d, io::DatasetHeader::read(yaml.string())};
    if (!s.header.shard) throw core::FileError(yaml.string() + ": not a shard (no 'shard' key): it is a whole dataset already");
    if (!s.header.complete) {
      throw core::FileError(yaml.string() + ": shard " + std::to_string(s.header.shard->index) + " is incomplete (" +
                            std::to_string(s.header.frames_written) + " of " +
                            std::to_string(s.header.shard->frames()) + " frames): finish it with --resume");
    }
    shards.push_back(std::move(s));
  }
  std::sort(shards.begin(), shards.end(),
            [](const Shard& a, const Shard& b) { return a.header.shard->index < b.header.shard->index; });
  const io::DatasetHeader& first = shards.front().header;
  const int count = first.shard->count;
  for (std::size_t i = 0; i < shards.size(); ++i) {
    const io::DatasetHeader& h = shards[i].header;
    const std::string name = (shards[i].dir / "dataset.yaml").string();
    if (h.shard->count != count) {
      throw core::FileError(name + ": shard of " + std::to_string(h.shard->count) + " parts, but " +
                            (shards.front().dir / "dataset.yaml").string() + " is one of " + std::to_string(count));
    }
    if (h.shard->index != static_cast<int>(i)) {
      throw core::InputError(name + ": is shard " + std::to_string(h.shard->index) + " where shard " + std::to_string(i) +
                             " was expected (shards sorted by index: one is missing or given twice)");
    }
    if (h.scenario_yaml != first.scenario_yaml || h.tool_version != first.tool_version ||
        h.motion_distortion != first.motion_distortion) {
      throw core::FileError(name + ": shard " + std::to_string(i) + " comes from another scenario, options or fmcw version than " +
                            (shards.front().dir / "dataset.yaml").string());
    }
    const int expected_first = i == 0 ? 0 : shards[i - 1].header.shard->end_frame;
    if (h.shard->first_frame != expected_first) {
      throw core::FileError(name + ": shard " + std::to_string(i) + " starts at frame " +
                            std::to_string(h.shard->first_frame) + ", expected " + std::to_string(expected_first));
    }
  }
  if (static_cast<int>(shards.size()) != count) {
    throw core::InputError("merge: " + std::to_string(shards.size()) + " shard folders given, the dataset has " +
                           std::to_string(count) + " shards");
  }

  const fs::path out(output_dir);
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) {
    throw core::InputError("output '" + output_dir + "' exists and is not a folder");
  }
  const io::FolderLock lock(output_dir);
  if (!io::is_empty_folder(output_dir)) {
    if (!overwrite) {
      throw core::InputError("output folder '" + output_dir + "' exists and is not empty (choose another folder or pass --overwrite)");
    }
    if (!io::holds_dataset(output_dir)) {
      throw core::InputError("output folder '" + output_dir +
                             "' holds no dataset.yaml or frames/: --overwrite replaces only a dataset (or what a "
                             "stopped merge left); choose another folder");
    }
  }
  // What is there is no dataset until the merge ends, and older frames would be taken for its own.
  fs::remove(out / "dataset.yaml", ec);
  fs::remove_all(out / "frames", ec);
  io::ensure_writable_directory((out / "frames").string());
  MergeSummary summary;
  summary.shards = count;
  std::string ego = io::kEgoCsvHeader;
  std::string objects = io::kObjectsCsvHeader;
  for (const Shard& s : shards) {
    for (int k = s.header.shard->first_frame; k < s.header.shard->end_frame; ++k) {
      const fs::path from = s.dir / "frames" / io::frame_file_name(k);
      if (!fs::is_regular_file(from, ec)) throw core::FileError(from.string() + ": missing frame of a complete shard");
      summary.frames_linked += place_frame(from, out / "frames" / io::frame_file_name(k)) ? 1 : 0;
      ++summary.frames;
    }
    ego += table_rows(s.dir / "ego.csv", io::kEgoCsvHeader);
    objects += table_rows(s.dir / "objects.csv", io::kObjectsCsvHeader);
  }
  io::write_file_atomically((out / "ego.csv").string(), [&](std::ostream& o) { o << ego; });
  io::write_file_atomically((out / "objects.csv").string(), [&](std::ostream& o) { o << objects; });
  io::DatasetHeader merged = first;
  merged.shard.reset();
  merged.complete = true;
  merged.frames_written = summary.frames;
  io::write_file_atomically((out / "dataset.yaml").string(), [&](std::ostream& o) { o << merged.to_yaml(); });
  return summary;
}

}  // namespace fmcw::sim
