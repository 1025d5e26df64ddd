// libFuzzer target: the scenario loader (YAML parsing, keys, types, ranges, rig, trajectories,
// and meshes: tri.obj beside the input is a one-triangle mesh that inputs may name). Bad input
// may only end in std::invalid_argument; anything else is a bug.

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <stdexcept>

#include "fmcw/sim/scenario.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::ofstream(fmcw::fuzz::scratch_dir() / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fmcw::fuzz::write_input("scenario.yaml", data, size);
  try {
    (void)fmcw::sim::load_scenario(path);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
