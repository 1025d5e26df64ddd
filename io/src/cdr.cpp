#include "fmcw/io/cdr.hpp"

#include <cstring>

#include "fmcw/core/check.hpp"

namespace fmcw::io {

using core::concat;

namespace {
// Alignment is counted from the end of the 4-byte encapsulation header.
constexpr std::size_t kHeader = 4;
std::size_t padding(std::size_t pos, std::size_t align) { return (align - (pos - kHeader) % align) % align; }
constexpr std::uint8_t kCdrLe[kHeader] = {0x00, 0x01, 0x00, 0x00};
}  // namespace

CdrWriter::CdrWriter() : own_(kCdrLe, kCdrLe + kHeader), buf_(&own_) {}

CdrWriter::CdrWriter(std::vector<std::uint8_t>& out) : buf_(&out), origin_(out.size()) {
  out.insert(out.end(), kCdrLe, kCdrLe + kHeader);
}

void CdrWriter::put(const void* p, std::size_t size, std::size_t align) {
  buf_->resize(buf_->size() + padding(buf_->size() - origin_, align), 0);
  const auto* b = static_cast<const std::uint8_t*>(p);
  buf_->insert(buf_->end(), b, b + size);
}

void CdrWriter::string(const std::string& s) {
  u32(static_cast<std::uint32_t>(s.size() + 1));
  buf_->insert(buf_->end(), s.begin(), s.end());
  buf_->push_back(0);
}

void CdrWriter::bytes(const std::uint8_t* data, std::size_t size) {
  count(size);
  buf_->insert(buf_->end(), data, data + size);
}

void CdrWriter::count(std::size_t n) {
  FMCW_CHECK_LIMIT(n <= 0xffffffffu, "CDR: a sequence of ", n, " elements is longer than CDR's uint32 count");
  u32(static_cast<std::uint32_t>(n));
}

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size, std::string where)
    : data_(data), size_(size), where_(std::move(where)) {
  FMCW_CHECK_FILE(size >= kHeader, where_, ": ", size, " bytes, shorter than the 4-byte CDR encapsulation header");
  FMCW_CHECK_FILE(data[0] == 0x00 && data[1] == 0x01, where_, ": encapsulation ", int(data[0]), " ", int(data[1]),
                  " is not CDR little endian (0 1)");
}

void CdrReader::get(void* p, std::size_t size, std::size_t align) {
  const std::size_t start = pos_ + padding(pos_, align);
  if (start > size_ || size_ - start < size) {
    throw core::FileError(concat(where_, ": the message ends at byte ", size_, " inside a field at byte ", start));
  }
  std::memcpy(p, data_ + start, size);
  pos_ = start + size;
}

std::string CdrReader::string(const char* field) {
  const std::uint32_t n = u32();
  if (n == 0 || n > size_ - pos_) {
    throw core::FileError(concat(where_, ": string '", field, "' of ", n, " bytes at byte ", pos_, " does not fit the ",
                                 size_, "-byte message"));
  }
  FMCW_CHECK_FILE(data_[pos_ + n - 1] == 0, where_, ": string '", field, "' at byte ", pos_, " lacks its NUL");
  std::string s(reinterpret_cast<const char*>(data_ + pos_), n - 1);
  pos_ += n;
  return s;
}

std::size_t CdrReader::count(const char* field, std::size_t min_element_size) {
  const std::uint32_t n = u32();
  if (static_cast<std::uint64_t>(n) * min_element_size > size_ - pos_) {
    throw core::FileError(concat(where_, ": sequence '", field, "' of ", n, " elements at byte ", pos_,
                                 " does not fit the ", size_, "-byte message"));
  }
  return n;
}

const std::uint8_t* CdrReader::bytes(const char* field, std::size_t& size) {
  size = count(field, 1);
  const std::uint8_t* p = data_ + pos_;
  pos_ += size;
  return p;
}

}  // namespace fmcw::io
