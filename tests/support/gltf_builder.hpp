#pragma once
// Writes small glTF 2.0 files (.gltf with an embedded buffer, or .glb) with known content, so mesh,
// skin and animation loading can be tested against exact answers. Header-only, for tests.
//
// The JSON is built eagerly in doc(); the binary buffer is kept beside it as bytes and its
// byteLength kept in doc() as data is appended. Only the buffer's `uri` is added at write time (and
// only for .gltf, only if the caller did not set one), so edits made through doc() after building
// (to corrupt a file on purpose) reach the written file unchanged. Data is stored little-endian
// (the host byte order of every machine we build on).

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace fmcw::test {

class GltfBuilder {
 public:
  // glTF enums (spec section 5.1.2 and 5.11.1).
  static constexpr int kUnsignedShort = 5123;
  static constexpr int kUnsignedInt = 5125;
  static constexpr int kFloat = 5126;
  static constexpr int kArrayBuffer = 34962;
  static constexpr int kElementArrayBuffer = 34963;
  static constexpr int kTriangles = 4;

  GltfBuilder() {
    doc_["asset"] = {{"version", "2.0"}, {"generator", "fmcw::test::GltfBuilder"}};
    doc_["scene"] = 0;
    doc_["scenes"] = nlohmann::json::array({{{"name", "scene"}, {"nodes", nlohmann::json::array()}}});
    doc_["nodes"] = nlohmann::json::array();
  }

  /// Node with TRS (never `matrix`); parent -1 makes it a root of the scene. Returns the node index.
  int add_node(const std::string& name, int parent = -1,
               const Eigen::Vector3d& translation = Eigen::Vector3d::Zero(),
               const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity(),
               const Eigen::Vector3d& scale = Eigen::Vector3d::Ones()) {
    nlohmann::json node = {{"name", name}};
    node["translation"] = {translation.x(), translation.y(), translation.z()};
    node["rotation"] = {rotation.x(), rotation.y(), rotation.z(), rotation.w()};  // glTF order x y z w
    node["scale"] = {scale.x(), scale.y(), scale.z()};
    Eigen::Affine3d T_parent_node = Eigen::Translation3d(translation) * rotation.normalized() * Eigen::Scaling(scale);
    return push_node(std::move(node), parent, T_parent_node.matrix());
  }

  /// Node with a `matrix` (column-major in the file, as glTF stores it) instead of TRS.
  int add_matrix_node(const std::string& name, int parent, const Eigen::Matrix4d& matrix) {
    nlohmann::json node = {{"name", name}};
    node["matrix"] = nlohmann::json::array();
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) node["matrix"].push_back(matrix(r, c));
    }
    return push_node(std::move(node), parent, matrix);
  }

  /// A triangle primitive (mode 4) on a new mesh attached to `node`. Indices are UNSIGNED_INT, or
  /// UNSIGNED_SHORT when `small_indices` and all fit. `material` names a material, created once
  /// per name. Returns the mesh index.
  int add_mesh(int node, const std::vector<Eigen::Vector3f>& positions, const std::vector<std::uint32_t>& indices,
               const std::string& material = "test_material", bool small_indices = false) {
    check_node(node, "add_mesh");
    std::vector<float> flat;
    flat.reserve(positions.size() * 3);
    for (const auto& p : positions) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
    const int position_accessor = add_float_accessor(flat, "VEC3", kArrayBuffer, true);

    const bool use_short = small_indices && std::all_of(indices.begin(), indices.end(),
                                                        [](std::uint32_t i) { return i < 65536u; });
    int index_accessor = -1;
    if (use_short) {
      std::vector<std::uint16_t> shorts(indices.begin(), indices.end());
      index_accessor = add_accessor(append_view(shorts, kElementArrayBuffer), kUnsignedShort, "SCALAR", indices.size());
    } else {
      index_accessor = add_accessor(append_view(indices, kElementArrayBuffer), kUnsignedInt, "SCALAR", indices.size());
    }

    nlohmann::json primitive = {{"attributes", {{"POSITION", position_accessor}}},
                                {"indices", index_accessor},
                                {"material", material_index(material)},
                                {"mode", kTriangles}};
    const int mesh = array_size("meshes");
    doc_["meshes"].push_back({{"name", "mesh_" + std::to_string(mesh)}, {"primitives", {primitive}}});
    doc_["nodes"][node]["mesh"] = mesh;
    return mesh;
  }

  /// Skin attributes on the (only) primitive of `mesh`: per vertex a list of (joint slot, weight)
  /// pairs, any count per vertex, written as JOINTS_k / WEIGHTS_k in groups of 4 padded with
  /// (joint 0, weight 0). Joints UNSIGNED_SHORT, weights FLOAT, exactly as given: tests pass bad
  /// weights on purpose, and the accessor count is influences.size() even when it differs from
  /// the vertex count.
  void set_skin_weights(int mesh, const std::vector<std::vector<std::pair<int, float>>>& influences) {
    if (mesh < 0 || mesh >= array_size("meshes")) {
      throw std::invalid_argument("set_skin_weights: no mesh " + std::to_string(mesh));
    }
    std::size_t most = 1;
    for (const auto& v : influences) most = std::max(most, v.size());
    const std::size_t groups = (most + 3) / 4;
    auto& attributes = doc_["meshes"][mesh]["primitives"][0]["attributes"];
    for (std::size_t g = 0; g < groups; ++g) {
      std::vector<std::uint16_t> joints;
      std::vector<float> weights;
      for (const auto& v : influences) {
        for (std::size_t k = 4 * g; k < 4 * g + 4; ++k) {
          const bool present = k < v.size();
          const int joint = present ? v[k].first : 0;
          if (joint < 0 || joint > 65535) {
            throw std::invalid_argument("set_skin_weights: joint slot " + std::to_string(joint) +
                                        " does not fit UNSIGNED_SHORT");
          }
          joints.push_back(static_cast<std::uint16_t>(joint));
          weights.push_back(present ? v[k].second : 0.0f);
        }
      }
      const std::string suffix = "_" + std::to_string(g);
      attributes["JOINTS" + suffix] =
          add_accessor(append_view(joints, kArrayBuffer), kUnsignedShort, "VEC4", influences.size());
      attributes["WEIGHTS" + suffix] = add_float_accessor(weights, "VEC4", kArrayBuffer, false);
    }
    for (std::size_t g = groups;; ++g) {  // fewer groups than an earlier call: drop the stale ones
      const std::string suffix = "_" + std::to_string(g);
      if (!attributes.contains("JOINTS" + suffix) && !attributes.contains("WEIGHTS" + suffix)) break;
      attributes.erase("JOINTS" + suffix);
      attributes.erase("WEIGHTS" + suffix);
    }
  }

  /// A skin over joint node indices. Empty `inverse_bind`: the inverse of each joint's global rest
  /// transform from the node hierarchy built so far (add the joints' parents first). Given ones
  /// are written as given, whatever their count. Returns the skin index.
  int add_skin(const std::vector<int>& joints, std::vector<Eigen::Matrix4d> inverse_bind = {}) {
    for (int j : joints) check_node(j, "add_skin");
    if (inverse_bind.empty()) {
      for (int j : joints) inverse_bind.push_back(global_rest(j).inverse());
    }
    std::vector<float> flat;
    for (const auto& m : inverse_bind) {
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) flat.push_back(static_cast<float>(m(r, c)));
      }
    }
    const int skin = array_size("skins");
    doc_["skins"].push_back({{"name", "skin_" + std::to_string(skin)},
                             {"joints", joints},
                             {"inverseBindMatrices", add_float_accessor(flat, "MAT4", -1, false)}});
    return skin;
  }

  void attach_skin(int node, int skin) {
    check_node(node, "attach_skin");
    doc_["nodes"][node]["skin"] = skin;
  }

  int add_animation(const std::string& name) {
    const int animation = array_size("animations");
    doc_["animations"].push_back(
        {{"name", name}, {"channels", nlohmann::json::array()}, {"samplers", nlohmann::json::array()}});
    return animation;
  }

  /// A sampler (own input and output accessors) and a channel targeting node/path
  /// ("translation" | "rotation" | "scale" | "weights"), interpolation "LINEAR" | "STEP" |
  /// "CUBICSPLINE". `values` are flat floats as glTF stores them: VEC3 for translation and scale,
  /// VEC4 x y z w for rotation, SCALAR for weights; CUBICSPLINE has per key in-tangent, value,
  /// out-tangent. Times [s] and values are written exactly as given, count mismatches included.
  void add_channel(int animation, int node, const std::string& path, const std::string& interpolation,
                   const std::vector<float>& times_s, const std::vector<float>& values) {
    if (animation < 0 || animation >= array_size("animations")) {
      throw std::invalid_argument("add_channel: no animation " + std::to_string(animation));
    }
    check_node(node, "add_channel");
    std::string type;
    std::size_t width = 0;
    if (path == "translation" || path == "scale") {
      type = "VEC3";
      width = 3;
    } else if (path == "rotation") {
      type = "VEC4";
      width = 4;
    } else if (path == "weights") {
      type = "SCALAR";
      width = 1;
    } else {
      throw std::invalid_argument("add_channel: unknown path '" + path + "'");
    }
    if (values.size() % width != 0) {
      throw std::invalid_argument("add_channel: " + std::to_string(values.size()) +
                                  " values is not a whole number of " + type + " for path '" + path + "'");
    }
    const int input = add_float_accessor(times_s, "SCALAR", -1, true);
    const int output = add_float_accessor(values, type, -1, false);
    auto& anim = doc_["animations"][animation];
    const int sampler = static_cast<int>(anim["samplers"].size());
    anim["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", interpolation}});
    anim["channels"].push_back({{"sampler", sampler}, {"target", {{"node", node}, {"path", path}}}});
  }

  /// The JSON before writing, for tests that corrupt a file on purpose.
  nlohmann::json& doc() { return doc_; }
  const nlohmann::json& doc() const { return doc_; }
  /// The binary buffer's bytes, for tests that corrupt data on purpose (byteLength is not updated).
  std::vector<std::uint8_t>& buffer() { return bin_; }
  const std::vector<std::uint8_t>& buffer() const { return bin_; }

  /// .gltf JSON with the buffer as a base64 data: URI.
  std::string gltf_text() const {
    nlohmann::json out = doc_;
    if (has_buffer(out) && !out["buffers"][0].contains("uri")) {
      out["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin_);
    }
    return out.dump(1) + "\n";
  }

  void write_gltf(const std::string& path) const { write_file(path, gltf_text()); }

  /// GLB container (spec section 4.4): 12-byte header, JSON chunk padded with spaces, BIN chunk
  /// padded with zeros, both to 4 bytes. The buffer has no uri unless the caller gave it one.
  void write_glb(const std::string& path) const {
    std::string json = doc_.dump();
    json.append(padding(json.size()), ' ');
    std::string bin(bin_.begin(), bin_.end());
    bin.append(padding(bin.size()), '\0');
    const bool with_bin = !bin_.empty();
    const std::uint32_t total =
        static_cast<std::uint32_t>(12 + 8 + json.size() + (with_bin ? 8 + bin.size() : 0));
    std::string out;
    put_u32(out, 0x46546C67u);  // "glTF"
    put_u32(out, 2);
    put_u32(out, total);
    put_u32(out, static_cast<std::uint32_t>(json.size()));
    put_u32(out, 0x4E4F534Au);  // "JSON"
    out += json;
    if (with_bin) {
      put_u32(out, static_cast<std::uint32_t>(bin.size()));
      put_u32(out, 0x004E4942u);  // "BIN\0"
      out += bin;
    }
    write_file(path, out);
  }

  static std::string base64(const std::vector<std::uint8_t>& bytes) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
      const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
      std::uint32_t v = static_cast<std::uint32_t>(bytes[i]) << 16;
      if (n > 1) v |= static_cast<std::uint32_t>(bytes[i + 1]) << 8;
      if (n > 2) v |= bytes[i + 2];
      for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63u] : '=';
    }
    return out;
  }

 private:
  struct RestNode {
    int parent;
    Eigen::Matrix4d T_parent_node;
  };

  static std::size_t padding(std::size_t size) { return (4 - size % 4) % 4; }

  static void put_u32(std::string& out, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out += static_cast<char>((v >> (8 * k)) & 0xFFu);
  }

  static void write_file(const std::string& path, const std::string& bytes) {
    std::ofstream file(path, std::ios::binary);
    if (!file) throw std::runtime_error("GltfBuilder: cannot open '" + path + "' for writing");
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!file) throw std::runtime_error("GltfBuilder: cannot write '" + path + "'");
  }

  static bool has_buffer(const nlohmann::json& doc) {
    return doc.contains("buffers") && doc["buffers"].is_array() && !doc["buffers"].empty() &&
           doc["buffers"][0].is_object();
  }

  /// Length of a top-level array; 0 when absent (without creating the key, which would be null).
  int array_size(const char* key) const {
    return doc_.contains(key) && doc_[key].is_array() ? static_cast<int>(doc_[key].size()) : 0;
  }

  void check_node(int node, const char* where) const {
    if (node < 0 || node >= static_cast<int>(rest_.size())) {
      throw std::invalid_argument(std::string(where) + ": no node " + std::to_string(node));
    }
  }

  int push_node(nlohmann::json node, int parent, const Eigen::Matrix4d& T_parent_node) {
    if (parent != -1) check_node(parent, "add_node");
    const int index = static_cast<int>(rest_.size());
    rest_.push_back({parent, T_parent_node});
    doc_["nodes"].push_back(std::move(node));
    if (parent == -1) {
      doc_["scenes"][0]["nodes"].push_back(index);
    } else {
      doc_["nodes"][parent]["children"].push_back(index);
    }
    return index;
  }

  /// T_root_node at rest, from the transforms given when the nodes were added.
  Eigen::Matrix4d global_rest(int node) const {
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    for (int n = node; n != -1; n = rest_[n].parent) T = rest_[n].T_parent_node * T;
    return T;
  }

  int material_index(const std::string& name) {
    const auto it = materials_.find(name);
    if (it != materials_.end()) return it->second;
    const int index = array_size("materials");
    doc_["materials"].push_back(
        {{"name", name}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}}}}});
    materials_[name] = index;
    return index;
  }

  /// Appends the values as a new 4-byte aligned bufferView; target -1: none (animation, skin data).
  template <typename T>
  int append_view(const std::vector<T>& values, int target) {
    bin_.resize(bin_.size() + padding(bin_.size()), 0);
    const std::size_t offset = bin_.size();
    const std::size_t length = values.size() * sizeof(T);
    bin_.resize(offset + length);
    if (length > 0) std::memcpy(bin_.data() + offset, values.data(), length);
    if (!has_buffer(doc_)) doc_["buffers"] = nlohmann::json::array({nlohmann::json::object()});
    doc_["buffers"][0]["byteLength"] = bin_.size();
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
    if (target != -1) view["target"] = target;
    const int index = array_size("bufferViews");
    doc_["bufferViews"].push_back(std::move(view));
    return index;
  }

  int add_accessor(int view, int component_type, const std::string& type, std::size_t count) {
    const int index = array_size("accessors");
    doc_["accessors"].push_back(
        {{"bufferView", view}, {"componentType", component_type}, {"type", type}, {"count", count}});
    return index;
  }

  /// FLOAT accessor over flat values; with_bounds adds per-component min/max over the finite
  /// values (required on POSITION and on animation inputs).
  int add_float_accessor(const std::vector<float>& flat, const std::string& type, int target, bool with_bounds) {
    const std::size_t width = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 16;
    const int accessor = add_accessor(append_view(flat, target), kFloat, type, flat.size() / width);
    if (with_bounds) {
      std::vector<std::optional<float>> lo(width), hi(width);
      for (std::size_t i = 0; i < flat.size(); ++i) {
        const float v = flat[i];
        if (!std::isfinite(v)) continue;
        auto& l = lo[i % width];
        auto& h = hi[i % width];
        l = l ? std::min(*l, v) : v;
        h = h ? std::max(*h, v) : v;
      }
      const bool complete = std::all_of(lo.begin(), lo.end(), [](const auto& v) { return v.has_value(); });
      if (complete) {
        auto& a = doc_["accessors"][accessor];
        a["min"] = nlohmann::json::array();
        a["max"] = nlohmann::json::array();
        for (std::size_t c = 0; c < width; ++c) {
          a["min"].push_back(*lo[c]);
          a["max"].push_back(*hi[c]);
        }
      }
    }
    return accessor;
  }

  nlohmann::json doc_;
  std::vector<std::uint8_t> bin_;
  std::vector<RestNode> rest_;
  std::map<std::string, int> materials_;
};

}  // namespace fmcw::test
