#pragma once
// A scenario simulated frame by frame in memory, the FrameSource of studies and of Python's
// fmcw.Scenario. In fmcw::eval_sim, the part of the evaluation that links the simulator.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "fmcw/eval/frame_source.hpp"
#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/scenario.hpp"

namespace fmcw::eval {

/// A scenario simulated frame by frame in memory (for studies: nothing is written to disk).
class ScenarioSource : public FrameSource {
 public:
  /// frames: 0 = the scenario's count; seed applies when override_seed.
  ScenarioSource(const std::string& scenario_file, int frames = 0, bool override_seed = false, std::uint64_t seed = 0);
  std::size_t size() const override { return static_cast<std::size_t>(loaded_.scenario.frames); }
  core::Frame frame(std::size_t k) override;
  std::string describe(std::size_t k) const override;
  const SourceInfo& info() const override { return info_; }

 private:
  sim::LoadedScenario loaded_;
  SourceInfo info_;
  std::unique_ptr<sim::LidarSimulator> simulator_;
};

/// A DatasetSource for a folder, a ScenarioSource for a .yaml/.yml file.
std::unique_ptr<FrameSource> open_frame_source(const std::string& path, int max_frames = 0);

}  // namespace fmcw::eval
