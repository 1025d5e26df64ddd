// The generator config: every key optional, every key checked.

#include <algorithm>
#include <filesystem>

#include "fmcw/sim/scenario.hpp"
#include "fmcw/sim/scenario_generator.hpp"
#include "fmcw/io/yaml_reader.hpp"
#include "layouts.hpp"

namespace fmcw::sim {

using io::YamlMap;
using io::YamlValue;
using io::is_existing_file;

namespace fs = std::filesystem;

namespace {

std::string resolve(const YamlValue& v, const std::string& base_dir) {
  const std::string text = v.as_string();
  if (text.empty()) v.fail("expected a path");
  fs::path p(text);
  if (p.is_relative()) p = fs::path(base_dir) / p;
  return fs::absolute(p).lexically_normal().string();
}

ValueRange read_range(YamlMap& m, const std::string& key, ValueRange fallback, double min, double max) {
  if (!m.has(key)) return fallback;
  const YamlValue v = m.at(key);
  const std::vector<double> x = v.as_doubles();
  if (x.size() != 1 && x.size() != 2) v.fail("expected a number or [low, high]");
  ValueRange r{x.front(), x.back()};
  if (!(r.lo >= min && r.hi <= max && r.lo <= r.hi)) {
    v.fail("expected " + std::to_string(min) + " <= low <= high <= " + std::to_string(max));
  }
  return r;
}

double read_probability(YamlMap& m, const std::string& key, double fallback) {
  const double p = m.get(key, fallback);
  if (!(p >= 0.0 && p <= 1.0)) m.at(key).fail("expected a probability in [0, 1]");
  return p;
}

// {name: weight, ...} with names from `known` (any name when known is empty).
WeightedNames read_weights(YamlMap& m, const std::string& key, WeightedNames fallback,
                           const std::vector<std::string>& known) {
  if (!m.has(key)) return fallback;
  const YamlValue v = m.at(key);
  if (!v.is_map()) v.fail("expected a map of name: weight");
  WeightedNames out;
  double total = 0.0;
  for (const auto& kv : v.node()) {
    const std::string name = kv.first.as<std::string>();
    const YamlValue w(kv.second, v.file(), v.path() + "." + name);
    if (!known.empty() && std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      w.fail("unknown name '" + name + "' (known: " + list + ")");
    }
    const double weight = w.as_double();
    if (!(weight >= 0.0 && weight <= 1e6)) w.fail("expected a weight in [0, 1e6]");
    out.names.push_back(name);
    out.weights.push_back(weight);
    total += weight;
  }
  if (!(total > 0.0)) v.fail("needs at least one weight above 0");
  return out;
}

WeightedNames weights(std::vector<std::string> names, std::vector<double> w) { return {std::move(names), std::move(w)}; }

}  // namespace

GeneratorConfig GeneratorConfig::load(const std::string& path) {
  const YamlValue root = YamlValue::load_file(path);
  const std::string dir = fs::path(path).parent_path().string();
  GeneratorConfig c;
  c.source_file = fs::absolute(path).lexically_normal().string();
  YamlMap m(root);
  c.frames = m.get("frames", c.frames);
  if (c.frames < 1 || c.frames > 100000) m.at("frames").fail("expected 1 <= frames <= 100000");
  c.rate_hz = m.get("rate_hz", c.rate_hz);
  if (!(c.rate_hz >= 0.1 && c.rate_hz <= 1000.0)) m.at("rate_hz").fail("expected 0.1 <= rate_hz <= 1000");
  c.layouts = read_weights(m, "layouts", weights(gen::layout_names(), {1, 1, 1, 1, 1}), gen::layout_names());
  if (!m.has("rigs")) m.at("rigs");  // required: names the key in the error
  {
    const WeightedNames rigs = read_weights(m, "rigs", {}, {});
    for (std::size_t k = 0; k < rigs.names.size(); ++k) {
      const YamlValue where = YamlValue(root.node()["rigs"][rigs.names[k]], root.file(), "rigs." + rigs.names[k]);
      const YamlValue name(YAML::Node(rigs.names[k]), root.file(), "rigs." + rigs.names[k]);
      std::string resolved = resolve(name, dir);
      if (!is_existing_file(resolved)) where.fail("no rig config at " + resolved);
      try {
        load_rig(resolved);  // a broken rig is this config's error, not every scenario's later
      } catch (const std::invalid_argument& e) {
        where.fail(std::string("the rig config does not load: ") + e.what());
      }
      c.rigs.names.push_back(resolved);
      c.rigs.weights.push_back(rigs.weights[k]);
    }
  }
  if (m.has("measurement")) {
    YamlMap mm(m.at("measurement"));
    c.measurement_model = mm.get("model", c.measurement_model);
    if (c.measurement_model != "gaussian" && c.measurement_model != "beat_frequency") {
      mm.at("model").fail("expected gaussian or beat_frequency");
    }
    c.range_sigma_m = read_range(mm, "range_sigma_m", c.range_sigma_m, 0.0, 1.0);
    c.velocity_sigma_mps = read_range(mm, "velocity_sigma_mps", c.velocity_sigma_mps, 0.0, 5.0);
    mm.finish();
  }
  c.assets_dir = m.has("assets") ? resolve(m.at("assets"), dir) : "";
  if (c.assets_dir.empty() || !fs::is_directory(c.assets_dir)) m.at("assets").fail("expected the folder of the meshes");
  c.materials = resolve(m.at("materials"), dir);
  if (!is_existing_file(c.materials)) m.at("materials").fail("no materials table at " + c.materials);
  c.classes = resolve(m.at("classes"), dir);
  if (!is_existing_file(c.classes)) m.at("classes").fail("no class table at " + c.classes);
  if (m.has("traffic")) {
    YamlMap t(m.at("traffic"));
    c.vehicles_per_100m = read_range(t, "vehicles_per_100m", c.vehicles_per_100m, 0.0, 20.0);
    c.cyclists_per_100m = read_range(t, "cyclists_per_100m", c.cyclists_per_100m, 0.0, 20.0);
    c.pedestrians_per_100m = read_range(t, "pedestrians_per_100m", c.pedestrians_per_100m, 0.0, 50.0);
    c.parked_share = read_range(t, "parked_share", c.parked_share, 0.0, 1.0);
    c.vehicle_mix = read_weights(t, "vehicle_mix", weights({"car", "van", "truck", "bus"}, {6, 2, 1, 1}),
                                 {"car", "van", "truck", "bus"});
    c.urban_speed_mps = read_range(t, "urban_speed_mps", c.urban_speed_mps, 1.0, 30.0);
    c.highway_speed_mps = read_range(t, "highway_speed_mps", c.highway_speed_mps, 5.0, 60.0);
    c.pedestrian_speed_mps = read_range(t, "pedestrian_speed_mps", c.pedestrian_speed_mps, 0.3, 4.0);
    c.cyclist_speed_mps = read_range(t, "cyclist_speed_mps", c.cyclist_speed_mps, 1.0, 15.0);
    c.turn_probability = read_probability(t, "turn_probability", c.turn_probability);
    c.stop_probability = read_probability(t, "stop_probability", c.stop_probability);
    c.stop_wait_s = read_range(t, "stop_wait_s", c.stop_wait_s, 0.0, 60.0);
    c.lane_change_probability = read_probability(t, "lane_change_probability", c.lane_change_probability);
    c.pedestrian_behaviour = read_weights(t, "pedestrian_behaviour", weights({"walk", "cross", "wait", "stand"}, {5, 3, 2, 2}),
                                          {"walk", "cross", "wait", "stand"});
    c.straight_road_lanes = read_weights(t, "straight_road_lanes", weights({"1", "2"}, {1, 1}), {"1", "2", "3"});
    t.finish();
  }
  if (c.vehicle_mix.names.empty()) c.vehicle_mix = weights({"car", "van", "truck", "bus"}, {6, 2, 1, 1});
  if (c.pedestrian_behaviour.names.empty()) c.pedestrian_behaviour = weights({"walk", "cross", "wait", "stand"}, {5, 3, 2, 2});
  if (c.straight_road_lanes.names.empty()) c.straight_road_lanes = weights({"1", "2"}, {1, 1});
  if (m.has("ego")) {
    YamlMap e(m.at("ego"));
    c.ego_speed_mps = read_range(e, "speed_mps", c.ego_speed_mps, 1.0, 30.0);
    c.ego_highway_speed_mps = read_range(e, "highway_speed_mps", c.ego_highway_speed_mps, 5.0, 60.0);
    c.ego_turn_probability = read_probability(e, "turn_probability", c.ego_turn_probability);
    c.ego_stop_probability = read_probability(e, "stop_probability", c.ego_stop_probability);
    c.ego_static_probability = read_probability(e, "static_probability", c.ego_static_probability);
    e.finish();
  }
  c.highway_barriers = read_probability(m, "highway_barriers", c.highway_barriers);
  c.clearance_m = m.get("clearance_m", c.clearance_m);
  if (!(c.clearance_m >= 0.0 && c.clearance_m <= 10.0)) m.at("clearance_m").fail("expected 0 <= clearance_m <= 10");
  m.finish();
  return c;
}

}  // namespace fmcw::sim
