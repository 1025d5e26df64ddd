#pragma once
// The memory a scenario will take, estimated from its file before anything large is allocated.

#include <cstdint>
#include <string>

namespace fmcw::sim {

/// Measured on this project's simulator (peak resident memory of `fmcw simulate` over scenes of
/// 1 to 8,000 copies of a 672-triangle building, and rigs of 0.36 and 1.44 M pixels), rounded
/// up: each placed triangle (its own vertices, BVH and ground truth) and each pixel of the rig
/// (scan, truth, the frame written) take about 200 and 233 bytes.
constexpr double kBytesPerTriangle = 256.0;
/// Each placed object besides its triangles (its entry, instance and per-frame truth): 10,000 and
/// 100,000 copies of a one-triangle mesh peaked at 43 and 260 MB, about 2.4 KB a copy.
constexpr double kBytesPerObject = 4096.0;
constexpr double kBytesPerPixel = 256.0;
constexpr double kBaseBytes = 64.0 * 1024.0 * 1024.0;

/// Half of this machine's physical memory.
std::uint64_t default_memory_budget_bytes();

/// A running estimate against a limit. add() throws std::invalid_argument naming where, the
/// estimate and the limit once the estimate would pass it.
class MemoryBudget {
 public:
  explicit MemoryBudget(std::uint64_t limit_bytes);  ///< 0: default_memory_budget_bytes()
  void add(double bytes, const std::string& where, const std::string& what);

 private:
  double limit_ = 0.0;
  double total_ = kBaseBytes;
};

}  // namespace fmcw::sim
