#pragma once
// Linear blend skinning with exact vertex velocities: a vertex v of a skinned mesh sits at
// p(t) = sum_i w_i M_i(t) B_i v and moves at dp/dt = sum_i w_i (dM_i/dt) B_i v, where M_i is
// joint i's world transform and B_i its inverse bind matrix (glTF 2.0 "Skins"; assimp's bone
// offset matrix). The skinned mesh node's own transform is not applied, as glTF requires.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace fmcw::sim {

struct SkinBinding {
  std::vector<int> joint_parts;                ///< the part (node) of each joint
  std::vector<Eigen::Matrix4d> inverse_bind;   ///< B_i per joint: mesh space -> joint space at bind
  std::vector<std::uint32_t> first_influence;  ///< per vertex + 1: vertex v's influences are [first[v], first[v + 1])
  std::vector<std::uint32_t> influence_joint;  ///< index into joint_parts
  std::vector<float> influence_weight;         ///< > 0; each vertex's weights sum to 1

  /// Throws std::invalid_argument, prefixed by `where`, unless the binding is consistent with
  /// `vertex_count` vertices and `part_count` parts: every vertex has an influence, joints in
  /// range, weights finite and positive summing to 1 within 1e-4, inverse bind matrices finite
  /// and affine.
  void validate(const std::string& where, std::size_t vertex_count, std::size_t part_count) const;
};

/// Joint i's skinning matrix M_i B_i and its derivative, from its part's world transform.
struct JointMatrices {
  std::vector<Eigen::Matrix<double, 3, 4>> M;
  std::vector<Eigen::Matrix<double, 3, 4>> M_dot;
};

/// positions (x y z per vertex, single precision, as Embree's vertex buffer takes them) and,
/// when velocities is not null, the exact velocity of every vertex.
void skin_vertices(const SkinBinding& skin, const JointMatrices& joints, const std::vector<Eigen::Vector3f>& rest,
                   float* positions, Eigen::Vector3d* velocities);

}  // namespace fmcw::sim
