#include "fmcw/io/openpcdet.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/npy.hpp"

namespace fmcw::io {

using core::concat;

namespace {
constexpr std::size_t kPointColumns = 5;  // x y z intensity v

const PcdField& require(const PcdCloud& cloud, const char* name, const std::string& where) {
  const PcdField* f = cloud.find(name);
  if (!f) {
    throw core::FileError(concat(where, ": no field '", name, "' for OpenPCDet's points (x y z intensity v)"));
  }
  return *f;
}

void write_text(const std::string& path, const std::string& text) {
  write_file_atomically(path,
                        [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

nlohmann::ordered_json vector_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
}  // namespace

std::vector<const core::ActorTruth*> openpcdet_boxes(const core::FrameTruth& truth) {
  std::vector<const core::ActorTruth*> boxes;
  for (const core::ActorTruth& a : truth.actors) {
    if (a.pixels > 0) boxes.push_back(&a);
  }
  return boxes;
}

std::string openpcdet_labels(const core::FrameTruth& truth, const std::string& where) {
  std::ostringstream out;
  out << std::setprecision(10);
  for (const core::ActorTruth* a : openpcdet_boxes(truth)) {
    const std::string& name = a->class_name;
    if (name.empty() ||
        std::any_of(name.begin(), name.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); })) {
      throw core::FileError(concat(where, ": actor ", a->id, ": class name '", name,
                                   "' cannot be a label's last column (empty or with white space)"));
    }
    const core::BoxTruth& b = a->box;
    const double values[] = {b.center_m.x(), b.center_m.y(), b.center_m.z(), b.size_m.x(),
                             b.size_m.y(),   b.size_m.z(),   b.yaw_rad};
    for (const double v : values) {
      if (!std::isfinite(v)) {
        throw core::FileError(concat(where, ": actor ", a->id, ": box value ", v, " is not finite"));
      }
      out << v << ' ';
    }
    out << name << '\n';
  }
  return out.str();
}

std::size_t write_openpcdet_frame(const std::string& points_path, const std::string& labels_path, const PcdCloud& cloud,
                                  const core::FrameTruth& truth, const std::string& where) {
  const PcdField& x = require(cloud, "x", where);
  const PcdField& y = require(cloud, "y", where);
  const PcdField& z = require(cloud, "z", where);
  const PcdField& v = require(cloud, "v", where);
  const PcdField* intensity = cloud.find("intensity");
  std::vector<float> points;
  std::size_t rows = 0;
  for (std::size_t i = 0; i < cloud.points(); ++i) {
    const bool has_return = std::isfinite(x.values[i]) && std::isfinite(y.values[i]) && std::isfinite(z.values[i]);
    if (!has_return) continue;
    const double remission = intensity ? intensity->values[i] : 0.0;
    if (!std::isfinite(remission) || !std::isfinite(v.values[i])) {
      throw core::FileError(
    concat(where, ": point ", i, " has a return but intensity ", remission, " and v ", v.values[i]));
    }
    for (const double value : {x.values[i], y.values[i], z.values[i], remission, v.values[i]}) {
      points.push_back(static_cast<float>(value));
    }
    ++rows;
  }
  const std::string labels = openpcdet_labels(truth, where);
  write_npy_f32(points_path, points, rows, kPointColumns);
  try {
    write_text(labels_path, labels);
  } catch (...) {
    // Points without their labels would look like a frame without objects: remove them too.
    std::remove(points_path.c_str());
    throw;
  }
  return rows;
}

void write_openpcdet_split(const std::string& path, const std::vector<std::string>& frame_ids) {
  std::string text;
  for (const std::string& id : frame_ids) text += id + "\n";
  write_text(path, text);
}

void write_openpcdet_meta(const std::string& path, const std::vector<std::string>& frame_ids,
                          const std::vector<core::FrameTruth>& truth, const std::string& source) {
  FMCW_CHECK_ARG(frame_ids.size() == truth.size(), path, ": ", frame_ids.size(), " frame ids for ", truth.size(),
                 " frames of ground truth");
  std::vector<std::string> classes;
  for (const core::FrameTruth& t : truth) {
    for (const core::ActorTruth& a : t.actors) {
      if (std::find(classes.begin(), classes.end(), a.class_name) == classes.end()) classes.push_back(a.class_name);
    }
  }
  nlohmann::ordered_json frames = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < truth.size(); ++k) {
    nlohmann::ordered_json boxes = nlohmann::ordered_json::array();
    for (const core::ActorTruth* a : openpcdet_boxes(truth[k])) {
      boxes.push_back({{"actor_id", a->id},
                       {"class", a->class_name},
                       {"velocity_mps", vector_json(a->box.velocity_mps)},
                       {"visible_fraction", a->box.visible_fraction},
                       {"truncated", a->box.truncated},
                       {"pixels", a->pixels}});
    }
    frames[frame_ids[k]] = {{"frame", k}, {"stamp_s", truth[k].stamp_s}, {"boxes", boxes}};
  }
  const nlohmann::ordered_json meta = {
      {"format", "fmcw-openpcdet"},
      {"format_version", 1},
      {"source", source},
      {"coordinate_frame", "rig: x forward, y left, z up [m]"},
      {"point_features", {"x", "y", "z", "intensity", "v"}},
      {"label_columns", {"x", "y", "z", "dx", "dy", "dz", "heading", "class_name"}},
      {"classes", classes},
      {"frames", frames},
  };
  write_text(path, meta.dump(2) + "\n");
}

}  // namespace fmcw::io
