// libFuzzer target: the scenario loader (YAML parsing, keys, types, ranges, rig, trajectories,
// and meshes: tri.obj beside the input is a one-triangle mesh that inputs may name). Bad input
// may only end in the documented errors (std::invalid_argument, core::LimitError); anything
// else is a bug.

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/sim/scenario.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::ofstream(fmcw::fuzz::scratch_dir() / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fmcw::fuzz::write_input("scenario.yaml", data, size);
  try {
    // A budget well under libFuzzer's -rss_limit_mb (2 GB): an input that asks for more is
    // refused by the estimate, the path a user's file takes too.
    (void)fmcw::sim::load_scenario(path, std::uint64_t{512} << 20);
  } catch (const std::invalid_argument&) {  // core::FileError, core::InputError
  } catch (const fmcw::core::LimitError&) {
  }
  return 0;
}
