#include "fmcw/core/head_model.hpp"

#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::core {

namespace {
int pixel_count(double fov_rad, double resolution_rad) {
  return static_cast<int>(std::lround(fov_rad / resolution_rad));
}

double yaw_of(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d forward = T.linear().col(0);
  return std::atan2(forward.y(), forward.x());
}

double wrap_angle(double a) { return std::remainder(a, 2.0 * M_PI); }
}  // namespace

void HeadModel::validate() const {
  const auto deg = [](double rad) { return rad * 180.0 / M_PI; };
  FMCW_CHECK_ARG(fov_horizontal_rad > 0.0 && fov_horizontal_rad <= 2.0 * M_PI, "head '", name,
                 "': horizontal field of view must be in (0, 360] deg, got ", deg(fov_horizontal_rad));
  FMCW_CHECK_ARG(fov_vertical_rad > 0.0 && fov_vertical_rad < M_PI, "head '", name,
                 "': vertical field of view must be in (0, 180) deg, got ", deg(fov_vertical_rad));
  FMCW_CHECK_ARG(resolution_horizontal_rad > 0.0 && resolution_vertical_rad > 0.0, "head '", name,
                 "': angular resolution must be > 0 deg, got ", deg(resolution_horizontal_rad), " x ",
                 deg(resolution_vertical_rad));
  const double pixels = (fov_horizontal_rad / resolution_horizontal_rad) * (fov_vertical_rad / resolution_vertical_rad);
  FMCW_CHECK_LIMIT(pixels <= static_cast<double>(kMaxPixels), "head '", name, "': field of view ", deg(fov_horizontal_rad), " x ",
                   deg(fov_vertical_rad), " deg at resolution ", deg(resolution_horizontal_rad), " x ",
                   deg(resolution_vertical_rad), " deg gives ", pixels, " pixels, more than the ", kMaxPixels,
                   " a head may have");
  FMCW_CHECK_ARG(cols() >= 1 && rows() >= 1, "head '", name, "': field of view ",
                 deg(fov_horizontal_rad), " x ", deg(fov_vertical_rad), " deg at resolution ",
                 deg(resolution_horizontal_rad), " x ", deg(resolution_vertical_rad),
                 " deg gives no pixels");
  FMCW_CHECK_ARG(max_range_m > 0.0 && std::isfinite(max_range_m), "head '", name,
                 "': max range must be > 0 m, got ", max_range_m);
  FMCW_CHECK_ARG(rate_hz > 0.0 && std::isfinite(rate_hz), "head '", name,
                 "': rate must be > 0 Hz, got ", rate_hz);
}

int HeadModel::cols() const { return pixel_count(fov_horizontal_rad, resolution_horizontal_rad); }
int HeadModel::rows() const { return pixel_count(fov_vertical_rad, resolution_vertical_rad); }

double HeadModel::azimuth_rad(int col) const {
  return 0.5 * fov_horizontal_rad - (col + 0.5) * resolution_horizontal_rad;
}
double HeadModel::elevation_rad(int row) const {
  return 0.5 * fov_vertical_rad - (row + 0.5) * resolution_vertical_rad;
}

Eigen::Vector3d HeadModel::direction_head(int row, int col) const {
  const double az = azimuth_rad(col);
  const double el = elevation_rad(row);
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

void RigModel::validate() const {
  FMCW_CHECK_ARG(!heads.empty(), "rig: no heads");
  for (const auto& head : heads) head.validate();
  for (const auto& head : heads) {
    FMCW_CHECK_ARG(head.rows() == heads.front().rows(), "rig: head '", head.name, "' has ",
                   head.rows(), " rows but head '", heads.front().name, "' has ",
                   heads.front().rows(), "; heads side by side in one image need equal rows");
  }
}

int RigModel::rows() const { return heads.empty() ? 0 : heads.front().rows(); }

int RigModel::cols() const {
  int cols = 0;
  for (const auto& head : heads) cols += head.cols();
  return cols;
}

std::vector<HeadInfo> RigModel::head_infos() const {
  std::vector<HeadInfo> infos;
  int col = 0;
  for (std::size_t h = 0; h < heads.size(); ++h) {
    const HeadModel& head = heads[h];
    HeadInfo info;
    info.name = head.name;
    info.T_rig_head = head.T_rig_head;
    info.col_begin = col;
    info.col_end = col + head.cols();
    col = info.col_end;
    if (h + 1 < heads.size()) {
      const HeadModel& next = heads[h + 1];
      // Right edge of this head and left edge of the next, as rig azimuths.
      const double right_edge = yaw_of(head.T_rig_head) - 0.5 * head.fov_horizontal_rad;
      const double left_edge = yaw_of(next.T_rig_head) + 0.5 * next.fov_horizontal_rad;
      const double tolerance = 0.5 * std::min(head.resolution_horizontal_rad, next.resolution_horizontal_rad);
      info.stitched_to_next = std::abs(wrap_angle(right_edge - left_edge)) <= tolerance &&
                              head.rows() == next.rows() &&
                              std::abs(head.fov_vertical_rad - next.fov_vertical_rad) <= tolerance;
    }
    infos.push_back(info);
  }
  return infos;
}

std::vector<Eigen::Vector3f> RigModel::directions_rig() const {
  const int n_rows = rows();
  const int n_cols = cols();
  std::vector<Eigen::Vector3f> dirs(static_cast<std::size_t>(n_rows) * static_cast<std::size_t>(n_cols));
  int col0 = 0;
  for (const auto& head : heads) {
    const Eigen::Matrix3d R = head.T_rig_head.linear();
    for (int r = 0; r < n_rows; ++r) {
      for (int c = 0; c < head.cols(); ++c) {
        dirs[static_cast<std::size_t>(r) * n_cols + col0 + c] = (R * head.direction_head(r, c)).cast<float>();
      }
    }
    col0 += head.cols();
  }
  return dirs;
}

RigModel RigModel::paper_rig() {
  RigModel rig;
  const double yaw_deg[3] = {40.0, 0.0, -40.0};
  const char* names[3] = {"left", "front", "right"};
  // Roof mounts, rig origin on the ground under the rear axle [m].
  const Eigen::Vector3d mounts[3] = {{1.2, 0.45, 1.6}, {1.4, 0.0, 1.6}, {1.2, -0.45, 1.6}};
  for (int h = 0; h < 3; ++h) {
    HeadModel head;
    head.name = names[h];
    head.T_rig_head = Eigen::Isometry3d::Identity();
    head.T_rig_head.linear() = Eigen::AngleAxisd(yaw_deg[h] * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    head.T_rig_head.translation() = mounts[h];
    rig.heads.push_back(head);
  }
  return rig;
}

}  // namespace fmcw::core
