#include "fmcw/io/aevascenes.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fmcw/core/check.hpp"
#include "fmcw/core/grid_projection.hpp"
#include "fmcw/io/input_file.hpp"
#include "fmcw/io/npz.hpp"

namespace fmcw::io {

using core::concat;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// JSON access that names the file and the path of what is missing or wrong.
struct JsonAt {
  const json& value;
  std::string where;  // "FILE: frames[3].boxes[0]"

  JsonAt at(const std::string& key) const {
    if (!value.is_object() || !value.contains(key)) throw core::FileError(concat(where, ": missing key '", key, "'"));
    return {value.at(key), where + "." + key};
  }
  JsonAt at(std::size_t k) const { return {value.at(k), concat(where, "[", k, "]")}; }
  bool has(const std::string& key) const { return value.is_object() && value.contains(key); }
  double number() const {
    if (!value.is_number()) throw core::FileError(concat(where, ": expected a number, got ", value.type_name()));
    const double v = value.get<double>();
    if (!std::isfinite(v)) throw core::FileError(concat(where, ": ", v, " is not a finite number"));
    return v;
  }
  std::string text() const {
    if (!value.is_string()) throw core::FileError(concat(where, ": expected a string, got ", value.type_name()));
    return value.get<std::string>();
  }
  std::size_t size(const char* what) const {
    if (!value.is_array()) throw core::FileError(concat(where, ": expected a list of ", what, ", got ", value.type_name()));
    return value.size();
  }
  Eigen::Vector3d xyz() const { return {at("x").number(), at("y").number(), at("z").number()}; }
  // {"translation": {x, y, z}, "rotation": {w, x, y, z}}, a unit quaternion.
  Eigen::Isometry3d pose() const {
    const JsonAt r = at("rotation");
    const Eigen::Quaterniond q(r.at("w").number(), r.at("x").number(), r.at("y").number(), r.at("z").number());
    if (std::abs(q.norm() - 1.0) > core::PoseSeries::kUnitTolerance) {
      throw core::FileError(concat(r.where, ": quaternion of norm ", q.norm(), ", expected a unit quaternion"));
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = at("translation").xyz();
    return T;
  }
};

std::int64_t nanoseconds(const JsonAt& t) {
  if (!t.value.is_number_integer()) throw core::FileError(concat(t.where, ": expected an integer number of nanoseconds"));
  return t.value.get<std::int64_t>();
}

// Seconds after the first frame: a double holds nanoseconds since 1970 only to about 0.2 us,
// too coarse to differentiate poses 0.1 s apart to 1 mm/s.
double stamp_after(const JsonAt& t, std::int64_t first_ns) { return static_cast<double>(nanoseconds(t) - first_ns) * 1e-9; }

AevaScenesBox read_box(const JsonAt& b) {
  AevaScenesBox box;
  box.track = b.at("id").text();
  box.class_name = b.at("class").text();
  box.T_vehicle_box = b.at("pose").pose();
  box.size_m = b.at("dimensions").xyz();
  if ((box.size_m.array() < 0.0).any()) throw core::FileError(concat(b.where, ".dimensions: negative size"));
  if (b.has("linear_velocity")) box.linear_velocity_mps = b.at("linear_velocity").xyz();
  if (b.has("angular_velocity")) box.angular_velocity_rps = b.at("angular_velocity").xyz();
  return box;
}

// The first of the keys a frame's point cloud entry may name its file by.
std::string cloud_path(const JsonAt& entry) {
  for (const char* key : {"point_cloud_compensated_path", "point_cloud_path"}) {
    if (entry.has(key)) return entry.at(key).text();
  }
  throw core::FileError(concat(entry.where, ": neither point_cloud_compensated_path nor point_cloud_path"));
}

// Per-point columns of one lidar's .npz, in its own frame.
struct LidarPoints {
  core::PointList points;
  std::vector<std::string> labels;  // empty when the file has none readable
};

const NpyArray& member(const std::map<std::string, NpyArray>& arrays, const std::string& name, const std::string& file) {
  const auto it = arrays.find(name);
  if (it == arrays.end()) throw core::FileError(concat(file, ": no array '", name, "'"));
  return it->second;
}

// A column of n values: shape (n,) or (n, 1).
std::vector<double> column(const std::map<std::string, NpyArray>& arrays, const std::string& name, std::size_t n,
                           const std::string& file) {
  const NpyArray& a = member(arrays, name, file);
  const bool shaped = (a.shape.size() == 1 && a.shape[0] == n) || (a.shape.size() == 2 && a.shape[0] == n && a.shape[1] == 1);
  if (!shaped) throw core::FileError(concat(file, ": array '", name, "' is not (", n, ",) or (", n, ", 1)"));
  return a.to_doubles(file + ": " + name);
}

LidarPoints read_lidar(const std::string& file, std::vector<std::string>* notes) {
  const std::map<std::string, NpyArray> arrays = read_npz(file);
  const NpyArray& xyz_array = member(arrays, "xyz", file);
  if (xyz_array.shape.size() != 2 || xyz_array.shape[1] != 3) throw core::FileError(concat(file, ": array 'xyz' is not (N, 3)"));
  const std::size_t n = xyz_array.shape[0];
  const std::vector<double> xyz = xyz_array.to_doubles(file + ": xyz");
  const std::vector<double> v = column(arrays, "velocity", n, file);
  const std::vector<double> refl = column(arrays, "reflectivity", n, file);
  const std::vector<double> line = column(arrays, "line_index", n, file);
  const std::vector<double> t_ns = column(arrays, "time_offset_ns", n, file);
  LidarPoints out;
  core::PointList& p = out.points;
  for (std::size_t i = 0; i < n; ++i) {
    for (const double value : {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], v[i], refl[i], t_ns[i]}) {
      if (!std::isfinite(value)) throw core::FileError(concat(file, ": point ", i, " holds a NaN or Inf"));
    }
    if (line[i] < 0 || line[i] > 65535) throw core::FileError(concat(file, ": point ", i, ": line_index ", line[i], " out of range"));
    p.x_m.push_back(static_cast<float>(xyz[3 * i]));
    p.y_m.push_back(static_cast<float>(xyz[3 * i + 1]));
    p.z_m.push_back(static_cast<float>(xyz[3 * i + 2]));
    p.radial_velocity_mps.push_back(static_cast<float>(v[i]));
    p.intensity.push_back(static_cast<float>(std::max(0.0, refl[i])));
    p.time_offset_s.push_back(static_cast<float>(t_ns[i] * 1e-9));
    p.line_index.push_back(static_cast<std::int32_t>(line[i]));
  }
  const auto labels = arrays.find("semantic_labels");
  if (labels != arrays.end() && labels->second.kind == 'U' && labels->second.size() == n) {
    out.labels = labels->second.to_strings(file + ": semantic_labels");
  } else if (notes) {
    notes->push_back("AevaScenes semantic_labels " +
                     (labels == arrays.end() ? std::string("missing")
                                             : labels->second.kind == 'O' ? "are pickled Python strings" : "unreadable") +
                     ": semantic classes left 0 (unlabelled)");
  }
  return out;
}

}  // namespace

AevaScenesSequence read_aevascenes_sequence(const std::string& dir) {
  const std::string file = (fs::path(dir) / "sequence.json").string();
  regular_file_size(file, "AevaScenes sequence.json");
  std::ifstream in(file, std::ios::binary);
  json root;
  try {
    root = json::parse(in);
  } catch (const json::exception& e) {
    throw core::FileError(concat(file, ": not valid JSON: ", e.what()));
  }
  AevaScenesSequence s;
  s.dir = dir;
  try {
    const JsonAt top{root, file};
    const JsonAt meta = top.at("metadata");
    s.uuid = meta.has("sequence_uuid") ? meta.at("sequence_uuid").text() : fs::path(dir).filename().string();
    const JsonAt lidars = meta.at("sensors").at("lidars");
    for (std::size_t k = 0; k < lidars.size("lidar ids"); ++k) {
      s.lidars.push_back(lidars.at(k).text());
      s.T_vehicle_lidar.push_back(meta.at("vehicle_to_lidar_extrinsics").at(s.lidars.back()).pose());
    }
    if (s.lidars.empty()) throw core::FileError(concat(lidars.where, ": no lidars"));
    const JsonAt frames = top.at("frames");
    if (frames.size("frames") == 0) throw core::FileError(concat(frames.where, ": no frames"));
    const std::int64_t first_ns = nanoseconds(frames.at(0).at("timestamp_ns"));
    std::map<std::string, std::size_t> tracks;
    for (std::size_t k = 0; k < frames.size("frames"); ++k) {
      const JsonAt f = frames.at(k);
      AevaScenesFrame frame;
      frame.stamp_s = stamp_after(f.at("timestamp_ns"), first_ns);
      frame.T_world_vehicle = f.at("ego_pose").pose();
      for (const std::string& lidar : s.lidars) {
        frame.files.push_back((fs::path(dir) / cloud_path(f.at("point_cloud").at(lidar))).string());
      }
      const JsonAt boxes = f.at("boxes");
      for (std::size_t b = 0; b < boxes.size("boxes"); ++b) {
        frame.boxes.push_back(read_box(boxes.at(b)));
        if (tracks.emplace(frame.boxes.back().track, s.track_ids.size()).second) s.track_ids.push_back(frame.boxes.back().track);
      }
      s.poses.stamp_s.push_back(frame.stamp_s);
      s.poses.position_m.push_back(frame.T_world_vehicle.translation());
      s.poses.orientation.emplace_back(frame.T_world_vehicle.linear());
      s.frames.push_back(std::move(frame));
    }
    if (s.frames.empty()) throw core::FileError(concat(frames.where, ": no frames"));
    if (s.frames.size() >= 2) s.poses.validate();
  } catch (const json::exception& e) {
    throw core::FileError(concat(file, ": ", e.what()));
  } catch (const core::InputError&) {
    core::rethrow_as_file_error(file + ": frames' ego_pose: ");
  }
  return s;
}

namespace {

// The box holding p (vehicle frame), with 2 cm to spare for points on its faces; -1 if none.
int box_of(const std::vector<AevaScenesBox>& boxes, const Eigen::Vector3d& p) {
  constexpr double kMargin = 0.02;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const Eigen::Vector3d q = boxes[b].T_vehicle_box.inverse() * p;
    if ((q.cwiseAbs().array() <= 0.5 * boxes[b].size_m.array() + kMargin).all()) return static_cast<int>(b);
  }
  return -1;
}

// Per-pixel truth of the assembled scan: instance, rigid velocity, its radial component (in the
// scan's frame, ego-compensated: e . V_point), semantic class.
void pixel_truth(const AevaScenesSequence& seq, const AevaScenesFrame& frame, const AevaScenesOptions& grid,
                 const std::vector<std::uint16_t>& classes, core::Frame& out) {
  const core::Scan& scan = out.scan;
  core::PixelGroundTruth gt = core::PixelGroundTruth::make_empty(scan.size());
  std::map<std::string, std::uint32_t> instance_of;
  for (std::size_t t = 0; t < seq.track_ids.size(); ++t) instance_of[seq.track_ids[t]] = static_cast<std::uint32_t>(t + 1);
  for (const core::HeadInfo& head : scan.heads) {
    for (int r = 0; r < scan.rows; ++r) {
      for (int c = head.col_begin; c < head.col_end; ++c) {
        const std::size_t i = scan.index(r, c);
        if (!scan.valid[i]) continue;
        const Eigen::Vector3d p = scan.position(i);
        Eigen::Vector3d v = Eigen::Vector3d::Zero();
        const int b = box_of(frame.boxes, p);
        if (b >= 0) {
          const AevaScenesBox& box = frame.boxes[static_cast<std::size_t>(b)];
          v = box.linear_velocity_mps + box.angular_velocity_rps.cross(p - box.T_vehicle_box.translation());
          gt.instance[i] = instance_of.at(box.track);
        }
        gt.moving[i] = v.norm() > grid.moving_threshold_mps ? 1 : 0;
        gt.vx_mps[i] = static_cast<float>(v.x());
        gt.vy_mps[i] = static_cast<float>(v.y());
        gt.vz_mps[i] = static_cast<float>(v.z());
        gt.range_m[i] = scan.range_m[i];  // no noise-free range in the data: the measured one
        gt.radial_velocity_mps[i] = static_cast<float>((p - head.origin_m()).normalized().dot(v));
        gt.semantic_class[i] = classes[i];
      }
    }
  }
  out.truth = std::move(gt);
}

core::FrameTruth frame_truth(const AevaScenesSequence& seq, const AevaScenesFrame& frame, const core::Frame& f) {
  core::FrameTruth truth;
  truth.stamp_s = frame.stamp_s;
  truth.ego.T_world_rig = frame.T_world_vehicle;
  const core::EgoMotion ego = seq.poses.size() >= 2 ? seq.poses.ego_motion_at(frame.stamp_s)
                                                    : core::EgoMotion{Eigen::Vector3d::Constant(NAN), Eigen::Vector3d::Constant(NAN)};
  truth.ego.velocity_mps = ego.velocity_mps;
  truth.ego.angular_velocity_rps = ego.angular_velocity_rps;
  std::map<std::uint32_t, int> pixels;
  for (const std::uint32_t id : f.truth->instance) ++pixels[id];
  for (const AevaScenesBox& box : frame.boxes) {
    core::ActorTruth a;
    a.id = static_cast<std::uint32_t>(std::find(seq.track_ids.begin(), seq.track_ids.end(), box.track) - seq.track_ids.begin() + 1);
    a.class_name = box.class_name;
    a.T_world_actor = frame.T_world_vehicle * box.T_vehicle_box;
    a.position_rig_m = box.T_vehicle_box.translation();
    a.velocity_rig_mps = box.linear_velocity_mps;
    a.angular_velocity_rig_rps = box.angular_velocity_rps;
    a.pixels = pixels.count(a.id) ? pixels[a.id] : 0;
    const Eigen::Vector3d heading = box.T_vehicle_box.linear().col(0);
    const Eigen::Vector3d heading_world = a.T_world_actor.linear().col(0);
    a.box.center_m = a.position_rig_m;
    a.box.size_m = box.size_m;
    a.box.yaw_rad = std::atan2(heading.y(), heading.x());
    a.box.velocity_mps = box.linear_velocity_mps;
    a.box.center_world_m = a.T_world_actor.translation();
    a.box.yaw_world_rad = std::atan2(heading_world.y(), heading_world.x());
    truth.actors.push_back(a);
  }
  return truth;
}

}  // namespace

core::Frame read_aevascenes_frame(const AevaScenesSequence& seq, std::size_t k, const AevaScenesOptions& grid,
                                  const core::ClassTable& classes, std::vector<std::string>* notes) {
  FMCW_CHECK_ARG(k < seq.frames.size(), "AevaScenes: frame ", k, " of a sequence of ", seq.frames.size());
  FMCW_CHECK_ARG(grid.resolution_deg > 0.0 && grid.wide_fov_deg > 0.0 && grid.narrow_fov_deg > 0.0 && grid.lines >= 0,
                 "AevaScenes grid: fields of view and resolution must be > 0, lines >= 0");
  const AevaScenesFrame& frame = seq.frames[k];
  std::vector<LidarPoints> lidars;
  int lines = grid.lines;
  for (const std::string& file : frame.files) {
    lidars.push_back(read_lidar(file, notes));
    for (const std::int32_t l : lidars.back().points.line_index) {
      if (grid.lines > 0 && l >= grid.lines) throw core::FileError(concat(file, ": line_index ", l, " >= ", grid.lines, " lines"));
      if (grid.lines == 0) lines = std::max(lines, l + 1);
    }
  }
  std::vector<core::GridProjection> heads;
  int cols = 0;
  for (std::size_t h = 0; h < lidars.size(); ++h) {
    core::GridProjectionParams p;
    p.fov_horizontal_deg = seq.lidars[h].find("narrow") != std::string::npos ? grid.narrow_fov_deg : grid.wide_fov_deg;
    p.resolution_horizontal_deg = grid.resolution_deg;
    p.lines = std::max(lines, 1);
    try {
      heads.push_back(core::project_to_grid(lidars[h].points, p));
    } catch (const core::InputError&) {
      core::rethrow_as_file_error(frame.files[h] + ": ");
    }
    cols += heads.back().scan.cols;
  }
  core::Frame out;
  core::Scan& scan = out.scan;
  scan = core::Scan::make_empty(std::max(lines, 1), cols);
  scan.heads.clear();
  scan.stamp_s = frame.stamp_s;
  scan.velocity_frame = core::VelocityFrame::kEgoCompensated;  // the files' convention
  scan.time_offset_s.assign(scan.size(), 0.0f);
  scan.line_index.assign(scan.size(), 0);
  std::vector<std::uint16_t> pixel_class(scan.size(), 0);
  std::set<std::string> unknown;  // labels said once each
  int col0 = 0;
  for (std::size_t h = 0; h < heads.size(); ++h) {
    const core::Scan& part = heads[h].scan;
    core::HeadInfo info;
    info.name = seq.lidars[h];
    info.T_rig_head = seq.T_vehicle_lidar[h];
    info.col_begin = col0;
    info.col_end = col0 + part.cols;
    scan.heads.push_back(info);
    for (int r = 0; r < part.rows; ++r) {
      for (int c = 0; c < part.cols; ++c) {
        const std::size_t j = part.index(r, c);
        const std::size_t i = scan.index(r, col0 + c);
        scan.line_index[i] = static_cast<std::uint16_t>(r);
        if (!part.valid[j]) continue;
        const Eigen::Vector3d p = info.T_rig_head * part.position(j);
        scan.x_m[i] = static_cast<float>(p.x());
        scan.y_m[i] = static_cast<float>(p.y());
        scan.z_m[i] = static_cast<float>(p.z());
        scan.range_m[i] = part.range_m[j];
        scan.radial_velocity_mps[i] = part.radial_velocity_mps[j];
        scan.intensity[i] = part.intensity[j];
        if (!part.time_offset_s.empty()) scan.time_offset_s[i] = part.time_offset_s[j];
        scan.valid[i] = 1;
        const std::int64_t point = heads[h].point_of_pixel[j];
        if (!lidars[h].labels.empty() && point >= 0) {
          const std::string& name = lidars[h].labels[static_cast<std::size_t>(point)];
          const std::optional<std::uint16_t> id = classes.find(name);
          pixel_class[i] = id.value_or(0);
          if (!id && notes && unknown.insert(name).second) {
            notes->push_back("AevaScenes semantic label '" + name + "' is not in the class table: class 0");
          }
        }
      }
    }
    col0 += part.cols;
  }
  pixel_truth(seq, frame, grid, pixel_class, out);
  out.frame_truth = frame_truth(seq, frame, out);
  if (grid.to_sensor_frame) {
    FMCW_CHECK_FILE(seq.poses.size() >= 2, seq.dir, ": one frame: no ego motion to undo the compensation with");
    const core::EgoMotion ego{out.frame_truth->ego.velocity_mps, out.frame_truth->ego.angular_velocity_rps};
    core::uncompensate_ego_velocity(out, ego);  // the truth's radial velocity too
  }
  return out;
}

}  // namespace fmcw::io
