#pragma once
// Strict YAML access: every read names file, line and key path on error, and every map must
// have its keys consumed, so an unknown or misspelt key is an error, not silently ignored.

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

namespace fmcw::io {

/// True for an existing regular file; false, never an exception, for a path the system rejects
/// (too long, a component not a folder, no permission): a scenario may name anything.
bool is_existing_file(const std::string& path);
/// text as a message may show it: control characters as \xNN, at most 80 characters and then
/// "... (N characters)".
std::string shown(const std::string& text);
/// Why path is no file to read: "is a directory", "is not a regular file" (a FIFO, a device),
/// "is a broken or looping link" or "does not exist".
std::string missing_file_reason(const std::string& path);

class YamlValue {
 public:
  YamlValue(YAML::Node node, std::string file, std::string path);
  /// Parses a file; core::FileError with file:line:column for malformed YAML, a missing file,
  /// or an empty document. fail() and every other error of a read is a core::FileError too.
  static YamlValue load_file(const std::string& file);

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  std::string where() const;  ///< "file:line: path"
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  double as_double() const;
  int as_int() const;
  std::uint64_t as_uint64() const;
  bool as_bool() const;
  std::string as_string() const;
  std::vector<YamlValue> items() const;           ///< a sequence's elements
  std::vector<double> as_doubles() const;          ///< a number or a sequence of numbers
  [[noreturn]] void fail(const std::string& what) const;
  const YAML::Node& node() const { return node_; }

 private:
  YAML::Node node_;
  std::string file_;
  std::string path_;
};

/// A YAML map whose keys must all be read before finish().
class YamlMap {
 public:
  explicit YamlMap(const YamlValue& value);
  bool has(const std::string& key) const;
  YamlValue at(const std::string& key);  ///< required key
  double get(const std::string& key, double fallback);
  int get(const std::string& key, int fallback);
  std::uint64_t get(const std::string& key, std::uint64_t fallback);
  bool get(const std::string& key, bool fallback);
  std::string get(const std::string& key, const std::string& fallback);
  /// Throws for any key that was never asked for, listing the keys that were (read them all,
  /// optional ones included, before calling this).
  void finish() const;
  const YamlValue& value() const { return value_; }

 private:
  YamlValue value_;
  std::set<std::string> used_;
};

}  // namespace fmcw::io
