#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/yaml_reader.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <stdexcept>

namespace fmcw::sim {

namespace {
Eigen::Affine3d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return Eigen::Affine3d(e);
}

void add_node(const aiScene* scene, const aiNode* node, int parent, const ReflectivityTable& table, float fallback,
              MeshAsset& asset, const Eigen::Affine3d& T_asset_parent) {
  MeshPart part;
  part.name = node->mName.C_Str();
  part.parent = parent;
  part.T_parent_part = to_eigen(node->mTransformation);
  const Eigen::Affine3d T_asset_part = T_asset_parent * part.T_parent_part;
  for (unsigned k = 0; k < node->mNumMeshes; ++k) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    float reflectivity = fallback;
    if (mesh->mMaterialIndex < scene->mNumMaterials) {
      aiString name;
      if (scene->mMaterials[mesh->mMaterialIndex]->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) {
        const auto it = table.find(name.C_Str());
        if (it != table.end()) reflectivity = it->second;
      }
    }
    const auto base = static_cast<std::uint32_t>(part.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      part.vertices.emplace_back(p.x, p.y, p.z);
      asset.rest_bounds.extend(T_asset_part * Eigen::Vector3d(p.x, p.y, p.z));
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int c = 0; c < 3; ++c) part.indices.push_back(base + face.mIndices[c]);
      part.triangle_reflectivity.push_back(reflectivity);
    }
  }
  const int self = static_cast<int>(asset.parts.size());
  asset.parts.push_back(std::move(part));
  for (unsigned c = 0; c < node->mNumChildren; ++c) {
    add_node(scene, node->mChildren[c], self, table, fallback, asset, T_asset_part);
  }
}
}  // namespace

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
  if (!is_existing_file(path)) {
    throw std::invalid_argument("mesh '" + path + "' does not exist");
  }
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                aiProcess_FindDegenerates | aiProcess_ValidateDataStructure);
  if (scene == nullptr || scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    throw std::invalid_argument("mesh '" + path + "' cannot be read: " + importer.GetErrorString());
  }
  MeshAsset asset;
  asset.path = path;
  add_node(scene, scene->mRootNode, -1, reflectivity, default_reflectivity, asset, Eigen::Affine3d::Identity());
  if (asset.triangle_count() == 0) throw std::invalid_argument("mesh '" + path + "' holds no triangles");
  return asset;
}

}  // namespace fmcw::sim
