// libFuzzer target: the mesh loader on glTF input (sim::load_mesh_asset). A file with animations
// or skins goes through the project's own glTF reader (JSON, buffers from data: URIs, files or
// the GLB binary chunk, accessors, sparse substitutions, nodes, skins with every JOINTS_n /
// WEIGHTS_n set, clips); any other glTF through assimp. Each input is tried as mesh.gltf and,
// when it starts with the GLB magic "glTF", also as mesh.glb. Bad input may only end in
// std::invalid_argument (core::FileError) or core::LimitError; anything else is a bug. A file
// that loads has its clips sampled (before, inside, at the end of and after their keys), and a
// pose or rate that is not finite aborts: the simulator takes them as they come.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fuzz_input_file.hpp"

// assimp 5.2 leaks inside itself on some bad files it refuses (240 bytes when a glTF's data: URI
// holds a character that is not base64: its decoder's buffer, lost to the exception), before our
// loader turns the failure into std::invalid_argument. Leaks within libassimp are not reported;
// any leak of ours still is (the loader holds assimp's scene in an Assimp::Importer). The same
// suppression as tests/sim/test_fbx_import.cpp.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

namespace {

void sample_clips(const fmcw::sim::MeshAsset& asset) {
  for (const auto& clip : asset.clips) {
    const double d = clip.duration_s;
    for (std::size_t k = 0; k < clip.tracks.size(); ++k) {
      const auto& rest = asset.parts.at(static_cast<std::size_t>(clip.tracks[k].part)).rest_trs;
      for (const double t : {-1.0, 0.0, d / 3.0, d / 2.0, d * 0.999, d, d + 1.0}) {
        Eigen::Matrix4d L, L_dot;
        clip.local_transform(k, rest, t, L, L_dot);
        if (!L.allFinite() || !L_dot.allFinite()) std::abort();
      }
    }
  }
}

void load(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = fmcw::fuzz::write_input(name, data, size);
  try {
    sample_clips(fmcw::sim::load_mesh_asset(path, {{"skin", 0.4f}}, 0.3f));
  } catch (const std::invalid_argument&) {  // core::FileError, core::InputError
  } catch (const fmcw::core::LimitError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  load("mesh.gltf", data, size);
  if (size >= 4 && std::memcmp(data, "glTF", 4) == 0) load("mesh.glb", data, size);
  return 0;
}
