#pragma once
// Internal to the simulator: a glTF 2.0 file (.gltf with data: URIs or external buffers, or a
// GLB container) parsed into its JSON and its binary buffers, with checked accessor reads.
// Every error is std::invalid_argument naming the file and the JSON path.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fmcw::sim::detail {

class GltfDocument {
 public:
  /// Reads a glTF or GLB file's JSON. nullopt when the file is neither (not a GLB by its magic,
  /// nor named .gltf): the caller uses another reader.
  static std::optional<GltfDocument> read(const std::string& path);
  /// Decodes or reads every buffer (data: URIs, files beside the glTF, the GLB's binary chunk);
  /// before the first read_accessor.
  void load_buffers();

  const nlohmann::json& root() const { return json_; }
  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& what) const;

  /// Accessor `index`, every element's components as doubles (normalized integers mapped to
  /// [0, 1] or [-1, 1] as the specification says; sparse substitutions applied). Checks the
  /// type against `types` (e.g. {"VEC3"}) and the bounds of its buffer view; `what` names the
  /// use in messages. components() gives the width of the last read.
  std::vector<double> read_accessor(std::size_t index, const std::vector<std::string>& types, const std::string& what,
                                    bool allow_integer = true) const;

  /// Counts `values` more decoded values (accessor components, joints' matrices) against what
  /// the file may ask for: 2^22 + 16 per byte of its buffers. Files that reuse one accessor or
  /// one skin many times, or declare huge accessors without data, stop here with `what` named,
  /// before the memory is taken.
  void charge(std::uint64_t values, const std::string& what) const;

  /// The element at json()[key][index] as an object, or an error naming it.
  const nlohmann::json& element(const char* key, std::size_t index) const;
  std::size_t count(const char* key) const;

 private:
  GltfDocument() = default;

  std::string path_;
  nlohmann::json json_;
  std::vector<std::vector<std::uint8_t>> buffers_;
  std::optional<std::vector<std::uint8_t>> glb_bin_;
  std::uint64_t value_budget_ = 0;
  mutable std::uint64_t values_read_ = 0;
};

/// Typed members of a JSON object; `where` is the object's JSON path, for messages.
std::size_t json_index(const GltfDocument& doc, const nlohmann::json& object, const char* key, const std::string& where);
std::optional<std::size_t> json_optional_index(const GltfDocument& doc, const nlohmann::json& object, const char* key,
                                               const std::string& where);
std::string json_string(const GltfDocument& doc, const nlohmann::json& object, const char* key,
                        const std::string& where, const std::string& fallback);
std::vector<double> json_numbers(const GltfDocument& doc, const nlohmann::json& object, const char* key,
                                 const std::string& where, std::size_t count);

}  // namespace fmcw::sim::detail
