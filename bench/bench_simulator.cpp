// Google Benchmark: one simulated frame of the paper rig on the intersection scenario, scene
// update included. items_per_second is rays per second.

#include <benchmark/benchmark.h>

#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/scenario.hpp"

namespace {

void BM_SimulateFrame(benchmark::State& state) {
  static const fmcw::sim::LoadedScenario loaded =
      fmcw::sim::load_scenario(FMCW_SOURCE_DIR "/scenarios/intersection.yaml");
  fmcw::sim::SimulationSetup setup = fmcw::sim::build_simulation(loaded, static_cast<int>(state.range(0)));
  fmcw::sim::LidarSimulator simulator(setup.scene, setup.ego, setup.params);
  std::uint64_t k = 0;
  fmcw::core::Frame frame;
  for (auto _ : state) {
    simulator.simulate(k % 100, loaded.scenario.frame_time_s(k % 100), frame);
    benchmark::DoNotOptimize(frame.scan.range_m.data());
    ++k;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * setup.params.rig.rows() *
                          setup.params.rig.cols());
}
BENCHMARK(BM_SimulateFrame)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
