// glTF files built to break the readers (what fuzz_mesh and a review of the project's reader
// found): each ended in a crash (ours or assimp's), an out-of-bounds read, gigabytes of memory, a
// silent misreading or non-finite geometry, and now ends in one std::invalid_argument naming the
// file and what is wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "fmcw/sim/animation_clip.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "support/gltf_builder.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::sim {
namespace {

using test::GltfBuilder;

class GltfReaderErrors : public test::TempDirTest {
 protected:
  // The message load_mesh_asset gives for the file, "no error" if it loads; checks that the
  // message names the file.
  std::string error(const std::string& file) {
    try {
      load_mesh_asset(file, {}, 0.3f);
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file), std::string::npos) << "the message names the file: " << m;
      return m;
    }
    return "no error";
  }
  std::string error(const GltfBuilder& b, bool glb = false) {
    const std::string file = path(glb ? "bad.glb" : "bad.gltf");
    glb ? b.write_glb(file) : b.write_gltf(file);
    return error(file);
  }
};

// One triangle on node 0 ('box'), moved by a LINEAR clip: read by the project's reader.
GltfBuilder rigid_file() {
  GltfBuilder b;
  const int box = b.add_node("box");
  b.add_mesh(box, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  b.add_channel(b.add_animation("slide"), box, "translation", "LINEAR", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0});
  return b;
}

// Two bones and a skinned triangle on node 2 (mesh 1, skin 0), with a clip.
GltfBuilder skinned_file() {
  GltfBuilder b;
  const int bone0 = b.add_node("bone0");
  const int bone1 = b.add_node("bone1", bone0, Eigen::Vector3d(0, 1, 0));
  const int body = b.add_node("body");
  const int mesh = b.add_mesh(body, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  b.set_skin_weights(mesh, {{{0, 1.0f}}, {{0, 0.5f}, {1, 0.5f}}, {{1, 1.0f}}});
  b.attach_skin(body, b.add_skin({bone0, bone1}));
  b.add_channel(b.add_animation("bend"), bone1, "translation", "LINEAR", {0.0f, 1.0f}, {0, 1, 0, 0, 1.5f, 0});
  return b;
}

TEST_F(GltfReaderErrors, EachMalformedFileGetsItsOwnMessage) {
  ASSERT_EQ(error(rigid_file()), "no error");
  ASSERT_EQ(error(skinned_file()), "no error");
  ASSERT_EQ(error(skinned_file(), true), "no error");
  {  // an accessor without a buffer view declaring 2^26 matrices: 8 GB of zeros were allocated
    GltfBuilder b = skinned_file();
    auto& ibm = b.doc()["accessors"][b.doc()["skins"][0]["inverseBindMatrices"].get<int>()];
    ibm.erase("bufferView");
    ibm["count"] = 1 << 26;
    const std::string m = error(b);
    EXPECT_NE(m.find("skins[0].inverseBindMatrices (accessors["), std::string::npos) << m;
    EXPECT_NE(m.find("would bring the values read from the file to 1073741824, more than the"), std::string::npos) << m;
  }
  {  // one accessor of 10^5 zero vertices shared by 300 primitives: 30 million vertices were read
    GltfBuilder b = rigid_file();
    auto& primitives = b.doc()["meshes"][0]["primitives"];
    primitives[0].erase("indices");
    const int position = primitives[0]["attributes"]["POSITION"].get<int>();
    b.doc()["accessors"][position].erase("bufferView");
    b.doc()["accessors"][position]["count"] = 99999;
    const nlohmann::json first = primitives[0];
    for (int k = 0; k < 299; ++k) primitives.push_back(first);
    const std::string m = error(b);
    EXPECT_NE(m.find("meshes[0].primitives[13] POSITION (accessors[" + std::to_string(position) +
                     "]) would bring the values read from the file to 4199958"),
              std::string::npos)
        << m;
  }
  {  // a skin of 2000 joints without inverse bind matrices on 150 nodes: 2000 identity matrices
     // were made for each node (quadratic memory)
    GltfBuilder b = skinned_file();
    b.doc()["skins"][0]["joints"] = std::vector<int>(2000, 0);
    b.doc()["skins"][0].erase("inverseBindMatrices");
    for (int k = 0; k < 150; ++k) {
      b.doc()["scenes"][0]["nodes"].push_back(b.doc()["nodes"].size());
      b.doc()["nodes"].push_back({{"mesh", 0}, {"skin", 0}});
    }
    EXPECT_NE(error(b).find("skins[0] (identity inverse bind matrices) would bring the values read from the file to"),
              std::string::npos);
  }
  {  // byteStride 2^40 over 2^24 + 1 elements: offset + stride (count - 1) wrapped to 0 and the
     // reader read 2^64 bytes past its buffer (a segmentation fault)
    GltfBuilder b = rigid_file();
    const std::uint64_t n = (1u << 24) + 1, bytes = n + 64;
    { std::ofstream create(path("big.bin")); }
    std::filesystem::resize_file(path("big.bin"), bytes);  // zeros
    auto& doc = b.doc();
    doc["buffers"].push_back({{"uri", "big.bin"}, {"byteLength", bytes}});
    doc["bufferViews"].push_back({{"buffer", 1}, {"byteLength", bytes}, {"byteStride", 1ull << 40}});
    doc["accessors"].push_back(
        {{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", 5126}, {"type", "VEC3"}, {"count", n}});
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = doc["accessors"].size() - 1;
    EXPECT_NE(error(b).find("POSITION (accessors[" + std::to_string(doc["accessors"].size() - 1) +
                            "]) reaches past the end of its buffer view or buffer"),
              std::string::npos);
  }
  {  // a translation of 1e308 under a scale of 1e308: the rest transform was infinite
    GltfBuilder b = rigid_file();
    b.doc()["nodes"].push_back({{"name", "giant"}, {"scale", {1e308, 1e308, 1e308}}, {"children", {0}}});
    b.doc()["scenes"][0]["nodes"] = {1};
    b.doc()["nodes"][0]["translation"] = {1e308, 0, 0};
    EXPECT_NE(error(b).find("nodes[0] ('box'): its transform at rest overflows"), std::string::npos);
  }
  {  // a scale of 1e300: finite as a double, infinite as the float vertices the simulator keeps
    GltfBuilder b = rigid_file();
    b.doc()["nodes"][0]["scale"] = {1e300, 1, 1};
    EXPECT_NE(error(b).find("nodes[0] ('box'): its vertices at rest overflow"), std::string::npos);
  }
  {  // mode 2^32 + 4 was read as 4 (triangles), componentType 2^32 + 5126 as 5126 (float)
    GltfBuilder b = rigid_file();
    b.doc()["meshes"][0]["primitives"][0]["mode"] = (1ull << 32) + 4;
    EXPECT_NE(error(b).find("meshes[0].primitives[0].mode is 4294967300, glTF has modes 0 to 6"), std::string::npos);
    b.doc()["meshes"][0]["primitives"][0]["mode"] = 7;
    EXPECT_NE(error(b).find("meshes[0].primitives[0].mode is 7, glTF has modes 0 to 6"), std::string::npos);
    b.doc()["meshes"][0]["primitives"][0]["mode"] = 4;
    b.doc()["accessors"][0]["componentType"] = (1ull << 32) + 5126;
    EXPECT_NE(error(b).find("POSITION (accessors[0]) has componentType 4294972422"), std::string::npos);
  }
  {  // more sparse substitutions than the accessor has elements
    GltfBuilder b = rigid_file();
    b.doc()["accessors"][0]["sparse"] = {{"count", 5},
                                         {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
                                         {"values", {{"bufferView", 0}}}};
    EXPECT_NE(error(b).find("POSITION (accessors[0]).sparse.count 5 is more than the accessor's count 3"),
              std::string::npos);
  }
  {  // primitives with fewer vertices than one point, line or triangle of their mode needs. In a
     // file without clips or skins, which assimp reads: a strip of 1 index made it allocate SIZE_MAX
     // faces (bad_alloc; an abort under ASan), a fan of 2 wrote past its faces, a line loop of 1
     // dereferenced a null pointer
    struct Case {
      int mode;
      int count;
      const char* message;
    };
    for (const Case& c : {Case{5, 1, "has 1 indices for mode 5 (triangle strip), which needs at least 3"},
                          Case{6, 2, "has 2 indices for mode 6 (triangle fan), which needs at least 3"},
                          Case{2, 1, "has 1 indices for mode 2 (line loop), which needs at least 2"},
                          Case{3, 0, "has 0 indices for mode 3 (line strip), which needs at least 2"}}) {
      for (const bool clip : {false, true}) {
        GltfBuilder b = rigid_file();
        if (!clip) b.doc().erase("animations");
        b.doc()["meshes"][0]["primitives"][0]["mode"] = c.mode;
        b.doc()["accessors"][1]["count"] = c.count;  // the indices
        EXPECT_NE(error(b).find(std::string("meshes[0].primitives[0] ") + c.message), std::string::npos) << c.message;
      }
    }
    GltfBuilder b = rigid_file();  // and without indices: the positions count
    b.doc()["meshes"][0]["primitives"][0].erase("indices");
    b.doc()["meshes"][0]["primitives"][0]["mode"] = 5;
    b.doc()["accessors"][0]["count"] = 2;
    EXPECT_NE(error(b).find("meshes[0].primitives[0] has 2 vertices for mode 5 (triangle strip)"), std::string::npos);
  }
  {  // JSON nested 300000 levels deep, with and without a clip: assimp (which reads glTF files
     // without clips or skins) recursed once per level and overflowed the stack
    for (const bool clip : {false, true}) {
      std::string text = "{\"asset\": {\"version\": \"2.0\"}, ";
      if (clip) text += "\"animations\": [{\"channels\": [], \"samplers\": []}], ";
      text += "\"extras\": " + std::string(300000, '[') + std::string(300000, ']') + "}";
      EXPECT_NE(error(write("deep.gltf", text)).find("the glTF JSON nests arrays and objects more than 256 levels deep"),
                std::string::npos)
          << clip;
    }
  }
}

TEST(KeyCurve, ACubicSplineRotationThroughTheZeroQuaternionHoldsTheNearerKey) {
  // Keys q and -q (the same rotation) with zero tangents: the spline is (1 - 2h(s)) q, zero at
  // the middle, where normalising it gave NaN.
  KeyCurve c;
  c.width = 4;
  c.interpolation = Interpolation::kCubicSpline;
  c.times_s = {0.0, 1.0};
  c.values = {0, 0, 0, 0, 0, 0, 0.6, 0.8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -0.6, -0.8, 0, 0, 0, 0};
  c.validate("test");
  for (const double t : {0.25, 0.5, 0.75}) {
    Eigen::Quaterniond q;
    Eigen::Vector3d omega;
    c.sample_rotation(t, q, omega);
    EXPECT_TRUE(q.coeffs().allFinite() && omega.allFinite()) << t;
    EXPECT_NEAR(q.norm(), 1.0, 1e-12) << t;
    EXPECT_NEAR(std::abs(q.z()), 0.6, 1e-12) << t;  // the same rotation throughout
  }
}

}  // namespace
}  // namespace fmcw::sim
