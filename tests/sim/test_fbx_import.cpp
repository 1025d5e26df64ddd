// FBX through the assimp path against known answers. The fixtures are made here at test time:
// GltfBuilder writes a glTF with known content and assimp's own exporter turns it into ASCII FBX,
// which load_mesh_asset then reads like any FBX from a modelling tool. A node turned by a LINEAR
// clip gives the Doppler of a rigid rotation, a bending two-bone strip moves as the analytic
// blend of its bones, a channel on a model outside the scene gets a notice, and a bad FBX gets a
// message that names the file.

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/SceneCombiner.h>
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <regex>

#include "fmcw/sim/lidar_simulator.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/scene.hpp"
#include "support/animated_scenes.hpp"
#include "support/gltf_builder.hpp"
#include "support/sim_scenes.hpp"
#include "support/temp_dir.hpp"

// assimp 5.2's FBX parser leaks what it had built (about 26 KB, all inside libassimp) when it
// meets a truncated file, before our loader turns its failure into the error the test expects.
// The sanitizer build is told so for this test program alone; no leak of ours is hidden by it
// (the loader holds assimp's scene in an Assimp::Importer, which frees it).
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

namespace fmcw::sim {
namespace {

using test::at;
using test::GltfBuilder;
using test::noise_free;
using test::box;
using test::one_head;
using test::scene_with;
using test::Strip;
using test::turn_keys;
using test::two_bone_strip;

// One FBX frame at the 24 frames per second the exporter writes [s].
constexpr double kFrame = 1.0 / 24.0;

// Turns a glTF into ASCII FBX with assimp 5.2.5's exporter, working around its faults: binary
// "fbx" export is broken, so "fbxa"; it drops the scene's root node, so the real root goes under
// a wrapper; it writes key times as seconds while glTF import gives milliseconds, so the times
// are rescaled to seconds at 1 tick per second, and the duration rounded up to whole seconds (the
// importer drops keys after it). `edit` may change the scene before export.
void gltf_to_fbx(const std::string& gltf, const std::string& fbx, const std::function<void(aiScene&)>& edit = {}) {
  Assimp::Importer importer;
  const aiScene* src = importer.ReadFile(gltf, aiProcess_Triangulate | aiProcess_ValidateDataStructure);
  if (src == nullptr) throw std::runtime_error("assimp cannot read '" + gltf + "': " + importer.GetErrorString());
  aiScene* s = nullptr;
  Assimp::SceneCombiner::CopyScene(&s, src);
  aiNode* wrapper = new aiNode("fbx_export_root");
  wrapper->addChildren(1, &s->mRootNode);
  s->mRootNode = wrapper;
  for (unsigned a = 0; a < s->mNumAnimations; ++a) {
    aiAnimation* an = s->mAnimations[a];
    const double k = 1.0 / (an->mTicksPerSecond > 0 ? an->mTicksPerSecond : 1.0);
    for (unsigned c = 0; c < an->mNumChannels; ++c) {
      aiNodeAnim* ch = an->mChannels[c];
      for (unsigned i = 0; i < ch->mNumPositionKeys; ++i) ch->mPositionKeys[i].mTime *= k;
      for (unsigned i = 0; i < ch->mNumRotationKeys; ++i) ch->mRotationKeys[i].mTime *= k;
      for (unsigned i = 0; i < ch->mNumScalingKeys; ++i) ch->mScalingKeys[i].mTime *= k;
    }
    an->mDuration = std::ceil(an->mDuration * k);
    an->mTicksPerSecond = 1.0;
  }
  if (edit) edit(*s);
  Assimp::Exporter exporter;
  const aiReturn r = exporter.Export(s, "fbxa", fbx);
  aiFreeScene(s);
  if (r != aiReturn_SUCCESS) throw std::runtime_error("assimp cannot write '" + fbx + "': " + exporter.GetErrorString());
}

std::string read_text(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The turntable box of the first test on its own node, turned at rate_rps about +z by a LINEAR
// clip "spin" keyed every 0.25 s over [0, 2.5] s. The turn stays under pi: the exporter writes
// rotations as Euler angles wrapped to (-180, 180] deg, and FBX interpolates Euler angles
// component-wise, so a key pair across +-180 deg would read back as a turn the long way round.
GltfBuilder turntable(double rate_rps) {
  GltfBuilder b;
  const int node = b.add_node("turntable");
  std::vector<Eigen::Vector3f> v;
  std::vector<std::uint32_t> idx;
  box({-0.6f, 0.4f, -0.5f}, {0.4f, 1.6f, 1.5f}, v, idx);
  b.add_mesh(node, v, idx);
  std::vector<float> times;
  const std::vector<float> values = turn_keys(rate_rps, 0.25, 2.5, times);
  b.add_channel(b.add_animation("spin"), node, "rotation", "LINEAR", times, values);
  return b;
}

class FbxImport : public test::TempDirTest {};

TEST_F(FbxImport, ALinearClipTurningANodeKeepsTheDopplerOfItsRotationThroughFbx) {
  // After the round trip every hit point of the box still moves at omega x (p - c), so its
  // Doppler is e . (omega x (p - c)); keys 0.25 s apart make slerp between them the constant-
  // rate turn, and the frames are taken between keys.
  const double omega = 1.2;  // [rad/s]
  turntable(omega).write_gltf(path("spin.gltf"));
  gltf_to_fbx(path("spin.gltf"), path("spin.fbx"));
  auto asset = std::make_shared<const MeshAsset>(load_mesh_asset(path("spin.fbx"), {}, 0.3f));
  EXPECT_TRUE(asset->notices.empty()) << asset->notices[0];
  const int part = asset->find_part("turntable");
  ASSERT_GE(part, 0);
  EXPECT_FALSE(asset->parts[static_cast<std::size_t>(part)].skin);
  EXPECT_EQ(asset->parts[static_cast<std::size_t>(part)].triangle_count(), 12u);
  ASSERT_EQ(asset->clips.size(), 1u);
  const AnimationClip& clip = asset->clips[0];
  EXPECT_EQ(clip.name, "spin");
  // FBX keeps time in frames of 24 per second, and 2.5 s is frame 60 exactly: the duration comes
  // back exact, not just within one frame.
  EXPECT_NEAR(clip.duration_s, 2.5, 1e-9);
  ASSERT_EQ(clip.tracks.size(), 1u);
  ASSERT_EQ(clip.tracks[0].part, part);
  // The keys themselves, at their times in seconds (frame / 24), and their values as the ASCII
  // FBX holds them: Euler angles in degrees with 6 significant digits, so within 5e-4 deg
  // (8.7e-6 rad) below 1000 deg.
  const KeyCurve& rotation = clip.tracks[0].rotation;
  ASSERT_EQ(rotation.times_s.size(), 11u);
  for (std::size_t k = 0; k < rotation.times_s.size(); ++k) {
    EXPECT_NEAR(rotation.times_s[k], 0.25 * static_cast<double>(k), 1e-9) << "key " << k;
    Eigen::Quaterniond q;
    Eigen::Vector3d w;
    rotation.sample_rotation(rotation.times_s[k], q, w);
    EXPECT_LT(q.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(omega * 0.25 * k, Eigen::Vector3d::UnitZ()))), 1e-5)
        << "key " << k;
  }

  const Eigen::Vector3d c(10.0, -1.0, 0.0);
  auto scene = scene_with(asset, at(c.x(), c.y(), c.z()), 0);
  const core::RigModel rig = one_head();
  LidarSimulator sim(scene, make_static_trajectory(Eigen::Isometry3d::Identity()), noise_free(rig));
  int hits = 0;
  double worst = 0.0;
  for (const double t : {0.7, 1.9}) {  // strictly between keys (0.5, 0.75) and (1.75, 2.0)
    const core::Frame f = sim.simulate(0, t);
    const Eigen::Vector3d origin = rig.heads[0].T_rig_head.translation();
    for (std::size_t i = 0; i < f.scan.size(); ++i) {
      if (f.truth->instance[i] != 7) continue;
      const Eigen::Vector3d p(f.scan.x_m[i], f.scan.y_m[i], f.scan.z_m[i]);
      const Eigen::Vector3d e = (p - origin).normalized();
      const double expected = e.dot(Eigen::Vector3d(0, 0, omega).cross(p - c));
      // The file's rounding bounds the error: keys off by <= 8.7e-6 rad each make omega off by
      // <= 7e-5 rad/s over a 0.25 s segment and the angle by <= 8.7e-6 rad; at <= 1.71 m from
      // the axis that is <= 1.4e-4 m/s. Single-precision hit points add ~1e-6 m/s.
      ASSERT_NEAR(f.truth->radial_velocity_mps[i], expected, 2e-4) << "pixel " << i << " at t " << t;
      ASSERT_NEAR(f.scan.radial_velocity_mps[i], expected, 2e-4);
      worst = std::max(worst, std::abs(f.truth->radial_velocity_mps[i] - expected));
      ++hits;
    }
  }
  EXPECT_GT(hits, 500);
  RecordProperty("worst_doppler_error_mps", std::to_string(worst));
}

TEST_F(FbxImport, ABendingTwoBoneStripFromFbxMovesAsTheAnalyticBlendOfItsBones) {
  // The skin is bound at the rest pose and the strip's node is the identity: the exporter
  // recomputes each bone's offset matrix as inverse(bone at rest) * (mesh node), which is then
  // the glTF inverse bind matrix, so the FBX describes the same bending strip.
  const Strip strip = two_bone_strip();
  const double omega = 0.8;  // [rad/s]; 1.6 rad at the last key, under pi (see turntable())
  GltfBuilder b = test::bending_strip(strip, omega);
  b.write_glb(path("strip.glb"));
  gltf_to_fbx(path("strip.glb"), path("strip.fbx"));
  auto asset = std::make_shared<const MeshAsset>(load_mesh_asset(path("strip.fbx"), {}, 0.3f));
  ASSERT_EQ(asset->clips.size(), 1u);
  EXPECT_EQ(asset->clips[0].name, "bend");
  EXPECT_NEAR(asset->clips[0].duration_s, 2.0, 1e-9);

  // The skin: the strip's part, its two joints at their nodes with their inverse bind matrices
  // (identity, and a shift by -1 along y), and each vertex's weights as written.
  const int strip_part = asset->find_part("strip");
  ASSERT_GE(strip_part, 0);
  const MeshPart& part = asset->parts[static_cast<std::size_t>(strip_part)];
  ASSERT_TRUE(part.skin) << "the strip is skinned";
  const SkinBinding& skin = *part.skin;
  ASSERT_EQ(skin.joint_parts.size(), 2u);
  const int j1 = skin.joint_parts[0] == asset->find_part("bone1") ? 0 : 1;
  ASSERT_EQ(skin.joint_parts[static_cast<std::size_t>(1 - j1)], asset->find_part("bone0"));
  ASSERT_EQ(skin.joint_parts[static_cast<std::size_t>(j1)], asset->find_part("bone1"));
  Eigen::Matrix4d B1 = Eigen::Matrix4d::Identity();
  B1(1, 3) = -1.0;
  EXPECT_TRUE(skin.inverse_bind[static_cast<std::size_t>(1 - j1)].isApprox(Eigen::Matrix4d::Identity(), 1e-6));
  EXPECT_TRUE(skin.inverse_bind[static_cast<std::size_t>(j1)].isApprox(B1, 1e-6)) << skin.inverse_bind[static_cast<std::size_t>(j1)];
  // FBX has one vertex per face corner; joined again, each is one of the strip's vertices, found
  // by its rest position (mesh space).
  ASSERT_EQ(part.vertices.size(), strip.vertices.size());
  std::vector<std::size_t> original(part.vertices.size());
  for (std::size_t v = 0; v < part.vertices.size(); ++v) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < strip.vertices.size(); ++k) {
      if ((strip.vertices[k] - part.vertices[v]).norm() < (strip.vertices[best] - part.vertices[v]).norm()) best = k;
    }
    ASSERT_LT((strip.vertices[best] - part.vertices[v]).norm(), 1e-6f) << "vertex " << v;
    original[v] = best;
    double w1 = 0.0;
    for (std::uint32_t i = skin.first_influence[v]; i < skin.first_influence[v + 1]; ++i) {
      if (skin.influence_joint[i] == static_cast<std::uint32_t>(j1)) w1 += skin.influence_weight[i];
    }
    EXPECT_NEAR(w1, strip.w1[best], 1e-6) << "vertex " << v;
  }

  const Eigen::Vector3d place(6.0, -1.0, 0.5);
  auto scene = scene_with(asset, at(place.x(), place.y(), place.z()), 0);
  const double t = 0.6;  // between the keys at 0.5 and 0.75 s
  scene->set_time(t);
  const test::StripMotion analytic = test::strip_motion(strip, place, omega, t);
  const std::vector<Eigen::Vector3d>& p = analytic.p;
  const std::vector<Eigen::Vector3d>& p_dot = analytic.p_dot;
  const test::StripRays rays = test::cast_at_strip(*scene);
  const Eigen::Vector3f& origin = rays.origin;
  const std::vector<Eigen::Vector3f>& dirs = rays.dirs;
  const std::vector<RayHit>& hits = rays.hits;
  int checked = 0, bent = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < hits.size(); ++k) {
    if (!std::isfinite(hits[k].distance_m)) continue;
    const Eigen::Vector3d x = origin.cast<double>() + hits[k].distance_m * dirs[k].cast<double>();
    // The hit triangle, as the strip's own vertices.
    const std::uint32_t* tri = &part.indices[3 * hits[k].primitive];
    const std::size_t a = original[tri[0]], b1 = original[tri[1]], b2 = original[tri[2]];
    // Barycentric coordinates of the hit in the analytic triangle (least squares in its plane).
    Eigen::Matrix<double, 3, 2> E;
    E << p[b1] - p[a], p[b2] - p[a];
    const Eigen::Vector2d uv = E.colPivHouseholderQr().solve(x - p[a]);
    ASSERT_LT((p[a] + E * uv - x).norm(), 1e-4) << "the hit lies on the analytic surface";
    ASSERT_GT(uv.minCoeff(), -1e-4) << "inside the analytic triangle";
    ASSERT_LT(uv.sum(), 1.0 + 1e-4) << "inside the analytic triangle";
    const Eigen::Vector3d expected = (1 - uv[0] - uv[1]) * p_dot[a] + uv[0] * p_dot[b1] + uv[1] * p_dot[b2];
    const SurfaceSample s = scene->resolve(hits[k], x);
    // The file's rounding bounds the error: the keys at 0.5 and 0.75 s, 22.9 and 34.4 deg with
    // 6 significant digits, are off by <= 5e-5 deg (8.7e-7 rad) each, so omega by <= 7e-6 rad/s
    // and the angle by <= 8.7e-7 rad; at <= 1.12 m from bone 1 that is <= 9e-6 m/s. Single-
    // precision vertices add ~1e-6 m/s.
    ASSERT_LT((s.velocity_world_mps - expected).norm(), 2e-5) << "ray " << k;
    EXPECT_EQ(s.actor_id, 7u);
    worst = std::max(worst, (s.velocity_world_mps - expected).norm());
    ++checked;
    bent += expected.norm() > 0.05 ? 1 : 0;
  }
  EXPECT_GT(checked, 300);
  EXPECT_GT(bent, 100);
  RecordProperty("worst_velocity_error_mps", std::to_string(worst));
}

TEST_F(FbxImport, AnAnimatedModelOutsideTheSceneIsIgnoredWithANotice) {
  // An FBX ties animation curves to models by id, and a model whose parent link is missing is in
  // no node tree: assimp still gives its channel (by the model's name), which names no node of
  // the asset. The loader says so once per clip and plays the rest of the clip.
  GltfBuilder b = turntable(1.2);
  const int lamp = b.add_node("lamp", -1, Eigen::Vector3d(0, 3, 0));
  b.add_channel(0, lamp, "translation", "LINEAR", {0.0f, 1.0f}, {0, 3, 0, 0, 4, 0});
  b.write_gltf(path("lamp.gltf"));
  gltf_to_fbx(path("lamp.gltf"), path("lamp.fbx"));
  {  // as exported, the lamp is a node and its channel plays
    const MeshAsset asset = load_mesh_asset(path("lamp.fbx"), {}, 0.3f);
    EXPECT_TRUE(asset.notices.empty());
    ASSERT_GE(asset.find_part("lamp"), 0);
    ASSERT_EQ(asset.clips.size(), 1u);
    EXPECT_EQ(asset.clips[0].tracks.size(), 2u);
  }
  // Cut the lamp model from the tree: drop the "OO" connection that makes it a child.
  std::string text = read_text(path("lamp.fbx"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex(R"(Model: (\d+), "Model::lamp")")));
  const std::regex link("\n[ \t]*C: \"OO\", " + m[1].str() + ", [0-9]+");
  ASSERT_TRUE(std::regex_search(text, link));
  text = std::regex_replace(text, link, "");
  const std::string file = write("orphan.fbx", text);
  const MeshAsset asset = load_mesh_asset(file, {}, 0.3f);
  EXPECT_EQ(asset.find_part("lamp"), -1);
  ASSERT_EQ(asset.notices.size(), 1u);
  EXPECT_EQ(asset.notices[0], "mesh '" + file + "': clip 'spin': 1 channel(s) ignored: they name no node");
  // The turntable still turns: its key at 0.5 s is 0.6 rad about +z.
  ASSERT_EQ(asset.clips.size(), 1u);
  ASSERT_EQ(asset.clips[0].tracks.size(), 1u);
  ASSERT_EQ(asset.clips[0].tracks[0].part, asset.find_part("turntable"));
  Eigen::Quaterniond q;
  Eigen::Vector3d w;
  asset.clips[0].tracks[0].rotation.sample_rotation(0.5, q, w);
  EXPECT_LT(q.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ()))), 1e-5);
  EXPECT_NEAR(asset.clips[0].duration_s, 2.5, kFrame);
}

TEST_F(FbxImport, BadFbxFilesGetAMessageNamingTheFile) {
  const auto error = [&](const std::string& file) {
    try {
      load_mesh_asset(file, {}, 0.3f);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  turntable(1.2).write_gltf(path("spin.gltf"));
  gltf_to_fbx(path("spin.gltf"), path("spin.fbx"));
  EXPECT_EQ(error(path("spin.fbx")), "no error");
  {  // cut short, as by a failed download: assimp's reason follows the file's name
    const std::string text = read_text(path("spin.fbx"));
    const std::string file = write("cut.fbx", text.substr(0, text.size() / 2));
    const std::string m = error(file);
    EXPECT_EQ(m.rfind("mesh '" + file + "' cannot be read: FBX", 0), 0u) << m;
  }
  {  // an animation-only export (a skeleton and its clip, no mesh): nothing to hit
    GltfBuilder b;
    const int hips = b.add_node("hips");
    b.add_node("spine", hips, Eigen::Vector3d(0, 0, 0.3));
    b.add_channel(b.add_animation("walk"), hips, "translation", "LINEAR", {0.0f, 1.0f}, {0, 0, 1, 1, 0, 1});
    b.write_gltf(path("skeleton.gltf"));
    gltf_to_fbx(path("skeleton.gltf"), path("skeleton.fbx"));
    EXPECT_EQ(error(path("skeleton.fbx")), "mesh '" + path("skeleton.fbx") + "' holds no triangles: assimp finds no mesh in it");
  }
  {  // a skinned mesh with vertices that no bone weights (half of a slab's 8 corners)
    GltfBuilder b;
    const int root = b.add_node("rig");
    const int bone = b.add_node("bone", root);
    const int mesh_node = b.add_node("slab", root);
    std::vector<Eigen::Vector3f> v;
    std::vector<std::uint32_t> idx;
    box({0.0f, -2.0f, -1.0f}, {0.5f, 2.0f, 1.0f}, v, idx);
    const int mesh = b.add_mesh(mesh_node, v, idx);
    b.set_skin_weights(mesh, std::vector<std::vector<std::pair<int, float>>>(v.size(), {{0, 1.0f}}));
    b.attach_skin(mesh_node, b.add_skin({bone}));
    b.add_channel(b.add_animation("slide"), bone, "translation", "LINEAR", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0});
    b.write_gltf(path("slab.gltf"));
    gltf_to_fbx(path("slab.gltf"), path("slab.fbx"));
    EXPECT_EQ(error(path("slab.fbx")), "no error");
    gltf_to_fbx(path("slab.gltf"), path("unweighted.fbx"), [](aiScene& s) {
      ASSERT_EQ(s.mMeshes[0]->mNumBones, 1u);
      ASSERT_EQ(s.mMeshes[0]->mBones[0]->mNumWeights, 8u);
      s.mMeshes[0]->mBones[0]->mNumWeights = 4;  // the exporter writes only the first four
    });
    const std::string m = error(path("unweighted.fbx"));
    EXPECT_EQ(m.rfind("mesh '" + path("unweighted.fbx") + "': node 'slab': vertex ", 0), 0u) << m;
    EXPECT_NE(m.find(" has no bone weight"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace fmcw::sim
