#include "fmcw/sim/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "fmcw/core/check.hpp"
#include "fmcw/io/yaml_reader.hpp"
#include "fmcw/core/threads.hpp"
#include "memory_budget.hpp"
#include "scene_limits.hpp"

namespace fmcw::sim {

using io::YamlMap;
using io::YamlValue;
using io::is_existing_file;
using io::missing_file_reason;

namespace fs = std::filesystem;

namespace {

constexpr double kDeg = M_PI / 180.0;

std::string resolve_path(const std::string& base_file, const std::string& path) {
  const fs::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::path(base_file).parent_path() / p).lexically_normal().string();
}

// pose: {x, y, z, roll_deg, pitch_deg, yaw_deg}; rotation applied as yaw, then pitch, then roll.
Eigen::Isometry3d read_pose(const YamlValue& value) {
  YamlMap m(value);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(m.get("x", 0.0), m.get("y", 0.0), m.get("z", 0.0));
  const double roll = m.get("roll_deg", 0.0) * kDeg;
  const double pitch = m.get("pitch_deg", 0.0) * kDeg;
  const double yaw = m.get("yaw_deg", 0.0) * kDeg;
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  m.finish();
  return T;
}

Eigen::Vector3d read_vector3(const YamlValue& value) {
  const std::vector<double> v = value.as_doubles();
  if (v.size() != 3) value.fail("expected a list of 3 numbers [x, y, z]");
  return {v[0], v[1], v[2]};
}

TrajectorySpec read_trajectory(const YamlValue& value) {
  YamlMap m(value);
  TrajectorySpec t;
  const YamlValue type_value = m.at("type");
  t.type = type_value.as_string();
  if (t.type == "static") {
    t.pose = m.has("pose") ? read_pose(m.at("pose")) : Eigen::Isometry3d::Identity();
  } else if (t.type == "constant_velocity") {
    t.pose = m.has("pose") ? read_pose(m.at("pose")) : Eigen::Isometry3d::Identity();
    t.velocity_mps = read_vector3(m.at("velocity_mps"));
  } else if (t.type == "constant_turn_rate") {
    t.pose = m.has("pose") ? read_pose(m.at("pose")) : Eigen::Isometry3d::Identity();
    t.speed_mps = m.at("speed_mps").as_double();
    t.yaw_rate_rps = m.get("yaw_rate_dps", 0.0) * kDeg;
  } else if (t.type == "waypoints") {
    const YamlValue points = m.at("points");
    for (const auto& item : points.items()) {
      const std::vector<double> p = item.as_doubles();
      if (p.size() != 2 && p.size() != 3) item.fail("expected [x, y] or [x, y, z]");
      t.path.points_m.emplace_back(p[0], p[1], p.size() == 3 ? p[2] : 0.0);
    }
    const YamlValue speeds = m.at("speed_mps");
    t.path.speeds_mps = speeds.as_doubles();
    t.path.start_time_s = m.get("start_time_s", 0.0);
    if (m.has("wait_s")) t.path.waits_s = m.at("wait_s").as_doubles();
    try {
      make_waypoint_trajectory(t.path);  // checks points and speeds
    } catch (const std::invalid_argument& e) {
      value.fail(e.what());
    }
  } else {
    type_value.fail("unknown trajectory type '" + t.type + "' (known: static, constant_velocity, constant_turn_rate, waypoints)");
  }
  m.finish();
  return t;
}

core::HeadModel read_head(const YamlValue& value, std::size_t index) {
  YamlMap m(value);
  core::HeadModel head;
  head.name = m.get("name", "head" + std::to_string(index));
  if (head.name.empty() || head.name.find_first_of(" \t") != std::string::npos) value.fail("head name must be one word");
  if (m.has("mount")) head.T_rig_head = read_pose(m.at("mount"));
  const auto pair = [&](const char* key, double dh, double dv) {
    if (!m.has(key)) {
      m.get(key, 0.0);  // mark as accepted for the error message of finish()
      return std::pair<double, double>(dh, dv);
    }
    const YamlValue v = m.at(key);
    const std::vector<double> d = v.as_doubles();
    if (d.size() != 2) v.fail("expected [horizontal, vertical] in degrees");
    return std::pair<double, double>(d[0], d[1]);
  };
  const auto fov = pair("fov_deg", 40.0, 30.0);
  const auto res = pair("resolution_deg", 0.2, 0.2);
  head.fov_horizontal_rad = fov.first * kDeg;
  head.fov_vertical_rad = fov.second * kDeg;
  head.resolution_horizontal_rad = res.first * kDeg;
  head.resolution_vertical_rad = res.second * kDeg;
  head.max_range_m = m.get("max_range_m", 150.0);
  head.rate_hz = m.get("rate_hz", 10.0);
  m.finish();
  try {
    head.validate();
  } catch (const std::exception&) {  // a LimitError (too many pixels) stays one
    core::rethrow_as_file_error(value.where() + ": ");
  }
  return head;
}

core::RigModel read_rig(const YamlValue& value, MemoryBudget* budget = nullptr) {
  YamlMap m(value);
  core::RigModel rig;
  const YamlValue heads = m.at("heads");
  const auto items = heads.items();
  if (items.empty()) heads.fail("a rig needs at least one head");
  double pixels = 0.0;
  for (std::size_t k = 0; k < items.size(); ++k) {
    rig.heads.push_back(read_head(items[k], k));
    pixels += static_cast<double>(rig.heads.back().rows()) * static_cast<double>(rig.heads.back().cols());
  }
  rig.scan_lines = m.get("scan_lines", false);
  m.finish();
  if (budget) {
    budget->add(pixels * kBytesPerPixel, heads.where(),
                "the " + std::to_string(items.size()) + " heads' " + std::to_string(static_cast<long long>(pixels)) + " pixels");
  }
  try {
    rig.validate();
  } catch (const std::exception&) {  // a LimitError (too many pixels) stays one
    core::rethrow_as_file_error(value.where() + ": ");
  }
  return rig;
}

void read_snr(const YamlValue& value, MeasurementParams::Snr& p) {
  YamlMap m(value);
  p.reference_db = m.get("reference_db", p.reference_db);
  p.reference_range_m = m.get("reference_range_m", p.reference_range_m);
  p.reference_reflectivity = m.get("reference_reflectivity", p.reference_reflectivity);
  p.sigma_reference_db = m.get("sigma_reference_db", p.sigma_reference_db);
  p.detection_threshold_db = m.get("detection_threshold_db", p.detection_threshold_db);
  p.detection_width_db = m.get("detection_width_db", p.detection_width_db);
  p.velocity_sigma_floor_mps = m.get("velocity_sigma_floor_mps", p.velocity_sigma_floor_mps);
  p.range_sigma_floor_m = m.get("range_sigma_floor_m", p.range_sigma_floor_m);
  m.finish();
}

MeasurementParams read_measurement(const YamlValue& value) {
  YamlMap m(value);
  MeasurementParams p;
  const std::string model = m.get("model", std::string("gaussian"));
  try {
    p.model = measurement_model_from_string(model);
  } catch (const std::invalid_argument& e) {
    m.at("model").fail(e.what());
  }
  p.range_sigma_m = m.get("range_sigma_m", p.range_sigma_m);
  p.velocity_sigma_mps = m.get("velocity_sigma_mps", p.velocity_sigma_mps);
  p.wavelength_m = m.get("wavelength_m", p.wavelength_m);
  p.bandwidth_hz = m.get("bandwidth_hz", p.bandwidth_hz);
  p.chirp_period_s = m.get("chirp_period_s", p.chirp_period_s);
  p.beat_frequency_sigma_hz = m.get("beat_frequency_sigma_hz", p.beat_frequency_sigma_hz);
  const std::string frame = m.get("velocity_frame", std::string("sensor"));
  if (frame != "sensor" && frame != "ego_compensated") {
    m.at("velocity_frame").fail("velocity_frame must be sensor or ego_compensated, got '" + frame + "'");
  }
  p.velocity_frame = core::velocity_frame_from_string(frame);
  if (m.has("snr")) read_snr(m.at("snr"), p.snr);
  m.finish();
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    value.fail(e.what());
  }
  return p;
}

std::string unknown_class(const Scenario& s, const std::string& name) {
  return "unknown class '" + name + "' (add it under classes: in a class table; known: " + s.classes.names() + ")";
}

// A class table: classes of the scenario's own, and the classes of mesh files' triangles.
//   classes: {forklift: 120}
//   meshes: {road_segment.gltf: {class: road, parts: {curb: sidewalk}}}
void read_class_table(const std::string& file, Scenario& s) {
  const YamlValue root = YamlValue::load_file(file);
  YamlMap m(root);
  if (m.has("classes")) {
    const YamlValue classes = m.at("classes");
    YamlMap cm(classes);
    for (const auto& kv : classes.node()) {
      const std::string name = kv.first.as<std::string>();
      const YamlValue id = cm.at(name);
      try {
        s.classes.add(name, id.as_uint64());
      } catch (const std::invalid_argument& e) {
        id.fail(e.what());
      }
    }
    cm.finish();
  } else {
    m.get("classes", 0.0);
  }
  if (m.has("meshes")) {
    const YamlValue meshes = m.at("meshes");
    YamlMap mm(meshes);
    for (const auto& kv : meshes.node()) {
      const std::string mesh = kv.first.as<std::string>();
      const YamlValue entry = mm.at(mesh);
      YamlMap em(entry);
      MeshClasses mc;
      mc.class_name = em.get("class", std::string());
      if (!mc.class_name.empty() && !s.classes.find(mc.class_name)) em.at("class").fail(unknown_class(s, mc.class_name));
      if (em.has("parts")) {
        const YamlValue parts = em.at("parts");
        YamlMap pm(parts);
        for (const auto& p : parts.node()) {
          const std::string part = p.first.as<std::string>();
          const YamlValue c = pm.at(part);
          if (!s.classes.find(c.as_string())) c.fail(unknown_class(s, c.as_string()));
          mc.parts[part] = c.as_string();
        }
        pm.finish();
      } else {
        em.get("parts", 0.0);
      }
      em.finish();
      s.mesh_classes[mesh] = mc;
    }
    mm.finish();
  } else {
    m.get("meshes", 0.0);
  }
  m.finish();
}

ReflectivityTable read_materials(const std::string& file) {
  const YamlValue root = YamlValue::load_file(file);
  YamlMap m(root);
  ReflectivityTable table;
  for (const auto& kv : root.node()) {
    const std::string key = kv.first.as<std::string>();
    const double r = m.at(key).as_double();
    if (r < 0.0 || r > 1.0) m.at(key).fail("reflectivity must be in [0, 1]");
    table[key] = static_cast<float>(r);
  }
  m.finish();
  return table;
}

AnimationSpec read_animation(const YamlValue& value) {
  YamlMap m(value);
  AnimationSpec a;
  a.given = true;
  a.clip = m.get("clip", std::string());
  ClipPlayback& p = a.playback;
  p.speed = m.get("speed", 1.0);
  p.loop = m.get("loop", true);
  p.start_s = m.get("start_s", 0.0);
  p.offset_s = m.get("offset_s", 0.0);
  const std::string clock = m.get("clock", std::string("time"));
  if (clock == "distance") {
    p.clock = ClipPlayback::Clock::kDistance;
    if (m.has("start_s")) m.at("start_s").fail("start_s is for clock: time; a distance clock runs with the path");
  } else if (clock != "time") {
    m.at("clock").fail("clock must be time or distance, got '" + clock + "'");
  }
  p.nominal_speed_mps = m.get("nominal_speed_mps", 0.0);
  if (!(p.nominal_speed_mps >= 0.0)) {
    m.at("nominal_speed_mps").fail("nominal_speed_mps must be >= 0 (0: the clip's own)");
  }
  if (m.has("nominal_speed_mps") && p.clock != ClipPlayback::Clock::kDistance) {
    m.at("nominal_speed_mps").fail("nominal_speed_mps is for clock: distance");
  }
  m.finish();
  return a;
}

// The clip an actor plays: the one its animation block names, else (animate on) the mesh's
// first, looped on time. Notices for clips that will not play.
void resolve_animation(ObjectSpec& o, const MeshAsset& asset, const YamlValue& item, std::set<std::string>& said,
                       std::vector<std::string>& notices) {
  AnimationSpec& a = o.animation;
  if (!o.animate || o.id == 0) {
    if (!asset.clips.empty() && said.insert(o.mesh_path).second) {
      notices.push_back(item.where() + ": mesh '" + o.mesh_path + "' has clip(s) " + asset.clip_names() + ", not played: " +
                        (o.id == 0 ? "static objects stand still" : "the actor has animate: false"));
    }
    return;
  }
  if (asset.clips.empty()) {
    if (a.given) item.fail("animation: mesh '" + o.mesh_path + "' has no clip");
    return;
  }
  const int k = a.clip.empty() ? 0 : asset.find_clip(a.clip);
  if (k < 0) {
    item.fail("animation.clip: mesh '" + o.mesh_path + "' has no clip '" + a.clip + "'; its clips: " + asset.clip_names());
  }
  a.clip_index = k;
  a.clip = asset.clips[static_cast<std::size_t>(k)].name;
  ClipPlayback& p = a.playback;
  if (p.clock == ClipPlayback::Clock::kDistance && p.nominal_speed_mps == 0.0) {
    p.nominal_speed_mps = asset.clips[static_cast<std::size_t>(k)].nominal_speed_mps;
    if (p.nominal_speed_mps == 0.0) {
      item.fail("animation: clock: distance needs nominal_speed_mps, and clip '" + a.clip + "' gives none");
    }
  }
}

ObjectSpec read_object(const YamlValue& value, bool is_actor, const std::string& scenario_file) {
  YamlMap m(value);
  ObjectSpec o;
  o.mesh = m.at("mesh").as_string();
  o.mesh_path = resolve_path(scenario_file, o.mesh);
  if (!is_existing_file(o.mesh_path)) m.at("mesh").fail("mesh file '" + o.mesh_path + "' " + missing_file_reason(o.mesh_path));
  if (m.has("mesh_transform")) {
    const YamlValue mt = m.at("mesh_transform");
    YamlMap t(mt);
    const double scale = t.get("scale", 1.0);
    if (!(scale > 0.0)) t.at("scale").fail("scale must be > 0");
    Eigen::Affine3d T = Eigen::Affine3d::Identity();
    T.translation() = Eigen::Vector3d(t.get("x", 0.0), t.get("y", 0.0), t.get("z", 0.0));
    T.linear() = (Eigen::AngleAxisd(t.get("yaw_deg", 0.0) * kDeg, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(t.get("pitch_deg", 0.0) * kDeg, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(t.get("roll_deg", 0.0) * kDeg, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix() *
                 scale;
    t.finish();
    o.T_body_asset = T;
  } else {
    m.get("mesh_transform", 0.0);
  }
  if (is_actor) {
    const YamlValue id = m.at("id");
    const std::uint64_t v = id.as_uint64();
    if (v == 0 || v > 0xFFFFFFFEull) id.fail("actor id must be in [1, 4294967294] (0 is the static world)");
    o.id = static_cast<std::uint32_t>(v);
    o.class_name = m.at("class").as_string();
    o.name = m.get("name", o.class_name + "_" + std::to_string(o.id));
    o.trajectory = read_trajectory(m.at("trajectory"));
    o.animate = m.get("animate", true);
    if (m.has("animation")) {
      const YamlValue av = m.at("animation");
      if (!o.animate) av.fail("an animation needs animate: true");
      o.animation = read_animation(av);
    }
  } else {
    o.name = m.get("name", std::string("static"));
    o.semantic_class = m.get("class", std::string());
    o.trajectory.type = "static";
    o.trajectory.pose = m.has("pose") ? read_pose(m.at("pose")) : Eigen::Isometry3d::Identity();
    if (!m.has("pose")) m.get("pose", 0.0);
    o.animate = false;
  }
  m.finish();
  return o;
}

void emit_pose(YAML::Emitter& out, const Eigen::Isometry3d& T) {
  const Eigen::Vector3d ypr = T.linear().eulerAngles(2, 1, 0) + Eigen::Vector3d::Zero();  // no -0
  out << YAML::Flow << YAML::BeginMap << YAML::Key << "x" << YAML::Value << T.translation().x() << YAML::Key << "y"
      << YAML::Value << T.translation().y() << YAML::Key << "z" << YAML::Value << T.translation().z() << YAML::Key
      << "yaw_deg" << YAML::Value << ypr[0] / kDeg << YAML::Key << "pitch_deg" << YAML::Value << ypr[1] / kDeg
      << YAML::Key << "roll_deg" << YAML::Value << ypr[2] / kDeg << YAML::EndMap;
}

void emit_trajectory(YAML::Emitter& out, const TrajectorySpec& t) {
  out << YAML::BeginMap << YAML::Key << "type" << YAML::Value << t.type;
  if (t.type == "waypoints") {
    out << YAML::Key << "points" << YAML::Value << YAML::BeginSeq;
    for (const auto& p : t.path.points_m) out << YAML::Flow << std::vector<double>{p.x(), p.y(), p.z()};
    out << YAML::EndSeq << YAML::Key << "speed_mps" << YAML::Value << YAML::Flow << t.path.speeds_mps << YAML::Key
        << "start_time_s" << YAML::Value << t.path.start_time_s;
    if (!t.path.waits_s.empty()) out << YAML::Key << "wait_s" << YAML::Value << YAML::Flow << t.path.waits_s;
  } else {
    out << YAML::Key << "pose" << YAML::Value;
    emit_pose(out, t.pose);
    if (t.type == "constant_velocity") {
      out << YAML::Key << "velocity_mps" << YAML::Value << YAML::Flow
          << std::vector<double>{t.velocity_mps.x(), t.velocity_mps.y(), t.velocity_mps.z()};
    } else if (t.type == "constant_turn_rate") {
      out << YAML::Key << "speed_mps" << YAML::Value << t.speed_mps << YAML::Key << "yaw_rate_dps" << YAML::Value
          << t.yaw_rate_rps / kDeg;
    }
  }
  out << YAML::EndMap;
}

}  // namespace

std::unique_ptr<Trajectory> TrajectorySpec::make() const {
  if (type == "constant_velocity") return make_constant_velocity_trajectory(pose, velocity_mps);
  if (type == "constant_turn_rate") return make_constant_turn_rate_trajectory(pose, speed_mps, yaw_rate_rps);
  if (type == "waypoints") return make_waypoint_trajectory(path);
  return make_static_trajectory(pose);
}

double TrajectorySpec::nominal_speed_mps() const {
  if (type == "constant_velocity") return velocity_mps.norm();
  if (type == "constant_turn_rate") return std::abs(speed_mps);
  if (type == "waypoints") {
    double sum = 0.0;
    for (const double s : path.speeds_mps) sum += s;
    return path.speeds_mps.empty() ? 0.0 : sum / static_cast<double>(path.speeds_mps.size());
  }
  return 0.0;
}

namespace {

// yaml-cpp throws its own exceptions from conversions the readers above did not foresee; they
// become the documented error, with the file and the place yaml-cpp names.
template <typename Read>
auto with_yaml_errors_named(const std::string& path, Read read) {
  try {
    return read();
  } catch (const YAML::Exception& e) {
    std::ostringstream msg;
    msg << path << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": " << e.msg;
    throw core::FileError(msg.str());
  }
}

LoadedScenario load_scenario_unchecked(const std::string& path, MemoryBudget& budget);

}  // namespace

core::RigModel load_rig(const std::string& path) {
  return with_yaml_errors_named(path, [&] { return read_rig(YamlValue::load_file(path)); });
}

LoadedScenario load_scenario(const std::string& path, std::uint64_t max_memory_bytes) {
  MemoryBudget budget(max_memory_bytes);
  return with_yaml_errors_named(path, [&] { return load_scenario_unchecked(path, budget); });
}

namespace {

LoadedScenario load_scenario_unchecked(const std::string& path, MemoryBudget& budget) {
  const YamlValue root = YamlValue::load_file(path);
  YamlMap m(root);
  LoadedScenario loaded;
  Scenario& s = loaded.scenario;
  s.source_file = path;
  s.name = m.get("name", fs::path(path).stem().string());
  if (s.name.empty() || s.name.size() > 200 ||
      std::any_of(s.name.begin(), s.name.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; })) {
    m.at("name").fail("name must be 1 to 200 characters without control characters (got " +
                      std::to_string(s.name.size()) + " characters)");
  }
  const int frames = m.get("frames", 1);
  if (frames < 1) m.at("frames").fail("frames must be >= 1, got " + std::to_string(frames));
  s.frames = frames;
  s.rate_hz = m.get("rate_hz", 10.0);
  if (!(s.rate_hz >= 1e-3 && s.rate_hz <= 1e6)) m.at("rate_hz").fail("rate_hz must be in [0.001, 1e6] Hz");
  s.start_time_s = m.get("start_time_s", 0.0);
  if (!(std::abs(s.start_time_s) <= 1e9)) m.at("start_time_s").fail("start_time_s must be within 1e9 s of 0");
  s.seed = m.get("seed", std::uint64_t{0});
  if (m.has("rig")) {
    const YamlValue rig = m.at("rig");
    if (rig.is_scalar()) {
      const std::string file = resolve_path(path, rig.as_string());
      if (!is_existing_file(file)) rig.fail("rig config '" + file + "' " + missing_file_reason(file));
      s.rig = load_rig(file);
      s.rig_source = file;
    } else {
      s.rig = read_rig(rig, &budget);
      s.rig_source = "inline";
    }
  } else {
    m.get("rig", 0.0);
    s.rig_source = "paper_rig (built in)";
  }
  if (m.has("measurement")) {
    s.measurement = read_measurement(m.at("measurement"));
  } else {
    m.get("measurement", 0.0);
  }
  if (m.has("simulation")) {
    const YamlValue sim = m.at("simulation");
    YamlMap sm(sim);
    s.motion_distortion = sm.get("motion_distortion", false);
    s.time_slices = sm.get("time_slices", 0);
    if (s.time_slices < 0) sm.at("time_slices").fail("time_slices must be >= 0 (0: one per column)");
    s.min_range_m = sm.get("min_range_m", 0.3);
    if (s.min_range_m < 0.0) sm.at("min_range_m").fail("min_range_m must be >= 0");
    if (sm.has("beam_divergence")) {
      const YamlValue bd = sm.at("beam_divergence");
      YamlMap b(bd);
      s.divergence.sub_rays = b.get("sub_rays", 19);
      s.divergence.divergence_rad = b.get("divergence_deg", 0.1) * kDeg;
      s.divergence.merge_range_m = b.get("merge_range_m", s.divergence.merge_range_m);
      s.divergence.merge_velocity_mps = b.get("merge_velocity_mps", s.divergence.merge_velocity_mps);
      b.finish();
      try {
        s.divergence.validate();
      } catch (const std::invalid_argument& e) {
        bd.fail(e.what());
      }
    } else {
      sm.get("beam_divergence", 0.0);
    }
    sm.finish();
  } else {
    m.get("simulation", 0.0);
  }
  s.moving_threshold_mps = m.get("moving_threshold_mps", 0.1);
  if (s.moving_threshold_mps < 0.0) m.at("moving_threshold_mps").fail("must be >= 0");
  if (m.has("materials")) {
    const YamlValue mat = m.at("materials");
    s.materials_file = resolve_path(path, mat.as_string());
    if (!is_existing_file(s.materials_file)) mat.fail("materials file '" + s.materials_file + "' " + missing_file_reason(s.materials_file));
    s.materials = read_materials(s.materials_file);
  } else {
    m.get("materials", 0.0);
  }
  s.default_reflectivity = static_cast<float>(m.get("default_reflectivity", 0.3));
  if (m.has("classes")) {
    const YamlValue c = m.at("classes");
    s.classes_file = resolve_path(path, c.as_string());
    if (!is_existing_file(s.classes_file)) c.fail("class table '" + s.classes_file + "' " + missing_file_reason(s.classes_file));
    read_class_table(s.classes_file, s);
  } else {
    m.get("classes", 0.0);
  }
  if (m.has("ground")) {
    const YamlValue g = m.at("ground");
    YamlMap gm(g);
    s.ground = gm.get("enabled", true);
    s.ground_z_m = gm.get("z_m", 0.0);
    s.ground_half_size_m = gm.get("half_size_m", 300.0);
    s.ground_reflectivity = static_cast<float>(gm.get("reflectivity", 0.1));
    s.ground_class = gm.get("class", s.ground_class);
    if (!s.classes.find(s.ground_class)) gm.at("class").fail(unknown_class(s, s.ground_class));
    if (!(s.ground_half_size_m > 0.0 && s.ground_half_size_m <= kMaxSceneExtent_m)) {
      gm.at("half_size_m").fail("must be in (0, " + std::to_string(static_cast<int>(kMaxSceneExtent_m)) +
                                "] m: farther out, single-precision ray tracing loses millimetres");
    }
    if (!(std::abs(s.ground_z_m) <= kMaxSceneExtent_m)) gm.at("z_m").fail("must be within 10000 m of 0");
    gm.finish();
  } else {
    m.get("ground", 0.0);
  }
  if (m.has("ego")) {
    const YamlValue ego = m.at("ego");
    YamlMap em(ego);
    s.ego = read_trajectory(em.at("trajectory"));
    em.finish();
  } else {
    m.get("ego", 0.0);
  }
  std::map<std::string, std::shared_ptr<const MeshAsset>> cache;
  std::set<std::string> said;  // meshes whose unplayed clips were noted
  const auto mesh = [&](ObjectSpec& o, const YamlValue& where) {
    auto it = cache.find(o.mesh_path);
    if (it == cache.end()) {
      try {
        it = cache.emplace(o.mesh_path, std::make_shared<const MeshAsset>(
                                            load_mesh_asset(o.mesh_path, s.materials, s.default_reflectivity)))
                 .first;
      } catch (const std::invalid_argument& e) {
        where.fail(e.what());
      }
      loaded.notices.insert(loaded.notices.end(), it->second->notices.begin(), it->second->notices.end());
      // Class-table parts that name neither a node nor a material of the mesh classify nothing.
      const auto table = s.mesh_classes.find(fs::path(o.mesh_path).filename().string());
      if (table != s.mesh_classes.end()) {
        const MeshAsset& asset = *it->second;
        std::string unused;
        for (const auto& [part, name] : table->second.parts) {
          if (asset.find_part(part) < 0 && std::find(asset.materials.begin(), asset.materials.end(), part) == asset.materials.end()) {
            unused += (unused.empty() ? "'" : ", '") + part + "'";
          }
        }
        if (!unused.empty()) {
          loaded.notices.push_back(s.classes_file + ": meshes." + table->first + ".parts: " + unused +
                                   " name no node or material of mesh '" + o.mesh_path + "': not used");
        }
      }
    }
    resolve_animation(o, *it->second, where, said, loaded.notices);
    return it->second;
  };
  if (m.has("static")) {
    for (const auto& item : m.at("static").items()) {
      // repeat: {count, dx, dy, dyaw_deg} places count copies, each offset from the previous.
      int count = 1;
      Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
      YAML::Node node = YAML::Clone(item.node());
      if (node["repeat"]) {
        YamlMap r(YamlValue(node["repeat"], item.file(), item.path() + ".repeat"));
        count = r.at("count").as_int();
        if (count < 1 || count > 100000) r.at("count").fail("count must be in [1, 100000]");
        step.translation() = Eigen::Vector3d(r.get("dx", 0.0), r.get("dy", 0.0), r.get("dz", 0.0));
        step.linear() = Eigen::AngleAxisd(r.get("dyaw_deg", 0.0) * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        r.finish();
        node.remove("repeat");
      }
      ObjectSpec base = read_object(YamlValue(node, item.file(), item.path()), false, path);
      if (base.semantic_class.empty()) {
        const auto table = s.mesh_classes.find(fs::path(base.mesh_path).filename().string());
        base.semantic_class = table != s.mesh_classes.end() && !table->second.class_name.empty() ? table->second.class_name
                                                                                                  : "other_structure";
      }
      if (!s.classes.find(base.semantic_class)) item.fail("class: " + unknown_class(s, base.semantic_class));
      Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
      // Room for every copy at once (growing one by one doubled into two arrays of copies at a
      // time), and at least twice the room when it grows, as push_back would.
      const std::size_t needed = s.statics.size() + static_cast<std::size_t>(count);
      if (needed > s.statics.capacity()) {
        s.statics.reserve(std::max(needed, 2 * s.statics.capacity()));
        loaded.static_meshes.reserve(std::max(needed, 2 * s.statics.capacity()));
      }
      for (int k = 0; k < count; ++k) {
        ObjectSpec copy = base;
        copy.trajectory.pose.translation() = base.trajectory.pose.translation() + offset.translation();
        copy.trajectory.pose.linear() = offset.linear() * base.trajectory.pose.linear();
        s.statics.push_back(copy);
        loaded.static_meshes.push_back(mesh(s.statics.back(), item));
        if (k == 0) {
          // Every copy is a mesh of its own in the scene: counted before the copies are made.
          const double triangles = static_cast<double>(loaded.static_meshes.back()->triangle_count());
          budget.add(count * (triangles * kBytesPerTriangle + kBytesPerObject), item.where(),
                     std::to_string(count) + " cop" + (count == 1 ? "y" : "ies") + " of '" + base.mesh_path + "' (" +
                         std::to_string(static_cast<long long>(triangles)) + " triangles each)");
        }
        offset = step * offset;
      }
    }
  } else {
    m.get("static", 0.0);
  }
  if (m.has("actors")) {
    std::map<std::uint32_t, std::string> ids;
    for (const auto& item : m.at("actors").items()) {
      s.actors.push_back(read_object(item, true, path));
      ObjectSpec& a = s.actors.back();
      a.semantic_class = a.class_name;
      if (!s.classes.find(a.class_name)) item.fail("class: " + unknown_class(s, a.class_name));
      if (!ids.emplace(a.id, item.path()).second) {
        item.fail("actor id " + std::to_string(a.id) + " is already used by " + ids[a.id]);
      }
      loaded.actor_meshes.push_back(mesh(a, item));
      budget.add(static_cast<double>(loaded.actor_meshes.back()->triangle_count()) * kBytesPerTriangle + kBytesPerObject,
                 item.where(),
                 "actor mesh '" + a.mesh_path + "'");
    }
  } else {
    m.get("actors", 0.0);
  }
  m.finish();
  return loaded;
}

}  // namespace

std::string scenario_to_yaml(const Scenario& s) {
  YAML::Emitter out;
  out.SetDoublePrecision(15);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << s.name;
  out << YAML::Key << "source_file" << YAML::Value << s.source_file;
  out << YAML::Key << "frames" << YAML::Value << s.frames;
  out << YAML::Key << "rate_hz" << YAML::Value << s.rate_hz;
  out << YAML::Key << "start_time_s" << YAML::Value << s.start_time_s;
  out << YAML::Key << "seed" << YAML::Value << s.seed;
  out << YAML::Key << "rig_source" << YAML::Value << s.rig_source;
  out << YAML::Key << "rig" << YAML::Value << YAML::BeginMap << YAML::Key << "heads" << YAML::Value << YAML::BeginSeq;
  for (const auto& h : s.rig.heads) {
    out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << h.name << YAML::Key << "mount" << YAML::Value;
    emit_pose(out, h.T_rig_head);
    out << YAML::Key << "fov_deg" << YAML::Value << YAML::Flow
        << std::vector<double>{h.fov_horizontal_rad / kDeg, h.fov_vertical_rad / kDeg} << YAML::Key << "resolution_deg"
        << YAML::Value << YAML::Flow
        << std::vector<double>{h.resolution_horizontal_rad / kDeg, h.resolution_vertical_rad / kDeg} << YAML::Key
        << "max_range_m" << YAML::Value << h.max_range_m << YAML::Key << "rate_hz" << YAML::Value << h.rate_hz
        << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (s.rig.scan_lines) out << YAML::Key << "scan_lines" << YAML::Value << true;  // only when set: old bytes kept
  out << YAML::EndMap;
  const MeasurementParams& mp = s.measurement;
  out << YAML::Key << "measurement" << YAML::Value << YAML::BeginMap << YAML::Key << "model" << YAML::Value
      << to_string(mp.model) << YAML::Key << "range_sigma_m" << YAML::Value << mp.range_sigma_m << YAML::Key
      << "velocity_sigma_mps" << YAML::Value << mp.velocity_sigma_mps << YAML::Key << "wavelength_m" << YAML::Value
      << mp.wavelength_m << YAML::Key << "bandwidth_hz" << YAML::Value << mp.bandwidth_hz << YAML::Key
      << "chirp_period_s" << YAML::Value << mp.chirp_period_s << YAML::Key << "beat_frequency_sigma_hz" << YAML::Value
      << mp.beat_frequency_sigma_hz;
  // Written only when not the default, so that datasets of the paper's scenarios keep their bytes.
  if (mp.velocity_frame != core::VelocityFrame::kSensor) {
    out << YAML::Key << "velocity_frame" << YAML::Value << core::to_string(mp.velocity_frame);
  }
  if (mp.model == MeasurementParams::Model::kSnr) {
    const MeasurementParams::Snr& q = mp.snr;
    out << YAML::Key << "snr" << YAML::Value << YAML::BeginMap << YAML::Key << "reference_db" << YAML::Value
        << q.reference_db << YAML::Key << "reference_range_m" << YAML::Value << q.reference_range_m << YAML::Key
        << "reference_reflectivity" << YAML::Value << q.reference_reflectivity << YAML::Key << "sigma_reference_db"
        << YAML::Value << q.sigma_reference_db << YAML::Key << "detection_threshold_db" << YAML::Value
        << q.detection_threshold_db << YAML::Key << "detection_width_db" << YAML::Value << q.detection_width_db
        << YAML::Key << "velocity_sigma_floor_mps" << YAML::Value << q.velocity_sigma_floor_mps << YAML::Key
        << "range_sigma_floor_m" << YAML::Value << q.range_sigma_floor_m << YAML::EndMap;
  }
  out << YAML::EndMap;
  out << YAML::Key << "simulation" << YAML::Value << YAML::BeginMap << YAML::Key << "motion_distortion" << YAML::Value
      << s.motion_distortion << YAML::Key << "time_slices" << YAML::Value << s.time_slices << YAML::Key << "min_range_m"
      << YAML::Value << s.min_range_m << YAML::Key << "beam_divergence" << YAML::Value << YAML::BeginMap << YAML::Key
      << "sub_rays" << YAML::Value << s.divergence.sub_rays << YAML::Key << "divergence_deg" << YAML::Value
      << s.divergence.divergence_rad / kDeg << YAML::Key << "merge_range_m" << YAML::Value << s.divergence.merge_range_m
      << YAML::Key << "merge_velocity_mps" << YAML::Value << s.divergence.merge_velocity_mps << YAML::EndMap << YAML::EndMap;
  out << YAML::Key << "moving_threshold_mps" << YAML::Value << s.moving_threshold_mps;
  out << YAML::Key << "materials" << YAML::Value << s.materials_file;
  out << YAML::Key << "default_reflectivity" << YAML::Value << s.default_reflectivity;
  if (!s.classes_file.empty()) out << YAML::Key << "classes" << YAML::Value << s.classes_file;
  out << YAML::Key << "ground" << YAML::Value << YAML::BeginMap << YAML::Key << "enabled" << YAML::Value << s.ground
      << YAML::Key << "z_m" << YAML::Value << s.ground_z_m << YAML::Key << "half_size_m" << YAML::Value
      << s.ground_half_size_m << YAML::Key << "reflectivity" << YAML::Value << s.ground_reflectivity << YAML::Key
      << "class" << YAML::Value << s.ground_class << YAML::EndMap;
  out << YAML::Key << "ego" << YAML::Value << YAML::BeginMap << YAML::Key << "trajectory" << YAML::Value;
  emit_trajectory(out, s.ego);
  out << YAML::EndMap;
  const auto emit_objects = [&](const char* key, const std::vector<ObjectSpec>& list, bool actors) {
    out << YAML::Key << key << YAML::Value << YAML::BeginSeq;
    for (const auto& o : list) {
      out << YAML::BeginMap;
      if (actors) out << YAML::Key << "id" << YAML::Value << o.id << YAML::Key << "class" << YAML::Value << o.class_name;
      out << YAML::Key << "name" << YAML::Value << o.name << YAML::Key << "mesh" << YAML::Value << o.mesh_path;
      if (actors) {
        out << YAML::Key << "animate" << YAML::Value << o.animate;
        if (o.animation.clip_index >= 0) {
          const ClipPlayback& p = o.animation.playback;
          const bool distance = p.clock == ClipPlayback::Clock::kDistance;
          out << YAML::Key << "animation" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "clip"
              << YAML::Value << o.animation.clip << YAML::Key << "speed" << YAML::Value << p.speed << YAML::Key << "loop"
              << YAML::Value << p.loop << YAML::Key << "offset_s" << YAML::Value << p.offset_s << YAML::Key << "clock"
              << YAML::Value << (distance ? "distance" : "time");
          if (distance) {
            out << YAML::Key << "nominal_speed_mps" << YAML::Value << p.nominal_speed_mps;
          } else {
            out << YAML::Key << "start_s" << YAML::Value << p.start_s;
          }
          out << YAML::EndMap;
        }
        out << YAML::Key << "trajectory" << YAML::Value;
        emit_trajectory(out, o.trajectory);
      } else {
        out << YAML::Key << "class" << YAML::Value << o.semantic_class << YAML::Key << "pose" << YAML::Value;
        emit_pose(out, o.trajectory.pose);
      }
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  };
  emit_objects("static", s.statics, false);
  emit_objects("actors", s.actors, true);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

SimulationSetup build_simulation(const LoadedScenario& loaded, int num_threads) {
  // Checked before the scene is built (the simulator checks it again).
  FMCW_CHECK_LIMIT(num_threads >= 0 && num_threads <= core::kMaxThreads, "simulator: num_threads (--threads) must be in [0, ",
                   core::kMaxThreads, "] (0: all cores), got ", num_threads);
  const Scenario& s = loaded.scenario;
  SimulationSetup setup;
  check_scene_limits(s);
  setup.scene = std::make_shared<Scene>();
  const auto class_id = [&](const std::string& name) { return *s.classes.find(name); };
  if (s.ground) setup.scene->add_ground_plane(s.ground_z_m, s.ground_half_size_m, s.ground_reflectivity, class_id(s.ground_class));
  for (std::size_t k = 0; k < s.statics.size(); ++k) {
    SceneObject o;
    o.name = s.statics[k].name;
    o.class_name = "static";
    o.asset = loaded.static_meshes[k];
    o.T_body_asset = s.statics[k].T_body_asset;
    o.trajectory = s.statics[k].trajectory.make();
    o.class_id = class_id(s.statics[k].semantic_class);
    const auto table = s.mesh_classes.find(fs::path(s.statics[k].mesh_path).filename().string());
    if (table != s.mesh_classes.end()) {
      for (const auto& [part, name] : table->second.parts) o.part_classes[part] = class_id(name);
    }
    setup.scene->add(std::move(o));
  }
  for (std::size_t k = 0; k < s.actors.size(); ++k) {
    const ObjectSpec& spec = s.actors[k];
    SceneObject o;
    o.name = spec.name;
    o.class_name = spec.class_name;
    o.actor_id = spec.id;
    o.asset = loaded.actor_meshes[k];
    o.T_body_asset = spec.T_body_asset;
    o.trajectory = spec.trajectory.make();
    o.clip = spec.animation.clip_index;
    o.playback = spec.animation.playback;
    o.class_id = class_id(spec.semantic_class);
    if (spec.animate) {
      const MeshAsset& asset = *o.asset;
      for (std::size_t p = 0; p < asset.parts.size(); ++p) {
        const MeshPart& part = asset.parts[p];
        if (part.name.rfind("wheel", 0) == 0 && !part.vertices.empty()) {
          float zmin = part.vertices[0].z(), zmax = zmin;
          for (const auto& v : part.vertices) {
            zmin = std::min(zmin, v.z());
            zmax = std::max(zmax, v.z());
          }
          o.wheels.emplace_back(static_cast<int>(p), 0.5 * static_cast<double>(zmax - zmin));
        }
      }
      if (spec.class_name == "pedestrian") {
        const double speed = spec.trajectory.nominal_speed_mps();
        for (const auto& [node, joint] : pedestrian_gait(speed)) {
          const int p = asset.find_part(node);
          if (p >= 0) o.joints.emplace_back(p, joint);
        }
        o.gait_speed_mps = speed;
      }
    }
    setup.scene->add(std::move(o));
  }
  setup.scene->build();
  setup.ego = std::shared_ptr<const Trajectory>(s.ego.make());
  setup.params.rig = s.rig;
  setup.params.measurement = s.measurement;
  setup.params.moving_threshold_mps = s.moving_threshold_mps;
  setup.params.motion_distortion = s.motion_distortion;
  setup.params.time_slices = s.time_slices;
  setup.params.min_range_m = s.min_range_m;
  setup.params.divergence = s.divergence;
  setup.params.seed = s.seed;
  setup.params.num_threads = num_threads;
  return setup;
}

}  // namespace fmcw::sim
