#include "fmcw/io/yaml_reader.hpp"

#include <yaml-cpp/depthguard.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::io {

bool is_existing_file(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

std::string shown(const std::string& text) {
  constexpr std::size_t kLongest = 80;
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < kLongest; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      static const char* hex = "0123456789abcdef";
      out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
    } else {
      out += text[i];
    }
  }
  if (text.size() > kLongest) out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

std::string missing_file_reason(const std::string& path) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(st)) return "is a directory";
  if (std::filesystem::exists(st)) return "is not a regular file";
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(path, ec))) return "is a broken or looping link";
  return "does not exist";
}

YamlValue::YamlValue(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

YamlValue YamlValue::load_file(const std::string& file) {
  if (!is_existing_file(file)) throw core::FileError(file + ": " + missing_file_reason(file));
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::DeepRecursion& e) {
    // yaml-cpp's own message for this is "bad file".
    std::ostringstream msg;
    msg << file << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": malformed YAML: nested deeper than "
        << e.depth() - 1 << " levels";
    throw core::FileError(msg.str());
  } catch (const YAML::Exception& e) {
    std::ostringstream msg;
    msg << file << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": malformed YAML: " << e.msg;
    throw core::FileError(msg.str());
  }
  if (!root.IsDefined() || root.IsNull()) throw core::FileError(file + ": empty YAML document");
  return YamlValue(root, file, "");
}

std::string YamlValue::where() const {
  std::ostringstream out;
  out << file_;
  const YAML::Mark mark = node_.Mark();
  if (mark.line >= 0) out << ":" << mark.line + 1;
  out << ": " << (path_.empty() ? "(top level)" : path_);
  return out.str();
}

void YamlValue::fail(const std::string& what) const { throw core::FileError(where() + ": " + what); }

double YamlValue::as_double() const {
  if (!node_.IsScalar()) fail("expected a number");
  const std::string text = node_.Scalar();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == nullptr || *end != '\0' || !std::isfinite(v)) fail("expected a finite number, got '" + shown(text) + "'");
  return v;
}

int YamlValue::as_int() const {
  const double v = as_double();
  if (v != std::floor(v) || std::abs(v) > std::numeric_limits<int>::max()) fail("expected an integer, got '" + shown(node_.Scalar()) + "'");
  return static_cast<int>(v);
}

std::uint64_t YamlValue::as_uint64() const {
  if (!node_.IsScalar()) fail("expected a non-negative integer");
  const std::string text = node_.Scalar();
  std::size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || text[0] == '-') fail("expected a non-negative integer, got '" + shown(text) + "'");
  return v;
}

bool YamlValue::as_bool() const {
  if (!node_.IsScalar()) fail("expected true or false");
  const std::string t = node_.Scalar();
  if (t == "true") return true;
  if (t == "false") return false;
  fail("expected true or false, got '" + shown(t) + "'");
}

std::string YamlValue::as_string() const {
  if (!node_.IsScalar()) fail("expected a string");
  return node_.Scalar();
}

std::vector<YamlValue> YamlValue::items() const {
  if (!node_.IsSequence()) fail("expected a list");
  std::vector<YamlValue> out;
  for (std::size_t k = 0; k < node_.size(); ++k) {
    out.emplace_back(node_[k], file_, path_ + "[" + std::to_string(k) + "]");
  }
  return out;
}

std::vector<double> YamlValue::as_doubles() const {
  if (node_.IsScalar()) return {as_double()};
  std::vector<double> out;
  for (const auto& item : items()) out.push_back(item.as_double());
  return out;
}

YamlMap::YamlMap(const YamlValue& value) : value_(value) {
  if (!value.is_map()) value.fail("expected a map of keys");
  // yaml-cpp keeps every entry of a key given twice and answers lookups with the first: the
  // second would be ignored without a word.
  std::map<std::string, int> lines;
  const std::string where = value_.path().empty() ? "the top level" : value_.path();
  for (const auto& kv : value.node()) {
    const int line = kv.first.Mark().line + 1;
    if (!kv.first.IsScalar()) {
      std::ostringstream msg;
      msg << value_.file() << ":" << line << ": "
          << (value_.path().empty() ? "top level" : value_.path()) << ": a key must be a plain word, got a "
          << (kv.first.IsSequence() ? "list" : kv.first.IsMap() ? "map" : "null");
      throw core::FileError(msg.str());
    }
    const auto [it, added] = lines.emplace(kv.first.Scalar(), line);
    if (!added) {
      throw core::FileError(value_.file() + ":" + std::to_string(line) + ": key '" + shown(kv.first.Scalar()) +
                            "' given twice in " + where + " (first at line " + std::to_string(it->second) +
                            "); keep one");
    }
  }
}

bool YamlMap::has(const std::string& key) const {
  const YAML::Node& node = value_.node();
  return static_cast<bool>(node[key]);
}

YamlValue YamlMap::at(const std::string& key) {
  used_.insert(key);
  const YAML::Node& node = value_.node();
  const std::string path = value_.path().empty() ? key : value_.path() + "." + key;
  if (!node[key]) value_.fail("missing required key '" + key + "'");
  return YamlValue(node[key], value_.file(), path);
}

double YamlMap::get(const std::string& key, double fallback) { return has(key) ? at(key).as_double() : (used_.insert(key), fallback); }
int YamlMap::get(const std::string& key, int fallback) { return has(key) ? at(key).as_int() : (used_.insert(key), fallback); }
std::uint64_t YamlMap::get(const std::string& key, std::uint64_t fallback) {
  return has(key) ? at(key).as_uint64() : (used_.insert(key), fallback);
}
bool YamlMap::get(const std::string& key, bool fallback) { return has(key) ? at(key).as_bool() : (used_.insert(key), fallback); }
std::string YamlMap::get(const std::string& key, const std::string& fallback) {
  return has(key) ? at(key).as_string() : (used_.insert(key), fallback);
}

void YamlMap::finish() const {
  for (const auto& kv : value_.node()) {
    const std::string key = kv.first.Scalar();
    if (used_.count(key)) continue;
    std::string list;
    for (const auto& a : used_) list += (list.empty() ? "" : ", ") + a;
    std::ostringstream msg;
    msg << value_.file() << ":" << kv.first.Mark().line + 1 << ": unknown key '" << shown(key) << "' in "
        << (value_.path().empty() ? "the top level" : value_.path()) << " (accepted: " << list << ")";
    throw core::FileError(msg.str());
  }
}

}  // namespace fmcw::io
