#pragma once
// Writes a small sequence in the AevaScenes layout from analytic scans (core/synthetic_scan.hpp):
// sequence.json and pointcloud_compensated/<lidar>_<stamp_ns>.npz per lidar and frame, written
// by the project's own .npz writer (io/npz.hpp, libzip). The truth it was made from is returned.

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "fmcw/core/ego_motion.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/npz.hpp"

namespace fmcw::test {

struct AevaScenesFixture {
  std::vector<core::Frame> frames;  ///< what was written, raw Doppler, with truth
  Eigen::Vector3d ego_velocity_mps{10.0, 0.0, 0.0};
  Eigen::Vector3d car_velocity_mps{-5.0, 0.0, 0.0};  ///< absolute, oncoming
  Eigen::Vector3d car_half_extent_m{2.2, 0.9, 0.75};
  std::vector<std::string> lidars{"front_wide_lidar", "left_lidar"};
};

// Two 130 x 10 deg heads (650 x 20 pixels each), front and left, on the roof.
inline core::RigModel aevascenes_test_rig() {
  core::RigModel rig;
  const auto head = [](const char* name, double x, double y, double yaw_deg) {
    core::HeadModel h;
    h.name = name;
    // The reader's default grid for a wide lidar: 130 deg at 0.2 deg.
    h.fov_horizontal_rad = 130.0 * M_PI / 180.0;
    h.resolution_horizontal_rad = 0.2 * M_PI / 180.0;
    h.fov_vertical_rad = 10.0 * M_PI / 180.0;
    h.resolution_vertical_rad = 0.5 * M_PI / 180.0;
    h.T_rig_head = Eigen::Isometry3d::Identity();
    h.T_rig_head.translation() = Eigen::Vector3d(x, y, 1.9);
    h.T_rig_head.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // A little pitch down so that the ground fills the lower rows.
    h.T_rig_head.linear() = h.T_rig_head.linear() * Eigen::AngleAxisd(4.0 * M_PI / 180.0, Eigen::Vector3d::UnitY());
    return h;
  };
  rig.heads = {head("front_wide_lidar", 1.5, 0.0, 0.0), head("left_lidar", 0.7, 0.5, 90.0)};
  return rig;
}

inline std::string json_xyz(const Eigen::Vector3d& v) {
  std::ostringstream o;
  o.precision(17);
  o << "{\"x\": " << v.x() << ", \"y\": " << v.y() << ", \"z\": " << v.z() << "}";
  return o.str();
}

inline std::string json_pose(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  std::ostringstream o;
  o.precision(17);
  o << "{\"translation\": " << json_xyz(T.translation()) << ", \"rotation\": {\"w\": " << q.w() << ", \"x\": " << q.x()
    << ", \"y\": " << q.y() << ", \"z\": " << q.z() << "}}";
  return o.str();
}

/// Writes `count` frames at 10 Hz to dir: the ego drives along x at 10 m/s, an oncoming car
/// (track "car-1") passes on the left, buildings stand on both sides.
inline AevaScenesFixture write_aevascenes_sequence(const std::filesystem::path& dir, int count) {
  AevaScenesFixture fx;
  namespace fs = std::filesystem;
  fs::create_directories(dir / "pointcloud_compensated");
  const core::RigModel rig = aevascenes_test_rig();
  std::ostringstream frames_json;
  for (int k = 0; k < count; ++k) {
    const double t = 0.1 * k;
    core::SyntheticSceneParams p;
    p.rig = rig;
    p.ego_velocity_mps = fx.ego_velocity_mps;
    p.seed = 7 + static_cast<std::uint64_t>(k);
    p.velocity_noise_mps = 0.02;
    core::SyntheticBox car;
    // 10 cm above the ground: the ground's points stay outside its box.
    car.center_m = Eigen::Vector3d(22.0, 3.0, 0.85) + (fx.car_velocity_mps - fx.ego_velocity_mps) * t;
    car.half_extent_m = fx.car_half_extent_m;
    car.velocity_mps = fx.car_velocity_mps;
    p.actors.push_back(car);
    for (const double x : {10.0, 30.0, 50.0}) {
      core::SyntheticBox building;
      building.center_m = Eigen::Vector3d(x, 12.0, 4.0) - fx.ego_velocity_mps * t;
      building.half_extent_m = Eigen::Vector3d(8.0, 3.0, 4.0);
      p.static_boxes.push_back(building);
    }
    core::Frame f = core::render_synthetic_scan(p);
    f.scan.stamp_s = t;
    core::Scan comp = f.scan;
    core::compensate_ego_velocity(comp, {fx.ego_velocity_mps, Eigen::Vector3d::Zero()});
    const long long stamp_ns = 1'700'000'000'000'000'000LL + static_cast<long long>(k) * 100'000'000LL;
    std::ostringstream clouds;
    for (std::size_t h = 0; h < comp.heads.size(); ++h) {
      const core::HeadInfo& head = comp.heads[h];
      std::vector<float> xyz, v, refl;
      std::vector<std::uint32_t> line, t_ns;
      std::vector<std::string> labels;
      std::vector<std::int64_t> label_idx;
      for (int r = 0; r < comp.rows; ++r) {
        for (int c = head.col_begin; c < head.col_end; ++c) {
          const std::size_t i = comp.index(r, c);
          if (!comp.valid[i]) continue;
          const Eigen::Vector3d q = head.T_rig_head.inverse() * comp.position(i);
          xyz.insert(xyz.end(), {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())});
          v.push_back(comp.radial_velocity_mps[i]);
          refl.push_back(100.0f * comp.intensity[i]);
          line.push_back(static_cast<std::uint32_t>(r));
          t_ns.push_back(static_cast<std::uint32_t>(1000 * (c - head.col_begin)));
          labels.push_back(f.truth->instance[i] ? "car" : "road");
          label_idx.push_back(f.truth->instance[i] ? 1 : 19);
        }
      }
      const std::size_t n = v.size();
      const std::string rel = "pointcloud_compensated/" + fx.lidars[h] + "_" + std::to_string(stamp_ns) + ".npz";
      io::write_npz((dir / rel).string(), {{"xyz", io::npy_f32(xyz, {n, 3})},
                                           {"velocity", io::npy_f32(v, {n, 1})},
                                           {"reflectivity", io::npy_f32(refl, {n, 1})},
                                           {"line_index", io::npy_u32(line, {n, 1})},
                                           {"time_offset_ns", io::npy_u32(t_ns, {n, 1})},
                                           {"semantic_labels", io::npy_strings(labels, {n, 1})},
                                           {"semantic_labels_idx", io::npy_i64(label_idx, {n, 1})}});
      clouds << (h ? ", " : "") << "\"" << fx.lidars[h] << "\": {\"point_cloud_path\": \"" << rel << "\"}";
    }
    Eigen::Isometry3d ego = Eigen::Isometry3d::Identity();
    ego.translation() = fx.ego_velocity_mps * t;
    Eigen::Isometry3d box = Eigen::Isometry3d::Identity();
    box.translation() = car.center_m;
    frames_json << (k ? ",\n" : "") << "{\"timestamp_ns\": " << stamp_ns << ", \"frame_idx\": " << k
                << ", \"ego_pose\": " << json_pose(ego) << ", \"point_cloud\": {" << clouds.str() << "}, \"boxes\": [{"
                << "\"id\": \"car-1\", \"reference_frame\": \"VEHICLE\", \"class\": \"car\", \"class_idx\": 1, "
                << "\"dimensions\": " << json_xyz(2.0 * fx.car_half_extent_m) << ", \"pose\": " << json_pose(box)
                << ", \"linear_velocity\": " << json_xyz(fx.car_velocity_mps)
                << ", \"angular_velocity\": " << json_xyz(Eigen::Vector3d::Zero()) << "}]}";
    f.frame_truth = core::FrameTruth{};
    fx.frames.push_back(std::move(f));
  }
  std::ostringstream seq;
  seq << "{\"metadata\": {\"sequence_uuid\": \"00000000-0000-4000-8000-000000000020\", \"sensors\": {\"lidars\": [\""
      << fx.lidars[0] << "\", \"" << fx.lidars[1] << "\"], \"cameras\": []}, \"vehicle_to_lidar_extrinsics\": {\""
      << fx.lidars[0] << "\": " << json_pose(rig.heads[0].T_rig_head) << ", \"" << fx.lidars[1]
      << "\": " << json_pose(rig.heads[1].T_rig_head) << "}},\n\"frames\": [\n" << frames_json.str() << "]}\n";
  const std::string text = seq.str();
  io::write_file_atomically((dir / "sequence.json").string(),
                            [&](std::ostream& o) { o.write(text.data(), static_cast<std::streamsize>(text.size())); });
  return fx;
}

}  // namespace fmcw::test
