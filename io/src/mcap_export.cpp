#include "fmcw/io/mcap_export.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "fmcw/core/check.hpp"
#include "fmcw/io/ros2_messages.hpp"

namespace fmcw::io {

using core::concat;

std::vector<std::vector<EstimatedObject>> read_estimated_objects(const std::string& results_json) {
  std::ifstream in(results_json);
  FMCW_CHECK_FILE(in.good(), results_json, ": cannot open");
  std::vector<std::vector<EstimatedObject>> frames;
  try {
    const nlohmann::json doc = nlohmann::json::parse(in);
    for (const auto& frame : doc.at("frames")) {
      std::vector<EstimatedObject> objects;
      for (const auto& o : frame.at("objects")) {
        EstimatedObject e;
        e.cluster = o.at("cluster").get<int>();
        e.valid = o.at("valid").get<bool>();
        for (int a = 0; a < 3; ++a) {
          e.centroid_m[a] = o.at("centroid_m").at(a).get<double>();
          const auto& v = o.at("velocity_mps").at(a);
          e.velocity_mps[a] = v.is_null() ? 0.0 : v.get<double>();  // NaN is written as null
        }
        objects.push_back(e);
      }
      frames.push_back(std::move(objects));
    }
  } catch (const nlohmann::json::exception& e) {
    throw core::FileError(concat(results_json, ": not a results.json of fmcw process: ", e.what()));
  }
  return frames;
}

namespace {
Eigen::Isometry3d yaw_pose(const Eigen::Vector3d& center, double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = center;
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

void set_rgba(ros2::Marker& m, float r, float g, float b, float a) {
  m.rgba[0] = r;
  m.rgba[1] = g;
  m.rgba[2] = b;
  m.rgba[3] = a;
}

// An arrow from `from` along `velocity` (its length: the distance covered in 1 s).
ros2::Marker velocity_arrow(const std::string& ns, int id, const Eigen::Vector3d& from, const Eigen::Vector3d& velocity) {
  ros2::Marker m;
  m.ns = ns;
  m.id = id;
  m.type = ros2::Marker::kArrow;
  m.scale = Eigen::Vector3d(0.1, 0.25, 0.3);  // shaft diameter, head diameter, head length [m]
  m.points = {from, from + velocity};
  set_rgba(m, 1.0f, 0.9f, 0.1f, 1.0f);
  return m;
}

std::vector<ros2::Marker> truth_markers(const core::FrameTruth& truth) {
  std::vector<ros2::Marker> out(1);
  out[0].action = ros2::Marker::kDeleteAll;  // the previous frame's boxes go
  for (const core::ActorTruth& a : truth.actors) {
    const bool has_box = a.box.size_m.minCoeff() > 0.0;
    const Eigen::Vector3d center = has_box ? a.box.center_m : a.position_rig_m;
    if (has_box) {
      ros2::Marker box;
      box.ns = "truth_boxes";
      box.id = static_cast<std::int32_t>(a.id);
      box.type = ros2::Marker::kCube;
      box.pose = yaw_pose(a.box.center_m, a.box.yaw_rad);
      box.scale = a.box.size_m;
      const bool person = a.class_name == "pedestrian" || a.class_name == "person";
      set_rgba(box, person ? 1.0f : 0.2f, person ? 0.5f : 0.6f, person ? 0.1f : 1.0f, 0.35f);
      out.push_back(box);
    }
    out.push_back(velocity_arrow("truth_velocity", static_cast<int>(a.id), center,
                                 has_box ? a.box.velocity_mps : a.velocity_rig_mps));
  }
  return out;
}

std::vector<ros2::Marker> estimated_markers(const std::vector<EstimatedObject>& objects) {
  std::vector<ros2::Marker> out(1);
  out[0].action = ros2::Marker::kDeleteAll;
  for (const EstimatedObject& o : objects) {
    ros2::Marker dot;
    dot.ns = "estimated_objects";
    dot.id = o.cluster;
    dot.type = ros2::Marker::kSphere;
    dot.pose.translation() = o.centroid_m;
    dot.scale = Eigen::Vector3d::Constant(0.4);
    set_rgba(dot, 1.0f, 0.2f, 0.2f, 0.8f);
    out.push_back(dot);
    if (o.valid) out.push_back(velocity_arrow("estimated_velocity", o.cluster, o.centroid_m, o.velocity_mps));
  }
  return out;
}
}  // namespace

struct McapSequenceWriter::State {
  McapExportOptions options;
  McapWriter writer;
  std::uint16_t points = 0, tf = 0, tf_static = 0, truth = 0, estimated = 0;
  bool first = true;
  std::size_t frames = 0;
  State(std::ostream& out, const McapExportOptions& o) : options(o), writer(out, o.writer) {}
};

McapSequenceWriter::McapSequenceWriter(std::ostream& out, const McapExportOptions& options)
    : s_(std::make_unique<State>(out, options)) {
  McapWriter& w = s_->writer;
  // Message encoding cdr, schema encoding ros2msg (specification, "Well-known message encodings").
  const std::uint16_t cloud = w.add_schema("sensor_msgs/msg/PointCloud2", "ros2msg", ros2::point_cloud2_definition());
  s_->points = w.add_channel(options.points_topic, cloud, "cdr");
  const std::uint16_t tf = w.add_schema("tf2_msgs/msg/TFMessage", "ros2msg", ros2::tf_message_definition());
  s_->tf_static = w.add_channel("/tf_static", tf, "cdr");
  if (options.ego_poses) s_->tf = w.add_channel("/tf", tf, "cdr");
  if (options.truth_markers || options.estimated_markers) {
    const std::uint16_t markers =
        w.add_schema("visualization_msgs/msg/MarkerArray", "ros2msg", ros2::marker_array_definition());
    if (options.truth_markers) s_->truth = w.add_channel("/markers/truth", markers, "cdr");
    if (options.estimated_markers) s_->estimated = w.add_channel("/markers/estimated", markers, "cdr");
  }
}

McapSequenceWriter::~McapSequenceWriter() = default;

std::uint64_t McapSequenceWriter::bytes_written() const { return s_->writer.bytes_written(); }

ros2::Time McapSequenceWriter::begin_frame(const PcdCloud& cloud, const std::string& source) {
  State& s = *s_;
  McapWriter& w = s.writer;
  const double stamp_s = stamp_from_comments(cloud, source);
  ros2::Time stamp;
  try {
    stamp = ros2::Time::from_seconds(stamp_s);
  } catch (const std::exception&) {
    core::rethrow_as_file_error(source + ": ");
  }
  if (s.first) {
    // The rig's heads, from the first frame (a dataset's heads do not move on the rig).
    McapEntries heads;
    std::vector<ros2::TransformStamped> mounts;
    for (const auto& c : cloud.comments) {
      if (c.rfind("fmcw_head ", 0) == 0) heads.emplace_back("head" + std::to_string(heads.size()), c);
    }
    for (const core::HeadInfo& h : heads_from_comments(cloud, source)) {
      mounts.push_back({stamp, s.options.rig_frame, h.name, h.T_rig_head});
    }
    if (mounts.empty()) mounts.push_back({stamp, s.options.rig_frame, "sensor", Eigen::Isometry3d::Identity()});
    w.add_metadata("fmcw", heads);
    w.write(s.tf_static, stamp.nanoseconds(), ros2::encode_tf(mounts));
    s.first = false;
  }
  return stamp;
}

void McapSequenceWriter::add_frame(const PcdCloud& cloud, const std::string& source, const core::FrameTruth* truth,
                                   const std::vector<EstimatedObject>* estimated) {
  const ros2::Time stamp = begin_frame(cloud, source);
  try {
    s_->writer.write(s_->points, stamp.nanoseconds(),
                     ros2::encode(ros2::point_cloud2_from_pcd(cloud, stamp, s_->options.rig_frame)));
  } catch (const core::InputError&) {
    core::rethrow_as_file_error(source + ": ");
  }
  end_frame(stamp, source, truth, estimated);
}

void McapSequenceWriter::add_packed_frame(const PcdCloud& cloud, PcdPackedData&& packed, const std::string& source,
                                          const core::FrameTruth* truth,
                                          const std::vector<EstimatedObject>* estimated) {
  const ros2::Time stamp = begin_frame(cloud, source);
  try {
    ros2::PointCloud2 msg = ros2::point_cloud2_from_packed(cloud, std::move(packed), stamp, s_->options.rig_frame);
    s_->writer.write(s_->points, stamp.nanoseconds(), [&](std::vector<std::uint8_t>& out) { ros2::encode(msg, out); });
    packed.data = std::move(msg.data);  // the caller's buffer again, for the next frame
  } catch (const core::InputError&) {
    core::rethrow_as_file_error(source + ": ");
  }
  end_frame(stamp, source, truth, estimated);
}

void McapSequenceWriter::end_frame(ros2::Time stamp, const std::string& source, const core::FrameTruth* truth,
                                   const std::vector<EstimatedObject>* estimated) {
  State& s = *s_;
  McapWriter& w = s.writer;
  if (s.options.ego_poses) {
    FMCW_CHECK_ARG(truth != nullptr, source, ": no ego pose for /tf");
    w.write(s.tf, stamp.nanoseconds(),
            ros2::encode_tf({{stamp, s.options.world_frame, s.options.rig_frame, truth->ego.T_world_rig}}));
  }
  if (s.options.truth_markers) {
    FMCW_CHECK_ARG(truth != nullptr, source, ": no truth for /markers/truth");
    w.write(s.truth, stamp.nanoseconds(), ros2::encode_markers(truth_markers(*truth), stamp, s.options.rig_frame));
  }
  if (s.options.estimated_markers) {
    FMCW_CHECK_ARG(estimated != nullptr, source, ": no estimates for /markers/estimated");
    w.write(s.estimated, stamp.nanoseconds(),
            ros2::encode_markers(estimated_markers(*estimated), stamp, s.options.rig_frame));
  }
  w.close_chunk();  // one chunk per frame: a viewer seeks frame by frame
  ++s.frames;
}

void McapSequenceWriter::finish() { s_->writer.finish(); }

}  // namespace fmcw::io
