// Google Benchmark: one simulated frame of the paper rig on the intersection scenario, scene
// update included, alone and with 30 skinned walkers added (each deformed and its BVH refit every
// frame); and that update on its own. items_per_second is rays per second.

#include <benchmark/benchmark.h>

#include <cmath>

#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/scenario.hpp"

namespace {

// The intersection scenario with 30 of the project's skinned walkers (7016 triangles each)
// crossing the junction in front of the rig, each playing its walk clip on its path's distance.
const fmcw::sim::LoadedScenario& intersection_with_walkers() {
  static const fmcw::sim::LoadedScenario loaded = [] {
    fmcw::sim::LoadedScenario l = fmcw::sim::load_scenario(FMCW_SOURCE_DIR "/scenarios/intersection.yaml");
    const auto walker = std::make_shared<const fmcw::sim::MeshAsset>(fmcw::sim::load_mesh_asset(
        FMCW_SOURCE_DIR "/assets/walker_skinned.gltf", l.scenario.materials, l.scenario.default_reflectivity));
    for (int k = 0; k < 30; ++k) {
      fmcw::sim::ObjectSpec o;
      o.id = 1000 + static_cast<std::uint32_t>(k);
      o.class_name = "pedestrian";
      o.name = "walker_" + std::to_string(k);
      o.mesh_path = walker->path;
      // Rows of walkers 6 to 33 m ahead, crossing left and right at 1.0 to 1.8 m/s.
      const double x = 6.0 + 0.9 * k, y = (k % 2 ? -7.0 : 7.0) + 0.3 * (k % 5);
      o.trajectory.type = "waypoints";
      o.trajectory.path.points_m = {{x, y, 0.0}, {x + 0.5, -y, 0.0}};
      o.trajectory.path.speeds_mps = {1.0 + 0.8 * (k % 3) / 2.0};
      o.animation.clip_index = 0;
      o.animation.playback.clock = fmcw::sim::ClipPlayback::Clock::kDistance;
      o.animation.playback.nominal_speed_mps = walker->clips[0].nominal_speed_mps;
      l.scenario.actors.push_back(o);
      l.actor_meshes.push_back(walker);
    }
    return l;
  }();
  return loaded;
}

void simulate_frames(benchmark::State& state, const fmcw::sim::LoadedScenario& loaded) {
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

void BM_SimulateFrame(benchmark::State& state) {
  static const fmcw::sim::LoadedScenario loaded =
      fmcw::sim::load_scenario(FMCW_SOURCE_DIR "/scenarios/intersection.yaml");
  simulate_frames(state, loaded);
}
BENCHMARK(BM_SimulateFrame)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SimulateFrameWith30SkinnedWalkers(benchmark::State& state) { simulate_frames(state, intersection_with_walkers()); }
BENCHMARK(BM_SimulateFrameWith30SkinnedWalkers)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The scene update alone: every actor moved, 30 skins deformed (210 480 triangles) and refit,
// the top level rebuilt. items_per_second is skinned triangles per second.
void BM_SceneUpdateWith30SkinnedWalkers(benchmark::State& state) {
  fmcw::sim::SimulationSetup setup = fmcw::sim::build_simulation(intersection_with_walkers(), 1);
  std::uint64_t k = 0;
  for (auto _ : state) {
    setup.scene->set_time(0.1 * static_cast<double>(k++ % 100));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 30 * 7016);
}
BENCHMARK(BM_SceneUpdateWith30SkinnedWalkers)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
