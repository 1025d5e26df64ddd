#include "fmcw/io/frame_input.hpp"

#include <cmath>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/dataset_files.hpp"

namespace fmcw::io {

using core::concat;

InputFormat parse_input_format(const std::string& text) {
  if (text == "pcd") return InputFormat::kPcd;
  if (text == "points") return InputFormat::kPoints;
  if (text == "aeva") return InputFormat::kAeva;
  if (text == "mcap") return InputFormat::kMcap;
  throw core::InputError("input format must be pcd, points, aeva or mcap, got '" + text + "'");
}

const std::vector<std::string>& input_format_names() {
  static const std::vector<std::string> names = {"pcd", "points", "aeva", "mcap"};
  return names;
}

std::vector<std::string> list_input_files(const std::string& input, InputFormat format) {
  if (format == InputFormat::kMcap) return list_frame_files(input, ".mcap");
  return list_frame_files(input, format == InputFormat::kAeva ? ".bin" : ".pcd");
}

core::PointList points_from_pcd(const PcdCloud& cloud, const std::string& source) {
  check_single_count(cloud, {"x", "y", "z", "v", "intensity", "t"}, source, "points need");
  for (const char* required : {"x", "y", "z", "v"}) {
    if (cloud.find(required) == nullptr) {
      throw core::FileError(concat(source, ": missing field '", required, "' (points need x y z v)"));
    }
  }
  const auto& x = cloud.find("x")->values;
  const auto& y = cloud.find("y")->values;
  const auto& z = cloud.find("z")->values;
  const auto& v = cloud.find("v")->values;
  const PcdField* intensity = cloud.find("intensity");
  const PcdField* t = cloud.find("t");
  core::PointList points;
  for (std::size_t i = 0; i < cloud.points(); ++i) {
    // NaN coordinates mark a beam without a return, as in the organized frames.
    if (!(std::isfinite(x[i]) && std::isfinite(y[i]) && std::isfinite(z[i]))) continue;
    for (const PcdField* f : {cloud.find("v"), intensity, t}) {
      if (f && !std::isfinite(f->values[i])) {
        throw core::FileError(concat(source, ": point ", i, " has finite x y z but field '", f->name, "' is ",
                                     f->values[i]));
      }
    }
    points.x_m.push_back(static_cast<float>(x[i]));
    points.y_m.push_back(static_cast<float>(y[i]));
    points.z_m.push_back(static_cast<float>(z[i]));
    points.radial_velocity_mps.push_back(static_cast<float>(v[i]));
    if (intensity) points.intensity.push_back(static_cast<float>(intensity->values[i]));
    if (t) points.time_offset_s.push_back(static_cast<float>(t->values[i]));
  }
  if (points.size() == 0) throw core::FileError(concat(source, ": no point with finite x y z"));
  return points;
}

namespace {
// Records the frame the file implies and applies the option's override.
void set_velocity_frame(InputFrame& out, core::VelocityFrame implied, std::string source,
                        const InputOptions& options) {
  out.file_velocity_frame = implied;
  out.velocity_frame_source = std::move(source);
  out.frame.scan.velocity_frame = options.velocity_frame.value_or(implied);
}

std::string comment_source(const PcdCloud& cloud) {
  for (const auto& c : cloud.comments) {
    if (c.rfind("fmcw_velocity_frame", 0) == 0) return "the file's fmcw_velocity_frame comment";
  }
  return "the default";
}
}  // namespace

InputFrame frame_from_cloud(const PcdCloud& cloud, const std::string& source, const InputOptions& options) {
  InputFrame out;
  if (cloud.height > 1 && options.format != InputFormat::kPoints) {
    out.frame = frame_from_pcd(cloud, source);
    if (options.negate_velocity) {
      for (float& v : out.frame.scan.radial_velocity_mps) v = -v;
    }
    set_velocity_frame(out, out.frame.scan.velocity_frame, comment_source(cloud), options);
    return out;
  }
  core::PointList points = points_from_pcd(cloud, source);
  if (options.negate_velocity) {
    for (float& v : points.radial_velocity_mps) v = -v;
  }
  options.grid.validate();  // a bad option is the caller's error (InputError), not the file's
  core::GridProjection projection;
  try {
    projection = core::project_to_grid(points, options.grid);
  } catch (const std::exception&) {
    core::rethrow_as_file_error(concat(source, ": "));  // a bad point is the file's
  }
  if (options.format == InputFormat::kMcap) projection.scan.stamp_s = stamp_from_comments(cloud, source);
  out.frame.scan = std::move(projection.scan);
  set_velocity_frame(out, velocity_frame_from_comments(cloud, source), comment_source(cloud), options);
  out.projected = true;
  out.stats = projection.stats;
  return out;
}

InputFrame read_input_frame(const std::string& path, const InputOptions& options) {
  // An MCAP file holds many frames: InputSequence reads it (fmcw process, fmcw export --to mcap).
  if (options.format == InputFormat::kMcap) {
    throw core::InputError(concat(path, ": --format mcap is read by `fmcw process` and `fmcw export --to mcap` only"));
  }
  InputFrame out;
  if (options.format == InputFormat::kPcd) {
    const PcdCloud cloud = read_pcd(path);
    out.frame = frame_from_pcd(cloud, path);
    set_velocity_frame(out, out.frame.scan.velocity_frame, comment_source(cloud), options);
    return out;
  }
  core::VelocityFrame implied = core::VelocityFrame::kEgoCompensated;
  std::string source = "the Aeva datasets' convention";
  core::GridProjection projection;
  if (options.format == InputFormat::kAeva) {
    AevaScanParams params;
    params.layout = options.aeva_layout;
    params.grid = options.grid;
    params.negate_velocity = options.negate_velocity;
    projection = read_aeva_scan(path, params);
  } else {
    const PcdCloud cloud = read_pcd(path);
    // A stamp comment is checked as the organized reader checks it, so that no reader takes a
    // file the other refuses. The projected scan keeps stamp 0, as it always has.
    stamp_from_comments(cloud, path);
    InputOptions points = options;
    points.format = InputFormat::kPoints;
    return frame_from_cloud(cloud, path, points);
  }
  out.frame.scan = std::move(projection.scan);
  set_velocity_frame(out, implied, source, options);
  out.projected = true;
  out.stats = projection.stats;
  return out;
}

}  // namespace fmcw::io
