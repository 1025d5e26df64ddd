#include "fmcw/io/mcap_writer.hpp"

#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <tuple>

#include "fmcw/core/check.hpp"
#include "mcap_records.hpp"

namespace fmcw::io {

using core::concat;
using mcap::RecordBuilder;

McapCompression parse_mcap_compression(const std::string& text) {
  if (text == "none") return McapCompression::kNone;
  if (text == "zstd") return McapCompression::kZstd;
  throw core::InputError("MCAP compression must be none or zstd, got '" + text + "'");
}

namespace {
struct ChunkIndexEntry {
  std::uint64_t start_ns, end_ns, offset, length;
  std::map<std::uint16_t, std::uint64_t> index_offsets;
  std::uint64_t index_length;
  std::string compression;
  std::uint64_t compressed, uncompressed;
};
}  // namespace

struct McapWriter::State {
  State(std::ostream& o, McapWriterOptions opt) : out(o), options(std::move(opt)) {}
  std::ostream& out;
  McapWriterOptions options;
  std::uint64_t offset = 0;
  std::uint32_t crc = 0;  ///< of every byte so far: the data section's, then the summary's
  std::vector<RecordBuilder> schemas, channels;  ///< repeated in the summary
  std::vector<std::pair<std::uint64_t, std::uint64_t>> metadata_at;  ///< offset, length
  std::vector<std::string> metadata_names;
  std::vector<ChunkIndexEntry> chunk_index;
  // The open chunk.
  std::vector<std::uint8_t> records;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> message_index;
  std::uint64_t chunk_start_ns = 0, chunk_end_ns = 0;
  // Statistics.
  std::uint64_t messages = 0, start_ns = 0, end_ns = 0;
  std::map<std::uint16_t, std::uint64_t> per_channel;
  bool finished = false;
  // Kept from chunk to chunk: a compression context and buffer allocated (and faulted in) once.
  std::unique_ptr<ZSTD_CCtx, std::size_t (*)(ZSTD_CCtx*)> zstd{nullptr, ZSTD_freeCCtx};
  std::vector<std::uint8_t> packed;

  void put(const std::uint8_t* p, std::size_t n) {
    out.write(reinterpret_cast<const char*>(p), static_cast<std::streamsize>(n));
    if (!out) throw std::runtime_error("MCAP: write failed (disk full?)");
    crc = mcap::crc32_update(crc, p, n);
    offset += n;
  }
  // <opcode><uint64 content length><content> (specification, "Records").
  void emit(std::uint8_t op, const std::vector<std::uint8_t>& content) {
    std::uint8_t head[9];
    head[0] = op;
    const std::uint64_t n = content.size();
    std::memcpy(head + 1, &n, 8);
    put(head, 9);
    put(content.data(), content.size());
  }
};

McapWriter::McapWriter(std::ostream& out, McapWriterOptions options) : s_(std::make_unique<State>(out, std::move(options))) {
  s_->put(mcap::kMagic, 8);
  RecordBuilder h;  // Header: profile, library
  h.str(s_->options.profile);
  h.str(s_->options.library);
  s_->emit(mcap::kHeader, h.bytes);
}

McapWriter::~McapWriter() = default;

std::uint64_t McapWriter::bytes_written() const { return s_->offset; }

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  FMCW_CHECK_LIMIT(s_->schemas.size() < 65535, "MCAP: too many schemas");
  const auto id = static_cast<std::uint16_t>(s_->schemas.size() + 1);  // 0 means "no schema"
  RecordBuilder r;  // Schema: id, name, encoding, data (uint32 length)
  r.u16(id);
  r.str(name);
  r.str(encoding);
  r.str(data);
  s_->emit(mcap::kSchema, r.bytes);
  s_->schemas.push_back(std::move(r));
  return id;
}

std::uint16_t McapWriter::add_channel(const std::string& topic, std::uint16_t schema_id,
                                      const std::string& message_encoding) {
  FMCW_CHECK_LIMIT(s_->channels.size() < 65535, "MCAP: too many channels");
  const auto id = static_cast<std::uint16_t>(s_->channels.size());
  RecordBuilder r;  // Channel: id, schema_id, topic, message_encoding, metadata (empty map)
  r.u16(id);
  r.u16(schema_id);
  r.str(topic);
  r.str(message_encoding);
  r.u32(0);
  s_->emit(mcap::kChannel, r.bytes);
  s_->channels.push_back(std::move(r));
  s_->per_channel[id] = 0;
  return id;
}

void McapWriter::add_metadata(const std::string& name, const McapEntries& entries) {
  close_chunk();
  RecordBuilder r;  // Metadata: name, metadata (Map<string, string>)
  r.str(name);
  const std::size_t map = r.begin_length();
  for (const auto& [k, v] : entries) {
    r.str(k);
    r.str(v);
  }
  r.end_length(map);
  s_->metadata_at.emplace_back(s_->offset, 9 + r.bytes.size());
  s_->metadata_names.push_back(name);
  s_->emit(mcap::kMetadata, r.bytes);
}

void McapWriter::write(std::uint16_t channel, std::uint64_t time_ns, const std::vector<std::uint8_t>& data) {
  write(channel, time_ns, [&](std::vector<std::uint8_t>& out) { mcap::append_bytes(out, data.data(), data.size()); });
}

void McapWriter::write(std::uint16_t channel, std::uint64_t time_ns,
                       const std::function<void(std::vector<std::uint8_t>&)>& append) {
  FMCW_CHECK_ARG(channel < s_->channels.size(), "MCAP: no channel ", channel);
  State& s = *s_;
  if (s.message_index.empty()) s.chunk_start_ns = s.chunk_end_ns = time_ns;
  s.chunk_start_ns = std::min(s.chunk_start_ns, time_ns);
  s.chunk_end_ns = std::max(s.chunk_end_ns, time_ns);
  if (s.messages == 0) s.start_ns = s.end_ns = time_ns;
  s.start_ns = std::min(s.start_ns, time_ns);
  s.end_ns = std::max(s.end_ns, time_ns);
  // MessageIndex offsets count from the start of the chunk's uncompressed records.
  const std::size_t start = s.records.size();
  s.message_index[channel].emplace_back(time_ns, start);
  RecordBuilder r;  // Message: channel_id, sequence, log_time, publish_time, then the data
  r.u8(mcap::kMessage);
  r.u64(0);  // the content's length, known once the data is in
  r.u16(channel);
  r.u32(static_cast<std::uint32_t>(s.per_channel[channel]));
  r.u64(time_ns);
  r.u64(time_ns);
  mcap::append_bytes(s.records, r.bytes.data(), r.bytes.size());
  append(s.records);
  const std::uint64_t length = s.records.size() - start - 9;
  std::memcpy(&s.records[start + 1], &length, 8);
  ++s.per_channel[channel];
  ++s.messages;
}

void McapWriter::close_chunk() {
  State& s = *s_;
  if (s.message_index.empty()) return;
  ChunkIndexEntry e;
  e.start_ns = s.chunk_start_ns;
  e.end_ns = s.chunk_end_ns;
  e.offset = s.offset;
  e.uncompressed = s.records.size();
  const std::uint32_t records_crc = mcap::crc32_update(0, s.records.data(), s.records.size());
  const std::uint8_t* payload = s.records.data();
  std::size_t payload_size = s.records.size();
  if (s.options.compression == McapCompression::kZstd) {
    e.compression = "zstd";
    if (!s.zstd) s.zstd.reset(ZSTD_createCCtx());
    if (!s.zstd) throw std::runtime_error("MCAP: zstd: cannot create a compression context");
    const std::size_t bound = ZSTD_compressBound(s.records.size());
    if (s.packed.size() < bound) s.packed.resize(bound);
    payload_size = ZSTD_compressCCtx(s.zstd.get(), s.packed.data(), s.packed.size(), s.records.data(),
                                     s.records.size(), s.options.zstd_level);
    if (ZSTD_isError(payload_size)) throw std::runtime_error(concat("MCAP: zstd: ", ZSTD_getErrorName(payload_size)));
    payload = s.packed.data();
  }
  e.compressed = payload_size;
  // Chunk: message_start_time, message_end_time, uncompressed_size, uncompressed_crc,
  // compression, records (uint64 length).
  RecordBuilder c;
  c.u8(mcap::kChunk);
  c.u64(8 + 8 + 8 + 4 + 4 + e.compression.size() + 8 + payload_size);
  c.u64(e.start_ns);
  c.u64(e.end_ns);
  c.u64(e.uncompressed);
  c.u32(records_crc);
  c.str(e.compression);
  c.u64(payload_size);
  s.put(c.bytes.data(), c.bytes.size());
  s.put(payload, payload_size);
  e.length = s.offset - e.offset;
  // MessageIndex per channel of the chunk: channel_id, records (Array<Tuple<timestamp, offset>>).
  const std::uint64_t index_start = s.offset;
  for (const auto& [channel, entries] : s.message_index) {
    RecordBuilder m;
    m.u16(channel);
    const std::size_t array = m.begin_length();
    for (const auto& [t, off] : entries) {
      m.u64(t);
      m.u64(off);
    }
    m.end_length(array);
    e.index_offsets[channel] = s.offset;
    s.emit(mcap::kMessageIndex, m.bytes);
  }
  e.index_length = s.offset - index_start;
  s.chunk_index.push_back(std::move(e));
  s.records.clear();
  s.message_index.clear();
}

void McapWriter::finish() {
  State& s = *s_;
  FMCW_CHECK_ARG(!s.finished, "MCAP: finish() called twice");
  close_chunk();
  RecordBuilder end;  // DataEnd: data_section_crc, of every byte from the magic up to here
  end.u32(s.crc);
  s.emit(mcap::kDataEnd, end.bytes);
  const std::uint64_t summary_start = s.offset;
  s.crc = 0;  // the summary CRC starts at the summary section
  std::vector<std::tuple<std::uint8_t, std::uint64_t, std::uint64_t>> groups;  // opcode, start, length
  const auto group = [&](std::uint8_t op, const auto& write_all) {
    const std::uint64_t start = s.offset;
    write_all();
    if (s.offset > start) groups.emplace_back(op, start, s.offset - start);
  };
  group(mcap::kSchema, [&] { for (const auto& r : s.schemas) s.emit(mcap::kSchema, r.bytes); });
  group(mcap::kChannel, [&] { for (const auto& r : s.channels) s.emit(mcap::kChannel, r.bytes); });
  group(mcap::kStatistics, [&] {
    RecordBuilder r;  // Statistics
    r.u64(s.messages);
    r.u16(static_cast<std::uint16_t>(s.schemas.size()));
    r.u32(static_cast<std::uint32_t>(s.channels.size()));
    r.u32(0);  // attachments
    r.u32(static_cast<std::uint32_t>(s.metadata_at.size()));
    r.u32(static_cast<std::uint32_t>(s.chunk_index.size()));
    r.u64(s.start_ns);
    r.u64(s.end_ns);
    const std::size_t map = r.begin_length();
    for (const auto& [channel, n] : s.per_channel) {
      r.u16(channel);
      r.u64(n);
    }
    r.end_length(map);
    s.emit(mcap::kStatistics, r.bytes);
  });
  group(mcap::kMetadataIndex, [&] {
    for (std::size_t k = 0; k < s.metadata_at.size(); ++k) {
      RecordBuilder r;  // MetadataIndex: offset, length, name
      r.u64(s.metadata_at[k].first);
      r.u64(s.metadata_at[k].second);
      r.str(s.metadata_names[k]);
      s.emit(mcap::kMetadataIndex, r.bytes);
    }
  });
  group(mcap::kChunkIndex, [&] {
    for (const ChunkIndexEntry& e : s.chunk_index) {
      RecordBuilder r;  // ChunkIndex
      r.u64(e.start_ns);
      r.u64(e.end_ns);
      r.u64(e.offset);
      r.u64(e.length);
      const std::size_t map = r.begin_length();
      for (const auto& [channel, off] : e.index_offsets) {
        r.u16(channel);
        r.u64(off);
      }
      r.end_length(map);
      r.u64(e.index_length);
      r.str(e.compression);
      r.u64(e.compressed);
      r.u64(e.uncompressed);
      s.emit(mcap::kChunkIndex, r.bytes);
    }
  });
  const std::uint64_t offsets_start = s.offset;
  for (const auto& [op, start, length] : groups) {
    RecordBuilder r;  // SummaryOffset: group_opcode, group_start, group_length
    r.u8(op);
    r.u64(start);
    r.u64(length);
    s.emit(mcap::kSummaryOffset, r.bytes);
  }
  // Footer: summary_start, summary_offset_start, summary_crc. The CRC covers the summary section
  // up to and including summary_offset_start (specification, "Footer").
  RecordBuilder f;
  f.u8(mcap::kFooter);
  f.u64(8 + 8 + 4);
  f.u64(summary_start);
  f.u64(offsets_start);
  s.put(f.bytes.data(), f.bytes.size());
  const std::uint32_t summary_crc = s.crc;
  s.put(reinterpret_cast<const std::uint8_t*>(&summary_crc), 4);
  s.put(mcap::kMagic, 8);
  s.finished = true;
}

}  // namespace fmcw::io
