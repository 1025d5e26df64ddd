// The project's glTF 2.0 reader for animated content: assimp 5.2 keeps only the key values of a
// CUBICSPLINE sampler (its tangents are dropped), interpolates STEP samplers linearly and reads
// only the first JOINTS/WEIGHTS set, so exact surface velocities need the file as written.

#include <algorithm>
#include <cmath>
#include <set>

#include "fmcw/core/errors.hpp"
#include "gltf_document.hpp"
#include "mesh_loaders.hpp"

namespace fmcw::sim::detail {

namespace {

using nlohmann::json;

const std::set<std::string> kPaths = {"translation", "rotation", "scale"};

std::string node_label(const GltfDocument& doc, std::size_t node) {
  const std::string name = json_string(doc, doc.element("nodes", node), "name", "nodes[" + std::to_string(node) + "]", "");
  return name.empty() ? "node_" + std::to_string(node) : name;
}

void check_extensions(const GltfDocument& doc) {
  if (!doc.root().contains("extensionsRequired")) return;
  const json& required = doc.root()["extensionsRequired"];
  if (!required.is_array()) doc.fail("extensionsRequired is not an array");
  for (const auto& e : required) {
    const std::string name = e.is_string() ? e.get<std::string>() : "?";
    // Quantized attributes are read as normalized integers; material and texture extensions do
    // not change geometry. Anything else would change what the triangles are.
    if (name == "KHR_mesh_quantization" || name.rfind("KHR_materials_", 0) == 0 || name.rfind("KHR_texture_", 0) == 0) {
      continue;
    }
    doc.fail("requires the glTF extension '" + name + "', which the simulator does not read");
  }
}

// The count of accessor `index` as the JSON gives it; nullopt when anything on the way is not
// as glTF has it (the reader that reads the file then says what).
std::optional<std::uint64_t> accessor_count(const json& root, const json& index) {
  if (!index.is_number_unsigned() || !root.contains("accessors") || !root["accessors"].is_array()) return std::nullopt;
  const json& accessors = root["accessors"];
  const auto k = index.get<std::uint64_t>();
  if (k >= accessors.size() || !accessors[k].is_object() || !accessors[k].contains("count") ||
      !accessors[k]["count"].is_number_unsigned()) {
    return std::nullopt;
  }
  return accessors[k]["count"].get<std::uint64_t>();
}

// Every primitive has at least the vertices (indices, or positions without indices) one point,
// line or triangle of its mode needs, as glTF requires: assimp 5.2, which reads the files without
// animations or skins, trusts the count and allocates count - 2 faces for a strip or fan of fewer
// than 3 (SIZE_MAX of them for 1), writes past the faces it allocated for a fan of 2, and
// dereferences a null pointer for a line loop of 1. Checked on the JSON alone, before either
// reader runs; a primitive whose mode or count is malformed is left to the reader to name.
void check_primitive_counts(const GltfDocument& doc) {
  const json& root = doc.root();
  if (!root.contains("meshes") || !root["meshes"].is_array()) return;
  static const char* const kModes[] = {"points", "lines", "line loop", "line strip", "triangles", "triangle strip", "triangle fan"};
  static const std::uint64_t kLeast[] = {1, 2, 2, 2, 3, 3, 3};
  for (std::size_t m = 0; m < root["meshes"].size(); ++m) {
    const json& mesh = root["meshes"][m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
      const json& prim = mesh["primitives"][p];
      if (!prim.is_object()) continue;
      const json mode_json = prim.contains("mode") ? prim["mode"] : json(4);
      if (!mode_json.is_number_unsigned() || mode_json.get<std::uint64_t>() > 6) continue;
      const auto mode = mode_json.get<std::size_t>();
      std::optional<std::uint64_t> count;
      const char* what = "indices";
      if (prim.contains("indices")) {
        count = accessor_count(root, prim["indices"]);
      } else if (prim.contains("attributes") && prim["attributes"].is_object() && prim["attributes"].contains("POSITION")) {
        count = accessor_count(root, prim["attributes"]["POSITION"]);
        what = "vertices";
      }
      if (count && *count < kLeast[mode]) {
        doc.fail("meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "] has " + std::to_string(*count) + " " +
                 what + " for mode " + std::to_string(mode) + " (" + kModes[mode] + "), which needs at least " +
                 std::to_string(kLeast[mode]));
      }
    }
  }
}

// Rest transform of a node: its matrix, or T R S.
MeshPart rest_part(const GltfDocument& doc, std::size_t node, bool& has_matrix) {
  const json& n = doc.element("nodes", node);
  const std::string where = "nodes[" + std::to_string(node) + "]";
  MeshPart part;
  part.name = node_label(doc, node);
  has_matrix = n.contains("matrix");
  if (has_matrix) {
    const std::vector<double> m = json_numbers(doc, n, "matrix", where, 16);
    Eigen::Matrix4d M = Eigen::Map<const Eigen::Matrix4d>(m.data());  // column-major, as glTF stores it
    if ((M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) doc.fail(where + ".matrix is not affine");
    part.T_parent_part = Eigen::Affine3d(M);
    part.rest_trs = decompose_trs(part.T_parent_part);
    return part;
  }
  if (n.contains("translation")) {
    const auto t = json_numbers(doc, n, "translation", where, 3);
    part.rest_trs.translation = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  if (n.contains("rotation")) {
    const auto q = json_numbers(doc, n, "rotation", where, 4);
    const Eigen::Quaterniond r(q[3], q[0], q[1], q[2]);
    if (r.norm() < 1e-9) doc.fail(where + ".rotation is a zero quaternion");
    part.rest_trs.rotation = r.normalized();
  }
  if (n.contains("scale")) {
    const auto s = json_numbers(doc, n, "scale", where, 3);
    part.rest_trs.scale = Eigen::Vector3d(s[0], s[1], s[2]);
  }
  part.T_parent_part.setIdentity();
  part.T_parent_part.translate(part.rest_trs.translation);
  part.T_parent_part.rotate(part.rest_trs.rotation.toRotationMatrix());
  part.T_parent_part.scale(part.rest_trs.scale);
  return part;
}

// The nodes of the default scene (else every root), parents before children; part_of[node] is
// the node's part, -1 for nodes outside the scene.
std::vector<int> build_parts(const GltfDocument& doc, MeshAsset& asset, std::vector<bool>& has_matrix) {
  const std::size_t n = doc.count("nodes");
  std::vector<long> parent(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const json& node = doc.element("nodes", i);
    if (!node.contains("children")) continue;
    if (!node["children"].is_array()) doc.fail("nodes[" + std::to_string(i) + "].children is not an array");
    for (const auto& c : node["children"]) {
      if (!c.is_number_unsigned() || c.get<std::uint64_t>() >= n) {
        doc.fail("nodes[" + std::to_string(i) + "].children names a node that does not exist");
      }
      const auto child = c.get<std::size_t>();
      if (parent[child] != -1 || child == i) doc.fail("nodes[" + std::to_string(child) + "] has two parents or is its own");
      parent[child] = static_cast<long>(i);
    }
  }
  std::vector<std::size_t> roots;
  if (doc.count("scenes") > 0) {
    const std::size_t scene = json_optional_index(doc, doc.root(), "scene", "").value_or(0);
    const json& sc = doc.element("scenes", scene);
    if (sc.contains("nodes")) {
      if (!sc["nodes"].is_array()) doc.fail("scenes[" + std::to_string(scene) + "].nodes is not an array");
      for (const auto& r : sc["nodes"]) {
        if (!r.is_number_unsigned() || r.get<std::uint64_t>() >= n || parent[r.get<std::size_t>()] != -1) {
          doc.fail("scenes[" + std::to_string(scene) + "].nodes names a node that does not exist or is not a root");
        }
        roots.push_back(r.get<std::size_t>());
      }
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      if (parent[i] == -1) roots.push_back(i);
    }
  }
  std::vector<int> part_of(n, -1);
  has_matrix.assign(n, false);
  // Depth first without recursion (a file may nest deeply), keeping the children's order.
  std::vector<std::pair<std::size_t, int>> stack;
  for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, -1);
  while (!stack.empty()) {
    const auto [node, parent_part] = stack.back();
    stack.pop_back();
    if (part_of[node] != -1) doc.fail("nodes[" + std::to_string(node) + "] appears twice in the scene");
    bool matrix = false;
    MeshPart part = rest_part(doc, node, matrix);
    has_matrix[node] = matrix;
    part.parent = parent_part;
    part_of[node] = static_cast<int>(asset.parts.size());
    asset.parts.push_back(std::move(part));
    const json& children = doc.element("nodes", node).value("children", json::array());
    for (auto c = children.rbegin(); c != children.rend(); ++c) stack.emplace_back(c->get<std::size_t>(), part_of[node]);
  }
  return part_of;
}

struct SkinSource {
  std::vector<int> joint_parts;
  std::vector<Eigen::Matrix4d> inverse_bind;
};

SkinSource read_skin(const GltfDocument& doc, std::size_t index, const std::vector<int>& part_of) {
  const json& skin = doc.element("skins", index);
  const std::string where = "skins[" + std::to_string(index) + "]";
  if (!skin.contains("joints") || !skin["joints"].is_array() || skin["joints"].empty()) doc.fail(where + ".joints is missing or empty");
  SkinSource out;
  for (const auto& j : skin["joints"]) {
    if (!j.is_number_unsigned() || j.get<std::uint64_t>() >= part_of.size()) doc.fail(where + ".joints names a node that does not exist");
    const int part = part_of[j.get<std::size_t>()];
    if (part < 0) doc.fail(where + ".joints names node " + std::to_string(j.get<std::size_t>()) + ", which is not in the scene");
    out.joint_parts.push_back(part);
  }
  if (const auto ibm = json_optional_index(doc, skin, "inverseBindMatrices", where)) {
    const std::vector<double> m = doc.read_accessor(*ibm, {"MAT4"}, where + ".inverseBindMatrices");
    if (m.size() / 16 < out.joint_parts.size()) {
      doc.fail(where + " has " + std::to_string(out.joint_parts.size()) + " joints but " + std::to_string(m.size() / 16) +
               " inverse bind matrices");
    }
    for (std::size_t k = 0; k < out.joint_parts.size(); ++k) out.inverse_bind.emplace_back(Eigen::Map<const Eigen::Matrix4d>(&m[16 * k]));
  } else {
    doc.charge(16 * out.joint_parts.size(), where + " (identity inverse bind matrices)");
    out.inverse_bind.assign(out.joint_parts.size(), Eigen::Matrix4d::Identity());
  }
  return out;
}

// Every JOINTS_n / WEIGHTS_n set of one primitive, appended vertex by vertex.
void read_influences(const GltfDocument& doc, const json& attributes, const std::string& where, std::size_t vertex_count,
                     std::size_t joint_count, SkinBinding& skin) {
  std::vector<std::vector<double>> joints, weights;
  for (int set = 0;; ++set) {
    const std::string j = "JOINTS_" + std::to_string(set), w = "WEIGHTS_" + std::to_string(set);
    if (!attributes.contains(j) && !attributes.contains(w)) break;
    if (!attributes.contains(j) || !attributes.contains(w)) doc.fail(where + " has only one of " + j + " and " + w);
    joints.push_back(doc.read_accessor(json_index(doc, attributes, j.c_str(), where), {"VEC4"}, where + " " + j));
    weights.push_back(doc.read_accessor(json_index(doc, attributes, w.c_str(), where), {"VEC4"}, where + " " + w));
    for (const auto* a : {&joints.back(), &weights.back()}) {
      if (a->size() != 4 * vertex_count) {
        doc.fail(where + " " + (a == &joints.back() ? j : w) + " has " + std::to_string(a->size() / 4) +
                 " elements for " + std::to_string(vertex_count) + " vertices");
      }
    }
  }
  if (joints.empty()) doc.fail(where + " is skinned but has no JOINTS_0 and WEIGHTS_0");
  std::vector<std::pair<std::uint32_t, double>> influences;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    influences.clear();
    for (std::size_t set = 0; set < joints.size(); ++set) {
      for (std::size_t c = 0; c < 4; ++c) {
        const double joint = joints[set][4 * v + c];
        if (joint < 0.0 || joint != std::floor(joint)) doc.fail(where + ": vertex " + std::to_string(v) + " has a joint index that is not an integer");
        influences.emplace_back(static_cast<std::uint32_t>(std::min(joint, 4e9)), weights[set][4 * v + c]);
      }
    }
    append_influences(influences, joint_count, "mesh '" + doc.path() + "': " + where + ": vertex " + std::to_string(v), skin);
  }
}

// The triangles of a primitive of mode 4 (list), 5 (strip) or 6 (fan), as vertex indices.
std::vector<std::uint32_t> triangles(const GltfDocument& doc, int mode, const std::vector<double>& idx,
                                     std::size_t vertex_count, const std::string& where) {
  for (const double i : idx) {
    if (i < 0.0 || i >= static_cast<double>(vertex_count) || i != std::floor(i)) {
      doc.fail(where + " has an index " + std::to_string(i) + " beyond its " + std::to_string(vertex_count) + " vertices");
    }
  }
  const auto at = [&](std::size_t k) { return static_cast<std::uint32_t>(idx[k]); };
  std::vector<std::uint32_t> out;
  if (mode == 4) {
    if (idx.size() % 3 != 0) doc.fail(where + " has " + std::to_string(idx.size()) + " indices, not a multiple of 3");
    for (std::size_t k = 0; k < idx.size(); ++k) out.push_back(at(k));
  } else if (mode == 5) {
    for (std::size_t k = 0; k + 2 < idx.size(); ++k) {
      out.insert(out.end(), {at(k), at(k + 1 + k % 2), at(k + 2 - k % 2)});
    }
  } else {
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) out.insert(out.end(), {at(k), at(k + 1), at(0)});
  }
  return out;
}

void read_mesh(const GltfDocument& doc, std::size_t node, const std::vector<int>& part_of, const ReflectivityTable& table,
               float fallback, MeshAsset& asset, std::size_t& morph_meshes, std::size_t& other_primitives) {
  const json& n = doc.element("nodes", node);
  const std::string nw = "nodes[" + std::to_string(node) + "]";
  const std::size_t mesh_index = json_index(doc, n, "mesh", nw);
  const json& mesh = doc.element("meshes", mesh_index);
  const std::string mw = "meshes[" + std::to_string(mesh_index) + "]";
  if (!mesh.contains("primitives") || !mesh["primitives"].is_array()) doc.fail(mw + ".primitives is missing");
  MeshPart& part = asset.parts[static_cast<std::size_t>(part_of[node])];
  std::optional<SkinSource> skin_source;
  auto skin = std::make_shared<SkinBinding>();
  if (const auto s = json_optional_index(doc, n, "skin", nw)) {
    skin_source = read_skin(doc, *s, part_of);
    skin->joint_parts = skin_source->joint_parts;
    skin->inverse_bind = skin_source->inverse_bind;
    skin->first_influence.assign(1, 0);
  }
  bool morph = false;
  for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
    const json& prim = mesh["primitives"][p];
    const std::string pw = mw + ".primitives[" + std::to_string(p) + "]";
    if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object()) doc.fail(pw + ".attributes is missing");
    const std::size_t mode_value = json_optional_index(doc, prim, "mode", pw).value_or(4);
    if (mode_value > 6) doc.fail(pw + ".mode is " + std::to_string(mode_value) + ", glTF has modes 0 to 6");
    const int mode = static_cast<int>(mode_value);
    if (mode < 4) {
      ++other_primitives;  // points and lines: no surface for a beam to hit
      continue;
    }
    if (prim.contains("targets") && prim["targets"].is_array() && !prim["targets"].empty()) morph = true;
    const json& attributes = prim["attributes"];
    const std::vector<double> positions =
        doc.read_accessor(json_index(doc, attributes, "POSITION", pw + ".attributes"), {"VEC3"}, pw + " POSITION");
    const std::size_t vertex_count = positions.size() / 3;
    std::vector<double> idx;
    if (const auto i = json_optional_index(doc, prim, "indices", pw)) {
      idx = doc.read_accessor(*i, {"SCALAR"}, pw + " indices");
    } else {
      for (std::size_t k = 0; k < vertex_count; ++k) idx.push_back(static_cast<double>(k));
    }
    const std::vector<std::uint32_t> tris = triangles(doc, mode, idx, vertex_count, pw);
    float reflectivity = fallback;
    std::string material;
    if (const auto m = json_optional_index(doc, prim, "material", pw)) {
      material = json_string(doc, doc.element("materials", *m), "name", "materials[" + std::to_string(*m) + "]", "");
      const auto it = table.find(material);
      if (it != table.end()) reflectivity = it->second;
    }
    const std::uint16_t material_index = asset.material_index(material);
    const auto base = static_cast<std::uint32_t>(part.vertices.size());
    if (part.vertices.size() + vertex_count > 0xFFFFFFF0u) doc.fail(pw + ": too many vertices");
    for (std::size_t v = 0; v < vertex_count; ++v) {
      part.vertices.emplace_back(static_cast<float>(positions[3 * v]), static_cast<float>(positions[3 * v + 1]),
                                 static_cast<float>(positions[3 * v + 2]));
      if (!part.vertices.back().allFinite()) doc.fail(pw + " POSITION of vertex " + std::to_string(v) + " is not finite");
    }
    for (const auto i : tris) part.indices.push_back(base + i);
    part.triangle_reflectivity.insert(part.triangle_reflectivity.end(), tris.size() / 3, reflectivity);
    part.triangle_material.insert(part.triangle_material.end(), tris.size() / 3, material_index);
    if (skin_source) read_influences(doc, attributes, pw, vertex_count, skin_source->joint_parts.size(), *skin);
  }
  if (morph) ++morph_meshes;
  if (skin_source && !part.vertices.empty()) {
    skin->validate("mesh '" + doc.path() + "': " + nw + " skin", part.vertices.size(), asset.parts.size());
    part.skin = std::move(skin);
  }
}

// Every node's rest transform and every vertex at rest must be finite: transforms of finite but
// huge numbers (a translation of 1e308 under a scale of 1e308) overflow, and the rest of the
// simulator expects finite geometry.
void check_rest_pose(const GltfDocument& doc, const MeshAsset& asset, const std::vector<int>& part_of) {
  const std::vector<Eigen::Affine3d> T = asset.rest_transforms();
  for (std::size_t node = 0; node < part_of.size(); ++node) {
    if (part_of[node] < 0) continue;
    const auto k = static_cast<std::size_t>(part_of[node]);
    const std::string what = "nodes[" + std::to_string(node) + "] ('" + asset.parts[k].name + "')";
    if (!T[k].matrix().allFinite()) doc.fail(what + ": its transform at rest overflows (translation, scale or matrix too large)");
    for (const auto& v : asset.rest_vertices(k, T)) {
      if (!v.allFinite()) doc.fail(what + ": its vertices at rest overflow (coordinates or transforms too large)");
    }
  }
}

AnimationClip read_animation(const GltfDocument& doc, std::size_t index, const std::vector<int>& part_of,
                             const std::vector<bool>& has_matrix, std::size_t& morph_channels, std::size_t& outside_channels) {
  const json& anim = doc.element("animations", index);
  const std::string aw = "animations[" + std::to_string(index) + "]";
  AnimationClip clip;
  clip.name = json_string(doc, anim, "name", aw, "");
  if (clip.name.empty()) clip.name = "animation_" + std::to_string(index);
  if (anim.contains("extras") && anim["extras"].is_object() && anim["extras"].contains("nominal_speed_mps")) {
    const json& v = anim["extras"]["nominal_speed_mps"];
    if (!v.is_number() || !(v.get<double>() > 0.0) || !std::isfinite(v.get<double>())) {
      doc.fail("clip '" + clip.name + "': extras.nominal_speed_mps must be a number > 0");
    }
    clip.nominal_speed_mps = v.get<double>();
  }
  if (!anim.contains("channels") || !anim["channels"].is_array() || !anim.contains("samplers") || !anim["samplers"].is_array()) {
    doc.fail("clip '" + clip.name + "' (" + aw + ") needs channels and samplers");
  }
  const json& samplers = anim["samplers"];
  std::vector<int> track_of_part(part_of.size(), -1);  // the clip's track for each part (parts <= nodes)
  for (std::size_t c = 0; c < anim["channels"].size(); ++c) {
    const json& ch = anim["channels"][c];
    const std::string cw = "clip '" + clip.name + "' channel " + std::to_string(c);
    if (!ch.is_object() || !ch.contains("target") || !ch["target"].is_object()) doc.fail(cw + " has no target");
    const json& target = ch["target"];
    const std::string path = json_string(doc, target, "path", cw + ".target", "");
    if (path == "weights") {
      ++morph_channels;
      continue;
    }
    if (kPaths.count(path) == 0) doc.fail(cw + " animates '" + path + "' (translation, rotation, scale or weights)");
    const auto node = json_optional_index(doc, target, "node", cw + ".target");
    if (!node) {
      ++outside_channels;  // an extension's target: nothing the simulator moves
      continue;
    }
    if (*node >= part_of.size()) doc.fail(cw + " targets node " + std::to_string(*node) + ", which does not exist");
    if (part_of[*node] < 0) {
      ++outside_channels;
      continue;
    }
    const std::string what = cw + " (node '" + node_label(doc, *node) + "', " + path + ")";
    if (has_matrix[*node]) doc.fail(what + ": the node has a matrix, which glTF does not let a clip animate");
    const std::size_t s = json_index(doc, ch, "sampler", cw);
    if (s >= samplers.size() || !samplers[s].is_object()) doc.fail(what + " names sampler " + std::to_string(s) + ", which does not exist");
    const json& sampler = samplers[s];
    const std::string interp = json_string(doc, sampler, "interpolation", what, "LINEAR");
    KeyCurve curve;
    if (interp == "STEP") {
      curve.interpolation = Interpolation::kStep;
    } else if (interp == "LINEAR") {
      curve.interpolation = Interpolation::kLinear;
    } else if (interp == "CUBICSPLINE") {
      curve.interpolation = Interpolation::kCubicSpline;
    } else {
      doc.fail(what + " has interpolation '" + interp + "' (STEP, LINEAR or CUBICSPLINE)");
    }
    curve.width = path == "rotation" ? 4 : 3;
    curve.times_s = doc.read_accessor(json_index(doc, sampler, "input", what), {"SCALAR"}, what + " input", false);
    curve.values = doc.read_accessor(json_index(doc, sampler, "output", what), {curve.width == 4 ? "VEC4" : "VEC3"},
                                     what + " output");
    curve.validate("mesh '" + doc.path() + "': " + what);
    const auto part = part_of[*node];
    int& track_index = track_of_part[static_cast<std::size_t>(part)];
    if (track_index < 0) {
      track_index = static_cast<int>(clip.tracks.size());
      clip.tracks.push_back({});
      clip.tracks.back().part = part;
    }
    NodeTrack* track = &clip.tracks[static_cast<std::size_t>(track_index)];
    KeyCurve& slot = path == "translation" ? track->translation : path == "rotation" ? track->rotation : track->scale;
    if (!slot.empty()) doc.fail(what + ": a second channel for the same node and property");
    slot = std::move(curve);
    clip.duration_s = std::max(clip.duration_s, slot.times_s.back());
  }
  return clip;
}

}  // namespace

std::optional<MeshAsset> load_animated_gltf(const std::string& path, const ReflectivityTable& reflectivity,
                                            float default_reflectivity) {
  std::optional<GltfDocument> read = GltfDocument::read(path);
  if (read) check_primitive_counts(*read);
  if (!read || (read->count("animations") == 0 && read->count("skins") == 0)) return std::nullopt;
  check_extensions(*read);
  read->load_buffers();
  const GltfDocument& doc = *read;
  MeshAsset asset;
  asset.path = path;
  std::vector<bool> has_matrix;
  const std::vector<int> part_of = build_parts(doc, asset, has_matrix);
  std::size_t morph_meshes = 0, other_primitives = 0, morph_channels = 0, outside_channels = 0;
  for (std::size_t node = 0; node < part_of.size(); ++node) {
    if (part_of[node] >= 0 && doc.element("nodes", node).contains("mesh")) {
      read_mesh(doc, node, part_of, reflectivity, default_reflectivity, asset, morph_meshes, other_primitives);
    }
  }
  check_rest_pose(doc, asset, part_of);
  for (std::size_t a = 0; a < doc.count("animations"); ++a) {
    asset.clips.push_back(read_animation(doc, a, part_of, has_matrix, morph_channels, outside_channels));
  }
  const auto note = [&](std::size_t count, const std::string& what) {
    if (count > 0) asset.notices.push_back("mesh '" + path + "': " + std::to_string(count) + " " + what);
  };
  note(morph_meshes, "mesh(es) with morph targets: the targets are ignored, the base shape is used");
  note(morph_channels, "morph-weight channel(s) ignored");
  note(other_primitives, "point or line primitive(s) ignored: they have no surface");
  note(outside_channels, "channel(s) ignored: they target no node of the scene");
  return asset;
}

void append_influences(std::vector<std::pair<std::uint32_t, double>>& influences, std::size_t joint_count,
                       const std::string& where, SkinBinding& skin) {
  double sum = 0.0;
  for (const auto& [joint, weight] : influences) {
    if (!std::isfinite(weight) || weight < 0.0) throw core::FileError(where + " has a weight " + std::to_string(weight));
    if (weight == 0.0) continue;
    if (joint >= joint_count) {
      throw core::FileError(where + " is bound to joint " + std::to_string(joint) + " but the skin has " +
                            std::to_string(joint_count) + " joints");
    }
    sum += weight;
  }
  if (std::abs(sum - 1.0) > 0.01) {
    throw core::FileError(where + ": its bone weights sum to " + std::to_string(sum) + ", not 1");
  }
  for (const auto& [joint, weight] : influences) {
    if (weight == 0.0) continue;
    skin.influence_joint.push_back(joint);
    skin.influence_weight.push_back(static_cast<float>(weight / sum));
  }
  skin.first_influence.push_back(static_cast<std::uint32_t>(skin.influence_joint.size()));
}

}  // namespace fmcw::sim::detail
