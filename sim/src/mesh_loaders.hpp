#pragma once
// Internal to the simulator: the two mesh readers behind load_mesh_asset.

#include <optional>
#include <string>
#include <vector>

#include "fmcw/sim/mesh_asset.hpp"

namespace fmcw::sim::detail {

/// A glTF 2.0 file (.gltf or .glb) with animations or skins, read by the project's own reader:
/// nodes, triangle primitives, skins with every JOINTS_n/WEIGHTS_n set, and every animation
/// channel with its STEP, LINEAR or CUBICSPLINE sampler as the file defines it. nullopt for any
/// other file (assimp reads it).
std::optional<MeshAsset> load_animated_gltf(const std::string& path, const ReflectivityTable& reflectivity,
                                            float default_reflectivity);

/// Any format assimp reads, with its node animations (keys interpolated linearly, rotations by
/// slerp: assimp keeps no interpolation mode) and its bones.
MeshAsset load_assimp_asset(const std::string& path, const ReflectivityTable& reflectivity, float default_reflectivity);

/// One vertex's influences as read from a file: checks them and appends them, normalised to
/// sum to 1, to the binding. Zero weights are dropped. Throws std::invalid_argument with `where`
/// for a joint index out of range, a negative or non-finite weight, or weights whose sum is
/// further than 0.01 from 1.
void append_influences(std::vector<std::pair<std::uint32_t, double>>& influences, std::size_t joint_count,
                       const std::string& where, SkinBinding& skin);

}  // namespace fmcw::sim::detail
