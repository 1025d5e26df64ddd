#include "fmcw/io/dataset_header.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/yaml_reader.hpp"

namespace fmcw::io {

namespace {
constexpr const char* kScenarioKey = "scenario:";

// The key's value as YAML; fails naming the key when it is absent.
YamlValue key(const YamlValue& parent, const std::string& name) {
  const YAML::Node node = parent.node()[name];
  if (!node.IsDefined()) parent.fail("missing key '" + name + "'");
  return YamlValue(node, parent.file(), parent.path().empty() ? name : parent.path() + "." + name);
}
}  // namespace

std::string frame_file_name(long long k) {
  char name[32];
  std::snprintf(name, sizeof name, "%06lld.pcd", k);
  return name;
}

ShardInfo ShardInfo::of(int index, int count, int total_frames) {
  FMCW_CHECK_ARG(count >= 1, "shard count must be >= 1, got ", count);
  FMCW_CHECK_ARG(index >= 0 && index < count, "shard index must be in [0, ", count - 1, "], got ", index);
  FMCW_CHECK_ARG(total_frames >= 1, "a dataset needs at least one frame, got ", total_frames);
  ShardInfo s;
  s.index = index;
  s.count = count;
  const auto bound = [&](int i) {
    return static_cast<int>(static_cast<long long>(i) * total_frames / count);
  };
  s.first_frame = bound(index);
  s.end_frame = bound(index + 1);
  return s;
}

std::string DatasetHeader::to_yaml() const {
  std::ostringstream yaml;
  yaml << "# FMCW LiDAR dataset written by fmcw simulate\n"
       << "format: fmcw-dataset\nformat_version: 1\n"
       << "tool_version: " << tool_version << "\n"
       << "complete: " << (complete ? "true" : "false") << "\n"
       << "frames_written: " << frames_written << "\n"
       << "frame_files: frames/%06d.pcd\n"
       << "fields: [x, y, z, range, v, intensity" << (motion_distortion ? ", t" : "")
       << ", gt_range, gt_v, gt_vx, gt_vy, gt_vz, instance, moving, class]\n";
  if (!classes.empty()) {
    yaml << "classes:  # semantic class ids of the field class (SemanticKITTI's where it has the class)\n";
    for (const auto& [id, name] : classes) yaml << "  - {id: " << id << ", name: " << name << "}\n";
  }
  if (shard) {
    yaml << "shard: {index: " << shard->index << ", count: " << shard->count << ", first_frame: " << shard->first_frame
         << ", end_frame: " << shard->end_frame << "}\n";
  }
  yaml << kScenarioKey << "\n";
  std::istringstream resolved(scenario_yaml);
  for (std::string line; std::getline(resolved, line);) yaml << "  " << line << "\n";
  return yaml.str();
}

DatasetHeader DatasetHeader::read(const std::string& file) {
  const YamlValue doc = YamlValue::load_file(file);
  if (!doc.is_map()) doc.fail("expected a map (a dataset.yaml written by fmcw simulate)");
  DatasetHeader h;
  const YamlValue format = key(doc, "format");
  if (format.as_string() != "fmcw-dataset") format.fail("expected 'fmcw-dataset', got '" + format.as_string() + "'");
  const YamlValue version = key(doc, "format_version");
  if (version.as_int() != 1) version.fail("format_version " + version.as_string() + " is not supported (this tool reads 1)");
  h.tool_version = key(doc, "tool_version").as_string();
  h.complete = key(doc, "complete").as_bool();
  const YamlValue written = key(doc, "frames_written");
  h.frames_written = written.as_int();
  if (h.frames_written < 0) written.fail("must be >= 0");
  const YamlValue fields = key(doc, "fields");
  for (const YamlValue& f : fields.items()) h.motion_distortion = h.motion_distortion || f.as_string() == "t";
  if (doc.node()["shard"].IsDefined()) {
    const YamlValue s = key(doc, "shard");
    ShardInfo shard;
    shard.index = key(s, "index").as_int();
    shard.count = key(s, "count").as_int();
    shard.first_frame = key(s, "first_frame").as_int();
    shard.end_frame = key(s, "end_frame").as_int();
    if (shard.count < 1 || shard.index < 0 || shard.index >= shard.count || shard.first_frame < 0 ||
        shard.end_frame < shard.first_frame) {
      s.fail("inconsistent shard (index in [0, count), 0 <= first_frame <= end_frame)");
    }
    if (h.frames_written > shard.frames()) written.fail("exceeds the shard's " + std::to_string(shard.frames()) + " frames");
    h.shard = shard;
  }
  if (doc.node()["classes"].IsDefined()) {
    for (const YamlValue& c : key(doc, "classes").items()) {
      const std::uint64_t id = key(c, "id").as_uint64();
      if (id > 65535) c.fail("class id " + std::to_string(id) + " is beyond 65535");
      h.classes.emplace_back(static_cast<std::uint16_t>(id), key(c, "name").as_string());
    }
  }
  const YamlValue scenario = key(doc, "scenario");
  if (!scenario.is_map()) scenario.fail("expected the resolved scenario as a map");
  h.scenario.name = key(scenario, "name").as_string();
  const YamlValue rate = key(scenario, "rate_hz");
  h.scenario.rate_hz = rate.as_double();
  if (!(h.scenario.rate_hz > 0.0)) rate.fail("must be > 0");
  h.scenario.seed = key(scenario, "seed").as_uint64();

  // The scenario block verbatim: every line after "scenario:", without its two-space indent.
  std::ifstream in(file, std::ios::binary);
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside) {
      inside = line == kScenarioKey;
      continue;
    }
    if (line.rfind("  ", 0) != 0) scenario.fail("expected every line of the scenario block indented by two spaces");
    h.scenario_yaml += line.substr(2) + "\n";
  }
  if (!inside) scenario.fail("expected 'scenario:' alone on a line, followed by the indented scenario");
  return h;
}

}  // namespace fmcw::io
