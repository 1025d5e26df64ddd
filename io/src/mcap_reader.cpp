#include "fmcw/io/mcap_reader.hpp"

#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "fmcw/core/check.hpp"
#include "mcap_records.hpp"

namespace fmcw::io {

using core::concat;
using mcap::ByteCursor;

namespace mcap {
const char* op_name(std::uint8_t op) {
  static const char* const names[] = {"?",          "Header",        "Footer",     "Schema",       "Channel",
                                      "Message",    "Chunk",         "MessageIndex", "ChunkIndex", "Attachment",
                                      "AttachmentIndex", "Statistics", "Metadata",   "MetadataIndex", "SummaryOffset",
                                      "DataEnd"};
  return op <= kDataEnd ? names[op] : "unknown";
}
}  // namespace mcap

namespace {
// A chunk's records are held in memory: one over this is refused rather than allocated.
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;
constexpr std::uint64_t kFooterBytes = 9 + 8 + 8 + 4;

std::string hex(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08x", v);
  return buf;
}

// The records of a Chunk record's content (specification, "Chunk"), uncompressed and checked.
std::vector<std::uint8_t> decode_chunk(const std::uint8_t* content, std::size_t n, const std::string& where,
                                        bool verify) {
  ByteCursor c(content, n, where);
  c.u64();  // message_start_time
  c.u64();  // message_end_time
  const std::uint64_t uncompressed = c.u64();
  const std::uint32_t crc = c.u32();
  const std::string compression = c.str("compression");
  const std::uint64_t length = c.u64();
  const std::uint8_t* records = c.take(length, "records");
  FMCW_CHECK_FILE(c.left() == 0, where, ": ", c.left(), " bytes after the chunk's records");
  FMCW_CHECK_LIMIT(uncompressed <= kMaxChunkBytes, where, ": a chunk of ", uncompressed,
                   " bytes uncompressed is over the reader's limit of 1 GiB");
  std::vector<std::uint8_t> out;
  if (compression.empty()) {
    FMCW_CHECK_FILE(length == uncompressed, where, ": uncompressed chunk of ", length, " bytes but uncompressed_size ",
                    uncompressed);
    out.assign(records, records + length);
  } else if (compression == "zstd") {
    out.resize(static_cast<std::size_t>(uncompressed));
    const std::size_t got = ZSTD_decompress(out.data(), out.size(), records, static_cast<std::size_t>(length));
    if (ZSTD_isError(got)) {
      throw core::FileError(concat(where, ": zstd chunk does not decompress: ", ZSTD_getErrorName(got)));
    }
    FMCW_CHECK_FILE(got == uncompressed, where, ": zstd chunk decompresses to ", got, " bytes, uncompressed_size says ",
                    uncompressed);
  } else {
    throw core::FileError(concat(where, ": chunk compression '", compression, "' is not supported (none, zstd)"));
  }
  if (verify && crc != 0) {
    const std::uint32_t actual = mcap::crc32_update(0, out.data(), out.size());
    if (actual != crc) {
      throw core::FileError(concat(where, ": bad CRC: the chunk's records have CRC-32 ", hex(actual),
                                   ", uncompressed_crc says ", hex(crc)));
    }
  }
  return out;
}

struct Record {
  std::uint8_t op;
  std::uint64_t offset;  ///< of the opcode
  const std::uint8_t* content;
  std::size_t length;
};

// The records of a buffer (a chunk's records): calls f for each.
template <typename F>
void for_each_record(const std::vector<std::uint8_t>& buf, const std::string& where, F&& f) {
  std::size_t pos = 0;
  while (pos < buf.size()) {
    FMCW_CHECK_FILE(buf.size() - pos >= 9, where, ": record at offset ", pos, " in the chunk: header cut off");
    std::uint64_t len = 0;
    std::memcpy(&len, &buf[pos + 1], 8);
    FMCW_CHECK_FILE(len <= buf.size() - pos - 9, where, ": record at offset ", pos, " in the chunk (",
                    mcap::op_name(buf[pos]), ", ", len, " bytes) runs past the chunk's end");
    f(Record{buf[pos], pos, buf.data() + pos + 9, static_cast<std::size_t>(len)});
    pos += 9 + static_cast<std::size_t>(len);
  }
}
}  // namespace

struct McapReader::Scan {
  McapReader& r;
  const std::string& topic;
  std::map<std::uint16_t, std::pair<std::string, std::string>> schemas;  // id -> name, encoding

  std::string at(std::uint64_t offset, std::uint8_t op) const {
    return concat(r.path_, ": record at offset ", offset, " (", mcap::op_name(op), ")");
  }

  void schema(const Record& rec, const std::string& where) {
    ByteCursor c(rec.content, rec.length, where);
    const std::uint16_t id = c.u16();
    std::string name = c.str("name");
    std::string encoding = c.str("encoding");
    c.take(c.u32(), "data");
    FMCW_CHECK_FILE(id != 0, where, ": schema id 0 is reserved");
    schemas.emplace(id, std::make_pair(std::move(name), std::move(encoding)));
  }

  void channel(const Record& rec, const std::string& where, std::uint64_t file_offset) {
    ByteCursor c(rec.content, rec.length, where);
    McapChannel ch;
    ch.id = c.u16();
    ch.schema_id = c.u16();
    ch.topic = c.str("topic");
    ch.message_encoding = c.str("message_encoding");
    c.take(c.u32(), "metadata");
    ch.record_offset = file_offset;
    if (r.channel_at_.count(ch.id)) return;  // a channel may be repeated (in chunks, in the summary)
    if (ch.schema_id != 0) {
      const auto s = schemas.find(ch.schema_id);
      FMCW_CHECK_FILE(s != schemas.end(), where, ": channel '", ch.topic, "' names schema id ", ch.schema_id,
                      ", which no Schema record before it defines");
      ch.schema_name = s->second.first;
      ch.schema_encoding = s->second.second;
    }
    r.channel_at_[ch.id] = r.channels_.size();
    if (ch.topic == topic && r.topic_channel_ < 0) r.topic_channel_ = static_cast<int>(r.channels_.size());
    r.channels_.push_back(std::move(ch));
  }

  void message(const Record& rec, const std::string& where, std::uint64_t chunk) {
    ByteCursor c(rec.content, rec.length, where);
    const std::uint16_t id = c.u16();
    c.u32();  // sequence
    const std::uint64_t log_time = c.u64();
    c.u64();  // publish_time
    const auto ch = r.channel_at_.find(id);
    FMCW_CHECK_FILE(ch != r.channel_at_.end(), where, ": message on channel ", id,
                    ", which no Channel record before it defines");
    ++r.channels_[ch->second].messages;
    if (static_cast<int>(ch->second) == r.topic_channel_) r.messages_.push_back({chunk, rec.offset, log_time});
  }

  void metadata(const Record& rec, const std::string& where) {
    ByteCursor c(rec.content, rec.length, where);
    const std::string name = c.str("name");
    const std::uint32_t n = c.u32();
    ByteCursor m(c.take(n, "metadata"), n, where);
    McapEntries entries;
    while (m.left() > 0) {
      std::string key = m.str("metadata key");
      entries.emplace_back(std::move(key), m.str("metadata value"));
    }
    r.metadata_[name] = std::move(entries);
  }

  void chunk(const Record& rec, const std::string& where) {
    const std::vector<std::uint8_t> records = decode_chunk(rec.content, rec.length, where, true);
    const std::string inner = concat(r.path_, ": chunk at offset ", rec.offset);
    for_each_record(records, inner, [&](const Record& in) {
      const std::string w = concat(inner, ", record at offset ", in.offset, " in it (", mcap::op_name(in.op), ")");
      if (in.op == mcap::kSchema) schema(in, w);
      if (in.op == mcap::kChannel) channel(in, w, rec.offset);
      if (in.op == mcap::kMessage) message(in, w, rec.offset);
    });
  }
};

McapReader::McapReader(const std::string& path, const std::string& topic) : path_(path) {
  in_.open(path, std::ios::binary);
  FMCW_CHECK_FILE(in_.good(), path, ": cannot open");
  in_.seekg(0, std::ios::end);
  size_ = static_cast<std::uint64_t>(in_.tellg());
  in_.seekg(0);
  scan(topic);
}

McapReader::~McapReader() = default;

const McapChannel* McapReader::topic_channel() const {
  return topic_channel_ < 0 ? nullptr : &channels_[static_cast<std::size_t>(topic_channel_)];
}

void McapReader::scan(const std::string& topic) {
  const auto read_at = [&](std::uint64_t offset, std::uint64_t n) {
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(n));
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(n));
    FMCW_CHECK_FILE(static_cast<std::uint64_t>(in_.gcount()) == n, path_, ": read error at offset ", offset);
    return buf;
  };
  FMCW_CHECK_FILE(size_ >= 8, path_, ": offset 0: ", size_, " bytes: not an MCAP file (no magic)");
  FMCW_CHECK_FILE(std::memcmp(read_at(0, 8).data(), mcap::kMagic, 8) == 0, path_,
                  ": offset 0: not an MCAP file (no MCAP magic)");
  FMCW_CHECK_FILE(size_ >= 8 + 9 + kFooterBytes + 8, path_, ": offset ", size_, ": the file ends after ", size_,
                  " bytes, before its footer: truncated");
  FMCW_CHECK_FILE(std::memcmp(read_at(size_ - 8, 8).data(), mcap::kMagic, 8) == 0, path_, ": offset ", size_ - 8,
                  ": no closing magic: the file is truncated (or was not finished)");
  // Footer (specification, "Footer"): summary_start, summary_offset_start, summary_crc.
  const std::uint64_t footer = size_ - 8 - kFooterBytes;
  const std::vector<std::uint8_t> f = read_at(footer, kFooterBytes);
  std::uint64_t length = 0, summary_start = 0;
  std::uint32_t summary_crc = 0;
  std::memcpy(&length, &f[1], 8);
  std::memcpy(&summary_start, &f[9], 8);
  std::memcpy(&summary_crc, &f[25], 4);
  FMCW_CHECK_FILE(f[0] == mcap::kFooter && length == kFooterBytes - 9, path_, ": record at offset ", footer,
                  ": expected the Footer (opcode 0x02, 20 bytes), found opcode ", int(f[0]), " of ", length, " bytes");
  FMCW_CHECK_FILE(summary_start == 0 || (summary_start >= 8 && summary_start <= footer), path_, ": record at offset ",
                  footer, " (Footer): summary_start ", summary_start, " lies outside the file");
  if (summary_start != 0 && summary_crc != 0) {
    const std::vector<std::uint8_t> summary = read_at(summary_start, footer + 9 + 16 - summary_start);
    const std::uint32_t actual = mcap::crc32_update(0, summary.data(), summary.size());
    FMCW_CHECK_FILE(actual == summary_crc, path_, ": record at offset ", footer, " (Footer): bad CRC: the summary has CRC-32 ",
                    hex(actual), ", summary_crc says ", hex(summary_crc));
  }
  // The data section, front to back (specification, "Data Section").
  const std::uint64_t data_end = summary_start != 0 ? summary_start : footer;
  Scan scan{*this, topic, {}};
  std::uint32_t crc = mcap::crc32_update(0, mcap::kMagic, 8);
  std::uint64_t pos = 8;
  bool first = true;
  while (pos < data_end) {
    FMCW_CHECK_FILE(data_end - pos >= 9, path_, ": record at offset ", pos, ": its header is cut off at ", data_end,
                    ": truncated");
    const std::vector<std::uint8_t> head = read_at(pos, 9);
    std::uint64_t len = 0;
    std::memcpy(&len, &head[1], 8);
    const std::string where = scan.at(pos, head[0]);
    FMCW_CHECK_FILE(len <= data_end - pos - 9, where, ": ", len, " bytes run past the end of the data at offset ",
                    data_end, ": truncated");
    FMCW_CHECK_FILE(!first || head[0] == mcap::kHeader, where, ": the first record must be the Header");
    first = false;
    if (head[0] == mcap::kDataEnd) {
      const std::vector<std::uint8_t> content = read_at(pos + 9, len);
      ByteCursor c(content.data(), content.size(), where);
      const std::uint32_t stated = c.u32();
      FMCW_CHECK_FILE(stated == 0 || stated == crc, where, ": bad CRC: the data section has CRC-32 ", hex(crc),
                      ", DataEnd says ", hex(stated));
      break;
    }
    const std::vector<std::uint8_t> content = read_at(pos + 9, len);
    crc = mcap::crc32_update(mcap::crc32_update(crc, head.data(), 9), content.data(), content.size());
    const Record rec{head[0], pos, content.data(), content.size()};
    switch (head[0]) {
      case mcap::kSchema: scan.schema(rec, where); break;
      case mcap::kChannel: scan.channel(rec, where, pos); break;
      case mcap::kMessage: scan.message(rec, where, 0); break;
      case mcap::kChunk: scan.chunk(rec, where); break;
      case mcap::kMetadata: scan.metadata(rec, where); break;
      default: break;  // indexes, attachments, records of later versions: not needed here
    }
    pos += 9 + len;
  }
}

const std::vector<std::uint8_t>& McapReader::chunk_records(std::uint64_t offset, bool verify) {
  if (cached_chunk_ != offset || cached_records_.empty()) {
    std::uint8_t head[9];
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(reinterpret_cast<char*>(head), 9);
    std::uint64_t len = 0;
    std::memcpy(&len, head + 1, 8);
    FMCW_CHECK_FILE(in_.gcount() == 9 && head[0] == mcap::kChunk && len <= size_ - offset - 9, path_,
                    ": record at offset ", offset, ": not the chunk it was (did the file change?)");
    std::vector<std::uint8_t> content(static_cast<std::size_t>(len));
    in_.read(reinterpret_cast<char*>(content.data()), static_cast<std::streamsize>(len));
    FMCW_CHECK_FILE(static_cast<std::uint64_t>(in_.gcount()) == len, path_, ": read error at offset ", offset);
    cached_records_ = decode_chunk(content.data(), content.size(),
                                        concat(path_, ": record at offset ", offset, " (Chunk)"), verify);
    cached_chunk_ = offset;
  }
  return cached_records_;
}

McapMessage McapReader::message(std::size_t k) {
  FMCW_CHECK_ARG(k < messages_.size(), "McapReader: message ", k, " of ", messages_.size());
  const Location& at = messages_[k];
  McapMessage m;
  m.log_time_ns = at.log_time_ns;
  std::vector<std::uint8_t> content;
  if (at.chunk == 0) {
    std::uint8_t head[9];
    in_.seekg(static_cast<std::streamoff>(at.offset));
    in_.read(reinterpret_cast<char*>(head), 9);
    std::uint64_t len = 0;
    std::memcpy(&len, head + 1, 8);
    content.resize(static_cast<std::size_t>(len));
    in_.read(reinterpret_cast<char*>(content.data()), static_cast<std::streamsize>(len));
    m.where = concat(path_, ": message at offset ", at.offset);
  } else {
    const std::vector<std::uint8_t>& records = chunk_records(at.chunk, false);
    std::uint64_t len = 0;
    std::memcpy(&len, &records[at.offset + 1], 8);
    const auto* p = records.data() + at.offset + 9;
    content.assign(p, p + len);
    m.where = concat(path_, ": message at offset ", at.offset, " in the chunk at offset ", at.chunk);
  }
  constexpr std::size_t kMessageHeader = 2 + 4 + 8 + 8;
  m.data.assign(content.begin() + kMessageHeader, content.end());
  return m;
}

}  // namespace fmcw::io
