#include "fmcw/io/truth_tables.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::io {

const char* const kEgoCsvHeader =
    "frame,time_s,x_m,y_m,z_m,qw,qx,qy,qz,vx_mps,vy_mps,vz_mps,wx_rps,wy_rps,wz_rps\n";
const char* const kObjectsCsvHeader =
    "frame,time_s,id,class,x_m,y_m,z_m,qw,qx,qy,qz,rig_x_m,rig_y_m,rig_z_m,vx_mps,vy_mps,vz_mps,wx_rps,wy_rps,wz_rps,"
    "pixels,box_x_m,box_y_m,box_z_m,box_length_m,box_width_m,box_height_m,box_yaw_rad,box_vx_mps,box_vy_mps,box_vz_mps,"
    "visible_fraction,truncated,box_world_x_m,box_world_y_m,box_world_z_m,box_world_yaw_rad\n";

namespace {
// objects.csv as datasets wrote it before boxes: still read (boxes left empty).
const char* const kObjectsCsvHeaderWithoutBoxes =
    "frame,time_s,id,class,x_m,y_m,z_m,qw,qx,qy,qz,rig_x_m,rig_y_m,rig_z_m,vx_mps,vy_mps,vz_mps,wx_rps,wy_rps,wz_rps,"
    "pixels\n";
}  // namespace

namespace {
void put(std::ostringstream& out, const Eigen::Vector3d& v) { out << ',' << v.x() << ',' << v.y() << ',' << v.z(); }
void put_pose(std::ostringstream& out, const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  put(out, T.translation());
  out << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
  return cells;
}

double number(const std::string& cell, const std::string& file, int line) {
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (cell.empty() || *end != '\0') {
    throw core::FileError(file + ":" + std::to_string(line) + ": expected a number, got '" + cell + "'");
  }
  return v;
}

Eigen::Isometry3d pose(const std::vector<std::string>& c, std::size_t at, const std::string& file, int line) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(number(c[at], file, line), number(c[at + 1], file, line), number(c[at + 2], file, line));
  const Eigen::Quaterniond q(number(c[at + 3], file, line), number(c[at + 4], file, line), number(c[at + 5], file, line),
                             number(c[at + 6], file, line));
  T.linear() = q.normalized().toRotationMatrix();
  return T;
}

Eigen::Vector3d vec(const std::vector<std::string>& c, std::size_t at, const std::string& file, int line) {
  return {number(c[at], file, line), number(c[at + 1], file, line), number(c[at + 2], file, line)};
}

// The rows of a table with one of the given headers; fn(cells, line, which header).
template <typename RowFn>
void read_rows(const std::string& file, std::initializer_list<const char*> headers, RowFn fn) {
  std::ifstream in(file);
  if (!in) throw core::FileError(file + ": cannot open");
  std::string line;
  std::getline(in, line);
  const char* header = nullptr;
  std::size_t which = 0;
  for (const char* h : headers) {
    if (line + "\n" == h) header = h;
    if (!header) ++which;
  }
  if (!header) throw core::FileError(file + ":1: unexpected header '" + line + "'");
  const std::size_t columns = split(std::string(header).substr(0, std::string(header).size() - 1)).size();
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    const auto cells = split(line);
    if (cells.size() != columns) {
      throw core::FileError(file + ":" + std::to_string(line_no) + ": " + std::to_string(cells.size()) +
                            " columns, expected " + std::to_string(columns));
    }
    fn(cells, line_no, which);
  }
}
}  // namespace

std::string ego_csv_row(std::size_t frame, const core::FrameTruth& truth) {
  std::ostringstream out;
  out << std::setprecision(10) << frame << ',' << truth.stamp_s;
  put_pose(out, truth.ego.T_world_rig);
  put(out, truth.ego.velocity_mps);
  put(out, truth.ego.angular_velocity_rps);
  out << '\n';
  return out.str();
}

std::string objects_csv_rows(std::size_t frame, const core::FrameTruth& truth) {
  std::ostringstream out;
  out << std::setprecision(10);
  for (const auto& a : truth.actors) {
    out << frame << ',' << truth.stamp_s << ',' << a.id << ',' << a.class_name;
    put_pose(out, a.T_world_actor);
    put(out, a.position_rig_m);
    put(out, a.velocity_rig_mps);
    put(out, a.angular_velocity_rig_rps);
    out << ',' << a.pixels;
    const core::BoxTruth& b = a.box;
    put(out, b.center_m);
    put(out, b.size_m);
    out << ',' << b.yaw_rad;
    put(out, b.velocity_mps);
    out << ',' << b.visible_fraction << ',' << (b.truncated ? 1 : 0);
    put(out, b.center_world_m);
    out << ',' << b.yaw_world_rad << '\n';
  }
  return out.str();
}

std::vector<core::FrameTruth> read_truth_tables(const std::string& ego_csv, const std::string& objects_csv) {
  std::vector<core::FrameTruth> frames;
  read_rows(ego_csv, {kEgoCsvHeader}, [&](const std::vector<std::string>& c, int line, std::size_t) {
    const auto frame = static_cast<std::size_t>(number(c[0], ego_csv, line));
    if (frame != frames.size()) {
      throw core::FileError(ego_csv + ":" + std::to_string(line) + ": frame " + c[0] + " out of order");
    }
    core::FrameTruth t;
    t.stamp_s = number(c[1], ego_csv, line);
    t.ego.T_world_rig = pose(c, 2, ego_csv, line);
    t.ego.velocity_mps = vec(c, 9, ego_csv, line);
    t.ego.angular_velocity_rps = vec(c, 12, ego_csv, line);
    frames.push_back(t);
  });
  read_rows(objects_csv, {kObjectsCsvHeader, kObjectsCsvHeaderWithoutBoxes}, [&](const std::vector<std::string>& c, int line,
                                                                                std::size_t header) {
    const auto frame = static_cast<std::size_t>(number(c[0], objects_csv, line));
    if (frame >= frames.size()) {
      throw core::FileError(objects_csv + ":" + std::to_string(line) + ": frame " + c[0] + " not in ego.csv");
    }
    core::ActorTruth a;
    a.id = static_cast<std::uint32_t>(number(c[2], objects_csv, line));
    a.class_name = c[3];
    a.T_world_actor = pose(c, 4, objects_csv, line);
    a.position_rig_m = vec(c, 11, objects_csv, line);
    a.velocity_rig_mps = vec(c, 14, objects_csv, line);
    a.angular_velocity_rig_rps = vec(c, 17, objects_csv, line);
    a.pixels = static_cast<int>(number(c[20], objects_csv, line));
    if (header == 0) {
      core::BoxTruth& b = a.box;
      b.center_m = vec(c, 21, objects_csv, line);
      b.size_m = vec(c, 24, objects_csv, line);
      b.yaw_rad = number(c[27], objects_csv, line);
      b.velocity_mps = vec(c, 28, objects_csv, line);
      b.visible_fraction = number(c[31], objects_csv, line);
      b.truncated = number(c[32], objects_csv, line) != 0.0;
      b.center_world_m = vec(c, 33, objects_csv, line);
      b.yaw_world_rad = number(c[36], objects_csv, line);
    }
    frames[frame].actors.push_back(a);
  });
  return frames;
}

bool objects_csv_has_boxes(const std::string& objects_csv) {
  std::ifstream in(objects_csv);
  if (!in) throw core::FileError(objects_csv + ": cannot open");
  std::string line;
  std::getline(in, line);
  line += "\n";
  if (line == kObjectsCsvHeader) return true;
  if (line == kObjectsCsvHeaderWithoutBoxes) return false;
  throw core::FileError(objects_csv + ":1: unexpected header '" + line.substr(0, line.size() - 1) + "'");
}

}  // namespace fmcw::io
