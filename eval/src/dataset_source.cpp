#include "fmcw/eval/frame_source.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "fmcw/io/pcd.hpp"
#include "fmcw/io/truth_tables.hpp"
#include "fmcw/sim/yaml_reader.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;

namespace {
std::string frame_name(std::size_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.pcd", k);
  return name;
}

// The .pcd files of frames/, which must be 000000.pcd, 000001.pcd, ... without gaps.
std::vector<std::string> numbered_frames(const fs::path& frames_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(frames_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && entry.path().extension() == ".pcd" && name[0] != '.') names.push_back(name);
  }
  if (ec) throw std::invalid_argument(frames_dir.string() + ": cannot list: " + ec.message());
  if (names.empty()) throw std::invalid_argument(frames_dir.string() + ": holds no .pcd frame");
  std::sort(names.begin(), names.end());
  std::vector<std::string> files;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (names[k] != frame_name(k)) {
      throw std::invalid_argument((frames_dir / frame_name(k)).string() + ": missing (found '" + names[k] +
                                  "'; frames must be numbered from 000000 without gaps)");
    }
    files.push_back((frames_dir / names[k]).string());
  }
  return files;
}
}  // namespace

DatasetSource::DatasetSource(const std::string& dir, int max_frames) {
  const fs::path root(dir);
  std::error_code ec;
  if (!fs::is_directory(root, ec)) throw std::invalid_argument("dataset '" + dir + "': not a folder");
  const fs::path yaml_file = root / "dataset.yaml";
  if (!fs::is_regular_file(yaml_file, ec)) {
    throw std::invalid_argument(yaml_file.string() + ": missing (not a dataset written by `fmcw simulate`)");
  }
  const fs::path frames_dir = root / "frames";
  if (!fs::is_directory(frames_dir, ec)) throw std::invalid_argument(frames_dir.string() + ": missing frames folder");

  // dataset.yaml is read leniently (a newer writer may add keys) but what is read must be right.
  const sim::YamlValue doc = sim::YamlValue::load_file(yaml_file.string());
  if (!doc.is_map()) doc.fail("expected a map");
  const auto key = [&](const sim::YamlValue& parent, const std::string& name) {
    const YAML::Node node = parent.node()[name];
    if (!node.IsDefined()) parent.fail("missing key '" + name + "'");
    return sim::YamlValue(node, parent.file(), parent.path().empty() ? name : parent.path() + "." + name);
  };
  const sim::YamlValue format = key(doc, "format");
  if (format.as_string() != "fmcw-dataset") format.fail("expected 'fmcw-dataset', got '" + format.as_string() + "'");
  const sim::YamlValue complete = key(doc, "complete");
  if (doc.node()["shard"].IsDefined()) {
    key(doc, "shard").fail("this is one shard of a dataset: join all shards with `fmcw merge` first");
  }
  if (!complete.as_bool()) {
    complete.fail("the dataset is incomplete (its writer stopped early): finish it with `fmcw simulate ... --resume`");
  }
  const sim::YamlValue written = key(doc, "frames_written");
  const sim::YamlValue scenario = key(doc, "scenario");
  info_.path = dir;
  info_.scenario = key(scenario, "name").as_string();
  info_.rate_hz = key(scenario, "rate_hz").as_double();
  if (!(info_.rate_hz > 0.0)) key(scenario, "rate_hz").fail("must be > 0");
  info_.seed = key(scenario, "seed").as_uint64();
  info_.config_yaml = YAML::Dump(scenario.node());

  files_ = numbered_frames(frames_dir);
  if (static_cast<int>(files_.size()) != written.as_int()) {
    written.fail("says " + std::to_string(written.as_int()) + " frames, but " + frames_dir.string() + " holds " +
                 std::to_string(files_.size()) + " .pcd files");
  }
  const std::string ego_csv = (root / "ego.csv").string();
  const std::string objects_csv = (root / "objects.csv").string();
  for (const std::string& f : {ego_csv, objects_csv}) {
    if (!fs::is_regular_file(f, ec)) throw std::invalid_argument(f + ": missing truth table");
  }
  truth_ = io::read_truth_tables(ego_csv, objects_csv);
  if (truth_.size() != files_.size()) {
    throw std::invalid_argument(ego_csv + ": " + std::to_string(truth_.size()) + " frames, but " +
                                frames_dir.string() + " holds " + std::to_string(files_.size()) + " frames");
  }
  if (max_frames > 0 && static_cast<std::size_t>(max_frames) < files_.size()) {
    files_.resize(static_cast<std::size_t>(max_frames));
    truth_.resize(static_cast<std::size_t>(max_frames));
  }
}

core::Frame DatasetSource::frame(std::size_t k) {
  const std::string& file = files_.at(k);
  if (!layout_.has_first() && k > 0) layout_.check(io::read_frame(files_.front()).scan, files_.front());
  core::Frame f = io::read_frame(file);
  layout_.check(f.scan, file);
  if (!f.truth) {
    throw std::invalid_argument(file + ": no ground-truth fields (gt_range gt_v gt_vx gt_vy gt_vz instance moving); "
                                "evaluation needs a simulated frame");
  }
  const core::FrameTruth& t = truth_[k];
  // A frame from another dataset or run would be compared with the wrong truth: the stamps tell.
  if (std::abs(f.scan.stamp_s - t.stamp_s) > 1e-4) {
    throw std::invalid_argument(file + ": stamp " + std::to_string(f.scan.stamp_s) + " s differs from ego.csv (" +
                                std::to_string(t.stamp_s) + " s for frame " + std::to_string(k) + ")");
  }
  f.frame_truth = t;
  return f;
}

std::unique_ptr<FrameSource> open_frame_source(const std::string& path, int max_frames) {
  const fs::path p(path);
  const std::string ext = p.extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) throw std::invalid_argument(path + ": file does not exist");
    return std::make_unique<ScenarioSource>(path, max_frames);
  }
  return std::make_unique<DatasetSource>(path, max_frames);
}

}  // namespace fmcw::eval
