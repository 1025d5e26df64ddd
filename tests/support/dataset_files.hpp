#pragma once
// A small moving scenario for dataset tests, and every file of a dataset folder as bytes.

#include <filesystem>
#include <map>
#include <string>

#include "support/cli.hpp"

namespace fmcw::test {

/// One 60 x 20 deg head at 0.5 deg (120 x 40 pixels), a driving ego, a ground, a building, and a
/// car and a pedestrian crossing, with the paper's noise: frames cost milliseconds, yet every
/// part of a frame (noise, truth tables, moving actors) is in it.
inline std::string small_scenario_yaml(int frames) {
  const std::string assets = std::string(FMCW_SOURCE_DIR) + "/assets/";
  return "name: small\nframes: " + std::to_string(frames) +
         "\nrate_hz: 10\nseed: 5\n"
         "rig:\n  heads:\n    - {name: front, mount: {x: 1.4, z: 1.6}, fov_deg: [60, 20], resolution_deg: [0.5, 0.5]}\n"
         "measurement: {model: gaussian, range_sigma_m: 0.025, velocity_sigma_mps: 0.031}\n"
         "ground: {z_m: 0, half_size_m: 200, reflectivity: 0.12}\n"
         "ego:\n  trajectory: {type: constant_velocity, pose: {x: 0}, velocity_mps: [8, 0, 0]}\n"
         "static:\n  - {mesh: " + assets + "building_block.gltf, pose: {x: 40, y: 12}}\n"
         "actors:\n"
         "  - {id: 1, class: car, mesh: " + assets + "car.gltf, trajectory: {type: waypoints, points: [[30, -10], [30, 40]], speed_mps: 6}}\n"
         "  - {id: 2, class: pedestrian, mesh: " + assets + "pedestrian.gltf, trajectory: {type: waypoints, points: [[15, 6], [15, -6]], speed_mps: 1.4}}\n";
}

/// Relative path -> bytes for every regular file below dir (hidden ones included).
inline std::map<std::string, std::string> folder_bytes(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[std::filesystem::relative(e.path(), dir).string()] = slurp(e.path());
  }
  return files;
}

/// Gtest-friendly comparison: the first file that differs, is missing or is extra, or "".
inline std::string first_difference(const std::map<std::string, std::string>& expected,
                                    const std::map<std::string, std::string>& actual) {
  for (const auto& [name, bytes] : expected) {
    const auto it = actual.find(name);
    if (it == actual.end()) return name + " is missing";
    if (it->second != bytes) return name + " differs (" + std::to_string(it->second.size()) + " bytes vs " +
                                    std::to_string(bytes.size()) + " expected)";
  }
  for (const auto& [name, bytes] : actual) {
    if (!expected.count(name)) return name + " should not be there";
  }
  return "";
}

}  // namespace fmcw::test
