#include "fmcw/io/input_file.hpp"

#include <filesystem>
#include <stdexcept>

#include "fmcw/core/check.hpp"

namespace fmcw::io {

using core::concat;
namespace fs = std::filesystem;

namespace {
const char* kind_of(fs::file_type type) {
  switch (type) {
    case fs::file_type::fifo: return "a FIFO";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::socket: return "a socket";
    default: return "not a file that can be read to its end";
  }
}
}  // namespace

std::uintmax_t regular_file_size(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);  // follows symbolic links
  if (ec || status.type() == fs::file_type::not_found) {
    throw core::FileError(concat(path, ": cannot open ", what, ": ",
                                 ec ? ec.message() : std::string("No such file or directory")));
  }
  if (status.type() == fs::file_type::directory) throw core::FileError(concat(path, ": is a directory, not a ", what));
  if (status.type() != fs::file_type::regular) {
    throw core::FileError(concat(path, ": is not a regular file (", kind_of(status.type()), "); ", what,
                                 "s are read from regular files only"));
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw core::FileError(concat(path, ": cannot read the size of the ", what, ": ", ec.message()));
  return size;
}

LineRead read_bounded_line(std::istream& in, std::string& line, std::size_t max_bytes) {
  using Traits = std::istream::traits_type;
  line.clear();
  std::streambuf* buf = in.rdbuf();
  for (;;) {
    const Traits::int_type c = buf->sbumpc();
    if (Traits::eq_int_type(c, Traits::eof())) {
      in.setstate(std::ios::eofbit);
      return line.empty() ? LineRead::kEnd : LineRead::kLine;
    }
    if (Traits::to_char_type(c) == '\n') return LineRead::kLine;
    if (line.size() == max_bytes) return LineRead::kTooLong;
    line.push_back(Traits::to_char_type(c));
  }
}

}  // namespace fmcw::io
