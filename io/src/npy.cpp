#include "fmcw/io/npy.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"

namespace fmcw::io {

using core::concat;

namespace {
constexpr char kMagic[] = "\x93NUMPY";        // 6 bytes, then the version
constexpr std::size_t kPreamble = 6 + 2 + 2;  // magic, version 1.0, header length
constexpr std::size_t kAlignment = 64;
}  // namespace

std::string npy_f32_header(std::size_t rows, std::size_t cols) {
  std::string dict = concat("{'descr': '<f4', 'fortran_order': False, 'shape': (", rows, ", ", cols, "), }");
  // Spaces, then the newline, up to the next multiple of 64 bytes from the file's start.
  const std::size_t unpadded = kPreamble + dict.size() + 1;
  dict.append((kAlignment - unpadded % kAlignment) % kAlignment, ' ');
  dict.push_back('\n');
  FMCW_CHECK_ARG(dict.size() <= 0xFFFF, "npy: header of ", dict.size(), " bytes does not fit format 1.0");
  std::string header(kMagic, 6);
  header.push_back('\x01');
  header.push_back('\x00');
  header.push_back(static_cast<char>(dict.size() & 0xFFu));
  header.push_back(static_cast<char>((dict.size() >> 8) & 0xFFu));
  return header + dict;
}

void write_npy_f32(const std::string& path, const std::vector<float>& values, std::size_t rows, std::size_t cols) {
  FMCW_CHECK_ARG(values.size() == rows * cols, path, ": ", values.size(), " values for a ", rows, " x ", cols,
                 " array");
  std::string body;
  body.reserve(4 * values.size());
  for (const float v : values) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, 4);
    for (int b = 0; b < 4; ++b) body.push_back(static_cast<char>((bits >> (8 * b)) & 0xFFu));  // little-endian
  }
  const std::string header = npy_f32_header(rows, cols);
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

}  // namespace fmcw::io
