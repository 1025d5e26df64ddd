#pragma once
// MCAP record primitives shared by the writer and the reader (MCAP specification, "Records" and
// "Serialization"): little-endian integers; a String is a uint32 byte length and the bytes; a
// Bytes field is a uint32 (Schema) or uint64 (Chunk) length and the bytes; Map and Array are a
// uint32 byte length of their entries, then the entries.

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "fmcw/core/check.hpp"

namespace fmcw::io::mcap {

/// The magic that starts and ends a file (specification, "Magic"): 0x89 "MCAP" '0' CR LF.
inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};

/// Record opcodes (specification, "Records").
enum Op : std::uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kMessageIndex = 0x07, kChunkIndex = 0x08, kAttachment = 0x09, kAttachmentIndex = 0x0A, kStatistics = 0x0B,
  kMetadata = 0x0C, kMetadataIndex = 0x0D, kSummaryOffset = 0x0E, kDataEnd = 0x0F,
};

/// CRC-32 (zlib's, the one the specification names) of n bytes, continuing `crc`.
inline std::uint32_t crc32_update(std::uint32_t crc, const std::uint8_t* p, std::size_t n) {
  while (n > 0) {  // zlib takes uInt lengths: in pieces
    const auto piece = static_cast<uInt>(std::min<std::size_t>(n, std::size_t{1} << 30));
    crc = static_cast<std::uint32_t>(crc32(crc, p, piece));
    p += piece;
    n -= piece;
  }
  return crc;
}

/// "Chunk", "Schema", ... for error messages.
const char* op_name(std::uint8_t op);

/// Appends n bytes to v (resize and copy: GCC 12 at -O3 warns falsely of a null argument in
/// vector::insert of a byte range).
inline void append_bytes(std::vector<std::uint8_t>& v, const void* p, std::size_t n) {
  if (n == 0) return;
  const std::size_t at = v.size();
  v.resize(at + n);
  std::memcpy(v.data() + at, p, n);
}

/// A record's content, built field by field.
class RecordBuilder {
 public:
  void u8(std::uint8_t v) { raw(&v, 1); }
  void u16(std::uint16_t v) { raw(&v, 2); }
  void u32(std::uint32_t v) { raw(&v, 4); }
  void u64(std::uint64_t v) { raw(&v, 8); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  void raw(const void* p, std::size_t n) { append_bytes(bytes, p, n); }
  /// Reserves a uint32 byte length to be filled by end_length (Map and Array fields).
  std::size_t begin_length() {
    u32(0);
    return bytes.size();
  }
  void end_length(std::size_t start) {
    const auto n = static_cast<std::uint32_t>(bytes.size() - start);
    std::memcpy(&bytes[start - 4], &n, 4);
  }
  std::vector<std::uint8_t> bytes;
};

/// Reads fields of a record's content; running past its end is a core::FileError naming where.
class ByteCursor {
 public:
  ByteCursor(const std::uint8_t* data, std::size_t size, std::string where)
      : data_(data), size_(size), where_(std::move(where)) {}
  std::uint8_t u8() { std::uint8_t v; get(&v, 1, "uint8"); return v; }
  std::uint16_t u16() { std::uint16_t v; get(&v, 2, "uint16"); return v; }
  std::uint32_t u32() { std::uint32_t v; get(&v, 4, "uint32"); return v; }
  std::uint64_t u64() { std::uint64_t v; get(&v, 8, "uint64"); return v; }
  std::string str(const char* field) {
    const std::uint32_t n = u32();
    need(n, field);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }
  /// A field of n bytes: a pointer to them.
  const std::uint8_t* take(std::uint64_t n, const char* field) {
    need(n, field);
    const std::uint8_t* p = data_ + pos_;
    pos_ += static_cast<std::size_t>(n);
    return p;
  }
  std::size_t pos() const { return pos_; }
  std::size_t left() const { return size_ - pos_; }
  const std::string& where() const { return where_; }

 private:
  void need(std::uint64_t n, const char* field) {
    if (n > size_ - pos_) {
      throw core::FileError(core::concat(where_, ": field '", field, "' of ", n, " bytes at byte ", pos_,
                                         " runs past the record's end (", size_, " bytes)"));
    }
  }
  void get(void* p, std::size_t n, const char* type) {
    need(n, type);
    std::memcpy(p, data_ + pos_, n);
    pos_ += n;
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::string where_;
};

}  // namespace fmcw::io::mcap
