#pragma once
// What a reader checks of a file before it reads it, and lines read with a bound: a file that
// is not what it claims costs an error, not its size in memory.

#include <cstdint>
#include <istream>
#include <string>

namespace fmcw::io {

/// The size of the file at `path` [bytes], checked before the file is opened. Throws
/// core::FileError naming the path when it cannot be found ("cannot open <what>: ..."),
/// is a directory ("is a directory") or is not a regular file ("is not a regular file": a FIFO
/// would block the reader and a device such as /dev/zero never ends).
std::uintmax_t regular_file_size(const std::string& path, const std::string& what);

enum class LineRead {
  kLine,     ///< a line, without its '\n'
  kEnd,      ///< the end of the stream, nothing read
  kTooLong,  ///< more than max_bytes before a '\n'; the rest of the line is not read
};

/// Reads one line of at most max_bytes characters. Unlike std::getline, a stream without a
/// newline costs max_bytes, not the stream's size. A '\r' before the '\n' stays in the line.
LineRead read_bounded_line(std::istream& in, std::string& line, std::size_t max_bytes);

}  // namespace fmcw::io
