#include "fmcw/eval/aevascenes_source.hpp"

#include "fmcw/core/errors.hpp"

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace fmcw::eval {

namespace fs = std::filesystem;

bool is_aevascenes_sequence(const std::string& dir) {
  std::error_code ec;
  return fs::is_directory(dir, ec) && fs::is_regular_file(fs::path(dir) / "sequence.json", ec);
}

AevaScenesSource::AevaScenesSource(const std::string& dir, int max_frames, io::AevaScenesOptions options)
    : sequence_(io::read_aevascenes_sequence(dir)), options_(options) {
  options_.to_sensor_frame = true;
  frames_ = sequence_.frames.size();
  if (max_frames > 0) frames_ = std::min(frames_, static_cast<std::size_t>(max_frames));
  if (sequence_.frames.size() < 2) {
    throw core::FileError(dir + "/sequence.json: one frame: the ego motion (and with it the ego velocity to evaluate) "
                          "needs at least two");
  }
  info_.scenario = sequence_.uuid;
  info_.path = dir;
  const double span = sequence_.frames.back().stamp_s - sequence_.frames.front().stamp_s;
  info_.rate_hz = static_cast<double>(sequence_.frames.size() - 1) / span;
  std::ostringstream config;
  config << "aevascenes: {sequence: " << sequence_.uuid << ", lidars: " << sequence_.lidars.size()
         << ", wide_fov_deg: " << options_.wide_fov_deg << ", narrow_fov_deg: " << options_.narrow_fov_deg
         << ", resolution_deg: " << options_.resolution_deg << ", lines: " << options_.lines
         << ", moving_threshold_mps: " << options_.moving_threshold_mps << "}";
  info_.config_yaml = config.str();
  // Frame 0 now: a broken file stops the run before anything is evaluated, and what it does not
  // read is said once.
  std::vector<std::string> notes;
  const core::Frame first = io::read_aevascenes_frame(sequence_, 0, options_, classes_, &notes);
  layout_.check(first.scan, describe(0));
  // Every frame gets frame 0's lines (a larger line index later is an error naming its file).
  options_.lines = first.scan.rows;
  for (const std::string& n : notes) {
    if (std::find(info_.notices.begin(), info_.notices.end(), n) == info_.notices.end()) info_.notices.push_back(n);
  }
}

core::Frame AevaScenesSource::frame(std::size_t k) {
  core::Frame f = io::read_aevascenes_frame(sequence_, k, options_, classes_);
  layout_.check(f.scan, describe(k));
  return f;
}

std::string AevaScenesSource::describe(std::size_t k) const {
  return sequence_.dir + "/sequence.json frame " + std::to_string(k);
}

}  // namespace fmcw::eval
