#include "fmcw/eval/frame_source.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "fmcw/core/ego_motion.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/io/dataset_header.hpp"
#include "fmcw/io/pcd.hpp"
#include "fmcw/io/truth_tables.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;

namespace {
// The .pcd files of frames/, which must be 000000.pcd, 000001.pcd, ... without gaps.
std::vector<std::string> numbered_frames(const fs::path& frames_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(frames_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && entry.path().extension() == ".pcd" && name[0] != '.') names.push_back(name);
  }
  if (ec) throw core::FileError(frames_dir.string() + ": cannot list: " + ec.message());
  if (names.empty()) throw core::FileError(frames_dir.string() + ": holds no .pcd frame");
  std::sort(names.begin(), names.end());
  std::vector<std::string> files;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string expected = io::frame_file_name(static_cast<long long>(k));
    if (names[k] != expected) {
      throw core::FileError((frames_dir / expected).string() + ": missing (found '" + names[k] +
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
  if (!fs::is_directory(root, ec)) throw core::FileError("dataset '" + dir + "': not a folder");
  const fs::path yaml_file = root / "dataset.yaml";
  if (!fs::is_regular_file(yaml_file, ec)) {
    throw core::FileError(yaml_file.string() + ": missing (not a dataset written by `fmcw simulate`)");
  }
  const fs::path frames_dir = root / "frames";
  if (!fs::is_directory(frames_dir, ec)) throw core::FileError(frames_dir.string() + ": missing frames folder");

  const std::string yaml = yaml_file.string();
  const io::DatasetHeader header = io::DatasetHeader::read(yaml);
  if (header.shard) throw core::FileError(yaml + ": shard: this is one shard of a dataset: join all shards with `fmcw merge` first");
  if (!header.complete) {
    throw core::FileError(yaml + ": complete: false: the dataset is incomplete (its writer stopped early): finish it "
                          "with `fmcw simulate ... --resume`");
  }
  info_.path = dir;
  info_.scenario = header.scenario.name;
  info_.rate_hz = header.scenario.rate_hz;
  info_.seed = header.scenario.seed;
  // The scenario block as written (whole lines), without the last line's newline.
  info_.config_yaml = header.scenario_yaml.substr(0, header.scenario_yaml.empty() ? 0 : header.scenario_yaml.size() - 1);

  files_ = numbered_frames(frames_dir);
  if (files_.size() != static_cast<std::size_t>(header.frames_written)) {
    throw core::FileError(yaml + ": frames_written: says " + std::to_string(header.frames_written) + " frames, but " +
                          frames_dir.string() + " holds " + std::to_string(files_.size()) + " .pcd files");
  }
  const std::string ego_csv = (root / "ego.csv").string();
  const std::string objects_csv = (root / "objects.csv").string();
  for (const std::string& f : {ego_csv, objects_csv}) {
    if (!fs::is_regular_file(f, ec)) throw core::FileError(f + ": missing truth table");
  }
  truth_ = io::read_truth_tables(ego_csv, objects_csv);
  if (truth_.size() != files_.size()) {
    throw core::FileError(ego_csv + ": " + std::to_string(truth_.size()) + " frames, but " +
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
    throw core::FileError(file + ": no ground-truth fields (gt_range gt_v gt_vx gt_vy gt_vz instance moving); "
                          "evaluation needs a simulated frame");
  }
  const core::FrameTruth& t = truth_[k];
  // A frame from another dataset or run would be compared with the wrong truth: the stamps tell.
  if (std::abs(f.scan.stamp_s - t.stamp_s) > 1e-4) {
    throw core::FileError(file + ": stamp " + std::to_string(f.scan.stamp_s) + " s differs from ego.csv (" +
                          std::to_string(t.stamp_s) + " s for frame " + std::to_string(k) + ")");
  }
  f.frame_truth = t;
  // Ego-compensated frames are evaluated as a real dataset's are with its poses (as
  // AevaScenesSource does): back in the sensor frame with the ego motion of the dataset's own
  // truth, so that the ego velocity is measured and tracks are carried with the rig.
  if (f.scan.velocity_frame == core::VelocityFrame::kEgoCompensated) {
    if (!t.ego.velocity_mps.allFinite() || !t.ego.angular_velocity_rps.allFinite()) {
      throw core::FileError((fs::path(info_.path) / "ego.csv").string() + ": frame " +
                            std::to_string(k) + ": the ego velocity is not finite, and " + file +
                            " is ego-compensated: it is undone with that velocity");
    }
    core::uncompensate_ego_velocity(
        f, core::EgoMotion{t.ego.velocity_mps, t.ego.angular_velocity_rps});
  }
  return f;
}

}  // namespace fmcw::eval
