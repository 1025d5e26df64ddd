// libFuzzer target: the PCD reader, a frame built from what it read, and the default motion
// method on that frame. Bad input may only end in the documented errors (core::FileError or
// core::InputError, both std::invalid_argument, or core::LimitError); any other exception, a
// crash, a leak, undefined behaviour or a runaway allocation is a bug.

#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/io/pcd.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fmcw::fuzz::write_input("input.pcd", data, size);
  try {
    const fmcw::io::PcdCloud cloud = fmcw::io::read_pcd(path);
    const fmcw::core::Frame frame = fmcw::io::frame_from_pcd(cloud, path);
    // Keep each input cheap: the motion methods run on clouds of the size a fuzzer makes.
    if (frame.scan.size() <= 4096) {
      static fmcw::core::MotionPipeline pipeline;
      (void)pipeline.process(frame.scan);
    }
  } catch (const std::invalid_argument&) {  // core::FileError, core::InputError
  } catch (const fmcw::core::LimitError&) {
  }
  return 0;
}
