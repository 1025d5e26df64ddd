#pragma once
// Triangle meshes loaded with assimp, kept as a node hierarchy so parts can move on their own.

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

namespace fmcw::sim {

/// Reflectivity [0, 1] by material name (assets/materials.yaml).
using ReflectivityTable = std::map<std::string, float>;

/// One node of an asset: its rest transform relative to its parent and its own triangles.
struct MeshPart {
  std::string name;
  int parent = -1;                                            ///< index into parts; -1: asset root
  Eigen::Affine3d T_parent_part = Eigen::Affine3d::Identity();  ///< rest transform (may scale)
  std::vector<Eigen::Vector3f> vertices;                      ///< part frame [m]
  std::vector<std::uint32_t> indices;                         ///< 3 per triangle
  std::vector<float> triangle_reflectivity;                   ///< one per triangle
  std::size_t triangle_count() const { return indices.size() / 3; }
};

struct MeshAsset {
  std::string path;
  std::vector<MeshPart> parts;  ///< parents precede children
  Eigen::AlignedBox3d rest_bounds;  ///< of all vertices at rest, asset frame
  std::size_t triangle_count() const;
  int find_part(const std::string& name) const;  ///< -1 when absent
};

/// A closed box [-h, h] (outward triangles) as a one-part asset named `name`: handy for
/// analytic scenes and studies, where every hit and velocity is known in closed form.
MeshAsset box_mesh(const Eigen::Vector3f& half_extent_m, float reflectivity, const std::string& name = "box");

/// Loads any format assimp reads (OBJ, glTF/GLB, PLY, STL, FBX, ...). Each triangle's
/// reflectivity comes from its material's name in the table, else default_reflectivity.
/// Throws std::invalid_argument naming the file when it is missing, unreadable by assimp, or
/// holds no triangle.
MeshAsset load_mesh_asset(const std::string& path, const ReflectivityTable& reflectivity,
                          float default_reflectivity);

}  // namespace fmcw::sim
