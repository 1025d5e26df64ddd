#pragma once
// OMG CDR (little endian, XCDR1 alignment) as ROS 2 serialises its messages (rmw's
// "cdr" message encoding): a 4-byte encapsulation header (0x00 0x01 0x00 0x00 = CDR_LE), then
// every primitive aligned to its own size counted from the end of that header; strings as a
// uint32 length that includes the terminating NUL, the bytes, the NUL; sequences as a uint32
// element count, then the elements.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fmcw::io {

class CdrWriter {
 public:
  CdrWriter();  ///< starts with the CDR_LE encapsulation header
  /// Appends the message (header first) to `out`, whose earlier bytes it leaves alone.
  explicit CdrWriter(std::vector<std::uint8_t>& out);
  CdrWriter(const CdrWriter&) = delete;
  CdrWriter& operator=(const CdrWriter&) = delete;
  void reserve(std::size_t bytes) { buf_->reserve(origin_ + bytes); }

  void u8(std::uint8_t v) { put(&v, 1, 1); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void u32(std::uint32_t v) { put(&v, 4, 4); }
  void i32(std::int32_t v) { put(&v, 4, 4); }
  void f32(float v) { put(&v, 4, 4); }
  void f64(double v) { put(&v, 8, 8); }
  void string(const std::string& s);
  /// A uint8[] sequence: its length, then the bytes.
  void bytes(const std::uint8_t* data, std::size_t size);
  /// A sequence's element count (the elements follow, written by the caller).
  void count(std::size_t n);

  /// The message (of a writer that owns its buffer).
  std::vector<std::uint8_t> take() { return std::move(own_); }

 private:
  void put(const void* p, std::size_t size, std::size_t align);
  std::vector<std::uint8_t> own_;
  std::vector<std::uint8_t>* buf_;
  std::size_t origin_ = 0;  ///< where the message starts in *buf_
};

/// Reads what CdrWriter writes, bounds-checked: running past the end or a malformed string or
/// count throws core::FileError "<where>: <what>".
class CdrReader {
 public:
  /// Checks the encapsulation header (CDR_LE only: what ROS 2 writes on little-endian machines).
  CdrReader(const std::uint8_t* data, std::size_t size, std::string where);

  std::uint8_t u8() { std::uint8_t v; get(&v, 1, 1); return v; }
  bool boolean() { return u8() != 0; }
  std::uint32_t u32() { std::uint32_t v; get(&v, 4, 4); return v; }
  std::int32_t i32() { std::int32_t v; get(&v, 4, 4); return v; }
  double f64() { double v; get(&v, 8, 8); return v; }
  std::string string(const char* field);
  /// A sequence's element count, checked against the bytes left (each element >= min_element_size).
  std::size_t count(const char* field, std::size_t min_element_size);
  /// A uint8[] sequence: a pointer into the buffer and its length.
  const std::uint8_t* bytes(const char* field, std::size_t& size);

 private:
  void get(void* p, std::size_t size, std::size_t align);
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 4;
  std::string where_;
};

}  // namespace fmcw::io
