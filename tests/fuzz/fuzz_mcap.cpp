// libFuzzer target: the MCAP reader (records, chunks, zstd, CRCs), the PointCloud2 decoding of
// the /points messages, and each cloud made into a frame as `fmcw process --format mcap` does
// (organized, or projected onto the grid). Bad input may only end in the documented errors
// (core::FileError or core::InputError, both std::invalid_argument, or core::LimitError); any
// other exception, a crash, a leak, undefined behaviour or a runaway allocation is a bug.

#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/io/frame_input.hpp"
#include "fmcw/io/input_sequence.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fmcw::fuzz::write_input("input.mcap", data, size);
  try {
    fmcw::io::InputOptions options;
    options.format = fmcw::io::InputFormat::kMcap;
    fmcw::io::InputSequence frames(path, options);
    // A few frames per input keep each run cheap.
    for (std::size_t k = 0; k < frames.size() && k < 4; ++k) (void)frames.read(k);
  } catch (const std::invalid_argument&) {  // core::FileError, core::InputError
  } catch (const fmcw::core::LimitError&) {
  }
  return 0;
}
