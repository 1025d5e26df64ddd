#pragma once
// An MCAP writer (https://mcap.dev/spec, major version 0): schemas and channels in the data
// section, messages in chunks (uncompressed or zstd), each chunk followed by its message
// indexes, then DataEnd with the data section's CRC-32, a summary section (schemas, channels,
// statistics, metadata index, chunk indexes), its summary offsets, and the footer with the
// summary's CRC-32, so that a viewer can seek without reading the whole file.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace fmcw::io {

enum class McapCompression { kNone, kZstd };

/// "none" or "zstd"; core::InputError otherwise.
McapCompression parse_mcap_compression(const std::string& text);

struct McapWriterOptions {
  std::string profile = "ros2";  ///< the Header's profile (specification, "Well-known profiles")
  std::string library = "fmcw";
  McapCompression compression = McapCompression::kZstd;
  /// zstd's fast mode -1: on frames about 1.8x the speed of level 1, 7 % larger (docs/PERFORMANCE.md).
  int zstd_level = -1;
};

using McapEntries = std::vector<std::pair<std::string, std::string>>;

class McapWriter {
 public:
  /// Writes the magic and the Header record to out (a binary stream, written front to back).
  McapWriter(std::ostream& out, McapWriterOptions options = {});
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A Schema record (ids from 1); the data is the schema text.
  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  /// A Channel record (ids from 0).
  std::uint16_t add_channel(const std::string& topic, std::uint16_t schema_id, const std::string& message_encoding);
  /// A Metadata record (and its index in the summary).
  void add_metadata(const std::string& name, const McapEntries& entries);
  /// A Message record in the open chunk; log and publish time both `time_ns`.
  void write(std::uint16_t channel, std::uint64_t time_ns, const std::vector<std::uint8_t>& data);
  /// The same, the data appended by `append` straight into the chunk's buffer.
  void write(std::uint16_t channel, std::uint64_t time_ns,
             const std::function<void(std::vector<std::uint8_t>&)>& append);
  /// Closes the open chunk (if it holds a message): the Chunk, then its MessageIndex records.
  void close_chunk();
  /// Closes the chunk, writes DataEnd, the summary, the summary offsets, the footer and the magic.
  void finish();

  std::uint64_t bytes_written() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace fmcw::io
