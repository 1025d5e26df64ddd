// Google Benchmark: the motion pipeline and its stages on the 600 x 150 benchmark frame.
// items_per_second is points (pixels of the range image) per second.

#include <benchmark/benchmark.h>

#include "fmcw/core/ceres_velocity.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/synthetic_scan.hpp"

namespace {

const fmcw::core::Frame& bench_frame() {
  static const fmcw::core::Frame frame = fmcw::core::render_synthetic_scan(fmcw::core::benchmark_scene(20, 1));
  return frame;
}

void BM_Pipeline(benchmark::State& state, const std::string& method) {
  fmcw::core::MotionPipelineParams params = fmcw::core::MotionPipelineParams::preset(method);
  params.num_threads = static_cast<int>(state.range(0));
  fmcw::core::MotionPipeline pipeline(params);
  const auto& scan = bench_frame().scan;
  std::uint64_t k = 0;
  for (auto _ : state) {
    auto est = pipeline.process(scan, k++);
    benchmark::DoNotOptimize(est.ego.velocity_mps);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(scan.size()));
}
BENCHMARK_CAPTURE(BM_Pipeline, fast, std::string("fast"))->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Pipeline, paper, std::string("paper"))->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

void BM_Segmentation(benchmark::State& state) {
  fmcw::core::SegmentationParams params;
  params.algorithm = state.range(0) == 0 ? fmcw::core::RegionAlgorithm::kRegionGrowing
                                         : fmcw::core::RegionAlgorithm::kUnionFind;
  state.SetLabel(state.range(0) == 0 ? "region_growing" : "union_find");
  fmcw::core::DopplerSegmenter segmenter(params);
  const auto& scan = bench_frame().scan;
  for (auto _ : state) {
    auto seg = segmenter.segment(scan);
    benchmark::DoNotOptimize(seg.labels.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(scan.size()));
}
BENCHMARK(BM_Segmentation)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// One 200-point object solve, closed form against Ceres.
fmcw::core::VelocityRows object_rows() {
  fmcw::core::VelocityRows rows;
  for (int k = 0; k < 200; ++k) {
    const double az = -0.05 + 0.0005 * k;
    const double el = -0.02 + 0.0002 * (k % 50);
    const Eigen::Vector3d e(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    rows.directions.push_back(e);
    rows.targets_mps.push_back(e.dot(Eigen::Vector3d(8.0, 1.0, 0.0)));
  }
  return rows;
}

void BM_ObjectSolveClosedForm(benchmark::State& state) {
  const auto rows = object_rows();
  for (auto _ : state) benchmark::DoNotOptimize(fmcw::core::solve_velocity_closed_form(rows).velocity_mps);
}
BENCHMARK(BM_ObjectSolveClosedForm)->Unit(benchmark::kMicrosecond);

void BM_ObjectSolveCeres(benchmark::State& state) {
  const auto rows = object_rows();
  for (auto _ : state) benchmark::DoNotOptimize(fmcw::core::solve_velocity_ceres(rows).velocity_mps);
}
BENCHMARK(BM_ObjectSolveCeres)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
