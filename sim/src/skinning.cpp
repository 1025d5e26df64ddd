#include "fmcw/sim/skinning.hpp"

#include <cmath>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::sim {

void SkinBinding::validate(const std::string& where, std::size_t vertex_count, std::size_t part_count) const {
  const auto fail = [&](const std::string& what) { throw core::FileError(where + ": " + what); };
  if (joint_parts.empty()) fail("the skin has no joint");
  if (inverse_bind.size() != joint_parts.size()) {
    fail(std::to_string(joint_parts.size()) + " joints but " + std::to_string(inverse_bind.size()) +
         " inverse bind matrices");
  }
  for (std::size_t j = 0; j < joint_parts.size(); ++j) {
    if (joint_parts[j] < 0 || static_cast<std::size_t>(joint_parts[j]) >= part_count) {
      fail("joint " + std::to_string(j) + " names no node");
    }
    const Eigen::Matrix4d& B = inverse_bind[j];
    if (!B.allFinite()) fail("the inverse bind matrix of joint " + std::to_string(j) + " is not finite");
    if ((B.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6 ||
        std::abs(B.topLeftCorner<3, 3>().determinant()) < 1e-12) {
      fail("the inverse bind matrix of joint " + std::to_string(j) + " is not an invertible affine transform");
    }
  }
  if (first_influence.size() != vertex_count + 1 || first_influence.front() != 0 ||
      first_influence.back() != influence_joint.size() || influence_weight.size() != influence_joint.size()) {
    fail("the influence lists do not match the " + std::to_string(vertex_count) + " vertices");
  }
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (first_influence[v + 1] <= first_influence[v]) fail("vertex " + std::to_string(v) + " has no bone weight");
    double sum = 0.0;
    for (std::uint32_t k = first_influence[v]; k < first_influence[v + 1]; ++k) {
      if (influence_joint[k] >= joint_parts.size()) {
        fail("vertex " + std::to_string(v) + " names joint " + std::to_string(influence_joint[k]) + " of " +
             std::to_string(joint_parts.size()));
      }
      if (!(influence_weight[k] > 0.0f) || !std::isfinite(influence_weight[k])) {
        fail("vertex " + std::to_string(v) + " has a weight that is not finite and positive");
      }
      sum += influence_weight[k];
    }
    if (std::abs(sum - 1.0) > 1e-4) fail("the weights of vertex " + std::to_string(v) + " sum to " + std::to_string(sum));
  }
}

void skin_vertices(const SkinBinding& skin, const JointMatrices& joints, const std::vector<Eigen::Vector3f>& rest,
                   float* positions, Eigen::Vector3d* velocities) {
  for (std::size_t v = 0; v < rest.size(); ++v) {
    const Eigen::Vector4d r(rest[v].x(), rest[v].y(), rest[v].z(), 1.0);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Eigen::Vector3d p_dot = Eigen::Vector3d::Zero();
    for (std::uint32_t k = skin.first_influence[v]; k < skin.first_influence[v + 1]; ++k) {
      const std::uint32_t j = skin.influence_joint[k];
      const double w = skin.influence_weight[k];
      p += w * (joints.M[j] * r);
      if (velocities != nullptr) p_dot += w * (joints.M_dot[j] * r);
    }
    positions[3 * v] = static_cast<float>(p.x());
    positions[3 * v + 1] = static_cast<float>(p.y());
    positions[3 * v + 2] = static_cast<float>(p.z());
    if (velocities != nullptr) velocities[v] = p_dot;
  }
}

}  // namespace fmcw::sim
