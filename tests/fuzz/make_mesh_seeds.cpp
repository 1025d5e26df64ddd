// Writes the seed corpus of fuzz_mesh (tests/fuzz/corpus/mesh) with the tests' glTF writer
// (tests/support/gltf_builder.hpp): small files, each reaching a different part of the reader.
//   build-fuzz/bin/make_mesh_seeds tests/fuzz/corpus/mesh
// (target make_mesh_seeds, built with FMCW_FUZZ=ON; it is not itself a fuzz target).

#include <cstdint>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "support/gltf_builder.hpp"

namespace {

using fmcw::test::GltfBuilder;
using Influences = std::vector<std::vector<std::pair<int, float>>>;

// A strip of 2 x (n + 1) vertices along +y, two triangles per step.
void strip(int n, std::vector<Eigen::Vector3f>& v, std::vector<std::uint32_t>& idx, Influences& inf) {
  for (int k = 0; k <= n; ++k) {
    const float y = 2.0f * static_cast<float>(k) / static_cast<float>(n);
    const float w = std::min(1.0f, std::max(0.0f, y - 0.5f));
    for (const float z : {-0.5f, 0.5f}) {
      v.emplace_back(0.0f, y, z);
      inf.push_back({{0, 1.0f - w}, {1, w}});
    }
  }
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(n); ++k) {
    const std::uint32_t a = 2 * k;
    idx.insert(idx.end(), {a, a + 2, a + 1, a + 1, a + 2, a + 3});
  }
}

std::vector<float> quaternions_about_z(const std::vector<float>& angles) {
  std::vector<float> out;
  for (const float a : angles) {
    const Eigen::Quaternionf q(Eigen::AngleAxisf(a, Eigen::Vector3f::UnitZ()));
    out.insert(out.end(), {q.x(), q.y(), q.z(), q.w()});
  }
  return out;
}

// Appends raw bytes as a new buffer view (4-byte aligned) and returns its index.
int raw_view(GltfBuilder& b, const std::vector<std::uint8_t>& bytes, int stride = 0) {
  auto& bin = b.buffer();
  bin.resize((bin.size() + 3) / 4 * 4, 0);
  const std::size_t offset = bin.size();
  bin.insert(bin.end(), bytes.begin(), bytes.end());
  b.doc()["buffers"][0]["byteLength"] = bin.size();
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes.size()}};
  if (stride > 0) view["byteStride"] = stride;
  b.doc()["bufferViews"].push_back(view);
  return static_cast<int>(b.doc()["bufferViews"].size()) - 1;
}

template <typename T>
std::vector<std::uint8_t> bytes_of(const std::vector<T>& values) {
  std::vector<std::uint8_t> out(values.size() * sizeof(T));
  if (!out.empty()) std::memcpy(out.data(), values.data(), out.size());
  return out;
}

int accessor(GltfBuilder& b, nlohmann::json a) {
  b.doc()["accessors"].push_back(std::move(a));
  return static_cast<int>(b.doc()["accessors"].size()) - 1;
}

// Two bones, a skinned strip, a LINEAR rotation clip and a STEP translation clip.
GltfBuilder skinned_strip() {
  GltfBuilder b;
  const int bone0 = b.add_node("bone0");
  const int bone1 = b.add_node("bone1", bone0, Eigen::Vector3d(0, 1, 0));
  const int mesh_node = b.add_node("strip");
  std::vector<Eigen::Vector3f> v;
  std::vector<std::uint32_t> idx;
  Influences inf;
  strip(3, v, idx, inf);
  const int mesh = b.add_mesh(mesh_node, v, idx, "skin", true);
  b.set_skin_weights(mesh, inf);
  b.attach_skin(mesh_node, b.add_skin({bone0, bone1}));
  const int walk = b.add_animation("walk");
  b.add_channel(walk, bone1, "rotation", "LINEAR", {0.0f, 0.5f, 1.0f}, quaternions_about_z({0.0f, 0.4f, 0.0f}));
  b.add_channel(walk, bone0, "translation", "STEP", {0.0f, 1.0f}, {0, 0, 0, 0.1f, 0, 0});
  b.doc()["animations"][0]["extras"] = {{"nominal_speed_mps", 1.4}};
  return b;
}

// A rigid wheel on a matrix-placed body: CUBICSPLINE rotation and scale, a weights channel.
GltfBuilder cubic_wheel() {
  GltfBuilder b;
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 3) = 2.0;
  const int body = b.add_matrix_node("body", -1, m);
  const int wheel = b.add_node("wheel", body, Eigen::Vector3d(0.5, 0, 0.3));
  b.add_mesh(wheel, {{0, 0, 0}, {0, 0.3f, 0}, {0, 0, 0.3f}, {0, 0.3f, 0.3f}}, {0, 1, 2, 1, 3, 2}, "tire");
  b.add_mesh(body, {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, {0, 1, 2}, "paint");
  const int roll = b.add_animation("roll");
  std::vector<float> cubic;
  const std::vector<float> q = quaternions_about_z({0.0f, 1.5f});
  for (int k = 0; k < 2; ++k) {
    cubic.insert(cubic.end(), {0, 0, 0.5f, 0});                         // in-tangent
    cubic.insert(cubic.end(), q.begin() + 4 * k, q.begin() + 4 * k + 4);  // value
    cubic.insert(cubic.end(), {0, 0, 0.5f, 0});                         // out-tangent
  }
  b.add_channel(roll, wheel, "rotation", "CUBICSPLINE", {0.0f, 1.0f}, cubic);
  b.add_channel(roll, wheel, "scale", "CUBICSPLINE", {0.0f, 1.0f}, {0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 1, 2, 1, 0, 0, 0});
  b.add_channel(roll, wheel, "weights", "LINEAR", {0.0f, 1.0f}, {0.0f, 1.0f});
  return b;
}

// Interleaved positions (byteStride), a sparse accessor, normalized UNSIGNED_BYTE weights over
// two JOINTS/WEIGHTS sets, a strip primitive without indices, a fan, a line primitive, a
// morph target, an accessor without a buffer view, a second scene.
GltfBuilder layouts() {
  GltfBuilder b;
  const int bone0 = b.add_node("bone0");
  const int bone1 = b.add_node("bone1", bone0, Eigen::Vector3d(0, 1, 0));
  const int mesh_node = b.add_node("patch");
  b.add_mesh(mesh_node, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  // Interleaved: position (12 bytes) + 4 padding bytes per vertex, 4 vertices.
  std::vector<float> inter = {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 0.2f, 0};
  const int iv = raw_view(b, bytes_of(inter), 16);
  const int pos = accessor(b, {{"bufferView", iv}, {"componentType", 5126}, {"type", "VEC3"}, {"count", 4}});
  // Sparse: vertex 2 of the positions moved up.
  const int si = raw_view(b, bytes_of(std::vector<std::uint16_t>{2, 0}));
  const int sv = raw_view(b, bytes_of(std::vector<float>{0, 1, 0.5f}));
  b.doc()["accessors"][pos]["sparse"] = {{"count", 1},
                                         {"indices", {{"bufferView", si}, {"componentType", 5123}}},
                                         {"values", {{"bufferView", sv}}}};
  // Two sets: JOINTS_0 UNSIGNED_BYTE, WEIGHTS_0 normalized UNSIGNED_BYTE, JOINTS_1 / WEIGHTS_1 FLOAT.
  const int j0 = raw_view(b, std::vector<std::uint8_t>(16, 0));
  std::vector<std::uint8_t> w0;
  for (int k = 0; k < 4; ++k) w0.insert(w0.end(), {128, 0, 0, 0});
  const int w0v = raw_view(b, w0);
  const int j1 = raw_view(b, bytes_of(std::vector<float>(16, 1.0f)));
  std::vector<float> w1;
  for (int k = 0; k < 4; ++k) w1.insert(w1.end(), {127.0f / 255.0f, 0, 0, 0});
  const int w1v = raw_view(b, bytes_of(w1));
  const int ja0 = accessor(b, {{"bufferView", j0}, {"componentType", 5121}, {"type", "VEC4"}, {"count", 4}});
  const int wa0 = accessor(b, {{"bufferView", w0v}, {"componentType", 5121}, {"normalized", true}, {"type", "VEC4"}, {"count", 4}});
  const int ja1 = accessor(b, {{"bufferView", j1}, {"componentType", 5126}, {"type", "VEC4"}, {"count", 4}});
  const int wa1 = accessor(b, {{"bufferView", w1v}, {"componentType", 5126}, {"type", "VEC4"}, {"count", 4}});
  const int fan_idx = raw_view(b, std::vector<std::uint8_t>{0, 1, 3, 2});
  const int fan = accessor(b, {{"bufferView", fan_idx}, {"componentType", 5121}, {"type", "SCALAR"}, {"count", 4}});
  const int zeros = accessor(b, {{"componentType", 5126}, {"type", "VEC3"}, {"count", 4}});
  nlohmann::json attributes = {{"POSITION", pos}, {"JOINTS_0", ja0}, {"WEIGHTS_0", wa0}, {"JOINTS_1", ja1}, {"WEIGHTS_1", wa1}};
  b.doc()["meshes"].push_back(
      {{"name", "layouts"},
       {"primitives",
        {{{"attributes", attributes}, {"mode", 5}, {"targets", {{{"POSITION", zeros}}}}},
         {{"attributes", attributes}, {"indices", fan}, {"mode", 6}},
         {{"attributes", attributes}, {"mode", 1}}}}});
  const int skinned = b.add_node("skinned");
  b.doc()["nodes"][skinned]["mesh"] = static_cast<int>(b.doc()["meshes"].size()) - 1;
  b.attach_skin(skinned, b.add_skin({bone0, bone1}));
  b.doc()["skins"][0].erase("inverseBindMatrices");
  b.doc()["scenes"].push_back({{"nodes", {mesh_node}}});
  const int clip = b.add_animation("sway");
  b.add_channel(clip, bone1, "translation", "LINEAR", {0.0f, 2.0f}, {0, 1, 0, 0.2f, 1, 0});
  b.doc()["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.doc()["extensionsRequired"] = {"KHR_mesh_quantization"};
  return b;
}

// No clip and no skin: assimp reads it.
GltfBuilder still_triangle() {
  GltfBuilder b;
  const int n = b.add_node("sign", -1, Eigen::Vector3d(0, 0, 1));
  b.add_mesh(n, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}, "metal");
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_mesh_seeds FOLDER\n";
    return 2;
  }
  const std::string dir = std::string(argv[1]) + "/";
  skinned_strip().write_gltf(dir + "skinned_strip.gltf");
  skinned_strip().write_glb(dir + "skinned_strip.glb");
  cubic_wheel().write_glb(dir + "cubic_wheel.glb");
  layouts().write_gltf(dir + "layouts.gltf");
  still_triangle().write_gltf(dir + "still_triangle.gltf");
  return 0;
}
