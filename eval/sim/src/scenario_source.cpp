#include "fmcw/eval/scenario_source.hpp"

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;

ScenarioSource::ScenarioSource(const std::string& scenario_file, int frames, bool override_seed, std::uint64_t seed)
    : loaded_(sim::load_scenario(scenario_file)) {
  sim::Scenario& s = loaded_.scenario;
  if (frames > 0) s.frames = frames;
  if (override_seed) s.seed = seed;
  info_.scenario = s.name;
  info_.path = scenario_file;
  info_.rate_hz = s.rate_hz;
  info_.seed = s.seed;
  info_.config_yaml = sim::scenario_to_yaml(s);
  info_.notices = loaded_.notices;
  const sim::SimulationSetup setup = sim::build_simulation(loaded_);
  simulator_ = std::make_unique<sim::LidarSimulator>(setup.scene, setup.ego, setup.params);
}

core::Frame ScenarioSource::frame(std::size_t k) {
  const auto index = static_cast<std::uint64_t>(k);
  return simulator_->simulate(index, loaded_.scenario.frame_time_s(index));
}

std::string ScenarioSource::describe(std::size_t k) const {
  std::ostringstream out;
  out << info_.path << " frame " << k;
  return out.str();
}

std::unique_ptr<FrameSource> open_frame_source(const std::string& path, int max_frames) {
  const fs::path p(path);
  const std::string ext = p.extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) throw core::FileError(path + ": file does not exist");
    return std::make_unique<ScenarioSource>(path, max_frames);
  }
  return std::make_unique<DatasetSource>(path, max_frames);
}

}  // namespace fmcw::eval
