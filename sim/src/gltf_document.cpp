#include "gltf_document.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/io/yaml_reader.hpp"

namespace fmcw::sim::detail {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;     // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;      // "BIN\0"
constexpr std::uint64_t kMaxFileBytes = 1ull << 31;  // 2 GiB: larger files are refused before reading
// Decoded values a file may ask for: this many, plus kValuesPerBufferByte per byte of its
// buffers (a float is 4 bytes, so one read of every accessor asks for at most 1 per byte; the
// margin is for accessors several primitives, nodes or channels share).
constexpr std::uint64_t kBaseValues = 1ull << 22;
constexpr std::uint64_t kValuesPerBufferByte = 16;
// JSON nesting: glTF itself needs under ten levels. Deeper files are refused, as the other
// reader (assimp, for files without animations or skins) recurses once per level.
constexpr std::size_t kMaxJsonDepth = 256;

std::uint32_t le32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

std::vector<std::uint8_t> read_bytes(const std::string& path, const std::string& what) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) throw core::FileError(what + " cannot be read: " + ec.message());
  if (size > kMaxFileBytes) throw core::LimitError(what + " is larger than 2 GiB");
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> bytes(size);
  if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) {
    throw core::FileError(what + " cannot be read");
  }
  return bytes;
}

bool decode_base64(const std::string& text, std::size_t begin, std::vector<std::uint8_t>& out) {
  const auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return -1;
  };
  std::uint32_t acc = 0;
  int bits = 0;
  for (std::size_t k = begin; k < text.size(); ++k) {
    if (text[k] == '=') break;
    const int v = value(text[k]);
    if (v < 0) return false;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xFF));
    }
  }
  return true;
}

std::string percent_decode(const std::string& uri) {
  std::string out;
  for (std::size_t k = 0; k < uri.size(); ++k) {
    if (uri[k] == '%' && k + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[k + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[k + 2]))) {
      out.push_back(static_cast<char>(std::stoi(uri.substr(k + 1, 2), nullptr, 16)));
      k += 2;
    } else {
      out.push_back(uri[k]);
    }
  }
  return out;
}

// The deepest nesting of arrays and objects in `root` (a scalar is depth 0), without recursion;
// stops counting once past `limit`.
std::size_t json_depth(const json& root, std::size_t limit) {
  std::size_t deepest = 0;
  std::vector<std::pair<const json*, std::size_t>> stack{{&root, 0}};
  while (!stack.empty()) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    if (!node->is_structured()) continue;
    deepest = std::max(deepest, depth + 1);
    if (deepest > limit) break;
    for (const auto& child : *node) stack.emplace_back(&child, depth + 1);
  }
  return deepest;
}

std::size_t component_size(std::uint64_t type) {
  switch (type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

std::size_t type_width(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

double read_component(const std::uint8_t* p, int type, bool normalized) {
  switch (type) {
    case 5120: {
      const auto v = static_cast<std::int8_t>(p[0]);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case 5121:
      return normalized ? p[0] / 255.0 : p[0];
    case 5122: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case 5123: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case 5125:
      return le32(p);
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

}  // namespace

void GltfDocument::fail(const std::string& what) const { throw core::FileError("mesh '" + path_ + "': " + what); }

std::optional<GltfDocument> GltfDocument::read(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::uint8_t magic[4] = {0, 0, 0, 0};
  {
    std::ifstream in(path, std::ios::binary);
    in.read(reinterpret_cast<char*>(magic), 4);
  }
  const bool glb = le32(magic) == kGlbMagic;
  if (!glb && ext != ".gltf" && ext != ".glb") return std::nullopt;
  GltfDocument doc;
  doc.path_ = path;
  const std::vector<std::uint8_t> bytes = read_bytes(path, "mesh '" + path + "'");
  const std::uint8_t* text = bytes.data();
  std::size_t text_size = bytes.size();
  if (glb) {
    // GLB: a 12-byte header, then chunks of (length, type, data) padded to 4 bytes.
    if (bytes.size() < 20) doc.fail("GLB file shorter than its header");
    if (le32(&bytes[4]) != 2) doc.fail("GLB version " + std::to_string(le32(&bytes[4])) + ", expected 2");
    if (le32(&bytes[8]) != bytes.size()) {
      doc.fail("GLB header says " + std::to_string(le32(&bytes[8])) + " bytes, the file has " +
               std::to_string(bytes.size()) + " (truncated?)");
    }
    std::size_t at = 12;
    bool has_json = false;
    while (at + 8 <= bytes.size()) {
      const std::uint64_t length = le32(&bytes[at]);
      const std::uint32_t type = le32(&bytes[at + 4]);
      if (at + 8 + length > bytes.size()) doc.fail("GLB chunk at byte " + std::to_string(at) + " runs past the file's end");
      if (!has_json) {
        if (type != kChunkJson) doc.fail("the first GLB chunk is not JSON");
        text = &bytes[at + 8];
        text_size = length;
        has_json = true;
      } else if (type == kChunkBin && !doc.glb_bin_) {
        doc.glb_bin_.emplace(bytes.begin() + static_cast<std::ptrdiff_t>(at + 8),
                             bytes.begin() + static_cast<std::ptrdiff_t>(at + 8 + length));
      }
      at += 8 + ((length + 3) & ~std::uint64_t{3});
    }
    if (!has_json) doc.fail("GLB file without a JSON chunk");
  }
  try {
    doc.json_ = json::parse(text, text + text_size);
  } catch (const json::exception& e) {
    throw core::FileError("mesh '" + path + "' cannot be read: malformed glTF JSON: " + e.what());
  }
  if (!doc.json_.is_object()) doc.fail("the glTF JSON is not an object");
  if (json_depth(doc.json_, kMaxJsonDepth) > kMaxJsonDepth) {
    doc.fail("the glTF JSON nests arrays and objects more than " + std::to_string(kMaxJsonDepth) + " levels deep");
  }
  if (!doc.json_.contains("asset") || !doc.json_["asset"].is_object() || !doc.json_["asset"].contains("version") ||
      !doc.json_["asset"]["version"].is_string() || doc.json_["asset"]["version"].get<std::string>().rfind("2.", 0) != 0) {
    doc.fail("asset.version must be \"2.x\" (glTF 2.0)");
  }
  return doc;
}

void GltfDocument::load_buffers() {
  for (std::size_t b = 0; b < count("buffers"); ++b) {
    const json& buffer = element("buffers", b);
    const std::string where = "buffers[" + std::to_string(b) + "]";
    const std::size_t length = json_index(*this, buffer, "byteLength", where);
    std::vector<std::uint8_t> data;
    if (!buffer.contains("uri")) {
      if (b != 0 || !glb_bin_) fail(where + " has no uri and is not a GLB's binary chunk");
      data = std::move(*glb_bin_);
    } else {
      const std::string uri = json_string(*this, buffer, "uri", where, "");
      if (uri.rfind("data:", 0) == 0) {
        const std::size_t comma = uri.find(',');
        if (comma == std::string::npos || uri.rfind(";base64", comma) == std::string::npos ||
            !decode_base64(uri, comma + 1, data)) {
          fail(where + ".uri is not a base64 data URI");
        }
      } else {
        const std::string file = (fs::path(path_).parent_path() / percent_decode(uri)).string();
        if (!io::is_existing_file(file)) fail(where + ".uri names '" + file + "', which does not exist");
        data = read_bytes(file, "mesh '" + path_ + "': " + where + " file '" + file + "'");
      }
    }
    if (data.size() < length) {
      fail(where + " holds " + std::to_string(data.size()) + " bytes, byteLength says " + std::to_string(length));
    }
    buffers_.push_back(std::move(data));
  }
  value_budget_ = kBaseValues;
  for (const auto& b : buffers_) value_budget_ += kValuesPerBufferByte * b.size();
}

void GltfDocument::charge(std::uint64_t values, const std::string& what) const {
  if (values > value_budget_ - values_read_) {
    fail(what + " would bring the values read from the file to " + std::to_string(values_read_ + values) +
         ", more than the " + std::to_string(value_budget_) + " its buffers allow (" + std::to_string(kBaseValues) + " + " +
         std::to_string(kValuesPerBufferByte) + " per buffer byte): an accessor or skin declared far larger than its data, or reused too often");
  }
  values_read_ += values;
}

std::size_t GltfDocument::count(const char* key) const {
  if (!json_.contains(key)) return 0;
  if (!json_[key].is_array()) fail(std::string(key) + " is not an array");
  return json_[key].size();
}

const json& GltfDocument::element(const char* key, std::size_t index) const {
  if (index >= count(key)) {
    fail(std::string(key) + "[" + std::to_string(index) + "] does not exist (" + std::to_string(count(key)) + " " + key + ")");
  }
  const json& e = json_[key][index];
  if (!e.is_object()) fail(std::string(key) + "[" + std::to_string(index) + "] is not an object");
  return e;
}

std::vector<double> GltfDocument::read_accessor(std::size_t index, const std::vector<std::string>& types,
                                                const std::string& what, bool allow_integer) const {
  const json& a = element("accessors", index);
  const std::string where = what + " (accessors[" + std::to_string(index) + "])";
  const std::string type = json_string(*this, a, "type", where, "");
  if (std::find(types.begin(), types.end(), type) == types.end()) fail(where + " has type '" + type + "'");
  const std::uint64_t component_value = json_index(*this, a, "componentType", where);
  const std::size_t csize = component_size(component_value);
  if (csize == 0) fail(where + " has componentType " + std::to_string(component_value));
  const int component = static_cast<int>(component_value);  // one of the six, checked above
  const bool normalized = a.contains("normalized") && a["normalized"].is_boolean() && a["normalized"].get<bool>();
  if (component != 5126 && !normalized && !allow_integer) fail(where + " must hold floats or normalized integers");
  if (type == "MAT4" && component != 5126) fail(where + ": MAT4 accessors must hold floats");
  const std::size_t width = type_width(type);
  const std::uint64_t n = json_index(*this, a, "count", where);
  if (n == 0) fail(where + " has count 0");
  const std::uint64_t element_size = csize * width;
  std::vector<double> out;
  if (const auto view_index = json_optional_index(*this, a, "bufferView", where)) {
    const json& view = element("bufferViews", *view_index);
    const std::string vw = "bufferViews[" + std::to_string(*view_index) + "]";
    const std::size_t buffer = json_index(*this, view, "buffer", vw);
    if (buffer >= buffers_.size()) fail(vw + ".buffer " + std::to_string(buffer) + " does not exist");
    const std::uint64_t view_offset = view.contains("byteOffset") ? json_index(*this, view, "byteOffset", vw) : 0;
    const std::uint64_t view_length = json_index(*this, view, "byteLength", vw);
    const std::uint64_t stride = view.contains("byteStride") ? json_index(*this, view, "byteStride", vw) : element_size;
    const std::uint64_t offset = a.contains("byteOffset") ? json_index(*this, a, "byteOffset", where) : 0;
    if (stride < element_size) fail(vw + ".byteStride " + std::to_string(stride) + " is smaller than an element");
    if (n > view_length) fail(where + " has more elements than its buffer view has bytes");
    // offset + stride (n - 1) + element_size <= view_length, written so that nothing overflows
    // (stride and offset may each be up to 2^40).
    if (view_offset + view_length > buffers_[buffer].size() || offset > view_length ||
        element_size > view_length - offset || n - 1 > (view_length - offset - element_size) / stride) {
      fail(where + " reaches past the end of its buffer view or buffer");
    }
    charge(n * width, where);
    out.resize(n * width);
    const std::uint8_t* base = buffers_[buffer].data() + view_offset + offset;
    for (std::uint64_t e = 0; e < n; ++e) {
      for (std::size_t c = 0; c < width; ++c) out[e * width + c] = read_component(base + e * stride + c * csize, component, normalized);
    }
  } else {
    charge(n * width, where);  // n <= 2^40, width <= 16: no overflow
    out.assign(n * width, 0.0);  // no buffer view: zeros, then any sparse substitution
  }
  if (a.contains("sparse")) {
    const json& sp = a["sparse"];
    const std::string sw = where + ".sparse";
    if (!sp.is_object() || !sp.contains("indices") || !sp.contains("values")) fail(sw + " needs indices and values");
    const std::size_t m = json_index(*this, sp, "count", sw);
    if (m > n) fail(sw + ".count " + std::to_string(m) + " is more than the accessor's count " + std::to_string(n));
    const auto part = [&](const char* key, int ctype, std::size_t w) {
      const json& p = sp[key];
      const std::string pw = sw + "." + key;
      const std::size_t view_index = json_index(*this, p, "bufferView", pw);
      const json& view = element("bufferViews", view_index);
      const std::size_t buffer = json_index(*this, view, "buffer", pw);
      if (buffer >= buffers_.size()) fail(pw + " names a buffer that does not exist");
      const std::uint64_t begin = (view.contains("byteOffset") ? json_index(*this, view, "byteOffset", pw) : 0) +
                                  (p.contains("byteOffset") ? json_index(*this, p, "byteOffset", pw) : 0);
      const std::uint64_t bytes = static_cast<std::uint64_t>(m) * w * component_size(ctype);
      if (component_size(ctype) == 0 || begin + bytes > buffers_[buffer].size()) fail(pw + " reaches past its buffer");
      std::vector<double> v(m * w);
      for (std::size_t k = 0; k < m * w; ++k) {
        v[k] = read_component(buffers_[buffer].data() + begin + k * component_size(ctype), ctype, normalized);
      }
      return v;
    };
    const std::uint64_t index_type_value = json_index(*this, sp["indices"], "componentType", sw + ".indices");
    if (index_type_value != 5121 && index_type_value != 5123 && index_type_value != 5125) {
      fail(sw + ".indices must be unsigned integers");
    }
    const int index_type = static_cast<int>(index_type_value);
    const std::vector<double> idx = part("indices", index_type, 1);
    const std::vector<double> values = part("values", component, width);
    for (std::size_t k = 0; k < m; ++k) {
      if (idx[k] >= static_cast<double>(n)) fail(sw + " index " + std::to_string(idx[k]) + " is beyond count");
      std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(k * width), width,
                  out.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(idx[k]) * width));
    }
  }
  return out;
}

std::size_t json_index(const GltfDocument& doc, const json& object, const char* key, const std::string& where) {
  const auto v = json_optional_index(doc, object, key, where);
  if (!v) doc.fail(where + "." + key + " is missing");
  return *v;
}

std::optional<std::size_t> json_optional_index(const GltfDocument& doc, const json& object, const char* key,
                                               const std::string& where) {
  if (!object.is_object() || !object.contains(key)) return std::nullopt;
  const json& v = object[key];
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0)) {
    doc.fail(where + "." + key + " must be a non-negative integer");
  }
  const std::uint64_t u = v.get<std::uint64_t>();
  if (u > (1ull << 40)) doc.fail(where + "." + key + " is too large: " + std::to_string(u));
  return static_cast<std::size_t>(u);
}

std::string json_string(const GltfDocument& doc, const json& object, const char* key, const std::string& where,
                        const std::string& fallback) {
  if (!object.contains(key)) return fallback;
  if (!object[key].is_string()) doc.fail(where + "." + key + " must be a string");
  return object[key].get<std::string>();
}

std::vector<double> json_numbers(const GltfDocument& doc, const json& object, const char* key, const std::string& where,
                                 std::size_t count) {
  const json& v = object[key];
  if (!v.is_array() || v.size() != count) doc.fail(where + "." + key + " must be an array of " + std::to_string(count) + " numbers");
  std::vector<double> out;
  for (const auto& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) doc.fail(where + "." + key + " must hold finite numbers");
    out.push_back(x.get<double>());
  }
  return out;
}

}  // namespace fmcw::sim::detail
