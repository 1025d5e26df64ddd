// Meshes through assimp: the node hierarchy with its triangles, bones as a skin per node, and
// node animations as clips of linearly interpolated keys (assimp keeps no interpolation mode).

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "mesh_loaders.hpp"

namespace fmcw::sim::detail {

namespace {

Eigen::Affine3d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return Eigen::Affine3d(e);
}

// A node's meshes that carry bones, with the index of their first vertex in the part.
struct BonedMesh {
  const aiMesh* mesh;
  std::uint32_t base;
};

struct Reader {
  const aiScene* scene;
  const ReflectivityTable& table;
  float fallback;
  MeshAsset& asset;
  std::vector<std::vector<BonedMesh>> boned;  // per part

  void add_node(const aiNode* root) {
    // Depth first without recursion (a file may nest deeply), children in order.
    std::vector<std::tuple<const aiNode*, int, Eigen::Affine3d>> stack{{root, -1, Eigen::Affine3d::Identity()}};
    while (!stack.empty()) {
      const auto [node, parent, T_asset_parent] = stack.back();
      stack.pop_back();
      const int self = static_cast<int>(asset.parts.size());
      asset.parts.emplace_back();
      boned.emplace_back();
      MeshPart& part = asset.parts.back();
      part.name = node->mName.C_Str();
      part.parent = parent;
      part.T_parent_part = to_eigen(node->mTransformation);
      part.rest_trs = decompose_trs(part.T_parent_part);
      const Eigen::Affine3d T_asset_part = T_asset_parent * part.T_parent_part;
      for (unsigned k = 0; k < node->mNumMeshes; ++k) add_mesh(scene->mMeshes[node->mMeshes[k]], part, self, T_asset_part);
      for (unsigned c = node->mNumChildren; c-- > 0;) stack.emplace_back(node->mChildren[c], self, T_asset_part);
    }
  }

  void add_mesh(const aiMesh* mesh, MeshPart& part, int self, const Eigen::Affine3d& T_asset_part) {
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return;
    float reflectivity = fallback;
    std::string material;
    if (mesh->mMaterialIndex < scene->mNumMaterials) {
      aiString name;
      if (scene->mMaterials[mesh->mMaterialIndex]->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) {
        material = name.C_Str();
        const auto it = table.find(material);
        if (it != table.end()) reflectivity = it->second;
      }
    }
    const std::uint16_t material_index = asset.material_index(material);
    const auto base = static_cast<std::uint32_t>(part.vertices.size());
    if (mesh->mNumBones > 0) boned[static_cast<std::size_t>(self)].push_back({mesh, base});
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      part.vertices.emplace_back(p.x, p.y, p.z);
      if (mesh->mNumBones == 0) asset.rest_bounds.extend(T_asset_part * Eigen::Vector3d(p.x, p.y, p.z));
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int c = 0; c < 3; ++c) part.indices.push_back(base + face.mIndices[c]);
      part.triangle_reflectivity.push_back(reflectivity);
      part.triangle_material.push_back(material_index);
    }
  }

  // The bones of a part's meshes as one skin; vertices of its meshes without bones follow the
  // part itself (the part is a joint with an identity inverse bind matrix).
  void add_skin(std::size_t p) {
    MeshPart& part = asset.parts[p];
    auto skin = std::make_shared<SkinBinding>();
    std::vector<std::vector<std::pair<std::uint32_t, double>>> influences(part.vertices.size());
    const auto joint = [&](int node, const Eigen::Matrix4d& B) {
      for (std::size_t j = 0; j < skin->joint_parts.size(); ++j) {
        if (skin->joint_parts[j] == node && skin->inverse_bind[j].isApprox(B, 1e-12)) return static_cast<std::uint32_t>(j);
      }
      skin->joint_parts.push_back(node);
      skin->inverse_bind.push_back(B);
      return static_cast<std::uint32_t>(skin->joint_parts.size() - 1);
    };
    std::vector<bool> boned_vertex(part.vertices.size(), false);
    for (const BonedMesh& m : boned[p]) {
      for (unsigned b = 0; b < m.mesh->mNumBones; ++b) {
        const aiBone* bone = m.mesh->mBones[b];
        const int node = asset.find_part(bone->mName.C_Str());
        const std::string where = "mesh '" + asset.path + "': bone '" + bone->mName.C_Str() + "' of mesh '" + m.mesh->mName.C_Str() + "'";
        if (node < 0) throw core::FileError(where + " names no node");
        const std::uint32_t j = joint(node, to_eigen(bone->mOffsetMatrix).matrix());
        for (unsigned w = 0; w < bone->mNumWeights; ++w) {
          const aiVertexWeight& vw = bone->mWeights[w];
          if (vw.mVertexId >= m.mesh->mNumVertices) throw core::FileError(where + " weights vertex " + std::to_string(vw.mVertexId) + ", which does not exist");
          influences[m.base + vw.mVertexId].emplace_back(j, vw.mWeight);
        }
      }
      for (unsigned v = 0; v < m.mesh->mNumVertices; ++v) boned_vertex[m.base + v] = true;
    }
    skin->first_influence.assign(1, 0);
    for (std::size_t v = 0; v < part.vertices.size(); ++v) {
      if (!boned_vertex[v]) influences[v].emplace_back(joint(static_cast<int>(p), Eigen::Matrix4d::Identity()), 1.0);
      if (influences[v].empty()) {
        throw core::FileError("mesh '" + asset.path + "': node '" + part.name + "': vertex " + std::to_string(v) + " has no bone weight");
      }
      append_influences(influences[v], skin->joint_parts.size(),
                        "mesh '" + asset.path + "': node '" + part.name + "': vertex " + std::to_string(v), *skin);
    }
    skin->validate("mesh '" + asset.path + "': node '" + part.name + "' skin", part.vertices.size(), asset.parts.size());
    part.skin = std::move(skin);
  }

  AnimationClip clip(unsigned index) {
    const aiAnimation* anim = scene->mAnimations[index];
    AnimationClip c;
    c.name = anim->mName.length > 0 ? anim->mName.C_Str() : "animation_" + std::to_string(index);
    // Ticks per second: 0 means the format did not say; assimp's convention is then 25.
    const double tps = anim->mTicksPerSecond > 0.0 ? anim->mTicksPerSecond : 25.0;
    std::size_t outside = 0;
    for (unsigned k = 0; k < anim->mNumChannels; ++k) {
      const aiNodeAnim* ch = anim->mChannels[k];
      const int part = asset.find_part(ch->mNodeName.C_Str());
      if (part < 0) {
        ++outside;
        continue;
      }
      NodeTrack track;
      track.part = part;
      const std::string what = "mesh '" + asset.path + "': clip '" + c.name + "' channel " + std::to_string(k) +
                               " (node '" + ch->mNodeName.C_Str() + "', ";
      const auto vectors = [&](const aiVectorKey* keys, unsigned n, KeyCurve& curve, const char* path) {
        curve.width = 3;
        for (unsigned i = 0; i < n; ++i) {
          curve.times_s.push_back(keys[i].mTime / tps);
          curve.values.insert(curve.values.end(), {keys[i].mValue.x, keys[i].mValue.y, keys[i].mValue.z});
        }
        if (n > 0) curve.validate(what + path + ")");
      };
      vectors(ch->mPositionKeys, ch->mNumPositionKeys, track.translation, "translation");
      vectors(ch->mScalingKeys, ch->mNumScalingKeys, track.scale, "scale");
      track.rotation.width = 4;
      for (unsigned i = 0; i < ch->mNumRotationKeys; ++i) {
        const aiQuaternion& q = ch->mRotationKeys[i].mValue;
        track.rotation.times_s.push_back(ch->mRotationKeys[i].mTime / tps);
        track.rotation.values.insert(track.rotation.values.end(), {q.x, q.y, q.z, q.w});
      }
      if (ch->mNumRotationKeys > 0) track.rotation.validate(what + "rotation)");
      for (const KeyCurve* curve : {&track.translation, &track.rotation, &track.scale}) {
        if (!curve->empty()) c.duration_s = std::max(c.duration_s, curve->times_s.back());
      }
      c.tracks.push_back(std::move(track));
    }
    if (outside > 0) {
      asset.notices.push_back("mesh '" + asset.path + "': clip '" + c.name + "': " + std::to_string(outside) +
                              " channel(s) ignored: they name no node");
    }
    if (anim->mNumMeshChannels > 0 || anim->mNumMorphMeshChannels > 0) {
      asset.notices.push_back("mesh '" + asset.path + "': clip '" + c.name + "': mesh and morph channels ignored");
    }
    return c;
  }
};

}  // namespace

MeshAsset load_assimp_asset(const std::string& path, const ReflectivityTable& reflectivity, float default_reflectivity) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                aiProcess_FindDegenerates | aiProcess_ValidateDataStructure);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    throw core::FileError("mesh '" + path + "' cannot be read: " + importer.GetErrorString());
  }
  // assimp reads a file without a mesh (an FBX of a skeleton, a camera path or an animation
  // alone) and flags the scene incomplete, with no error to give.
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) {
    throw core::FileError("mesh '" + path + "' holds no triangles: assimp finds no mesh in it");
  }
  MeshAsset asset;
  asset.path = path;
  Reader reader{scene, reflectivity, default_reflectivity, asset, {}};
  reader.add_node(scene->mRootNode);
  for (std::size_t p = 0; p < asset.parts.size(); ++p) {
    if (!reader.boned[p].empty()) reader.add_skin(p);
  }
  for (unsigned a = 0; a < scene->mNumAnimations; ++a) asset.clips.push_back(reader.clip(a));
  return asset;
}

}  // namespace fmcw::sim::detail
