#pragma once
// An MCAP reader (https://mcap.dev/spec): reads the file front to back once, checking the magic
// at both ends, every record's length, the Footer and the summary's CRC-32, each chunk's
// uncompressed CRC-32 and the data section's (DataEnd), and remembers where the messages of one
// topic lie; message(k) then reads the k-th of them. Chunks may be uncompressed or zstd.
// Every error is one core::FileError naming the file, the record's offset and what is wrong
// (a core::LimitError for sizes beyond the reader's limits).

#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fmcw/io/mcap_writer.hpp"

namespace fmcw::io {

struct McapChannel {
  std::uint16_t id = 0;
  std::string topic;
  std::string message_encoding;
  std::uint16_t schema_id = 0;
  std::string schema_name;      ///< "" when the channel has no schema (schema_id 0)
  std::string schema_encoding;
  std::uint64_t record_offset = 0;  ///< of its Channel record
  std::uint64_t messages = 0;
};

/// One message of the chosen topic.
struct McapMessage {
  std::uint64_t log_time_ns = 0;
  std::vector<std::uint8_t> data;
  std::string where;  ///< "FILE: message at offset N in the chunk at offset C" for errors
};

class McapReader {
 public:
  /// Reads and checks the file, remembering the messages on `topic` ("" for none).
  McapReader(const std::string& path, const std::string& topic);
  ~McapReader();

  const std::string& path() const { return path_; }
  const std::vector<McapChannel>& channels() const { return channels_; }
  /// The channel of the topic, nullptr when no channel has it.
  const McapChannel* topic_channel() const;
  /// Metadata records by name (a later record of the same name replaces an earlier one).
  const std::map<std::string, McapEntries>& metadata() const { return metadata_; }
  /// Messages on the topic, in file order.
  std::size_t size() const { return messages_.size(); }
  McapMessage message(std::size_t k);

 private:
  struct Location {
    std::uint64_t chunk = 0;   ///< offset of the Chunk record; 0 for a message outside chunks
    std::uint64_t offset = 0;  ///< in the chunk's records, or in the file
    std::uint64_t log_time_ns = 0;
  };
  struct Scan;
  void scan(const std::string& topic);
  const std::vector<std::uint8_t>& chunk_records(std::uint64_t chunk_offset, bool verify);

  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::vector<McapChannel> channels_;
  std::map<std::uint16_t, std::size_t> channel_at_;
  std::map<std::string, McapEntries> metadata_;
  std::vector<Location> messages_;
  int topic_channel_ = -1;
  std::uint64_t cached_chunk_ = 0;
  std::vector<std::uint8_t> cached_records_;
};

}  // namespace fmcw::io
