#pragma once
// PCD and PointCloud2 values: a field's (type, size) as PCD names it ('F' float, 'U' unsigned,
// 'I' signed; 1 to 8 bytes), read from and written to little-endian bytes as double (exact for
// every type but 64-bit integers beyond 2^53).

#include <cstdint>
#include <cstring>

namespace fmcw::io::detail {

inline bool valid_type_size(char type, int size) {
  if (type == 'F') return size == 4 || size == 8;
  if (type == 'U' || type == 'I') return size == 1 || size == 2 || size == 4 || size == 8;
  return false;
}

inline double decode(const unsigned char* p, char type, int size) {
  switch (type) {
    case 'F': {
      if (size == 4) { float v; std::memcpy(&v, p, 4); return v; }
      double v; std::memcpy(&v, p, 8); return v;
    }
    case 'U': {
      if (size == 1) return *p;
      if (size == 2) { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
      if (size == 4) { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
      std::uint64_t v; std::memcpy(&v, p, 8); return static_cast<double>(v);
    }
    default: {
      if (size == 1) { std::int8_t v; std::memcpy(&v, p, 1); return v; }
      if (size == 2) { std::int16_t v; std::memcpy(&v, p, 2); return v; }
      if (size == 4) { std::int32_t v; std::memcpy(&v, p, 4); return v; }
      std::int64_t v; std::memcpy(&v, p, 8); return static_cast<double>(v);
    }
  }
}

inline void encode(double value, char type, int size, unsigned char* p) {
  switch (type) {
    case 'F': {
      if (size == 4) { const float v = static_cast<float>(value); std::memcpy(p, &v, 4); return; }
      std::memcpy(p, &value, 8);
      return;
    }
    case 'U': {
      if (size == 1) { *p = static_cast<std::uint8_t>(value); return; }
      if (size == 2) { const auto v = static_cast<std::uint16_t>(value); std::memcpy(p, &v, 2); return; }
      if (size == 4) { const auto v = static_cast<std::uint32_t>(value); std::memcpy(p, &v, 4); return; }
      const auto v = static_cast<std::uint64_t>(value); std::memcpy(p, &v, 8); return;
    }
    default: {
      if (size == 1) { const auto v = static_cast<std::int8_t>(value); std::memcpy(p, &v, 1); return; }
      if (size == 2) { const auto v = static_cast<std::int16_t>(value); std::memcpy(p, &v, 2); return; }
      if (size == 4) { const auto v = static_cast<std::int32_t>(value); std::memcpy(p, &v, 4); return; }
      const auto v = static_cast<std::int64_t>(value); std::memcpy(p, &v, 8); return;
    }
  }
}

}  // namespace fmcw::io::detail
