#pragma once
// Triangle meshes kept as a node hierarchy so parts can move on their own, with the file's
// keyframe clips and skins (linear blend skinning), loaded with assimp or, for animated
// glTF 2.0, with the project's own reader (docs/SIMULATOR.md, "Your own meshes").

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fmcw/sim/animation_clip.hpp"
#include "fmcw/sim/skinning.hpp"

namespace fmcw::sim {

/// Reflectivity [0, 1] by material name (assets/materials.yaml).
using ReflectivityTable = std::map<std::string, float>;

/// One node of an asset: its rest transform relative to its parent and its own triangles.
struct MeshPart {
  std::string name;
  int parent = -1;                                            ///< index into parts; -1: asset root
  Eigen::Affine3d T_parent_part = Eigen::Affine3d::Identity();  ///< rest transform (may scale)
  NodeTrs rest_trs;  ///< T_parent_part as translation, rotation, scale: what a clip's curves replace
  std::vector<Eigen::Vector3f> vertices;                      ///< part frame [m]; mesh space when skinned
  std::vector<std::uint32_t> indices;                         ///< 3 per triangle
  std::vector<float> triangle_reflectivity;                   ///< one per triangle
  std::vector<std::uint16_t> triangle_material;               ///< one per triangle: index into MeshAsset::materials
  /// Set: the vertices are skinned by these joints, and the part's own transform is not applied.
  std::shared_ptr<const SkinBinding> skin;
  std::size_t triangle_count() const { return indices.size() / 3; }
};

struct MeshAsset {
  std::string path;
  std::vector<MeshPart> parts;  ///< parents precede children
  Eigen::AlignedBox3d rest_bounds;  ///< of all vertices at rest (skinned ones at their rest pose), asset frame
  std::vector<AnimationClip> clips;  ///< in the file's order
  std::vector<std::string> materials;  ///< material names, as triangle_material indexes them
  /// What the file holds that the simulator does not use (morph targets, point primitives, ...),
  /// one line each, for the caller to say once.
  std::vector<std::string> notices;
  std::size_t triangle_count() const;
  int find_part(const std::string& name) const;  ///< -1 when absent
  /// The index of a material name in `materials`, added when new.
  std::uint16_t material_index(const std::string& name);
  /// A clip by name, or by its index written as a number; -1 when there is none such.
  int find_clip(const std::string& name_or_index) const;
  /// "walk", "idle" (for messages); "none" when the file has no clip.
  std::string clip_names() const;
  /// Every part's rest transform in the asset frame (parents before children).
  std::vector<Eigen::Affine3d> rest_transforms() const;
  /// Part k's vertices at rest in the asset frame: skinned with the joints' rest transforms, or
  /// moved by its own rest transform.
  std::vector<Eigen::Vector3f> rest_vertices(std::size_t k, const std::vector<Eigen::Affine3d>& T_asset_part) const;
};

/// Splits an affine transform into translation, rotation and scale (T R S; a shear, which T R S
/// cannot hold, is dropped).
NodeTrs decompose_trs(const Eigen::Affine3d& T);

/// A closed box [-h, h] (outward triangles) as a one-part asset named `name`: handy for
/// analytic scenes and studies, where every hit and velocity is known in closed form.
MeshAsset box_mesh(const Eigen::Vector3f& half_extent_m, float reflectivity, const std::string& name = "box");

/// Loads any format assimp reads (OBJ, glTF/GLB, PLY, STL, FBX, ...), with its node clips and
/// skins. A glTF 2.0 file with animations or skins is read by the project's own glTF reader,
/// which keeps STEP and CUBICSPLINE interpolation with its tangents and any number of joint
/// weights per vertex. Each triangle's reflectivity comes from its material's name in the table,
/// else default_reflectivity. Throws core::FileError naming the file when it is missing,
/// unreadable, holds no triangle, or holds a bad clip or skin (naming the clip, channel or
/// vertex and what is wrong); core::LimitError for a glTF over 2 GiB or over 65535 materials.
MeshAsset load_mesh_asset(const std::string& path, const ReflectivityTable& reflectivity,
                          float default_reflectivity);

}  // namespace fmcw::sim
