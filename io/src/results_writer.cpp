#include "fmcw/io/results_writer.hpp"

#include "fmcw/io/csv_cell.hpp"

#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/pcd.hpp"

namespace fmcw::io {

namespace fs = std::filesystem;

namespace {
std::string num(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  std::ostringstream out;
  out << std::setprecision(9) << v;
  return out.str();
}

nlohmann::json json_number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json velocity_json(const core::VelocityEstimate& e) {
  const Eigen::Vector3d sd = e.axis_std_mps();
  return {{"valid", e.valid},
          {"velocity_mps", {json_number(e.velocity_mps.x()), json_number(e.velocity_mps.y()), json_number(e.velocity_mps.z())}},
          {"std_mps", {json_number(sd.x()), json_number(sd.y()), json_number(sd.z())}},
          {"condition_number", json_number(e.condition_number)},
          {"residual_rms_mps", json_number(e.residual_rms_mps)},
          {"points_used", e.num_points}};
}

std::string velocity_csv(const core::VelocityEstimate& e) {
  const Eigen::Vector3d sd = e.axis_std_mps();
  std::ostringstream row;
  row << num(e.velocity_mps.x()) << ',' << num(e.velocity_mps.y()) << ',' << num(e.velocity_mps.z()) << ','
      << num(sd.x()) << ',' << num(sd.y()) << ',' << num(sd.z()) << ',' << num(e.condition_number) << ','
      << num(e.residual_rms_mps) << ',' << e.num_points << ',' << (e.valid ? 1 : 0);
  return row.str();
}
}  // namespace

ResultsWriter::ResultsWriter(const std::string& dir) : dir_(dir) {
  ensure_writable_directory(dir);
  open(ego_, "ego.csv",
       "frame,source,method,status,static_pixels,clusters,vx_mps,vy_mps,vz_mps,std_x_mps,std_y_mps,std_z_mps,"
       "condition_number,residual_rms_mps,points_used,valid\n");
  open(objects_, "objects.csv",
       "frame,cluster,pixels,centroid_x_m,centroid_y_m,centroid_z_m,vx_mps,vy_mps,vz_mps,std_x_mps,std_y_mps,"
       "std_z_mps,condition_number,residual_rms_mps,points_used,valid\n");
  open(timing_, "timing.csv", "frame,method,clustering_ms,ego_ms,objects_ms,total_ms\n");
  open(json_, "results.json", "{\"frames\": [\n");
}

ResultsWriter::~ResultsWriter() {
  if (!finished_) {
    for (Table* t : {&ego_, &objects_, &timing_, &json_}) {
      t->out.close();
      std::error_code ec;
      fs::remove(t->tmp, ec);
    }
  }
}

void ResultsWriter::open(Table& table, const std::string& name, const std::string& header) {
  table.path = (fs::path(dir_) / name).string();
  table.tmp = (fs::path(dir_) / (".tmp." + name)).string();
  table.out.open(table.tmp, std::ios::binary | std::ios::trunc);
  if (!table.out) throw std::runtime_error("cannot write '" + table.path + "'");
  table.out << header;
}

void ResultsWriter::add(std::size_t frame_index, const std::string& source, const core::MotionEstimate& e) {
  ego_.out << frame_index << ',' << csv_cell(source) << ',' << e.method << ',' << core::to_string(e.status) << ','
           << e.num_static_pixels << ',' << e.clusters.size() << ',' << velocity_csv(e.ego) << '\n';
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& c : e.clusters) {
    objects_.out << frame_index << ',' << c.id << ',' << c.num_pixels << ',' << num(c.centroid_m.x()) << ','
                 << num(c.centroid_m.y()) << ',' << num(c.centroid_m.z()) << ',' << velocity_csv(c.velocity) << '\n';
    nlohmann::json o = velocity_json(c.velocity);
    o["cluster"] = c.id;
    o["pixels"] = c.num_pixels;
    o["centroid_m"] = {c.centroid_m.x(), c.centroid_m.y(), c.centroid_m.z()};
    objects.push_back(o);
  }
  timing_.out << frame_index << ',' << e.method << ',' << num(e.timing.clustering_ms) << ',' << num(e.timing.ego_ms)
              << ',' << num(e.timing.objects_ms) << ',' << num(e.timing.total_ms) << '\n';
  const nlohmann::json frame = {{"frame", frame_index}, {"source", source},   {"method", e.method},
                                {"status", core::to_string(e.status)},      {"message", e.message},
                                {"static_pixels", e.num_static_pixels},     {"ego", velocity_json(e.ego)},
                                {"objects", objects}};
  json_.out << (first_json_ ? "  " : ",\n  ") << frame.dump();
  first_json_ = false;
  for (Table* t : {&ego_, &objects_, &timing_, &json_}) {
    if (!t->out) throw std::runtime_error("cannot write '" + t->path + "': write failed (disk full?)");
  }
}

void ResultsWriter::close(Table& table) {
  table.out.close();
  if (table.out.fail()) throw std::runtime_error("cannot write '" + table.path + "': close failed (disk full?)");
  std::error_code ec;
  fs::rename(table.tmp, table.path, ec);
  if (ec) throw std::runtime_error("cannot write '" + table.path + "': " + ec.message());
}

void ResultsWriter::finish() {
  json_.out << "\n]}\n";
  for (Table* t : {&ego_, &objects_, &timing_, &json_}) close(*t);
  finished_ = true;
}

void write_labelled_pcd(const std::string& path, const core::Scan& scan, const core::MotionEstimate& estimate) {
  core::Frame frame;
  frame.scan = scan;
  PcdCloud cloud = pcd_from_frame(frame, false);
  PcdField label{"label", 'I', 4, std::vector<double>(scan.size())};
  for (std::size_t i = 0; i < scan.size(); ++i) label.values[i] = estimate.labels[i];
  cloud.fields.push_back(std::move(label));
  write_pcd(path, cloud);
}

}  // namespace fmcw::io
