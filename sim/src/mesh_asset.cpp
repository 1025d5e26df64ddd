#include "fmcw/sim/mesh_asset.hpp"

#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/io/yaml_reader.hpp"
#include "mesh_loaders.hpp"

namespace fmcw::sim {

std::size_t MeshAsset::triangle_count() const {
  std::size_t n = 0;
  for (const auto& p : parts) n += p.triangle_count();
  return n;
}

int MeshAsset::find_part(const std::string& name) const {
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts[k].name == name) return static_cast<int>(k);
  }
  return -1;
}

std::uint16_t MeshAsset::material_index(const std::string& name) {
  for (std::size_t k = 0; k < materials.size(); ++k) {
    if (materials[k] == name) return static_cast<std::uint16_t>(k);
  }
  if (materials.size() >= 0xFFFF) throw core::LimitError("mesh '" + path + "' has more than 65535 materials");
  materials.push_back(name);
  return static_cast<std::uint16_t>(materials.size() - 1);
}

int MeshAsset::find_clip(const std::string& name_or_index) const {
  for (std::size_t k = 0; k < clips.size(); ++k) {
    if (clips[k].name == name_or_index) return static_cast<int>(k);
  }
  if (!name_or_index.empty() && name_or_index.size() < 10 &&
      name_or_index.find_first_not_of("0123456789") == std::string::npos) {
    const auto k = std::stoul(name_or_index);
    if (k < clips.size()) return static_cast<int>(k);
  }
  return -1;
}

std::string MeshAsset::clip_names() const {
  if (clips.empty()) return "none";
  std::string out;
  for (std::size_t k = 0; k < clips.size(); ++k) out += (k ? ", '" : "'") + clips[k].name + "'";
  return out;
}

std::vector<Eigen::Affine3d> MeshAsset::rest_transforms() const {
  std::vector<Eigen::Affine3d> T(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const int parent = parts[k].parent;
    T[k] = parent < 0 ? parts[k].T_parent_part : T[static_cast<std::size_t>(parent)] * parts[k].T_parent_part;
  }
  return T;
}

std::vector<Eigen::Vector3f> MeshAsset::rest_vertices(std::size_t k, const std::vector<Eigen::Affine3d>& T_asset_part) const {
  const MeshPart& part = parts[k];
  std::vector<Eigen::Vector3f> out(part.vertices.size());
  if (!part.skin) {
    for (std::size_t v = 0; v < out.size(); ++v) out[v] = (T_asset_part[k] * part.vertices[v].cast<double>()).cast<float>();
    return out;
  }
  JointMatrices joints;
  for (std::size_t j = 0; j < part.skin->joint_parts.size(); ++j) {
    joints.M.push_back((T_asset_part[static_cast<std::size_t>(part.skin->joint_parts[j])].matrix() * part.skin->inverse_bind[j]).topRows<3>());
  }
  skin_vertices(*part.skin, joints, part.vertices, out.data()->data(), nullptr);
  return out;
}

NodeTrs decompose_trs(const Eigen::Affine3d& T) {
  NodeTrs trs;
  trs.translation = T.translation();
  Eigen::Matrix3d R, S;
  T.computeRotationScaling(&R, &S);  // polar decomposition: linear = R S, R a rotation
  trs.rotation = Eigen::Quaterniond(R).normalized();
  trs.scale = S.diagonal();
  return trs;
}

MeshAsset box_mesh(const Eigen::Vector3f& h, float reflectivity, const std::string& name) {
  MeshAsset asset;
  asset.path = "<box>";
  MeshPart part;
  part.name = name;
  for (int k = 0; k < 8; ++k) {
    part.vertices.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
  }
  // Two counter-clockwise (seen from outside) triangles per face.
  const std::uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                      {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) {
    part.indices.insert(part.indices.end(), {f[0], f[1], f[2]});
    part.triangle_reflectivity.push_back(reflectivity);
  }
  for (const auto& v : part.vertices) asset.rest_bounds.extend(v.cast<double>());
  asset.parts.push_back(std::move(part));
  return asset;
}

MeshAsset load_mesh_asset(const std::string& path, const ReflectivityTable& reflectivity, float default_reflectivity) {
  if (!io::is_existing_file(path)) {
    throw core::FileError("mesh '" + path + "' does not exist");
  }
  std::optional<MeshAsset> gltf = detail::load_animated_gltf(path, reflectivity, default_reflectivity);
  MeshAsset asset = gltf ? std::move(*gltf) : detail::load_assimp_asset(path, reflectivity, default_reflectivity);
  // Skinned parts (and every part of the glTF reader, which leaves the bounds to this) at rest.
  const std::vector<Eigen::Affine3d> T = asset.rest_transforms();
  for (std::size_t k = 0; k < asset.parts.size(); ++k) {
    if (!gltf && !asset.parts[k].skin) continue;  // assimp's reader added them as it read them
    for (const auto& v : asset.rest_vertices(k, T)) asset.rest_bounds.extend(v.cast<double>());
  }
  if (asset.triangle_count() == 0) throw core::FileError("mesh '" + path + "' holds no triangles");
  return asset;
}

}  // namespace fmcw::sim
