// Procedural scenarios: a layout, static objects beside its roads, the ego, then traffic drawn
// one road user at a time and kept only if it stays clear of everything placed before.

#include "fmcw/sim/scenario_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <map>
#include <sstream>

#include "clearance_index.hpp"
#include "fmcw/core/check.hpp"
#include "fmcw/core/random.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/io/yaml_reader.hpp"
#include "layouts.hpp"

namespace fmcw::sim {

namespace fs = std::filesystem;
using gen::Vec2;

class GeneratorAssets {
 public:
  struct Mesh {
    std::string path;
    Eigen::AlignedBox2d footprint;  // actors: whole mesh; statics: below kFootprintHeight_m
  };
  std::map<std::string, Mesh> meshes;  // by role: car, van, ..., building_block, tree, pole, sign
  const Mesh& get(const std::string& role) const { return meshes.at(role); }
};

std::shared_ptr<const GeneratorAssets> load_generator_assets(const GeneratorConfig& config) {
  auto out = std::make_shared<GeneratorAssets>();
  const std::vector<std::pair<std::string, bool>> roles = {
      {"car", false},  {"van", false},   {"truck", false}, {"bus", false},           {"cyclist", false},
      {"pedestrian", false}, {"walker_skinned", false}, {"building_block", true}, {"building_tall", true},
      {"tree", true},  {"pole", true},   {"sign", true},  {"barrier", true}};
  for (const auto& [role, is_static] : roles) {
    const std::string path = (fs::path(config.assets_dir) / (role + ".gltf")).string();
    FMCW_CHECK_FILE(io::is_existing_file(path), config.source_file, ": assets: no ", role, ".gltf in ", config.assets_dir);
    const MeshAsset asset = load_mesh_asset(path, {}, 0.3f);
    GeneratorAssets::Mesh m;
    m.path = path;
    m.footprint = footprint_below(asset, Eigen::Affine3d::Identity(), is_static ? kFootprintHeight_m : 1e300);
    FMCW_CHECK_FILE(!m.footprint.isEmpty(), path, ": no triangle below ", kFootprintHeight_m, " m");
    out->meshes[role] = m;
  }
  return out;
}

namespace {

constexpr double kMargin_m = 0.01;  // kept beyond the clearance, so the written file's rounding cannot break it

double r3(double x) { return std::round(x * 1000.0) / 1000.0; }
double r2(double x) { return std::round(x * 100.0) / 100.0; }

std::string num(double x, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, x);
  std::string s(buf);
  if (s.find_first_not_of("-0.") == std::string::npos) return "0";  // no "-0.000"
  if (s.find('.') == std::string::npos) return s;  // no decimals: its zeros are the number's
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

std::size_t pick(std::mt19937_64& rng, const WeightedNames& w) {
  double total = 0.0;
  for (double x : w.weights) total += x;
  double u = gen::uniform(rng, 0.0, total);
  for (std::size_t k = 0; k < w.weights.size(); ++k) {
    if (u < w.weights[k]) return k;
    u -= w.weights[k];
  }
  for (std::size_t k = w.weights.size(); k-- > 0;) {
    if (w.weights[k] > 0.0) return k;
  }
  return 0;
}

double draw(std::mt19937_64& rng, const ValueRange& r) { return gen::uniform(rng, r.lo, r.hi); }
bool chance(std::mt19937_64& rng, double p) { return gen::uniform(rng, 0.0, 1.0) < p; }

// What a road user does, as written to the scenario.
struct Motion {
  bool is_static = false;
  Eigen::Vector2d pose_xy = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  WaypointPath path;
  double cruise_mps = 0.0;
  bool stops = false;

  std::shared_ptr<const Trajectory> make() const {
    if (is_static) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(pose_xy.x(), pose_xy.y(), 0.0);
      T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      return make_static_trajectory(T);
    }
    return make_waypoint_trajectory(path);
  }
};

struct Limits {
  double lateral_mps2 = 2.0;
  double accel_mps2 = 2.0;
  double decel_mps2 = 3.0;
};

// A route driven from arc length s0 at cruise speed, slowing for curves, optionally stopping
// (and waiting) with its centre `stop_back` behind the stop line. From rest if start_s > 0.
Motion drive(const gen::Route& route, double s0, double cruise, double start_s, bool stop, double wait_s,
             double stop_back, const Limits& lim) {
  const std::vector<double> s = gen::arc_lengths(route.pts);
  const std::vector<double> kappa = gen::curvatures(route.pts, s);
  const double s_end = s.back();
  double s_stop = stop && route.stop_s >= 0.0 ? route.stop_s - stop_back : -1.0;
  if (s_stop < s0 + 8.0) s_stop = -1.0;
  // Arc positions of curved points, for denser waypoints near them.
  std::vector<double> curved;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (kappa[k] > 0.004) curved.push_back(s[k]);
  }
  if (s_stop >= 0.0) curved.push_back(s_stop);
  std::sort(curved.begin(), curved.end());
  const auto feature_distance = [&](double at) {
    if (curved.empty()) return 1e9;
    const auto it = std::lower_bound(curved.begin(), curved.end(), at);
    double d = 1e9;
    if (it != curved.end()) d = *it - at;
    if (it != curved.begin()) d = std::min(d, at - *(it - 1));
    return d;
  };
  const auto kappa_near = [&](double a, double b) {
    double k = 0.0;
    const auto lo = static_cast<std::size_t>(std::lower_bound(s.begin(), s.end(), a) - s.begin());
    for (std::size_t i = lo; i < s.size() && s[i] <= b; ++i) k = std::max(k, kappa[i]);
    return k;
  };
  std::vector<double> at = {s0};
  while (at.back() < s_end - 1e-6) {
    const double here = at.back();
    const double step = std::clamp(2.0 + 0.4 * feature_distance(here), 2.0, 15.0);
    double next = std::min(here + step, s_end);
    if (s_stop > here + 1.0 && s_stop < next) next = s_stop;
    if (s_end - next < 1.5) next = s_end;
    at.push_back(next);
  }
  // Speed limits at the waypoints, then acceleration and braking passes.
  std::vector<double> v(at.size());
  for (std::size_t i = 0; i < at.size(); ++i) {
    const double k = kappa_near(at[i] - 2.0, at[i] + 2.0);
    v[i] = std::min(cruise, k > 1e-6 ? std::sqrt(lim.lateral_mps2 / k) : cruise);
    if (s_stop >= 0.0 && std::abs(at[i] - s_stop) < 1e-9) v[i] = 0.0;
  }
  if (start_s > 0.0) v.front() = 0.0;
  for (std::size_t i = 1; i < v.size(); ++i) {
    v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2.0 * lim.accel_mps2 * (at[i] - at[i - 1])));
  }
  for (std::size_t i = v.size() - 1; i-- > 0;) {
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2.0 * lim.decel_mps2 * (at[i + 1] - at[i])));
  }
  Motion m;
  m.cruise_mps = cruise;
  m.stops = s_stop >= 0.0;
  m.path.start_time_s = r2(start_s);
  for (std::size_t i = 0; i < at.size(); ++i) {
    const Vec2 p = gen::point_at(route.pts, s, at[i]);
    m.path.points_m.emplace_back(r3(p.x()), r3(p.y()), 0.0);
    const double speed = v[i] < 0.05 ? 0.0 : r2(v[i]);
    m.path.speeds_mps.push_back(speed);
    m.path.waits_s.push_back(m.stops && std::abs(at[i] - s_stop) < 1e-9 ? r2(wait_s) : 0.0);
  }
  // Two neighbours at rest would never move: lift the later one (only after rounding).
  for (std::size_t i = 1; i < m.path.speeds_mps.size(); ++i) {
    if (m.path.speeds_mps[i] == 0.0 && m.path.speeds_mps[i - 1] == 0.0) m.path.speeds_mps[i] = 0.1;
  }
  if (std::all_of(m.path.waits_s.begin(), m.path.waits_s.end(), [](double w) { return w == 0.0; })) m.path.waits_s.clear();
  return m;
}

Motion walk(const Vec2& a, const Vec2& b, double speed, double start_s) {
  Motion m;
  m.cruise_mps = speed;
  m.path.start_time_s = r2(start_s);
  m.path.points_m = {Eigen::Vector3d(r3(a.x()), r3(a.y()), 0.0), Eigen::Vector3d(r3(b.x()), r3(b.y()), 0.0)};
  m.path.speeds_mps = {r2(speed)};
  return m;
}

Motion stand(const Vec2& p, double yaw_rad) {
  Motion m;
  m.is_static = true;
  m.pose_xy = Vec2(r3(p.x()), r3(p.y()));
  m.yaw_rad = r2(yaw_rad * 180.0 / M_PI) * M_PI / 180.0;
  return m;
}

struct Placed {
  std::string class_name;
  std::string role;  // mesh role
  Motion motion;
  std::string behaviour;
  std::shared_ptr<const Trajectory> trajectory;  // made from motion once
};

// Keeps static objects off the roads, walkways and bays: discs they must not reach into.
class KeepOut {
 public:
  void add(const Vec2& p, double r) {
    cells_[key(p)].push_back({p, r});
    max_r_ = std::max(max_r_, r);
  }
  void add_line(const Vec2& a, const Vec2& b, double r) {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm())));
    for (int k = 0; k <= n; ++k) add(a + (b - a) * (static_cast<double>(k) / n), r);
  }
  // True if the footprint (box in a frame at p, yaw) comes within a disc.
  bool hits(const Eigen::AlignedBox2d& box, const Vec2& p, double yaw) const {
    const double reach = (box.max() - box.min()).norm() + max_r_ + 1.0;
    const int lo_x = cell(p.x() - reach), hi_x = cell(p.x() + reach), lo_y = cell(p.y() - reach), hi_y = cell(p.y() + reach);
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (int i = lo_x; i <= hi_x; ++i) {
      for (int j = lo_y; j <= hi_y; ++j) {
        const auto it = cells_.find({i, j});
        if (it == cells_.end()) continue;
        for (const auto& [q, r] : it->second) {
          const Vec2 d = q - p;
          const Vec2 local(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
          const double dx = std::max({box.min().x() - local.x(), 0.0, local.x() - box.max().x()});
          const double dy = std::max({box.min().y() - local.y(), 0.0, local.y() - box.max().y()});
          if (dx * dx + dy * dy < r * r) return true;
        }
      }
    }
    return false;
  }

 private:
  static int cell(double x) { return static_cast<int>(std::floor(x / 5.0)); }
  static std::pair<int, int> key(const Vec2& p) { return {cell(p.x()), cell(p.y())}; }
  std::map<std::pair<int, int>, std::vector<std::pair<Vec2, double>>> cells_;
  double max_r_ = 0.0;
};

Footprint footprint_of(const GeneratorAssets::Mesh& mesh, const Motion& m, const std::string& what) {
  Footprint f;
  f.what = what;
  f.box = mesh.footprint;
  f.motion = m.make();
  return f;
}

std::string pose_text(const Vec2& p, double yaw_rad) {
  return "{x: " + num(p.x()) + ", y: " + num(p.y()) + (yaw_rad != 0.0 ? ", yaw_deg: " + num(yaw_rad * 180.0 / M_PI, 2) : "") + "}";
}

std::string list_text(const std::vector<double>& v, int digits) {
  std::string out = "[";
  for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + num(v[k], digits);
  return out + "]";
}

std::string trajectory_text(const Motion& m) {
  if (m.is_static) return "{type: static, pose: " + pose_text(m.pose_xy, m.yaw_rad) + "}";
  std::string pts = "[";
  for (std::size_t k = 0; k < m.path.points_m.size(); ++k) {
    pts += std::string(k ? ", " : "") + "[" + num(m.path.points_m[k].x()) + ", " + num(m.path.points_m[k].y()) + "]";
  }
  pts += "]";
  std::string out = "{type: waypoints, points: " + pts + ", speed_mps: " +
                    (m.path.speeds_mps.size() == 1 ? num(m.path.speeds_mps.front(), 2) : list_text(m.path.speeds_mps, 2));
  if (m.path.start_time_s != 0.0) out += ", start_time_s: " + num(m.path.start_time_s, 2);
  if (!m.path.waits_s.empty()) out += ", wait_s: " + list_text(m.path.waits_s, 2);
  return out + "}";
}

double yaw_along(const gen::Route& r, double s0) {
  const std::vector<double> s = gen::arc_lengths(r.pts);
  const Vec2 a = gen::point_at(r.pts, s, s0), b = gen::point_at(r.pts, s, s0 + 1.0);
  return std::atan2(b.y() - a.y(), b.x() - a.x());
}

double route_length(const gen::Route& r) { return gen::arc_lengths(r.pts).back(); }

}  // namespace

GeneratedScenario generate_scenario(const GeneratorConfig& config, const GeneratorAssets& assets, std::uint64_t seed,
                                    int index) {
  const std::uint64_t scenario_seed = core::mix_seed(seed, static_cast<std::uint64_t>(index));
  std::mt19937_64 rng(scenario_seed);
  char name_buf[32];
  std::snprintf(name_buf, sizeof(name_buf), "gen_%05d", index);
  GeneratedScenario out;
  ManifestRow& row = out.row;
  row.name = name_buf;
  row.file = "scenarios/" + row.name + ".yaml";
  row.seed = scenario_seed;
  row.frames = config.frames;
  row.rate_hz = config.rate_hz;

  const std::string layout_name = config.layouts.names[pick(rng, config.layouts)];
  const int straight_lanes = std::stoi(config.straight_road_lanes.names[pick(rng, config.straight_road_lanes)]);
  const bool parking = layout_name != "highway" && layout_name != "roundabout" && config.parked_share.hi > 0.0 && chance(rng, 0.6);
  const gen::Layout layout = gen::make_layout(layout_name, straight_lanes, parking, rng);
  row.layout = layout.name;
  row.lanes_per_direction = layout.lanes_per_direction;
  row.lane_length_m = layout.lane_length_m;
  row.sidewalk_length_m = layout.sidewalk_length_m;
  const std::string rig = config.rigs.names[pick(rng, config.rigs)];
  row.rig = fs::path(rig).filename().string();
  row.range_sigma_m = std::round(draw(rng, config.range_sigma_m) * 1e4) / 1e4;
  row.velocity_sigma_mps = std::round(draw(rng, config.velocity_sigma_mps) * 1e4) / 1e4;

  std::vector<double> times;
  for (int k = 0; k < config.frames; ++k) times.push_back(static_cast<double>(k) / config.rate_hz);
  const double duration = times.back();
  const double need = config.clearance_m + kMargin_m;
  ClearanceIndex index_(times);

  // Static objects, off every road, walkway and bay, and clear of each other.
  KeepOut keep_out;
  for (const auto& r : layout.routes) {
    for (const Vec2& p : r.pts) keep_out.add(p, 1.3 + need + 0.2);
  }
  for (const auto& w : layout.walkways) keep_out.add_line(w.a, w.b, 0.3 + need);
  for (const auto& c : layout.crossings) keep_out.add_line(c.from, c.to, 0.3 + need);
  for (const auto& b : layout.parking) keep_out.add(b.p, 2.7 + need);
  std::vector<std::pair<std::string, gen::Pose2>> statics;
  const auto place_static = [&](const std::string& role, const gen::Pose2& pose) {
    const GeneratorAssets::Mesh& mesh = assets.get(role);
    if (keep_out.hits(mesh.footprint, pose.p, pose.yaw_rad)) return;
    const Motion m = stand(pose.p, pose.yaw_rad);
    Footprint f = footprint_of(mesh, m, "static " + std::to_string(statics.size()) + " (" + role + ")");
    if (index_.gap_to_fixed(f) < need) return;
    index_.add_fixed(f);
    statics.emplace_back(role, gen::Pose2{m.pose_xy, m.yaw_rad});
  };
  for (const auto& b : layout.buildings) place_static(chance(rng, 0.7) ? "building_block" : "building_tall", b);
  for (const auto& t : layout.trees) place_static("tree", t);
  for (const auto& p : layout.poles) place_static("pole", p);
  for (const auto& s : layout.signs) place_static("sign", s);
  if (!layout.barriers.empty() && chance(rng, config.highway_barriers)) {
    const std::size_t before = statics.size();
    for (const auto& b : layout.barriers) place_static("barrier", b);
    row.barriers = static_cast<int>(statics.size() - before);
  }
  row.static_objects = static_cast<int>(statics.size());

  const bool highway = !layout.urban;
  const Limits vehicle_limits{highway ? 1.5 : 2.0, 2.0, 3.0};

  // The ego: along a route, turning, stopping, or waiting at the stop line.
  std::vector<const gen::Route*> ego_routes;
  const bool ego_turns = chance(rng, config.ego_turn_probability);
  for (const auto& r : layout.routes) {
    const bool turning = r.kind != "straight" && r.kind != "lane_change" && r.kind != "ramp";
    if (turning == ego_turns || r.kind.rfind("exit_", 0) == 0) ego_routes.push_back(&r);
  }
  if (ego_routes.empty()) {
    for (const auto& r : layout.routes) ego_routes.push_back(&r);
  }
  Motion ego;
  bool ego_placed = false;
  for (int attempt = 0; attempt < 50 && !ego_placed; ++attempt) {
    const gen::Route& route = *ego_routes[static_cast<std::size_t>(gen::uniform_int(rng, 0, static_cast<int>(ego_routes.size()) - 1))];
    const double len = route_length(route);
    const double ahead = route.stop_s >= 0.0 ? route.stop_s : 0.5 * len;
    const double s0 = std::max(0.0, ahead - (highway ? gen::uniform(rng, 100.0, 250.0) : gen::uniform(rng, 15.0, 60.0)));
    if (!highway && chance(rng, config.ego_static_probability) && route.stop_s >= 0.0) {
      const std::vector<double> s = gen::arc_lengths(route.pts);
      const double at = route.stop_s - 0.5 * kEgoLength_m - 0.5;
      ego = stand(gen::point_at(route.pts, s, at), yaw_along(route, at));
      row.ego_route = "static";
    } else {
      const double cruise = r2(draw(rng, highway ? config.ego_highway_speed_mps : config.ego_speed_mps));
      const bool stop = !highway && chance(rng, config.ego_stop_probability);
      ego = drive(route, s0, cruise, 0.0, stop, draw(rng, config.stop_wait_s), 0.5 * kEgoLength_m + 0.5, vehicle_limits);
      row.ego_route = route.kind;
      row.ego_stops = ego.stops;
      for (double v : ego.path.speeds_mps) row.ego_max_speed_mps = std::max(row.ego_max_speed_mps, v);
    }
    Footprint f;
    f.what = "ego";
    f.box = Eigen::AlignedBox2d(Eigen::Vector2d(-0.5 * kEgoLength_m, -0.5 * kEgoWidth_m),
                                Eigen::Vector2d(0.5 * kEgoLength_m, 0.5 * kEgoWidth_m));
    try {
      f.motion = ego.make();
    } catch (const std::invalid_argument&) {
      continue;
    }
    auto path = index_.sweep(f);
    if (index_.probe(path, "ego", need).min_clearance_m < need) continue;
    index_.add_moving(std::move(path), "ego");
    ego_placed = true;
  }
  FMCW_CHECK_ARG(ego_placed, "generator: no clear place for the ego in scenario ", row.name);

  // Traffic: each candidate is tried a few times (other start, other route), then given up.
  std::vector<Placed> actors;
  std::vector<double> cruise_speeds;
  const auto try_place = [&](const std::string& class_name, const std::string& role, const std::string& behaviour,
                             const auto& make_motion) {
    for (int attempt = 0; attempt < 4; ++attempt) {
      Motion m;
      if (!make_motion(m)) continue;
      Footprint f;
      f.what = "actor " + std::to_string(actors.size() + 1) + " (" + class_name + ")";
      f.box = assets.get(role).footprint;
      try {
        f.motion = m.make();
      } catch (const std::invalid_argument&) {
        ++row.rejected_candidates;  // a curve the spline cannot follow: draw again
        continue;
      }
      auto path = index_.sweep(f);
      if (index_.probe(path, f.what, need).min_clearance_m < need) {
        ++row.rejected_candidates;
        continue;
      }
      index_.add_moving(std::move(path), f.what);
      actors.push_back({class_name, role, m, behaviour, f.motion});
      return true;
    }
    return false;
  };

  // Parked vehicles in their bays.
  const double parked_share = draw(rng, config.parked_share);
  for (const auto& bay : layout.parking) {
    if (!chance(rng, parked_share)) continue;
    const std::string cls = chance(rng, 0.75) ? "car" : "van";
    if (try_place(cls, cls, "parked", [&](Motion& m) { m = stand(bay.p, bay.yaw_rad); return true; })) ++row.parked;
  }
  // Vehicles along the lanes.
  const double vehicle_density = draw(rng, config.vehicles_per_100m);
  const int vehicles = static_cast<int>(std::lround(vehicle_density * layout.lane_length_m / 100.0));
  for (int k = 0; k < vehicles; ++k) {
    const std::string cls = config.vehicle_mix.names[pick(rng, config.vehicle_mix)];
    const GeneratorAssets::Mesh& mesh = assets.get(cls);
    const double half_length = 0.5 * (mesh.footprint.max().x() - mesh.footprint.min().x());
    const bool turn = chance(rng, config.turn_probability);
    const bool lane_change = chance(rng, config.lane_change_probability);
    std::vector<const gen::Route*> choice;
    for (const auto& r : layout.routes) {
      const bool turning = r.kind == "left" || r.kind == "right" || r.kind.rfind("exit_", 0) == 0;
      const bool changing = r.kind == "lane_change";
      if ((turning == turn || r.kind.rfind("exit_", 0) == 0) && (changing == lane_change || r.kind == "ramp")) choice.push_back(&r);
    }
    if (choice.empty()) {
      for (const auto& r : layout.routes) choice.push_back(&r);
    }
    const double speed_scale = (cls == "truck" || cls == "bus") ? 0.85 : 1.0;
    std::string kind;
    const bool placed = try_place(cls, cls, "drive", [&](Motion& m) {
      const gen::Route& route = *choice[static_cast<std::size_t>(gen::uniform_int(rng, 0, static_cast<int>(choice.size()) - 1))];
      kind = route.kind;
      const double cruise = speed_scale * draw(rng, highway ? config.highway_speed_mps : config.urban_speed_mps);
      const double len = route_length(route);
      const bool late = chance(rng, 0.3);
      const double s0 = late ? 0.0 : gen::uniform(rng, 0.0, std::max(0.0, len - cruise * duration - 30.0));
      const double start = late ? gen::uniform(rng, 0.0, 0.7 * duration) : 0.0;
      const bool stop = !highway && chance(rng, config.stop_probability);
      m = drive(route, s0, cruise, start, stop, draw(rng, config.stop_wait_s), half_length + 0.5, vehicle_limits);
      m.cruise_mps = cruise;
      return true;
    });
    if (!placed) continue;
    const Placed& p = actors.back();
    cruise_speeds.push_back(p.motion.cruise_mps);
    (cls == "car" ? row.cars : cls == "van" ? row.vans : cls == "truck" ? row.trucks : row.buses)++;
    row.vehicles_stopping += p.motion.stops ? 1 : 0;
    row.vehicles_turning += kind == "left" || kind == "right" || kind.rfind("exit_", 0) == 0 ? 1 : 0;
    row.lane_changes += kind == "lane_change" || kind == "ramp" ? 1 : 0;
  }
  if (layout.urban) {
    const double cyclist_density = draw(rng, config.cyclists_per_100m);
    const int cyclists = static_cast<int>(std::lround(cyclist_density * layout.lane_length_m / 100.0));
    for (int k = 0; k < cyclists && !layout.bike_routes.empty(); ++k) {
      const bool placed = try_place("cyclist", "cyclist", "ride", [&](Motion& m) {
        const gen::Route& route = layout.bike_routes[static_cast<std::size_t>(
            gen::uniform_int(rng, 0, static_cast<int>(layout.bike_routes.size()) - 1))];
        const double cruise = draw(rng, config.cyclist_speed_mps);
        const double len = route_length(route);
        const double s0 = gen::uniform(rng, 0.0, std::max(0.0, len - cruise * duration - 10.0));
        m = drive(route, s0, cruise, 0.0, chance(rng, config.stop_probability), draw(rng, config.stop_wait_s), 1.4,
                  Limits{2.0, 1.0, 2.0});
        return true;
      });
      if (placed) {
        ++row.cyclists;
        cruise_speeds.push_back(actors.back().motion.cruise_mps);
      }
    }
    const double pedestrian_density = draw(rng, config.pedestrians_per_100m);
    const int pedestrians = static_cast<int>(std::lround(pedestrian_density * layout.sidewalk_length_m / 100.0));
    for (int k = 0; k < pedestrians; ++k) {
      const std::string behaviour = config.pedestrian_behaviour.names[pick(rng, config.pedestrian_behaviour)];
      const std::string role = chance(rng, 0.3) ? "walker_skinned" : "pedestrian";
      const bool placed = try_place("pedestrian", role, behaviour, [&](Motion& m) {
        const double speed = draw(rng, config.pedestrian_speed_mps);
        if ((behaviour == "cross" || behaviour == "wait") && !layout.crossings.empty()) {
          const gen::Crossing& c = layout.crossings[static_cast<std::size_t>(
              gen::uniform_int(rng, 0, static_cast<int>(layout.crossings.size()) - 1))];
          const Vec2 along = (c.to - c.from).normalized();
          const Vec2 side(-along.y(), along.x());
          const Vec2 from = c.from + side * gen::uniform(rng, -1.0, 1.0);
          const double start = behaviour == "cross" ? gen::uniform(rng, 0.0, 0.5 * duration) : gen::uniform(rng, 1.0, 0.8 * duration);
          m = walk(from, from + (c.to - c.from), speed, start);
          return true;
        }
        if (layout.walkways.empty()) return false;
        const gen::Walkway& w = layout.walkways[static_cast<std::size_t>(
            gen::uniform_int(rng, 0, static_cast<int>(layout.walkways.size()) - 1))];
        const double len = (w.b - w.a).norm();
        const double t0 = gen::uniform(rng, 0.0, 1.0);
        const Vec2 start = w.a + t0 * (w.b - w.a);
        const bool forward = chance(rng, 0.5);
        const Vec2 u = (forward ? Vec2(w.b - w.a) : Vec2(w.a - w.b)) / len;
        if (behaviour == "stand" || behaviour == "wait") {
          m = stand(start, gen::uniform(rng, -M_PI, M_PI));
          return true;
        }
        const double room = forward ? (1.0 - t0) * len : t0 * len;
        const double go = std::min(room, speed * duration + 2.0);
        if (go < 3.0) return false;
        m = walk(start, start + u * go, speed, 0.0);
        return true;
      });
      if (!placed) continue;
      ++row.pedestrians;
      const Placed& p = actors.back();
      if (p.motion.is_static) {
        ++row.pedestrians_standing;
      } else {
        cruise_speeds.push_back(p.motion.cruise_mps);
        if (behaviour == "cross") ++row.pedestrians_crossing;
        if (behaviour == "wait") ++row.pedestrians_waiting;
      }
    }
  }
  if (!cruise_speeds.empty()) {
    row.min_speed_mps = *std::min_element(cruise_speeds.begin(), cruise_speeds.end());
    row.max_speed_mps = *std::max_element(cruise_speeds.begin(), cruise_speeds.end());
    double sum = 0.0;
    for (double v : cruise_speeds) sum += v;
    row.mean_speed_mps = sum / static_cast<double>(cruise_speeds.size());
  }
  row.actors_per_100m = 100.0 * static_cast<double>(cruise_speeds.size()) / layout.lane_length_m;

  // The clearance of the finished scenario, measured again from scratch over every pair.
  {
    std::vector<Footprint> moving, fixed;
    Footprint e;
    e.what = "ego";
    e.box = Eigen::AlignedBox2d(Eigen::Vector2d(-0.5 * kEgoLength_m, -0.5 * kEgoWidth_m),
                                Eigen::Vector2d(0.5 * kEgoLength_m, 0.5 * kEgoWidth_m));
    e.motion = ego.make();
    moving.push_back(e);
    for (std::size_t k = 0; k < actors.size(); ++k) {
      Footprint f;
      f.what = "actor " + std::to_string(k + 1);
      f.box = assets.get(actors[k].role).footprint;
      f.motion = actors[k].trajectory;
      moving.push_back(f);
    }
    for (std::size_t k = 0; k < statics.size(); ++k) {
      Footprint f;
      f.what = "static " + std::to_string(k);
      f.box = assets.get(statics[k].first).footprint;
      f.T_world_body = stand(statics[k].second.p, statics[k].second.yaw_rad).make()->state(0.0).T_world_body;
      fixed.push_back(f);
    }
    const ClearanceResult r = check_clearance(moving, fixed, times);
    row.min_clearance_m = r.min_clearance_m;
    row.clearance_ok = r.ok(config.clearance_m);
  }

  // The scenario file.
  std::ostringstream y;
  y << "# Generated by `fmcw generate` (set seed " << seed << ", scenario " << index << "): a " << layout.name
    << " with " << layout.lanes_per_direction << " lane(s) per direction.\n"
    << "# Regenerate rather than edit: the set's manifest describes it, and its clearance was checked.\n";
  y << "name: " << row.name << "\nframes: " << config.frames << "\nrate_hz: " << num(config.rate_hz, 6)
    << "\nseed: " << scenario_seed << "\nrig: " << rig << "\n";
  y << "measurement: {model: " << config.measurement_model << ", range_sigma_m: " << num(row.range_sigma_m, 4)
    << ", velocity_sigma_mps: " << num(row.velocity_sigma_mps, 4) << "}\n";
  y << "materials: " << config.materials << "\nclasses: " << config.classes << "\n";
  y << "ground: {z_m: -0.02, half_size_m: " << num(layout.extent_m + 60.0, 0) << ", reflectivity: 0.12, class: road}\n";
  y << "ego:\n  trajectory: " << trajectory_text(ego) << "\n";
  y << "static:\n";
  if (statics.empty()) y << "  []\n";
  for (const auto& [role, pose] : statics) {
    y << "  - {mesh: " << assets.get(role).path << ", pose: " << pose_text(pose.p, pose.yaw_rad) << "}\n";
  }
  y << "actors:\n";
  if (actors.empty()) y << "  []\n";
  for (std::size_t k = 0; k < actors.size(); ++k) {
    const Placed& a = actors[k];
    y << "  - {id: " << (k + 1) << ", class: " << a.class_name << ", mesh: " << assets.get(a.role).path;
    if (a.role == "walker_skinned") {
      y << ", animation: {clock: distance, offset_s: " << num(gen::uniform(rng, 0.0, 1.0), 2) << "}";
    }
    y << ",\n     trajectory: " << trajectory_text(a.motion) << "}\n";
  }
  out.yaml = y.str();
  return out;
}

std::vector<SetEntry> read_set_manifest(const std::string& path) {
  std::ifstream in(path);
  FMCW_CHECK_FILE(in.good() && io::is_existing_file(path), path, ": no manifest here (a set folder written by fmcw generate holds one)");
  const auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
  };
  std::string line;
  FMCW_CHECK_FILE(static_cast<bool>(std::getline(in, line)), path, ": empty, expected a header line");
  const std::vector<std::string> header = split(line);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    FMCW_CHECK_FILE(it != header.end(), path, ":1: no column '", name, "'");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t name_col = column("name"), file_col = column("file");
  std::vector<SetEntry> out;
  std::set<std::string> seen;
  for (int line_no = 2; std::getline(in, line); ++line_no) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line);
    FMCW_CHECK_FILE(cells.size() == header.size(), path, ":", line_no, ": ", cells.size(), " columns, expected ",
                    header.size());
    SetEntry e{cells[name_col], cells[file_col]};
    const bool safe_name = !e.name.empty() && e.name.size() <= 128 && e.name != "." && e.name != ".." &&
                           std::all_of(e.name.begin(), e.name.end(), [](char c) {
                             return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
                           });
    FMCW_CHECK_FILE(safe_name, path, ":", line_no, ": name must be 1 to 128 letters, digits, '_', '-' or '.'");
    const fs::path f(e.file);
    bool inside = !e.file.empty() && f.is_relative();
    for (const auto& part : f) inside = inside && part != "..";
    FMCW_CHECK_FILE(inside, path, ":", line_no, ": file '", e.file, "' must be a path inside the set folder");
    FMCW_CHECK_FILE(seen.insert(e.name).second, path, ":", line_no, ": name '", e.name, "' repeats an earlier row");
    out.push_back(e);
  }
  FMCW_CHECK_FILE(!out.empty(), path, ": no scenario rows");
  return out;
}

std::string manifest_header() {
  return "name,file,layout,seed,frames,rate_hz,rig,range_sigma_m,velocity_sigma_mps,lanes_per_direction,lane_length_m,"
         "sidewalk_length_m,ego_route,ego_stops,ego_max_speed_mps,cars,vans,trucks,buses,cyclists,pedestrians,parked,"
         "static_objects,barriers,vehicles_stopping,vehicles_turning,lane_changes,pedestrians_crossing,pedestrians_waiting,pedestrians_standing,"
         "min_speed_mps,max_speed_mps,mean_speed_mps,actors_per_100m,rejected_candidates,min_clearance_m,clearance_ok";
}

std::string manifest_line(const ManifestRow& r) {
  std::ostringstream o;
  o << r.name << ',' << r.file << ',' << r.layout << ',' << r.seed << ',' << r.frames << ',' << num(r.rate_hz, 6) << ','
    << r.rig << ',' << num(r.range_sigma_m, 4) << ',' << num(r.velocity_sigma_mps, 4) << ',' << r.lanes_per_direction
    << ',' << num(r.lane_length_m, 1) << ',' << num(r.sidewalk_length_m, 1) << ',' << r.ego_route << ','
    << (r.ego_stops ? "true" : "false") << ',' << num(r.ego_max_speed_mps, 2) << ',' << r.cars << ',' << r.vans << ','
    << r.trucks << ',' << r.buses << ',' << r.cyclists << ',' << r.pedestrians << ',' << r.parked << ','
    << r.static_objects << ',' << r.barriers << ',' << r.vehicles_stopping << ',' << r.vehicles_turning << ',' << r.lane_changes << ','
    << r.pedestrians_crossing << ',' << r.pedestrians_waiting
    << ',' << r.pedestrians_standing << ',' << num(r.min_speed_mps, 2) << ',' << num(r.max_speed_mps, 2) << ','
    << num(r.mean_speed_mps, 2) << ',' << num(r.actors_per_100m, 3) << ',' << r.rejected_candidates << ','
    << num(r.min_clearance_m, 3) << ',' << (r.clearance_ok ? "true" : "false");
  return o.str();
}

}  // namespace fmcw::sim
