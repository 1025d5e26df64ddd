#include "fmcw/sim/dataset_writer.hpp"

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fmcw/core/errors.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/dataset_header.hpp"
#include "fmcw/io/output_folder.hpp"
#include "fmcw/io/pcd.hpp"
#include "fmcw/io/truth_tables.hpp"

namespace fmcw::sim {

namespace fs = std::filesystem;

namespace {

// Text as whole lines, each ending in a newline: the form DatasetHeader::read gives back.
std::string whole_lines(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) out += line + "\n";
  return out;
}

// "line N: 'a' here, 'b' there" for the first line where two texts differ.
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream ia(a), ib(b);
  std::string la, lb;
  for (int n = 1;; ++n) {
    const bool more_a = static_cast<bool>(std::getline(ia, la));
    const bool more_b = static_cast<bool>(std::getline(ib, lb));
    if (!more_a && !more_b) return "none";
    if (!more_a) la = "(end)";
    if (!more_b) lb = "(end)";
    if (la != lb) return "scenario line " + std::to_string(n) + ": '" + la + "' in the dataset, '" + lb + "' now";
  }
}

// Frame index of a k-th CSV row ("frame,..."), or -1 when the row does not start with one.
long long row_frame(const std::string& row) {
  const std::size_t comma = row.find(',');
  if (comma == 0 || comma == std::string::npos) return -1;
  long long v = 0;
  for (std::size_t i = 0; i < comma; ++i) {
    if (row[i] < '0' || row[i] > '9' || v > 100000000000LL) return -1;
    v = v * 10 + (row[i] - '0');
  }
  return v;
}

// Keeps the header and the rows of frames [first, end) of a truth table, drops the rest (rows of
// frames after the last whole one, and a row cut short by a kill). Returns the distinct frames kept.
int truncate_table(const fs::path& file, const char* header, int first, int end) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw core::FileError(file.string() + ": missing; the dataset cannot be resumed");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  if (text.rfind(header, 0) != 0) throw core::FileError(file.string() + ": does not start with the expected header");
  std::string kept = header;
  int frames = 0;
  long long last = -1;
  for (std::size_t pos = std::strlen(header); pos < text.size();) {
    const std::size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) break;  // a row cut short: it belongs to no whole frame
    const std::string row = text.substr(pos, nl - pos + 1);
    pos = nl + 1;
    const long long k = row_frame(row);
    if (k < first || k >= end) continue;
    if (k != last) {
      ++frames;
      last = k;
    }
    kept += row;
  }
  io::write_file_atomically(file.string(), [&](std::ostream& out) { out << kept; });
  return frames;
}

// Removes what a stopped run may leave beyond its whole frames: temporary files, and frame files
// outside [first, end).
void remove_partial_files(const fs::path& dir, int first, int end) {
  for (const fs::path& folder : {dir, dir / "frames"}) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      const std::string name = entry.path().filename().string();
      bool stale = name.rfind(".tmp.", 0) == 0;
      if (folder != dir && entry.path().extension() == ".pcd" && !stale) {
        const long long k = row_frame(name.substr(0, name.size() - 4) + ",");
        stale = k < first || k >= end;
      }
      if (stale) fs::remove(entry.path());
    }
    if (ec) throw std::runtime_error("cannot list '" + folder.string() + "': " + ec.message());
  }
}

// Why the kept frame k is not the one this run would write (it cannot be read whole, or its
// stamp is another frame's), or "" when it is.
std::string kept_frame_fault(const fs::path& file, double stamp_s) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return "missing";
  try {
    const core::Frame frame = io::read_frame(file.string());
    if (!(std::abs(frame.scan.stamp_s - stamp_s) <= 1e-9 * std::max(1.0, std::abs(stamp_s)))) {
      return "stamp " + std::to_string(frame.scan.stamp_s) + " s where frame time " + std::to_string(stamp_s) + " s was written";
    }
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Checks that the dataset in dir was started with the same scenario and options, cleans up after
// the stop, and returns how many whole frames it holds. Every frame it counts is read back: from
// the first that is missing, cut short or not the frame this run would write, the frames are
// simulated again (note says which and why).
int prepare_resume(const fs::path& dir, const io::DatasetHeader& wanted, int total_frames, const Scenario& scenario,
                   std::string& note) {
  const std::string yaml_file = (dir / "dataset.yaml").string();
  const io::DatasetHeader found = io::DatasetHeader::read(yaml_file);
  const std::string hint = " (resume needs the same scenario file, --frames, --seed, --shard and fmcw version)";
  if (found.tool_version != wanted.tool_version) {
    throw core::InputError(yaml_file + ": written by fmcw " + found.tool_version + ", this is " +
                           wanted.tool_version + hint);
  }
  if (found.scenario_yaml != wanted.scenario_yaml) {
    throw core::InputError(yaml_file + ": the dataset was started with another scenario or options, first difference at " +
                           first_difference(found.scenario_yaml, wanted.scenario_yaml) + hint);
  }
  const auto shard_text = [](const std::optional<io::ShardInfo>& s) {
    return s ? std::to_string(s->index) + "/" + std::to_string(s->count) : std::string("none");
  };
  if (found.shard.has_value() != wanted.shard.has_value() || (found.shard && !(*found.shard == *wanted.shard))) {
    throw core::InputError(yaml_file + ": the dataset is shard " + shard_text(found.shard) + ", this run is shard " +
                           shard_text(wanted.shard) + hint);
  }
  const int first = wanted.shard ? wanted.shard->first_frame : 0;
  int done = found.frames_written;
  if (done > total_frames) {
    throw core::InputError(yaml_file + ": counts " + std::to_string(done) + " frames, more than the " +
                           std::to_string(total_frames) + " this run writes; the dataset cannot be resumed");
  }
  for (int k = first; k < first + done; ++k) {
    const fs::path file = dir / "frames" / io::frame_file_name(k);
    const std::string fault = kept_frame_fault(file, scenario.frame_time_s(static_cast<std::uint64_t>(k)));
    if (fault.empty()) continue;
    note = file.string() + ": " + fault + "; it and the " + std::to_string(first + done - k - 1) +
           " frames after it are simulated again";
    done = k - first;
    break;
  }
  remove_partial_files(dir, first, first + done);
  const int ego_frames = truncate_table(dir / "ego.csv", io::kEgoCsvHeader, first, first + done);
  truncate_table(dir / "objects.csv", io::kObjectsCsvHeader, first, first + done);
  if (ego_frames != done) {
    throw core::FileError((dir / "ego.csv").string() + ": holds " + std::to_string(ego_frames) +
                          " frames but dataset.yaml counts " + std::to_string(done) +
                          "; the dataset cannot be resumed");
  }
  return done;
}

// Appends text to a file and flushes, so that it is on disk before dataset.yaml counts it.
void append(std::ofstream& out, const fs::path& file, const std::string& text) {
  out << text;
  out.flush();
  if (!out) throw std::runtime_error("cannot write '" + file.string() + "': " + std::strerror(errno));
}

}  // namespace

DatasetSummary write_dataset(const LoadedScenario& loaded_in, const DatasetOptions& options,
                             const std::function<void(int, int)>& progress) {
  LoadedScenario loaded = loaded_in;
  Scenario& s = loaded.scenario;
  if (options.frames > 0) s.frames = options.frames;
  if (options.override_seed) s.seed = options.seed;
  const io::ShardInfo shard = io::ShardInfo::of(options.shard_index, options.shard_count, s.frames);
  io::DatasetHeader header;
  header.tool_version = options.tool_version;
  header.motion_distortion = s.motion_distortion;
  if (options.shard_count > 1) header.shard = shard;
  header.scenario_yaml = whole_lines(scenario_to_yaml(s));
  for (const core::SemanticClass& c : s.classes.classes()) header.classes.emplace_back(c.id, c.name);

  // The scene first: what fails there (Embree, memory) fails before any file is written.
  SimulationSetup setup = build_simulation(loaded, options.num_threads);
  LidarSimulator simulator(setup.scene, setup.ego, setup.params);

  const fs::path dir(options.output_dir);
  const fs::path yaml_file = dir / "dataset.yaml";
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw core::InputError("output '" + options.output_dir + "' exists and is not a folder");
  }
  // One writer per dataset, from the first look at the folder to the last frame.
  const io::FolderLock lock(options.output_dir);
  const bool occupied = !io::is_empty_folder(options.output_dir);
  DatasetSummary summary;
  summary.frames_total = shard.frames();
  if (options.resume && occupied) {
    if (!fs::is_regular_file(yaml_file, ec)) {
      throw core::InputError("cannot resume: '" + options.output_dir + "' holds no dataset.yaml");
    }
    io::ensure_writable_directory((dir / "frames").string());
    summary.frames_resumed = prepare_resume(dir, header, shard.frames(), s, summary.resume_note);
  } else {
    if (occupied && !options.overwrite) {
      throw core::InputError("output folder '" + options.output_dir +
                             "' exists and is not empty (choose another folder, pass --overwrite, or --resume "
                             "to continue a stopped run)");
    }
    // --overwrite replaces a dataset, nothing else: a folder of other files is left as it is.
    if (occupied && !io::holds_dataset(options.output_dir)) {
      throw core::InputError("output folder '" + options.output_dir +
                             "' holds no dataset.yaml or frames/: --overwrite replaces only a dataset that fmcw "
                             "writes; choose another folder");
    }
    io::ensure_writable_directory((dir / "frames").string());
    // Files of an earlier dataset here would be taken for part of this one.
    remove_partial_files(dir, 0, 0);
  }
  summary.frames_written = summary.frames_resumed;
  const auto write_header = [&] {
    header.frames_written = summary.frames_written;
    header.complete = summary.frames_written == shard.frames();
    io::write_file_atomically(yaml_file.string(), [&](std::ostream& out) { out << header.to_yaml(); });
  };
  if (summary.frames_resumed == 0) {
    for (const auto& table : {std::pair{"ego.csv", io::kEgoCsvHeader}, std::pair{"objects.csv", io::kObjectsCsvHeader}}) {
      io::write_file_atomically((dir / table.first).string(), [&](std::ostream& out) { out << table.second; });
    }
  }
  write_header();
  if (summary.frames_written == shard.frames()) return summary;

  const auto t0 = std::chrono::steady_clock::now();
  std::ofstream ego_out(dir / "ego.csv", std::ios::binary | std::ios::app);
  std::ofstream objects_out(dir / "objects.csv", std::ios::binary | std::ios::app);
  if (!ego_out || !objects_out) {
    throw std::runtime_error("cannot open the truth tables in '" + options.output_dir + "': " + std::strerror(errno));
  }
  core::Frame frame;
  try {
    for (int k = shard.first_frame + summary.frames_written; k < shard.end_frame; ++k) {
      if (options.stop_requested && options.stop_requested()) {
        summary.interrupted = true;
        break;
      }
      simulator.simulate(static_cast<std::uint64_t>(k), s.frame_time_s(static_cast<std::uint64_t>(k)), frame);
      io::write_frame((dir / "frames" / io::frame_file_name(k)).string(), frame);
      append(ego_out, dir / "ego.csv", io::ego_csv_row(static_cast<std::size_t>(k), *frame.frame_truth));
      append(objects_out, dir / "objects.csv", io::objects_csv_rows(static_cast<std::size_t>(k), *frame.frame_truth));
      summary.returns += frame.scan.num_valid();
      ++summary.frames_written;
      write_header();
      if (progress) progress(summary.frames_written, shard.frames());
    }
  } catch (const std::runtime_error&) {
    core::rethrow_with_context("", "; " + options.output_dir + " holds " + std::to_string(summary.frames_written) +
                                       " of " + std::to_string(shard.frames()) +
                                       " frames whole: fix the cause and continue with --resume");
  }
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace fmcw::sim
